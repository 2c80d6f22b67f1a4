//! The sky (`volfog::sky`): [`SkyLight`] owns the sky texture and runs `sky_solve`
//! (the whole texture, or a band of rows per frame), `sky_horizon` (the horizon
//! average that colours matching fog) and `sky_draw` (the sky behind the scene, the
//! phase applied per pixel).

use wgpu::util::DeviceExt;

use super::{
    RenderPipelineDesc, bind_group, bind_group_layout, compute_pipeline, render_pipeline,
    sampler_entry, shader_module, storage_buffer_entry, storage_entry, texture_entry,
    uniform_entry,
};
use crate::cpu::sky::{SKY_TEXTURE_HEIGHT, SKY_TEXTURE_WIDTH};
use crate::limits::{InvalidValue, check};
use crate::shaders::CodegenError;
use crate::uniforms::{FrustumRays, SkyAtmosphere};

/// Format of the sky texture (two layers: Rayleigh, Mie).
pub const SKY_TEXTURE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Bytes of the `sky_horizon` output (Rayleigh rgb at 0, Mie rgb at 16).
pub const SKY_HORIZON_BYTES: u64 = 32;

/// Errors of [`SkyLight`].
#[derive(Debug, thiserror::Error)]
pub enum SkyError {
    /// A value is out of range.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// A shader failed to compose.
    #[error(transparent)]
    Shader(#[from] CodegenError),
}

/// The sky light: its texture, the solve, the horizon average and the draw.
///
/// ```no_run
/// # fn f(device: &wgpu::Device, queue: &wgpu::Queue, view: &wgpu::TextureView) -> Result<(), volfog::pipeline::sky::SkyError> {
/// use glam::{Mat4, Vec3};
/// use volfog::pipeline::sky::SkyLight;
/// use volfog::uniforms::{FrustumRays, SkyAtmosphere};
///
/// let mut sky = SkyLight::new(device, wgpu::TextureFormat::Rgba16Float)?;
/// sky.set_atmosphere(SkyAtmosphere::earth(Vec3::new(0.0, 0.5, -0.87).normalize())?);
/// let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.78, 0.1, 500.0);
/// sky.prepare(queue, &FrustumRays::new(Mat4::IDENTITY, proj)?, 64)?; // all 64 rows now
/// let mut encoder = device.create_command_encoder(&Default::default());
/// sky.encode_solve(&mut encoder);
/// sky.encode_horizon(&mut encoder);
/// // in a render pass on `view`, before the scene: sky.draw(&mut pass);
/// queue.submit([encoder.finish()]);
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct SkyLight {
    atmosphere: SkyAtmosphere,
    next_row: u32,
    band: (u32, u32),
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    atmosphere_buffer: wgpu::Buffer,
    rays_buffer: wgpu::Buffer,
    horizon: wgpu::Buffer,
    solve: wgpu::ComputePipeline,
    solve_group: wgpu::BindGroup,
    horizon_pipeline: wgpu::ComputePipeline,
    horizon_group: wgpu::BindGroup,
    draw_pipeline: wgpu::RenderPipeline,
    draw_group: wgpu::BindGroup,
}

impl SkyLight {
    /// Layout of `sky_solve`: 0 `SkyAtmosphere`, 1 the sky texture (storage, write).
    pub fn solve_layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            uniform_entry(0, wgpu::ShaderStages::COMPUTE),
            storage_entry(1, wgpu::TextureViewDimension::D2Array, SKY_TEXTURE_FORMAT),
        ]
    }

    /// Layout of `sky_horizon`: 0 `SkyAtmosphere`, 1 the horizon buffer.
    pub fn horizon_layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            uniform_entry(0, wgpu::ShaderStages::COMPUTE),
            storage_buffer_entry(1, wgpu::ShaderStages::COMPUTE, false),
        ]
    }

    /// Layout of `sky_draw`: 0 `FrustumRays`, 1 `SkyAtmosphere`, 2 the sky texture,
    /// 3 its sampler.
    pub fn draw_layout_entries() -> [wgpu::BindGroupLayoutEntry; 4] {
        [
            uniform_entry(0, wgpu::ShaderStages::VERTEX),
            uniform_entry(1, wgpu::ShaderStages::FRAGMENT),
            texture_entry(
                2,
                wgpu::ShaderStages::FRAGMENT,
                wgpu::TextureViewDimension::D2Array,
                true,
            ),
            sampler_entry(3, wgpu::ShaderStages::FRAGMENT, true),
        ]
    }

    /// The passes for a colour target of `format`, with a placeholder atmosphere (set
    /// yours with [`SkyLight::set_atmosphere`] before the first solve).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Result<Self, SkyError> {
        let atmosphere = SkyAtmosphere::earth(glam::Vec3::Y)?;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("volfog sky"),
            size: wgpu::Extent3d {
                width: SKY_TEXTURE_WIDTH,
                height: SKY_TEXTURE_HEIGHT,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SKY_TEXTURE_FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("volfog sky"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let uniform = |label, contents: &[u8], extra| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST | extra,
            })
        };
        let atmosphere_buffer = uniform(
            "volfog sky atmosphere",
            &atmosphere.to_bytes(),
            wgpu::BufferUsages::empty(),
        );
        let rays_buffer = uniform(
            "volfog sky rays",
            &FrustumRays::default().to_bytes(),
            wgpu::BufferUsages::empty(),
        );
        let horizon = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog sky horizon"),
            size: SKY_HORIZON_BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let solve_layout =
            bind_group_layout(device, "volfog sky_solve", &Self::solve_layout_entries());
        let solve_module = shader_module(device, "sky_solve", &[])?;
        let solve = compute_pipeline(
            device,
            "volfog sky_solve",
            &solve_module,
            "sky_solve",
            &solve_layout,
        );
        let solve_group = bind_group(
            device,
            "volfog sky_solve",
            &solve_layout,
            &[
                (0, atmosphere_buffer.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(&view)),
            ],
        );
        let horizon_layout = bind_group_layout(
            device,
            "volfog sky_horizon",
            &Self::horizon_layout_entries(),
        );
        let horizon_module = shader_module(device, "sky_horizon", &[])?;
        let horizon_pipeline = compute_pipeline(
            device,
            "volfog sky_horizon",
            &horizon_module,
            "sky_horizon",
            &horizon_layout,
        );
        let horizon_group = bind_group(
            device,
            "volfog sky_horizon",
            &horizon_layout,
            &[
                (0, atmosphere_buffer.as_entire_binding()),
                (1, horizon.as_entire_binding()),
            ],
        );
        let draw_layout =
            bind_group_layout(device, "volfog sky_draw", &Self::draw_layout_entries());
        let draw_module = shader_module(device, "sky_draw", &[])?;
        let draw_pipeline = render_pipeline(
            device,
            RenderPipelineDesc {
                label: "volfog sky_draw",
                vertex: (&draw_module, "sky_draw_vs"),
                fragment: (&draw_module, "sky_draw_fs"),
                bind_group_layouts: &[Some(&draw_layout)],
                buffers: &[],
                primitive: wgpu::PrimitiveState::default(),
                target: format.into(),
                samples: 1,
            },
        );
        let draw_group = bind_group(
            device,
            "volfog sky_draw",
            &draw_layout,
            &[
                (0, rays_buffer.as_entire_binding()),
                (1, atmosphere_buffer.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&view)),
                (3, wgpu::BindingResource::Sampler(&sampler)),
            ],
        );
        Ok(Self {
            atmosphere,
            next_row: 0,
            band: (0, 0),
            texture,
            view,
            sampler,
            atmosphere_buffer,
            rays_buffer,
            horizon,
            solve,
            solve_group,
            horizon_pipeline,
            horizon_group,
            draw_pipeline,
            draw_group,
        })
    }

    /// Sets the atmosphere (the sun moved, the time of day changed): the next solves
    /// start again at row 0. Checked as [`SkyAtmosphere::validated`] does.
    pub fn set_atmosphere(&mut self, atmosphere: SkyAtmosphere) -> Result<(), InvalidValue> {
        self.atmosphere = atmosphere.validated()?;
        self.next_row = 0;
        Ok(())
    }

    /// The current atmosphere.
    pub fn atmosphere(&self) -> &SkyAtmosphere {
        &self.atmosphere
    }

    /// Uploads this frame's camera rays and the atmosphere with the band of `rows`
    /// (1..=64) texture rows the next [`SkyLight::encode_solve`] fills, continuing
    /// where the last band ended (wrapping at the top). Call once per submission.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        rays: &FrustumRays,
        rows: u32,
    ) -> Result<(), InvalidValue> {
        check(
            (1..=SKY_TEXTURE_HEIGHT).contains(&rows),
            "SkyLight::prepare rows",
            rows,
            "1..=64 rows of the sky texture",
        )?;
        let rays = rays.validated()?;
        let first = self.next_row;
        let rows = rows.min(SKY_TEXTURE_HEIGHT - first);
        self.band = (first, rows);
        self.next_row = (first + rows) % SKY_TEXTURE_HEIGHT;
        let uniform = SkyAtmosphere {
            first_row: first,
            ..self.atmosphere
        };
        queue.write_buffer(&self.atmosphere_buffer, 0, &uniform.to_bytes());
        queue.write_buffer(&self.rays_buffer, 0, &rays.to_bytes());
        Ok(())
    }

    /// Records `sky_solve` over the band of rows `prepare` chose.
    pub fn encode_solve(&self, encoder: &mut wgpu::CommandEncoder) {
        self.encode_solve_timed(encoder, None);
    }

    /// [`SkyLight::encode_solve`] with timestamp writes around the pass.
    pub fn encode_solve_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let (_, rows) = self.band;
        if rows == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("volfog sky_solve"),
            timestamp_writes,
        });
        pass.set_pipeline(&self.solve);
        pass.set_bind_group(0, &self.solve_group, &[]);
        pass.dispatch_workgroups(SKY_TEXTURE_WIDTH.div_ceil(8), rows.div_ceil(8), 1);
    }

    /// Records `sky_horizon` (the horizon average of [`SkyLight::horizon_buffer`]).
    pub fn encode_horizon(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("volfog sky_horizon"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.horizon_pipeline);
        pass.set_bind_group(0, &self.horizon_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// Draws the sky (a fullscreen triangle, no depth) into the caller's render pass.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.draw_pipeline);
        pass.set_bind_group(0, &self.draw_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// The sky texture (2 layers, Rayleigh and Mie).
    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// A 2D-array view of the sky texture, for `volfog::sky::sky_sample`.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// The sampler `sky_sample` expects: linear, repeat in u, clamp in v.
    pub fn sampler(&self) -> &wgpu::Sampler {
        &self.sampler
    }

    /// The horizon average `sky_horizon` writes (Rayleigh rgb at byte 0, Mie at 16).
    pub fn horizon_buffer(&self) -> &wgpu::Buffer {
        &self.horizon
    }

    /// GPU memory the sky holds (texture and buffers), bytes.
    pub fn memory_bytes(&self) -> u64 {
        (SKY_TEXTURE_WIDTH * SKY_TEXTURE_HEIGHT * 2 * 8) as u64
            + self.atmosphere_buffer.size()
            + self.rays_buffer.size()
            + self.horizon.size()
    }
}
