//! [`EpipolarShafts`]: the runtime object (its buffers, the frame it prepares, the
//! memory it holds).

use wgpu::util::DeviceExt;

use super::inputs::Groups;
use super::pipelines::Pipelines;
use super::textures::Textures;
use super::{EpipolarError, EpipolarPass, LEVEL_STRIDE};
use crate::pipeline::TimestampPairs;
use crate::uniforms::{self, EpipolarFrame, EpipolarSampling, EpipolarView, HeightFog};

/// Epipolar sun shafts for one camera and target size.
///
/// ```no_run
/// # fn f(device: &wgpu::Device, queue: &wgpu::Queue, depth: &wgpu::Texture, shadow: &wgpu::Texture, color: &wgpu::TextureView) -> Result<(), volfog::pipeline::epipolar::EpipolarError> {
/// use glam::{Mat4, Vec3};
/// use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
/// use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
///
/// let mut shafts = EpipolarShafts::new(device, EpipolarSampling::new(1920, 1080, 2048))?;
/// shafts.set_inputs(device, depth, shadow)?; // again when either texture is recreated
/// let apply = shafts.create_apply(device, wgpu::TextureFormat::Rgba16Float)?;
/// let sun = Vec3::new(0.3, 0.4, -0.87).normalize();
/// let medium = HeightFog::new(Vec3::splat(0.02), 0.01, Vec3::Y, 0.0, 0.0)?
///     .with_sun(sun, Vec3::splat(2.0), 0.6)?;
/// let view = EpipolarView {
///     view_from_world: Mat4::IDENTITY,
///     clip_from_view: glam::camera::rh::proj::directx::perspective(1.0, 1.78, 0.1, 500.0),
///     // the cascade's matrix, as for VolumetricFog's ShadowCascades
///     light_from_world: volfog::pipeline::cascade_projection(sun, Vec3::ZERO, 100.0, 400.0),
///     cascade: 0,
///     rayleigh: Vec3::ZERO,
///     phase: EpipolarPhase::HenyeyGreenstein,
///     start_depth: 0.0,
///     max_depth: 500.0,
///     depth_bias: 0.001,
/// };
/// shafts.prepare(queue, &view, &medium)?;
/// let mut encoder = device.create_command_encoder(&Default::default());
/// shafts.encode(&mut encoder, EpipolarMode::Tree)?;
/// shafts.record_apply(&mut encoder, &apply, color);
/// queue.submit([encoder.finish()]);
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct EpipolarShafts {
    pub(super) sampling: EpipolarSampling,
    pub(super) prepared: bool,
    pub(super) frame: wgpu::Buffer,
    pub(super) medium: wgpu::Buffer,
    pub(super) levels: wgpu::Buffer,
    pub(super) counters: wgpu::Buffer,
    pub(super) counters_readback: wgpu::Buffer,
    pub(super) textures: Textures,
    pub(super) pipelines: Pipelines,
    pub(super) groups: Option<Groups>,
    pub(super) timestamps: Option<TimestampPairs>,
}

impl EpipolarShafts {
    /// Allocates the textures and compiles the passes for `sampling`.
    pub fn new(device: &wgpu::Device, sampling: EpipolarSampling) -> Result<Self, EpipolarError> {
        sampling.validate()?;
        let s = &sampling;
        let textures = Textures::new(device, s);
        let pipelines = Pipelines::new(device, s)?;
        let uniform = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let top = s.shadow_size.trailing_zeros();
        let mut level_bytes = vec![0u8; (LEVEL_STRIDE * u64::from(top + 1)) as usize];
        for l in 0..=top {
            let at = (LEVEL_STRIDE * u64::from(l)) as usize;
            level_bytes[at..at + 4].copy_from_slice(&l.to_le_bytes());
        }
        let levels = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("volfog epipolar tree levels"),
            contents: &level_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog epipolar counters"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let counters_readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog epipolar counters readback"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let timestamps = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| {
                TimestampPairs::new(
                    device,
                    "volfog epipolar timestamps",
                    EpipolarPass::ALL.len() as u32,
                )
            });
        Ok(Self {
            sampling,
            prepared: false,
            frame: uniform(
                "volfog epipolar frame",
                uniforms::to_uniform_bytes(&EpipolarFrame::default()).len() as u64,
            ),
            medium: uniform(
                "volfog epipolar medium",
                HeightFog::default().to_bytes().len() as u64,
            ),
            levels,
            counters,
            counters_readback,
            textures,
            pipelines,
            groups: None,
            timestamps,
        })
    }

    /// The sampling this object was made for.
    pub fn sampling(&self) -> &EpipolarSampling {
        &self.sampling
    }

    /// Writes the frame: the camera and cascade in `view`, the medium `medium` in
    /// world space (its `sun_direction` is the light's; uniform fog has falloff 0, a
    /// `top_height` ends it; `sun_transmittance` attenuates the sun's light by the fog
    /// between each point and the sun; as the far field of a `VolumetricFog`, pass its
    /// tail with `sun_transmittance` as `FogConfig::light_transmittance`). Returns the
    /// frame written.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        view: &EpipolarView,
        medium: &HeightFog,
    ) -> Result<EpipolarFrame, EpipolarError> {
        let frame = EpipolarFrame::new(&self.sampling, view, medium.sun_direction)?;
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(&frame));
        queue.write_buffer(
            &self.medium,
            0,
            &EpipolarFrame::medium(medium, view.view_from_world).to_bytes(),
        );
        self.prepared = true;
        Ok(frame)
    }

    /// Writes a frame built by hand (for example with the epipole placed exactly on
    /// the screen's edge) and the medium already in view space. The frame's sampling
    /// fields must be this object's.
    pub fn prepare_frame(
        &mut self,
        queue: &wgpu::Queue,
        frame: &EpipolarFrame,
        medium_in_view: &HeightFog,
    ) -> Result<(), EpipolarError> {
        let s = &self.sampling;
        crate::limits::check(
            (
                frame.slices,
                frame.samples,
                frame.initial_step,
                frame.shadow_size,
                frame.downscale,
            ) == (
                s.slices,
                s.samples,
                s.initial_step,
                s.shadow_size,
                s.downscale,
            ) && frame.screen_size == glam::Vec2::new(s.width as f32, s.height as f32),
            "EpipolarFrame",
            (
                frame.slices,
                frame.samples,
                frame.initial_step,
                frame.shadow_size,
                frame.downscale,
            ),
            "the sampling of this EpipolarShafts (slices, samples, initial_step, shadow_size, downscale, screen_size)",
        )?;
        crate::limits::check(
            frame.light_screen.is_finite()
                && frame.light_screen.abs().max_element() <= uniforms::EPIPOLE_LIMIT,
            "EpipolarFrame.light_screen",
            frame.light_screen,
            "finite, |x|, |y| <= EPIPOLE_LIMIT",
        )?;
        medium_in_view.validate()?;
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(frame));
        queue.write_buffer(&self.medium, 0, &medium_in_view.to_bytes());
        self.prepared = true;
        Ok(())
    }

    /// Bytes of every texture and buffer this object owns.
    pub fn memory_bytes(&self) -> u64 {
        let t = &self.textures;
        let textures = [
            &t.coords,
            &t.sources,
            &t.tree,
            &t.scratch,
            &t.marched,
            &t.interpolated,
            &t.shafts,
        ]
        .into_iter()
        .chain(t.low.as_ref())
        .map(crate::pipeline::fog::texture_bytes)
        .sum::<u64>();
        textures
            + self.frame.size()
            + self.medium.size()
            + self.levels.size()
            + self.counters.size()
            + self.counters_readback.size()
            + self
                .timestamps
                .as_ref()
                .map_or(0, TimestampPairs::buffer_bytes)
    }
}
