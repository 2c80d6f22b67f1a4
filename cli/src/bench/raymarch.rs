//! The per-pixel raymarch reference (`raymarch.wgsl`): the fog of the froxel pipeline
//! computed the way renderers without froxels do it, one ray of `steps` samples per
//! pixel, with the same medium, lights, shadow cascades and ESM as a
//! [`VolumetricFog`](volfog::pipeline::VolumetricFog) frame.
//!
//! Also the shader composition of the bench passes: bench WGSL is composed at run time
//! with naga_oil after [`volfog::shaders::add_to_composer`], so it imports the same
//! modules as the prebuilt passes.

use naga_oil::compose::ShaderDefValue;
use volfog::pipeline::FrameUniforms;
use volfog::pipeline::apply::FOG_BLEND;
use volfog::uniforms::{
    self, FogFrame, FogLight, FogLighting, FogMedium, LocalVolume, ShadowCascades,
};

/// Samples per pixel of the reference.
pub const RAYMARCH_STEPS: u32 = 64;

const RAYMARCH_WGSL: &str = include_str!("raymarch.wgsl");
/// The raymarch shader's path in the repository.
pub const RAYMARCH_PATH: &str = "cli/src/bench/raymarch.wgsl";

/// A bench shader failed to compose.
#[derive(Debug, thiserror::Error)]
#[error("composing {file} failed:\n{report}")]
pub struct ShaderError {
    /// The shader file.
    pub file: &'static str,
    /// naga_oil's report (file, line, column, source line).
    pub report: String,
}

/// Composes a bench shader (which may `#import volfog::...`) into a naga module.
pub fn compose(
    source: &str,
    file: &'static str,
    defs: &[(&str, ShaderDefValue)],
) -> Result<naga::Module, ShaderError> {
    volfog_cost::floor::compose(source, file, defs).map_err(|report| ShaderError { file, report })
}

/// Creates a wgpu shader module from a composed bench shader.
pub fn shader_module(
    device: &wgpu::Device,
    source: &str,
    file: &'static str,
    defs: &[(&str, ShaderDefValue)],
) -> Result<wgpu::ShaderModule, ShaderError> {
    let module = compose(source, file, defs)?;
    Ok(device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(file),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    }))
}

/// The fullscreen vertex + fragment pipeline state shared by the bench's render passes.
pub fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    layout: &wgpu::BindGroupLayout,
    target: wgpu::ColorTargetState,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entries.0),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entries.1),
            compilation_options: Default::default(),
            targets: &[Some(target)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A fullscreen render pass onto `target` (loaded, not cleared).
pub fn fullscreen_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    volfog::pipeline::apply::composite_pass(encoder, label, target, timestamp_writes)
}

/// What the reference is compiled for.
#[derive(Debug, Clone, Copy)]
pub struct RaymarchOptions {
    /// Samples per pixel.
    pub steps: u32,
    /// Noise fbm octaves (`FogConfig::noise_octaves`).
    pub noise_octaves: u32,
    /// Format of the colour target the fog is blended onto.
    pub color_format: wgpu::TextureFormat,
    /// Capacity of the light buffer.
    pub max_lights: u32,
    /// Capacity of the local volume buffer.
    pub max_local_volumes: u32,
}

/// The compiled reference pass and its uniform and storage buffers.
#[derive(Debug)]
pub struct Raymarch {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    froxels: wgpu::Buffer,
    frame: wgpu::Buffer,
    medium: wgpu::Buffer,
    lighting: wgpu::Buffer,
    cascades: wgpu::Buffer,
    lights: wgpu::Buffer,
    local_volumes: wgpu::Buffer,
}

fn buffer(
    device: &wgpu::Device,
    label: &str,
    size: usize,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn layout_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty,
        count: None,
    }
}

fn uniform(binding: u32) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

fn storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

fn unfilterable(binding: u32, dimension: wgpu::TextureViewDimension) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: dimension,
            multisampled: false,
        },
    )
}

impl Raymarch {
    /// The pass's shader composed for `options` (entry points `raymarch_vs` and
    /// `raymarch_fs`).
    pub fn module(options: &RaymarchOptions) -> Result<naga::Module, ShaderError> {
        compose(
            RAYMARCH_WGSL,
            RAYMARCH_PATH,
            &[
                ("RAYMARCH_STEPS", ShaderDefValue::UInt(options.steps)),
                ("NOISE_OCTAVES", ShaderDefValue::UInt(options.noise_octaves)),
                (
                    "LIGHT_CAPACITY",
                    ShaderDefValue::UInt(options.max_lights.max(1)),
                ),
                (
                    "VOLUME_CAPACITY",
                    ShaderDefValue::UInt(options.max_local_volumes.max(1)),
                ),
            ],
        )
    }

    /// Composes and compiles the pass.
    pub fn new(device: &wgpu::Device, options: &RaymarchOptions) -> Result<Self, ShaderError> {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(RAYMARCH_PATH),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(Self::module(options)?)),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bench raymarch"),
            entries: &[
                uniform(0),
                uniform(1),
                uniform(2),
                uniform(3),
                uniform(4),
                unfilterable(5, wgpu::TextureViewDimension::D2Array),
                storage(6),
                storage(7),
                unfilterable(8, wgpu::TextureViewDimension::D2),
            ],
        });
        let pipeline = fullscreen_pipeline(
            device,
            "bench raymarch",
            &module,
            ("raymarch_vs", "raymarch_fs"),
            &layout,
            wgpu::ColorTargetState {
                format: options.color_format,
                blend: Some(FOG_BLEND),
                write_mask: wgpu::ColorWrites::ALL,
            },
        );
        let u = wgpu::BufferUsages::UNIFORM;
        let s = wgpu::BufferUsages::STORAGE;
        let lights = uniforms::to_storage_bytes(&vec![
            FogLight::default();
            options.max_lights.max(1) as usize
        ]);
        let volumes = uniforms::to_storage_bytes(&vec![
            LocalVolume::default();
            options.max_local_volumes.max(1) as usize
        ]);
        Ok(Self {
            layout,
            pipeline,
            froxels: buffer(
                device,
                "raymarch froxels",
                uniforms::Froxels::default().to_bytes().len(),
                u,
            ),
            frame: buffer(
                device,
                "raymarch frame",
                uniforms::to_uniform_bytes(&FogFrame::default()).len(),
                u,
            ),
            medium: buffer(
                device,
                "raymarch medium",
                uniforms::to_uniform_bytes(&FogMedium::default()).len(),
                u,
            ),
            lighting: buffer(
                device,
                "raymarch lighting",
                uniforms::to_uniform_bytes(&FogLighting::default()).len(),
                u,
            ),
            cascades: buffer(
                device,
                "raymarch cascades",
                uniforms::to_uniform_bytes(&ShadowCascades::default()).len(),
                u,
            ),
            lights: buffer(device, "raymarch lights", lights.len(), s),
            local_volumes: buffer(device, "raymarch local volumes", volumes.len(), s),
        })
    }

    /// Uploads a frame's uniforms (`FrameInputs::uniforms`, as `VolumetricFog::prepare`
    /// uploads them) and the same lights and local volumes (at most the capacities
    /// given to [`Raymarch::new`]).
    pub fn upload(
        &self,
        queue: &wgpu::Queue,
        uploaded: &FrameUniforms,
        lights: &[FogLight],
        local_volumes: &[LocalVolume],
    ) {
        queue.write_buffer(&self.froxels, 0, &uploaded.froxels.to_bytes());
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(&uploaded.frame));
        queue.write_buffer(
            &self.medium,
            0,
            &uniforms::to_uniform_bytes(&uploaded.medium),
        );
        queue.write_buffer(
            &self.lighting,
            0,
            &uniforms::to_uniform_bytes(&uploaded.lighting),
        );
        queue.write_buffer(
            &self.cascades,
            0,
            &uniforms::to_uniform_bytes(&uploaded.cascades),
        );
        if !lights.is_empty() {
            queue.write_buffer(&self.lights, 0, &uniforms::to_storage_bytes(lights));
        }
        if !local_volumes.is_empty() {
            queue.write_buffer(
                &self.local_volumes,
                0,
                &uniforms::to_storage_bytes(local_volumes),
            );
        }
    }

    /// A bind group: the filtered ESM array (e.g. `VolumetricFog::esm_texture`, viewed
    /// as a 2D array) and a depth-aspect view of the scene depth, the target's size.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        esm: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        let buffers = [
            &self.froxels,
            &self.frame,
            &self.medium,
            &self.lighting,
            &self.cascades,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        entries.extend([
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(esm),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: self.lights.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 7,
                resource: self.local_volumes.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 8,
                resource: wgpu::BindingResource::TextureView(depth),
            },
        ]);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench raymarch"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records the fullscreen raymarch, blending (in-scatter, transmittance) onto
    /// `target` (loaded) as the apply pass does.
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        bind_group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = fullscreen_pass(encoder, "bench raymarch", target, timestamp_writes);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
}
