//! [`VolumetricFog`]: the whole froxel pipeline behind one object.
//!
//! Per frame: [`VolumetricFog::prepare`] uploads the camera, medium, lights and
//! shadow cascades; [`VolumetricFog::encode`] records ESM downsample -> blur ->
//! inject -> temporal -> scan; [`VolumetricFog::apply_fullscreen`] fogs a lit colour
//! target using its depth buffer, or forward shaders read the integrated volume through
//! [`VolumetricFog::fog_bind_group`] (the `volfog::bindings` layout).
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, color: &wgpu::TextureView, depth: &wgpu::TextureView) -> Result<(), volfog::pipeline::FogError> {
//! use volfog::pipeline::{FogConfig, FrameInputs, ShadowInputs, VolumetricFog};
//!
//! let mut fog = VolumetricFog::new(device, &FogConfig::default())?;
//! let projection = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 500.0);
//! let view = glam::camera::rh::view::look_at_mat4(glam::Vec3::new(0.0, 2.0, 10.0), glam::Vec3::ZERO, glam::Vec3::Y);
//! fog.prepare(queue, &FrameInputs::new(view, projection, 0.0))?;
//! let mut encoder = device.create_command_encoder(&Default::default());
//! fog.encode(device, &mut encoder, &ShadowInputs::default());
//! fog.apply_fullscreen(device, &mut encoder, color, depth);
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

use glam::{Mat4, UVec3, Vec3, Vec4};

use super::apply::{fog_layout_entries, fog_sampler, ApplyPass, Filtering};
use super::esm::{EsmPasses, ESM_FORMAT};
use super::inject::{InjectOptions, InjectPass, InjectResources};
use super::scan::ScanPass;
use super::temporal::TemporalPass;
use crate::codegen::CodegenError;
use crate::cpu::froxel::froxel_jitter;
use crate::cpu::scan::ScanStep;
use crate::gpu::TimestampPairs;
use crate::uniforms::{
    self, check, AmbientSh, DirectionalLight, FogFrame, FogLight, FogLighting, FogMedium, Froxels,
    HeightFog, InvalidValue, LocalVolume, ShadowCascades,
};

/// The volume texel format.
pub const VOLUME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Most lights one workgroup of the inject pass can gather (its workgroup list).
pub const MAX_LIGHTS: u32 = 64;
/// Most local volumes.
pub const MAX_LOCAL_VOLUMES: u32 = 256;
/// Most froxels in a volume (64 MiB per rgba16float volume).
pub const MAX_FROXELS: u64 = 8 * 1024 * 1024;

/// Configuration of a [`VolumetricFog`].
#[derive(Debug, Clone, PartialEq)]
pub struct FogConfig {
    /// Froxels across the screen (x, y) and depth slices (z).
    pub volume_size: UVec3,
    /// View depth (m) where the volume starts, > 0.
    pub near: f32,
    /// View depth (m) where the volume ends, > near.
    pub far: f32,
    /// Slice distribution curve (0 linear, ln(far / near) exponential).
    pub slice_curve: f32,
    /// ESM size per cascade in texels; the shadow map is 4x as large.
    pub esm_resolution: u32,
    /// Shadow cascades, 1..=4.
    pub cascades: u32,
    /// ESM exponent for depths in [0, 1]: <= 88 unless `esm_log_space`.
    pub esm_exponent: f32,
    /// Filter the ESM in log space (`VOLFOG_ESM_LOG_SPACE`).
    pub esm_log_space: bool,
    /// Box blur radius (taps = 2 radius + 1), 1..=16.
    pub esm_blur_radius: u32,
    /// Capacity of the point/spot light buffer, 0..=64.
    pub max_lights: u32,
    /// Capacity of the local volume buffer, 0..=256.
    pub max_local_volumes: u32,
    /// Jitter froxel samples each frame (Halton 2, 3, 5).
    pub jitter: bool,
    /// Blend with the reprojected previous frame.
    pub temporal: bool,
    /// Weight of the history, [0, 1).
    pub history_weight: f32,
    /// Scan step.
    pub scan_step: ScanStep,
    /// AC4 two-colour sun phase instead of Henyey-Greenstein.
    pub two_color_phase: bool,
    /// Noise fbm octaves, 1..=8.
    pub noise_octaves: u32,
    /// Multiply the density by a 3D texture (see [`VolumetricFog::set_density_texture`]).
    pub density_texture: bool,
    /// Filtering of the integrated volume when applying.
    pub apply_filtering: Filtering,
    /// Format of the colour target `apply_fullscreen` blends onto.
    pub color_format: wgpu::TextureFormat,
    /// Record GPU timestamps per pass (needs `Features::TIMESTAMP_QUERY`).
    pub timestamps: bool,
}

impl Default for FogConfig {
    fn default() -> Self {
        Self {
            volume_size: UVec3::new(160, 90, 128),
            near: 0.5,
            far: 128.0,
            slice_curve: 4.0,
            esm_resolution: 256,
            cascades: 4,
            esm_exponent: 40.0,
            esm_log_space: false,
            esm_blur_radius: 5,
            max_lights: 64,
            max_local_volumes: 16,
            jitter: true,
            temporal: true,
            history_weight: 0.9,
            scan_step: ScanStep::EnergyConserving,
            two_color_phase: false,
            noise_octaves: 1,
            density_texture: false,
            apply_filtering: Filtering::Sampler,
            color_format: wgpu::TextureFormat::Rgba16Float,
            timestamps: false,
        }
    }
}

impl FogConfig {
    /// Checks every field; the error names the field and its valid range.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        let s = self.volume_size;
        check(
            s.cmpge(UVec3::ONE).all()
                && s.cmple(UVec3::splat(uniforms::MAX_FROXELS_PER_AXIS)).all()
                && u64::from(s.x) * u64::from(s.y) * u64::from(s.z) <= MAX_FROXELS,
            "FogConfig.volume_size",
            s,
            "1..=2048 froxels per axis and at most 8388608 froxels in all",
        )?;
        check(
            self.near.is_finite() && self.near > 0.0,
            "FogConfig.near",
            self.near,
            "a finite depth > 0 m",
        )?;
        check(
            self.far.is_finite() && self.far > self.near,
            "FogConfig.far",
            self.far,
            "a finite depth > near",
        )?;
        check(
            (0.0..=uniforms::MAX_SLICE_CURVE).contains(&self.slice_curve),
            "FogConfig.slice_curve",
            self.slice_curve,
            "0..=30",
        )?;
        check(
            (4..=2048).contains(&self.esm_resolution),
            "FogConfig.esm_resolution",
            self.esm_resolution,
            "4..=2048 texels",
        )?;
        check(
            (1..=uniforms::MAX_CASCADES as u32).contains(&self.cascades),
            "FogConfig.cascades",
            self.cascades,
            "1..=4",
        )?;
        let max_exponent = if self.esm_log_space {
            1.0e4
        } else {
            uniforms::MAX_LINEAR_ESM_EXPONENT
        };
        check(
            self.esm_exponent.is_finite()
                && self.esm_exponent > 0.0
                && self.esm_exponent <= max_exponent,
            "FogConfig.esm_exponent",
            self.esm_exponent,
            if self.esm_log_space {
                "0 < c <= 10000"
            } else {
                "0 < c <= 88 (exp(c) overflows f32 above; set esm_log_space for more)"
            },
        )?;
        check(
            (1..=16).contains(&self.esm_blur_radius),
            "FogConfig.esm_blur_radius",
            self.esm_blur_radius,
            "1..=16",
        )?;
        check(
            self.max_lights <= MAX_LIGHTS,
            "FogConfig.max_lights",
            self.max_lights,
            "0..=64",
        )?;
        check(
            self.max_local_volumes <= MAX_LOCAL_VOLUMES,
            "FogConfig.max_local_volumes",
            self.max_local_volumes,
            "0..=256",
        )?;
        check(
            (0.0..1.0).contains(&self.history_weight),
            "FogConfig.history_weight",
            self.history_weight,
            "0 <= w < 1",
        )?;
        check(
            (1..=8).contains(&self.noise_octaves),
            "FogConfig.noise_octaves",
            self.noise_octaves,
            "1..=8",
        )?;
        Ok(())
    }

    fn inject_options(&self) -> InjectOptions {
        InjectOptions {
            jitter: self.jitter,
            two_color_phase: self.two_color_phase,
            density_texture: self.density_texture,
            esm_log_space: self.esm_log_space,
            noise_octaves: self.noise_octaves,
        }
    }
}

/// Errors of [`VolumetricFog`].
#[derive(Debug, thiserror::Error)]
pub enum FogError {
    /// A configuration or input value is out of range.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// The device lacks a capability the configuration needs.
    #[error("the device lacks {what}: {detail}")]
    MissingCapability {
        /// The capability.
        what: &'static str,
        /// What is needed and what the device offers.
        detail: String,
    },
    /// Composing a shader variant failed.
    #[error(transparent)]
    Shader(#[from] CodegenError),
}

/// Per-frame inputs.
#[derive(Debug, Clone)]
pub struct FrameInputs<'a> {
    /// World -> view transform of the camera (right-handed, looking down -Z).
    pub view_from_world: Mat4,
    /// Projection (view -> clip, WebGPU depth range; standard, reversed or infinite).
    pub clip_from_view: Mat4,
    /// Seconds since start (noise animation, density scrolling).
    pub time: f32,
    /// The medium.
    pub medium: FogMedium,
    /// The directional light.
    pub sun: DirectionalLight,
    /// Ambient radiance as L1 SH.
    pub ambient: AmbientSh,
    /// Point and spot lights (at most `max_lights`).
    pub lights: &'a [FogLight],
    /// Local volumes (at most `max_local_volumes`).
    pub local_volumes: &'a [LocalVolume],
    /// Shadow cascades; `count` 0 disables shadows.
    pub cascades: ShadowCascades,
    /// Drop the history (after a camera cut).
    pub reset_history: bool,
    /// Analytic height fog continuing beyond the far plane when applying (world
    /// space; see [`HeightFog::from_medium`]); [`HeightFog::none`] for none.
    pub tail: HeightFog,
}

impl FrameInputs<'_> {
    /// Inputs with the default medium and sun, a dim constant ambient, no lights, no
    /// local volumes and no shadows.
    pub fn new(view_from_world: Mat4, clip_from_view: Mat4, time: f32) -> Self {
        Self {
            view_from_world,
            clip_from_view,
            time,
            medium: FogMedium::default(),
            sun: DirectionalLight::default(),
            ambient: AmbientSh::constant(Vec3::new(0.08, 0.1, 0.14)),
            lights: &[],
            local_volumes: &[],
            cascades: ShadowCascades::default(),
            reset_history: false,
            tail: HeightFog::none(),
        }
    }
}

/// Inputs of [`VolumetricFog::encode`] that live on the GPU.
#[derive(Debug, Default, Clone, Copy)]
pub struct ShadowInputs<'a> {
    /// The cascaded shadow map: a `D2Array` view (depth aspect) of a depth texture with
    /// `4 * esm_resolution` texels per side and one layer per cascade, usable as a
    /// texture binding. `None` skips the ESM passes (the frame's cascades must then
    /// have `count` 0).
    pub shadow_map: Option<&'a wgpu::TextureView>,
}

/// GPU time per pass in milliseconds (when timestamps are enabled and supported).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PassTimings {
    /// ESM downsample.
    pub esm_downsample: f64,
    /// ESM blur (both directions).
    pub esm_blur: f64,
    /// Inject.
    pub inject: f64,
    /// Temporal reprojection.
    pub temporal: f64,
    /// Scan.
    pub scan: f64,
    /// Fullscreen apply.
    pub apply: f64,
}

const PASS_COUNT: u32 = 6;

/// The compute passes of a frame, in the order [`VolumetricFog::encode`] records them
/// (see [`VolumetricFog::encode_pass`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FogPass {
    /// ESM downsample (only with a shadow map and cascades).
    EsmDownsample,
    /// ESM blur, both directions (only with a shadow map and cascades).
    EsmBlur,
    /// Density and lighting injection.
    Inject,
    /// Temporal reprojection (only with `FogConfig::temporal`).
    Temporal,
    /// Front-to-back integration; ends the frame.
    Scan,
}

impl FogPass {
    /// Every pass, in order.
    pub const ALL: [FogPass; 5] = [
        FogPass::EsmDownsample,
        FogPass::EsmBlur,
        FogPass::Inject,
        FogPass::Temporal,
        FogPass::Scan,
    ];
}

fn volume_texture(device: &wgpu::Device, label: &str, size: UVec3) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.x,
            height: size.y,
            depth_or_array_layers: size.z,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: VOLUME_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn esm_texture(device: &wgpu::Device, label: &str, size: u32, layers: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: ESM_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn storage_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Checks that a device can run a configuration.
pub fn check_device(device: &wgpu::Device, config: &FogConfig) -> Result<(), FogError> {
    let limits = device.limits();
    let s = config.volume_size;
    if s.max_element() > limits.max_texture_dimension_3d {
        return Err(FogError::MissingCapability {
            what: "3D textures of the volume size",
            detail: format!(
                "volume {s} needs max_texture_dimension_3d >= {}, the device allows {}",
                s.max_element(),
                limits.max_texture_dimension_3d
            ),
        });
    }
    let shadow = config.esm_resolution * 4;
    if shadow > limits.max_texture_dimension_2d || config.cascades > limits.max_texture_array_layers
    {
        return Err(FogError::MissingCapability {
            what: "2D array textures of the shadow map size",
            detail: format!(
                "{shadow} x {shadow} x {} needs max_texture_dimension_2d >= {shadow} and max_texture_array_layers >= {}, the device allows {} and {}",
                config.cascades, config.cascades, limits.max_texture_dimension_2d, limits.max_texture_array_layers
            ),
        });
    }
    if limits.max_storage_buffers_per_shader_stage < 2
        || limits.max_storage_textures_per_shader_stage < 1
    {
        return Err(FogError::MissingCapability {
            what: "storage buffers and textures in compute shaders",
            detail: format!(
                "2 storage buffers and 1 storage texture per stage are needed, the device allows {} and {}",
                limits.max_storage_buffers_per_shader_stage, limits.max_storage_textures_per_shader_stage
            ),
        });
    }
    if config.timestamps && !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        return Err(FogError::MissingCapability {
            what: "timestamp queries",
            detail: "FogConfig.timestamps needs Features::TIMESTAMP_QUERY enabled on the device"
                .to_string(),
        });
    }
    Ok(())
}

/// The froxel volumetric fog pipeline.
pub struct VolumetricFog {
    config: FogConfig,
    esm_passes: EsmPasses,
    inject: InjectPass,
    temporal: TemporalPass,
    scan: ScanPass,
    apply: ApplyPass,
    // Volumes: the scattering volume (inject output; with temporal reprojection it is
    // also the scan output) and the two history volumes.
    scattering: wgpu::Texture,
    history: [wgpu::Texture; 2],
    esm: wgpu::Texture,
    esm_scratch: wgpu::Texture,
    default_density: wgpu::Texture,
    density_view: wgpu::TextureView,
    density_sampler: wgpu::Sampler,
    froxels: wgpu::Buffer,
    frame: wgpu::Buffer,
    medium: wgpu::Buffer,
    lighting: wgpu::Buffer,
    cascades: wgpu::Buffer,
    tail: wgpu::Buffer,
    lights: wgpu::Buffer,
    local_volumes: wgpu::Buffer,
    inject_group: wgpu::BindGroup,
    temporal_groups: [wgpu::BindGroup; 2],
    scan_groups: [wgpu::BindGroup; 2],
    fog_layout: wgpu::BindGroupLayout,
    fog_group: wgpu::BindGroup,
    timestamps: Option<TimestampPairs>,
    frame_index: u32,
    history_index: usize,
    prev_clip_from_world: Option<Mat4>,
    shadows_enabled: bool,
    default_density_written: bool,
    uploaded: Option<UploadedUniforms>,
}

/// The uniforms `prepare` uploaded last (for CPU references and debugging).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UploadedUniforms {
    /// Froxel placement.
    pub froxels: Froxels,
    /// Camera and temporal state.
    pub frame: FogFrame,
    /// Medium (with the local volume count).
    pub medium: FogMedium,
    /// Lighting (with the light count).
    pub lighting: FogLighting,
    /// Shadow cascades.
    pub cascades: ShadowCascades,
}

impl std::fmt::Debug for VolumetricFog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VolumetricFog")
            .field("config", &self.config)
            .field("frame_index", &self.frame_index)
            .finish_non_exhaustive()
    }
}

impl VolumetricFog {
    /// Creates every texture, pipeline and bind group for a configuration.
    pub fn new(device: &wgpu::Device, config: &FogConfig) -> Result<Self, FogError> {
        config.validate()?;
        check_device(device, config)?;
        let size = config.volume_size;
        let esm_passes = EsmPasses::new(device, config.esm_log_space, config.esm_blur_radius)?;
        let inject = InjectPass::new(device, config.inject_options())?;
        let temporal = TemporalPass::new(device);
        let scan = ScanPass::new(device, config.scan_step);
        let apply = ApplyPass::new(device, config.apply_filtering, config.color_format);

        let scattering = volume_texture(device, "volfog scattering", size);
        let history = [
            volume_texture(device, "volfog history 0", size),
            volume_texture(device, "volfog history 1", size),
        ];
        let esm = esm_texture(device, "volfog esm", config.esm_resolution, config.cascades);
        let esm_scratch = esm_texture(
            device,
            "volfog esm scratch",
            config.esm_resolution,
            config.cascades,
        );
        // Written with the first `prepare` (a queue is needed): a unit density factor.
        let default_density = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("volfog unit density"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let density_view = default_density.create_view(&Default::default());
        let density_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("volfog density"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            address_mode_w: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });

        let froxels = uniform_buffer(
            device,
            "volfog froxels",
            Froxels::default().to_bytes().len(),
        );
        let frame = uniform_buffer(
            device,
            "volfog frame",
            uniforms::to_uniform_bytes(&FogFrame::default()).len(),
        );
        let medium = uniform_buffer(
            device,
            "volfog medium",
            uniforms::to_uniform_bytes(&FogMedium::default()).len(),
        );
        let lighting = uniform_buffer(
            device,
            "volfog lighting",
            uniforms::to_uniform_bytes(&FogLighting::default()).len(),
        );
        let cascades = uniform_buffer(
            device,
            "volfog cascades",
            uniforms::to_uniform_bytes(&ShadowCascades::default()).len(),
        );
        let tail = uniform_buffer(
            device,
            "volfog tail",
            uniforms::to_uniform_bytes(&HeightFog::none()).len(),
        );
        let light_bytes = uniforms::to_storage_bytes(&vec![
            FogLight::default();
            config.max_lights.max(1) as usize
        ]);
        let lights = storage_buffer(device, "volfog lights", light_bytes.len());
        let volume_bytes = uniforms::to_storage_bytes(&vec![
            LocalVolume::default();
            config.max_local_volumes.max(1)
                as usize
        ]);
        let local_volumes = storage_buffer(device, "volfog local volumes", volume_bytes.len());

        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let scattering_view = view(&scattering);
        let history_views = [view(&history[0]), view(&history[1])];
        let esm_view = array_view(&esm);
        let inject_group = inject.bind_group(
            device,
            &InjectResources {
                froxels: &froxels,
                frame: &frame,
                medium: &medium,
                lighting: &lighting,
                cascades: &cascades,
                esm: &esm_view,
                lights: &lights,
                local_volumes: &local_volumes,
                scattering: &scattering_view,
                density_texture: Some((&density_view, &density_sampler)),
            },
        );
        // Frame parity p writes history[p] from history[1 - p].
        let temporal_groups = [0, 1].map(|p| {
            temporal.bind_group(
                device,
                &froxels,
                &frame,
                &scattering_view,
                &history_views[1 - p],
                &history_views[p],
            )
        });
        let scan_groups = if config.temporal {
            [0, 1].map(|p| scan.bind_group(device, &froxels, &history_views[p], &scattering_view))
        } else {
            [0, 1].map(|_| scan.bind_group(device, &froxels, &scattering_view, &history_views[0]))
        };
        let integrated_view = if config.temporal {
            &scattering_view
        } else {
            &history_views[0]
        };
        let fog_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volfog fog (volfog::bindings)"),
            entries: &fog_layout_entries(
                config.apply_filtering,
                wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ),
        });
        let fog_sampler = fog_sampler(device);
        let fog_group = Self::make_fog_group(
            device,
            &fog_layout,
            config.apply_filtering,
            &froxels,
            integrated_view,
            &tail,
            &fog_sampler,
        );
        let timestamps = config
            .timestamps
            .then(|| TimestampPairs::new(device, "volfog timestamps", PASS_COUNT));
        Ok(Self {
            config: config.clone(),
            esm_passes,
            inject,
            temporal,
            scan,
            apply,
            scattering,
            history,
            esm,
            esm_scratch,
            default_density,
            density_view,
            density_sampler,
            froxels,
            frame,
            medium,
            lighting,
            cascades,
            tail,
            lights,
            local_volumes,
            inject_group,
            temporal_groups,
            scan_groups,
            fog_layout,
            fog_group,
            timestamps,
            frame_index: 0,
            history_index: 0,
            prev_clip_from_world: None,
            shadows_enabled: false,
            default_density_written: false,
            uploaded: None,
        })
    }

    fn make_fog_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        froxels: &wgpu::Buffer,
        integrated: &wgpu::TextureView,
        tail: &wgpu::Buffer,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        let mut resources = vec![
            (0, froxels.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(integrated)),
            (3, tail.as_entire_binding()),
        ];
        if filtering == Filtering::Sampler {
            resources.push((2, wgpu::BindingResource::Sampler(sampler)));
        }
        super::bind_group(device, "volfog fog", layout, &resources)
    }

    /// The configuration in use.
    pub fn config(&self) -> &FogConfig {
        &self.config
    }

    /// Replaces the configuration, recreating every resource (the old ones are
    /// released); the history starts over.
    pub fn reconfigure(
        &mut self,
        device: &wgpu::Device,
        config: &FogConfig,
    ) -> Result<(), FogError> {
        *self = Self::new(device, config)?;
        Ok(())
    }

    /// Uses a 3D texture (r channel, filterable) as density multiplier; needs
    /// `FogConfig::density_texture`.
    pub fn set_density_texture(
        &mut self,
        device: &wgpu::Device,
        view: &wgpu::TextureView,
    ) -> Result<(), FogError> {
        if !self.config.density_texture {
            return Err(FogError::Invalid(InvalidValue {
                field: "FogConfig.density_texture",
                value: "false".to_string(),
                expected: "true to use a density texture",
            }));
        }
        self.density_view = view.clone();
        self.rebuild_inject_group(device);
        Ok(())
    }

    fn rebuild_inject_group(&mut self, device: &wgpu::Device) {
        let scattering_view = self.scattering.create_view(&Default::default());
        let esm_view = array_view(&self.esm);
        self.inject_group = self.inject.bind_group(
            device,
            &InjectResources {
                froxels: &self.froxels,
                frame: &self.frame,
                medium: &self.medium,
                lighting: &self.lighting,
                cascades: &self.cascades,
                esm: &esm_view,
                lights: &self.lights,
                local_volumes: &self.local_volumes,
                scattering: &scattering_view,
                density_texture: Some((&self.density_view, &self.density_sampler)),
            },
        );
    }

    /// Checks and uploads one frame's inputs.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        inputs: &FrameInputs<'_>,
    ) -> Result<(), FogError> {
        let c = &self.config;
        let froxels = Froxels::new(
            inputs.clip_from_view,
            c.volume_size,
            c.near,
            c.far,
            c.slice_curve,
        )?;
        check(
            inputs.view_from_world.is_finite()
                && inputs.view_from_world.determinant().abs() > 1e-12,
            "FrameInputs.view_from_world",
            inputs.view_from_world,
            "a finite, invertible transform",
        )?;
        check(
            inputs.time.is_finite(),
            "FrameInputs.time",
            inputs.time,
            "a finite time",
        )?;
        inputs.medium.validate()?;
        inputs.sun.validate()?;
        check(
            inputs.ambient.rgb.iter().all(|v| v.is_finite()),
            "FrameInputs.ambient",
            inputs.ambient,
            "finite SH coefficients",
        )?;
        check(
            inputs.lights.len() <= c.max_lights as usize,
            "FrameInputs.lights",
            inputs.lights.len(),
            "at most FogConfig.max_lights lights",
        )?;
        for light in inputs.lights {
            light.validate()?;
        }
        check(
            inputs.local_volumes.len() <= c.max_local_volumes as usize,
            "FrameInputs.local_volumes",
            inputs.local_volumes.len(),
            "at most FogConfig.max_local_volumes volumes",
        )?;
        for v in inputs.local_volumes {
            check(
                v.local_from_world.is_finite()
                    && v.density.is_finite()
                    && v.edge > 0.0
                    && v.edge <= 1.0
                    && v.shape <= 1,
                "FrameInputs.local_volumes",
                v,
                "finite transforms and densities, 0 < edge <= 1, shape 0 or 1",
            )?;
        }
        inputs.cascades.validate(c.esm_log_space)?;
        inputs.tail.validate()?;
        check(
            inputs.cascades.count <= c.cascades,
            "ShadowCascades.count",
            inputs.cascades.count,
            "at most FogConfig.cascades",
        )?;

        let world_from_view = inputs.view_from_world.inverse();
        let clip_from_world = inputs.clip_from_view * inputs.view_from_world;
        let history_valid =
            c.temporal && !inputs.reset_history && self.prev_clip_from_world.is_some();
        let frame = FogFrame {
            world_from_view,
            prev_clip_from_world: self.prev_clip_from_world.unwrap_or(clip_from_world),
            camera_position: world_from_view.w_axis.truncate(),
            time: inputs.time,
            jitter: if c.jitter {
                froxel_jitter(self.frame_index)
            } else {
                Vec3::ZERO
            },
            history_weight: c.history_weight,
            history_valid: u32::from(history_valid),
        };
        let medium = FogMedium {
            local_volume_count: inputs.local_volumes.len() as u32,
            ..inputs.medium
        };
        let lighting = FogLighting {
            sun: inputs.sun,
            ambient_r: inputs.ambient.rgb[0],
            ambient_g: inputs.ambient.rgb[1],
            ambient_b: inputs.ambient.rgb[2],
            light_count: inputs.lights.len() as u32,
        };
        queue.write_buffer(&self.froxels, 0, &froxels.to_bytes());
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(&frame));
        queue.write_buffer(&self.medium, 0, &uniforms::to_uniform_bytes(&medium));
        queue.write_buffer(&self.lighting, 0, &uniforms::to_uniform_bytes(&lighting));
        queue.write_buffer(
            &self.cascades,
            0,
            &uniforms::to_uniform_bytes(&inputs.cascades),
        );
        let tail = inputs.tail.to_view_space(inputs.view_from_world);
        queue.write_buffer(&self.tail, 0, &uniforms::to_uniform_bytes(&tail));
        if !inputs.lights.is_empty() {
            queue.write_buffer(&self.lights, 0, &uniforms::to_storage_bytes(inputs.lights));
        }
        if !inputs.local_volumes.is_empty() {
            queue.write_buffer(
                &self.local_volumes,
                0,
                &uniforms::to_storage_bytes(inputs.local_volumes),
            );
        }
        if !self.default_density_written {
            queue.write_texture(
                self.default_density.as_image_copy(),
                &[255],
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: None,
                    rows_per_image: None,
                },
                self.default_density.size(),
            );
            self.default_density_written = true;
        }
        self.prev_clip_from_world = Some(clip_from_world);
        self.shadows_enabled = inputs.cascades.count > 0;
        self.uploaded = Some(UploadedUniforms {
            froxels,
            frame,
            medium,
            lighting,
            cascades: inputs.cascades,
        });
        Ok(())
    }

    fn timestamp_writes(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.timestamps.as_ref().map(|t| t.compute(pass))
    }

    /// Records ESM downsample -> blur -> inject -> temporal -> scan for the frame
    /// uploaded by the last [`VolumetricFog::prepare`].
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        shadow: &ShadowInputs<'_>,
    ) {
        for pass in FogPass::ALL {
            self.encode_pass(device, encoder, shadow, pass);
        }
    }

    /// Records one pass of [`VolumetricFog::encode`], e.g. to submit and time each
    /// pass on its own. Calling it for every pass of [`FogPass::ALL`] in order records
    /// the same work as `encode`; the frame ends with [`FogPass::Scan`]. Passes that
    /// do not run in this configuration or frame (ESM without a shadow map or without
    /// cascades, temporal when disabled) record nothing.
    pub fn encode_pass(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        shadow: &ShadowInputs<'_>,
        pass: FogPass,
    ) {
        let c = &self.config;
        let size = c.volume_size.to_array();
        let parity = self.history_index;
        let shadow_map = shadow.shadow_map.filter(|_| self.shadows_enabled);
        match pass {
            FogPass::EsmDownsample => {
                let Some(shadow_map) = shadow_map else {
                    return;
                };
                let esm_view = array_view(&self.esm);
                let downsample = self.esm_passes.downsample_bind_group(
                    device,
                    &self.cascades,
                    shadow_map,
                    &esm_view,
                );
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("volfog esm_downsample"),
                    timestamp_writes: self.timestamp_writes(0),
                });
                self.esm_passes.encode_downsample(
                    &mut pass,
                    &downsample,
                    c.esm_resolution,
                    c.cascades,
                );
            }
            FogPass::EsmBlur => {
                if shadow_map.is_none() {
                    return;
                }
                let esm_view = array_view(&self.esm);
                let scratch_view = array_view(&self.esm_scratch);
                let blur_x = self
                    .esm_passes
                    .blur_bind_group(device, &esm_view, &scratch_view);
                let blur_y = self
                    .esm_passes
                    .blur_bind_group(device, &scratch_view, &esm_view);
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("volfog esm_blur"),
                    timestamp_writes: self.timestamp_writes(1),
                });
                self.esm_passes
                    .encode_blur(&mut pass, &blur_x, 0, c.esm_resolution, c.cascades);
                self.esm_passes
                    .encode_blur(&mut pass, &blur_y, 1, c.esm_resolution, c.cascades);
            }
            FogPass::Inject => {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("volfog inject"),
                    timestamp_writes: self.timestamp_writes(2),
                });
                self.inject.encode(&mut pass, &self.inject_group, size);
            }
            FogPass::Temporal => {
                if !c.temporal {
                    return;
                }
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("volfog temporal"),
                    timestamp_writes: self.timestamp_writes(3),
                });
                self.temporal
                    .encode(&mut pass, &self.temporal_groups[parity], size);
            }
            FogPass::Scan => {
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("volfog scan"),
                        timestamp_writes: self.timestamp_writes(4),
                    });
                    self.scan
                        .encode(&mut pass, &self.scan_groups[parity], [size[0], size[1]]);
                }
                if self.config.temporal {
                    self.history_index = 1 - parity;
                }
                self.frame_index = self.frame_index.wrapping_add(1);
            }
        }
    }

    /// Records the fullscreen apply: blends fog onto `color` (loaded, format
    /// `FogConfig::color_format`) using `depth` (a depth-aspect view of the scene's
    /// depth texture with the same size).
    pub fn apply_fullscreen(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) {
        let group = self.apply.bind_group(
            device,
            &self.froxels,
            &self.integrated_view(),
            &self.tail,
            depth,
        );
        self.apply.record(
            encoder,
            color,
            &group,
            self.timestamps.as_ref().map(|t| t.render(5, true, true)),
        );
    }

    /// The integrated volume (rgb in-scatter, a transmittance) after `encode`.
    pub fn integrated_texture(&self) -> &wgpu::Texture {
        if self.config.temporal {
            &self.scattering
        } else {
            &self.history[0]
        }
    }

    /// A view of the integrated volume.
    pub fn integrated_view(&self) -> wgpu::TextureView {
        self.integrated_texture().create_view(&Default::default())
    }

    /// The scattering volume written by inject (before temporal and scan; with
    /// temporal reprojection it is overwritten by the scan).
    pub fn scattering_texture(&self) -> &wgpu::Texture {
        &self.scattering
    }

    /// The filtered ESM array (one layer per cascade).
    pub fn esm_texture(&self) -> &wgpu::Texture {
        &self.esm
    }

    /// The `volfog::bindings` layout forward shaders use to read the fog (visible to
    /// fragment and compute stages).
    pub fn fog_bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.fog_layout
    }

    /// The bind group matching [`VolumetricFog::fog_bind_group_layout`].
    pub fn fog_bind_group(&self) -> &wgpu::BindGroup {
        &self.fog_group
    }

    /// The `Froxels` uniform buffer (binding 0 of the fog bind group).
    pub fn froxels_buffer(&self) -> &wgpu::Buffer {
        &self.froxels
    }

    /// The uniforms of the last `prepare`.
    pub fn uploaded(&self) -> Option<&UploadedUniforms> {
        self.uploaded.as_ref()
    }

    /// Frames encoded so far.
    pub fn frame_index(&self) -> u32 {
        self.frame_index
    }

    /// GPU memory of every texture and buffer this object owns, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        let texture = |t: &wgpu::Texture| {
            let s = t.size();
            let texel = t.format().block_copy_size(None).unwrap_or(4) as u64;
            u64::from(s.width) * u64::from(s.height) * u64::from(s.depth_or_array_layers) * texel
        };
        let textures = texture(&self.scattering)
            + texture(&self.history[0])
            + texture(&self.history[1])
            + texture(&self.esm)
            + texture(&self.esm_scratch)
            + texture(&self.default_density);
        let buffers = [
            &self.froxels,
            &self.frame,
            &self.medium,
            &self.lighting,
            &self.cascades,
            &self.tail,
            &self.lights,
            &self.local_volumes,
        ]
        .iter()
        .map(|b| b.size())
        .sum::<u64>();
        let queries = self
            .timestamps
            .as_ref()
            .map(TimestampPairs::buffer_bytes)
            .unwrap_or(0);
        textures + buffers + queries
    }

    /// Resolves the timestamps of the last encoded frame into the readback buffer;
    /// call after `encode` and `apply_fullscreen`, before submitting.
    pub fn resolve_timestamps(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(t) = &self.timestamps {
            t.resolve(encoder);
        }
    }

    /// Reads the per-pass GPU times of the last resolved frame (blocks until the GPU
    /// is done). `None` without timestamps or when the readback fails. Passes that
    /// did not run read 0.
    pub fn read_timings(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<PassTimings> {
        let ms = self.timestamps.as_ref()?.read_ms(device, queue).ok()?;
        Some(PassTimings {
            esm_downsample: ms[0],
            esm_blur: ms[1],
            inject: ms[2],
            temporal: ms[3],
            scan: ms[4],
            apply: ms[5],
        })
    }
}

/// A world-space orthographic light projection for one cascade: the light looks
/// along `-direction` (direction towards the light) at `center`, covering a square of
/// `half_extent` metres and `depth_range` metres of depth centred on `center`.
pub fn cascade_projection(
    direction: Vec3,
    center: Vec3,
    half_extent: f32,
    depth_range: f32,
) -> Mat4 {
    let dir = direction.normalize();
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let eye = center + dir * (depth_range * 0.5);
    let view = glam::camera::rh::view::look_at_mat4(eye, center, up);
    let proj = glam::camera::rh::proj::directx::orthographic(
        -half_extent,
        half_extent,
        -half_extent,
        half_extent,
        0.0,
        depth_range,
    );
    proj * view
}

/// Splits of `count` cascades between `near` and `far` (m), blending logarithmic and
/// uniform splits by `lambda` in [0, 1] (the practical split scheme).
pub fn cascade_splits(count: u32, near: f32, far: f32, lambda: f32) -> Vec4 {
    let mut splits = [far; 4];
    for (i, split) in splits.iter_mut().enumerate().take(count as usize) {
        let f = (i + 1) as f32 / count as f32;
        let log = near * (far / near).powf(f);
        let uniform = near + (far - near) * f;
        *split = lambda * log + (1.0 - lambda) * uniform;
    }
    Vec4::from_array(splits)
}
