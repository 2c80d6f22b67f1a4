//! Adapter selection and small wgpu helpers shared by the self-check, the tests, the
//! demo and the benchmark.
//!
//! The adapter is the one named by the `WGPU_ADAPTER_NAME` environment variable
//! (a case-insensitive substring, e.g. `llvmpipe` for Mesa's lavapipe) when set, else
//! the first Vulkan adapter. When none exists the error carries the command that
//! installs lavapipe; volfog never falls back silently.

use std::borrow::Cow;

use glam::Vec4;

/// The Debian command that installs Mesa's lavapipe software Vulkan driver.
pub const INSTALL_HINT: &str =
    "apt-get update && apt-get install -y mesa-vulkan-drivers libvulkan1";

/// Errors of adapter selection and GPU helpers.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter (or none matching `WGPU_ADAPTER_NAME`) was found.
    #[error(
        "no Vulkan adapter{} found (adapters seen: {}); install Mesa's lavapipe with: {}",
        requested.as_ref().map(|r| format!(" matching WGPU_ADAPTER_NAME={r:?}")).unwrap_or_default(),
        if available.is_empty() { "none".to_string() } else { available.join(", ") },
        INSTALL_HINT
    )]
    NoAdapter {
        /// The requested name, if any.
        requested: Option<String>,
        /// Names of the adapters that were found.
        available: Vec<String>,
    },
    /// The adapter refused to create a device.
    #[error("requesting a device from {adapter} failed: {message}")]
    Device {
        /// Adapter name.
        adapter: String,
        /// wgpu's message.
        message: String,
    },
    /// A GPU operation failed (validation error, mapping failure).
    #[error("GPU operation failed: {0}")]
    Operation(String),
}

/// An adapter with its device and queue.
#[derive(Debug)]
pub struct Gpu {
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// The queue.
    pub queue: wgpu::Queue,
    /// Adapter information (name, driver).
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// Opens the selected adapter with default limits and no optional features.
    pub fn new() -> Result<Self, GpuError> {
        Self::with_features(wgpu::Features::empty())
    }

    /// The features [`Gpu::shared`] enables where the adapter has them.
    pub const SHARED_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
        .union(wgpu::Features::FLOAT32_BLENDABLE)
        .union(wgpu::Features::FLOAT32_FILTERABLE)
        .union(wgpu::Features::MULTIVIEW)
        .union(wgpu::Features::SELECTIVE_MULTIVIEW);

    /// One device for the whole process (the GPU test binary shares it), with those
    /// of [`Gpu::SHARED_FEATURES`] the adapter supports. Panics with the install
    /// command when no adapter exists: a GPU test without a GPU fails.
    pub fn shared() -> &'static Gpu {
        static SHARED: std::sync::OnceLock<Gpu> = std::sync::OnceLock::new();
        SHARED.get_or_init(|| match Gpu::with_features(Self::SHARED_FEATURES) {
            Ok(gpu) => {
                eprintln!("adapter: {}", gpu.describe());
                gpu
            }
            Err(e) => panic!("{e}"),
        })
    }

    /// Fails (panics) naming `feature` when the device lacks it: a test that needs a
    /// feature never passes silently without it.
    pub fn require(&self, feature: wgpu::Features) {
        assert!(
            self.device.features().contains(feature),
            "this test needs the device feature {feature:?}, which {} does not offer",
            self.describe()
        );
    }

    /// Opens the selected adapter, enabling those of `wanted` that it supports.
    pub fn with_features(wanted: wgpu::Features) -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(desc);
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        let requested = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .filter(|s| !s.is_empty());
        let available: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        let adapter = adapters
            .into_iter()
            .find(|a| match &requested {
                Some(name) => a
                    .get_info()
                    .name
                    .to_lowercase()
                    .contains(&name.to_lowercase()),
                None => true,
            })
            .ok_or_else(|| GpuError::NoAdapter {
                requested: requested.clone(),
                available,
            })?;
        let info = adapter.get_info();
        let features = adapter.features() & wanted;
        let mut limits = wgpu::Limits::default().using_resolution(adapter.limits());
        if features.contains(wgpu::Features::MULTIVIEW) {
            // Multiview draws as many views as the adapter allows (the default limit is 0).
            limits.max_multiview_view_count = adapter.limits().max_multiview_view_count;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("volfog"),
            required_features: features,
            required_limits: limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| GpuError::Device {
            adapter: info.name.clone(),
            message: e.to_string(),
        })?;
        Ok(Self {
            adapter,
            device,
            queue,
            info,
        })
    }

    /// A one-line description of the adapter: name, driver and backend.
    pub fn describe(&self) -> String {
        format!(
            "{} ({} {}, {:?})",
            self.info.name, self.info.driver, self.info.driver_info, self.info.backend
        )
    }

    /// Creates a shader module from a naga module.
    pub fn shader_from_naga(&self, label: &str, module: naga::Module) -> wgpu::ShaderModule {
        self.device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Naga(Cow::Owned(module)),
            })
    }

    /// Creates a shader module from WGSL text.
    pub fn shader_from_wgsl(&self, label: &str, wgsl: &str) -> wgpu::ShaderModule {
        self.device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(Cow::Owned(wgsl.to_string())),
            })
    }

    /// Runs `f` inside a validation error scope and turns a validation error into
    /// [`GpuError::Operation`].
    pub fn checked<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        match pollster::block_on(scope.pop()) {
            Some(err) => Err(GpuError::Operation(err.to_string())),
            None => Ok(value),
        }
    }

    /// Copies a buffer back to the CPU.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let size = buffer.size();
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        self.map_read(&staging)
    }

    fn map_read(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Operation(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Operation(e.to_string()))?
            .map_err(|e| GpuError::Operation(e.to_string()))?;
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Operation(e.to_string()))?
            .to_vec();
        staging.unmap();
        Ok(bytes)
    }

    /// Creates a 3D rgba16float texture (sampled, storage, copy src/dst) holding
    /// `texels` (x fastest, then y, then z).
    pub fn texture_3d_rgba16f(
        &self,
        label: &str,
        size: [u32; 3],
        texels: &[Vec4],
    ) -> wgpu::Texture {
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: size[2],
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        self.write_rgba16f(&texture, texels);
        texture
    }

    /// Creates a 2D rgba16float texture (render attachment, sampled, copy src/dst)
    /// holding `texels` (row-major from the top).
    pub fn texture_2d_rgba16f(
        &self,
        label: &str,
        size: [u32; 2],
        texels: &[Vec4],
    ) -> wgpu::Texture {
        let texture = texture_2d(
            &self.device,
            label,
            (size[0], size[1]),
            wgpu::TextureFormat::Rgba16Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
        );
        self.write_rgba16f(&texture, texels);
        texture
    }

    fn write_rgba16f(&self, texture: &wgpu::Texture, texels: &[Vec4]) {
        if texels.is_empty() {
            return;
        }
        let size = texture.size();
        let data: Vec<half::f16> = texels
            .iter()
            .flat_map(|t| t.to_array().map(half::f16::from_f32))
            .collect();
        self.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(size.width * 8),
                rows_per_image: Some(size.height),
            },
            size,
        );
    }

    /// Reads a 3D (or 2D) texture of 8-byte rgba16float texels back as f32.
    pub fn read_texture_rgba16f(&self, texture: &wgpu::Texture) -> Result<Vec<Vec4>, GpuError> {
        let raw = self.read_texture_raw(texture, 8)?;
        let halfs: &[half::f16] = bytemuck::cast_slice(&raw);
        Ok(halfs
            .chunks_exact(4)
            .map(|c| Vec4::new(c[0].to_f32(), c[1].to_f32(), c[2].to_f32(), c[3].to_f32()))
            .collect())
    }

    /// Reads a texture of `bytes_per_texel`-byte texels back, tightly packed.
    pub fn read_texture_raw(
        &self,
        texture: &wgpu::Texture,
        bytes_per_texel: u32,
    ) -> Result<Vec<u8>, GpuError> {
        let size = texture.size();
        let row = size.width * bytes_per_texel;
        let padded =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog texture readback"),
            size: u64::from(padded)
                * u64::from(size.height)
                * u64::from(size.depth_or_array_layers),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(size.height),
                },
            },
            size,
        );
        self.queue.submit([encoder.finish()]);
        let bytes = self.map_read(&staging)?;
        let mut out = Vec::with_capacity((row * size.height * size.depth_or_array_layers) as usize);
        for chunk in bytes.chunks_exact(padded as usize) {
            out.extend_from_slice(&chunk[..row as usize]);
        }
        Ok(out)
    }

    /// Runs a compute entry point over `count` invocations with `inputs` in a read-only
    /// storage buffer (binding 0) and `outputs_per_item * count` f32 in a read-write
    /// storage buffer (binding 1), both in group 0, and returns the outputs.
    ///
    /// The shader must declare `@group(0) @binding(0) var<storage, read> input: array<...>`
    /// and `@group(0) @binding(1) var<storage, read_write> output: array<...>`, use
    /// `@workgroup_size(64)` and ignore invocations at or beyond `count`.
    pub fn run_kernel(
        &self,
        module: &wgpu::ShaderModule,
        entry: &str,
        inputs: &[u8],
        output_bytes: u64,
        count: u32,
    ) -> Result<Vec<u8>, GpuError> {
        self.run_kernel_with(module, entry, inputs, output_bytes, count, &[])
    }

    /// [`Gpu::run_kernel`] with more resources in group 0: `extra[i]` at binding
    /// `2 + i` (textures and samplers the kernel reads).
    pub fn run_kernel_with(
        &self,
        module: &wgpu::ShaderModule,
        entry: &str,
        inputs: &[u8],
        output_bytes: u64,
        count: u32,
        extra: &[wgpu::BindingResource<'_>],
    ) -> Result<Vec<u8>, GpuError> {
        use wgpu::util::DeviceExt;
        let input = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("kernel input"),
                contents: if inputs.is_empty() { &[0; 16] } else { inputs },
                usage: wgpu::BufferUsages::STORAGE,
            });
        let output = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel output"),
            size: output_bytes.max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let pipeline = self.checked(|| {
            self.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        })?;
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ];
        entries.extend(
            extra
                .iter()
                .enumerate()
                .map(|(i, resource)| wgpu::BindGroupEntry {
                    binding: 2 + i as u32,
                    resource: resource.clone(),
                }),
        );
        let bind_group = self.checked(|| {
            self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("kernel"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            })
        })?;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(count.div_ceil(64), 1, 1);
        }
        self.queue.submit([encoder.finish()]);
        let mut bytes = self.read_buffer(&output)?;
        bytes.truncate(output_bytes as usize);
        Ok(bytes)
    }
}

/// A 2D texture of one mip level and one sample.
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}
