//! [`VolumetricFog`]: the whole froxel pipeline behind one object.
//!
//! Once: [`VolumetricFog::new`], [`VolumetricFog::set_shadow_map`] (when the sun casts
//! shadows into the fog), [`VolumetricFog::create_apply`] per colour format and
//! [`ApplyPipeline::depth_bind_group`] per depth texture. Per frame:
//! [`VolumetricFog::prepare`] checks and uploads the camera, medium, lights and shadow
//! cascades; [`VolumetricFog::encode`] records ESM downsample -> blur -> inject ->
//! temporal -> scan; [`VolumetricFog::draw_apply`] fogs the lit scene inside the
//! caller's render pass (or [`VolumetricFog::record_apply`] in a pass of its own), and
//! forward shaders read the integrated volume through
//! [`VolumetricFog::fog_bind_group`] (the `volfog::bindings` layout).
//!
//! The frame contract: `prepare` starts frame n (its history parity is n % 2, its
//! jitter the n-th Halton point); `encode` and the apply take `&self` and record the
//! prepared frame, so recording it twice records the same work. Reprojection reads
//! the camera stored on the GPU beside the history volume it reprojects, so a command
//! buffer that is never submitted cannot leave the next frame with the wrong history.
//! `prepare` writes through the queue, which takes effect at the next submit: submit a
//! frame's commands before preparing the next one.
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, color: &wgpu::TextureView, depth: &wgpu::TextureView) -> Result<(), volfog::pipeline::FogError> {
//! use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
//!
//! let mut fog = VolumetricFog::new(device, &FogConfig::default())?;
//! let apply = fog.create_apply(device, wgpu::TextureFormat::Rgba16Float)?;
//! let depth_group = apply.depth_bind_group(device, depth);
//! // every frame:
//! let projection = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 500.0);
//! let view = glam::camera::rh::view::look_at_mat4(glam::Vec3::new(0.0, 2.0, 10.0), glam::Vec3::ZERO, glam::Vec3::Y);
//! fog.prepare(queue, &FrameInputs::new(view, projection, 0.0))?;
//! let mut encoder = device.create_command_encoder(&Default::default());
//! fog.encode(&mut encoder)?;
//! fog.record_apply(&mut encoder, &apply, color, &depth_group)?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```
//!
//! [`ApplyPipeline::depth_bind_group`]: super::apply::ApplyPipeline::depth_bind_group

mod atlas_layers;
mod buffers;
mod cascades;
mod composite;
mod config;
mod error;
mod frame;
mod groups;
mod inputs;
mod local_shadows;
mod medium_shadows;
mod resources;
mod shared;
mod stereo;
mod textures;
mod timings;
mod user_textures;

pub use cascades::{cascade_projection, cascade_splits};
pub use config::{FogConfig, LocalShadowConfig};
pub use error::FogError;
pub use inputs::{FrameInputs, FrameUniforms};
pub use local_shadows::{LocalShadowStats, ShadowedLight};
pub use resources::{SCENE_DEPTH_FORMATS, SHADOW_MAP_FORMATS, VOLUME_FORMAT, check_device};
pub use shared::SharedFog;
pub use stereo::StereoFog;
pub use timings::{FogPass, PassTimings};

use super::apply::{FogResources, fog_bind_group, fog_layout_entries, fog_sampler};
use super::cull::{FroxelCullPass, LiveBlocks, live_slices_texture};
use super::esm::EsmPasses;
use super::inject::{InjectOptions, InjectPass};
use super::noise::{NoiseBake, noise_sampler};
use super::scan::ScanPass;
use super::temporal::TemporalPass;
use super::timestamps::TimestampPairs;
use crate::uniforms::{self, CloudLayer, HistoryState};
use buffers::Buffers;
use groups::{
    InjectTextures, blur_groups, inject_bind_group, inject_culling, inject_output, scan_groups,
    temporal_groups,
};
use local_shadows::LocalShadows;
use medium_shadows::MediumShadows;
pub(crate) use resources::{
    array_view, check_cloud_map, check_density_texture, check_scene_depth, check_shadow_map,
    esm_texture, storage_buffer, texture_bytes, uniform_buffer, volume_texture,
};
use textures::{
    CloudShadow, Culling, Density, Noise, ShadowMap, Temporal, density_sampler, empty_cloud_map,
    esm_side, esm_texture_scratch, unit_density_texture,
};

/// The froxel volumetric fog pipeline.
pub struct VolumetricFog {
    config: FogConfig,
    esm: EsmPasses,
    /// Inject without local shadows: every frame whose lights project nothing.
    inject: InjectPass,
    /// Inject with local shadows and its bind groups, compiled once the first shadow
    /// maps or cookies are set: frames with a shadowed or cookied light.
    inject_shadowed: Option<(InjectPass, [wgpu::BindGroup; 2])>,
    scan: ScanPass,
    /// The scan that adds the transient lights and its bind groups by parity
    /// (`FogConfig::max_transient_lights` > 0): frames with transient lights.
    scan_transient: Option<(ScanPass, [wgpu::BindGroup; 2])>,
    buffers: Buffers,
    /// Inject output; with temporal reprojection also the scan output (the integrated
    /// volume).
    scattering: wgpu::Texture,
    /// The scan output without temporal reprojection.
    integrated: Option<wgpu::Texture>,
    temporal: Option<Temporal>,
    esm_texture: wgpu::Texture,
    esm_scratch: wgpu::Texture,
    blur_groups: [wgpu::BindGroup; 2],
    density: Option<Density>,
    culling: Option<Culling>,
    noise: Option<Noise>,
    clouds: Option<CloudShadow>,
    local_shadows: Option<LocalShadows>,
    /// The medium's shadows (`FogConfig::medium_shadows`).
    medium_shadows: Option<MediumShadows>,
    /// Inject bind groups by frame parity (they differ in the live-slice texture).
    inject_groups: [wgpu::BindGroup; 2],
    scan_groups: [wgpu::BindGroup; 2],
    /// Transient lights of the prepared frame.
    transient_lights: u32,
    shadow_map: Option<ShadowMap>,
    fog_layout: wgpu::BindGroupLayout,
    fog_group: wgpu::BindGroup,
    integrated_view: wgpu::TextureView,
    fog_sampler: wgpu::Sampler,
    timestamps: Option<TimestampPairs>,
    /// Frames prepared so far; the prepared frame is `frames - 1`.
    frames: u32,
    /// The prepared frame's far-plane tail: empty ones are applied without it.
    tail: crate::pipeline::apply::Tail,
    shadows_enabled: bool,
}

impl std::fmt::Debug for VolumetricFog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VolumetricFog")
            .field("config", &self.config)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}

fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

impl VolumetricFog {
    /// Creates every texture, pipeline and bind group for a configuration.
    pub fn new(device: &wgpu::Device, config: &FogConfig) -> Result<Self, FogError> {
        config.validate()?;
        check_device(device, config)?;
        let size = config.volume_size;
        let esm = EsmPasses::new(device, &config.esm_options())?;
        let inject = InjectPass::with_custom_density(
            device,
            InjectOptions {
                local_shadows: false,
                ..config.inject_options()
            },
            config.custom_density.as_ref(),
        )?;
        let scan = ScanPass::new(device, config.scan_step, config.depth_cull)?;
        let buffers = Buffers::new(device, config);
        let culling = if config.depth_cull {
            let columns = [size.x, size.y];
            let live = [0, 1]
                .map(|i| live_slices_texture(device, &format!("volfog live slices {i}"), columns));
            Some(Culling {
                pass: FroxelCullPass::new(device)?,
                views: [view(&live[0]), view(&live[1])],
                live,
                blocks: LiveBlocks::new(device, size.to_array()),
                depth: None,
                all_live: false,
            })
        } else {
            None
        };

        let scattering = volume_texture(device, "volfog scattering", size);
        let scattering_view = view(&scattering);
        let temporal = if config.temporal {
            let volumes =
                [0, 1].map(|i| volume_texture(device, &format!("volfog history {i}"), size));
            let state_bytes = uniforms::to_storage_bytes(&[HistoryState::default()]).len();
            // Readable (COPY_SRC) for inspection, like the volumes.
            let states = [0, 1].map(|i| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("volfog history state {i}")),
                    size: state_bytes as u64,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            });
            let views = [view(&volumes[0]), view(&volumes[1])];
            // The separate pass unless inject does the blend.
            let pass = if config.fused_temporal() {
                None
            } else {
                let pass = TemporalPass::new(device, config.depth_cull)?;
                let groups = temporal_groups(
                    device,
                    &pass,
                    &buffers,
                    &scattering_view,
                    &views,
                    &states,
                    culling.as_ref(),
                );
                Some((pass, groups))
            };
            Some(Temporal {
                volumes,
                views,
                states,
                pass,
            })
        } else {
            None
        };
        let integrated =
            (!config.temporal).then(|| volume_texture(device, "volfog integrated", size));
        let scan_groups_of = |scan: &ScanPass| {
            scan_groups(
                device,
                scan,
                &buffers,
                &scattering_view,
                temporal.as_ref(),
                integrated.as_ref(),
                culling.as_ref(),
            )
        };
        let scan_groups = scan_groups_of(&scan);
        let scan_transient = if config.max_transient_lights > 0 {
            let pass =
                ScanPass::with_transient_lights(device, config.scan_step, config.depth_cull)?;
            let groups = scan_groups_of(&pass);
            Some((pass, groups))
        } else {
            None
        };

        let esm_texture = esm_texture(device, "volfog esm", esm_side(config), config.cascades);
        let esm_scratch = esm_texture_scratch(device, config);
        let (esm_view, scratch_view) = (array_view(&esm_texture), array_view(&esm_scratch));
        let blur_groups = blur_groups(device, &esm, &esm_view, &scratch_view);
        let density = config.density_texture.then(|| Density {
            texture: unit_density_texture(device),
            user: false,
            unit_written: false,
            sampler: density_sampler(device),
        });
        let noise = if config.noise_texture {
            Some(Noise {
                device: device.clone(),
                pass: NoiseBake::new(device)?,
                texture: NoiseBake::create_texture(device),
                sampler: noise_sampler(device),
                baked: false,
            })
        } else {
            None
        };
        let clouds = config.cloud_shadow.then(|| CloudShadow {
            layer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("volfog cloud layer"),
                size: uniforms::to_uniform_bytes(&CloudLayer::default()).len() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            map: empty_cloud_map(device),
            user: false,
            empty_written: false,
            sampler: crate::pipeline::clouds::cloud_map_sampler(device),
        });
        let local_shadows = LocalShadows::new(device, config)?;
        let medium_shadows =
            MediumShadows::new(device, config, &buffers, density.as_ref(), noise.as_ref())?;
        let fused = temporal.as_ref().filter(|_| config.fused_temporal());
        // No scene depth yet: the placeholder (its taps all count until one is set).
        let scene_depth = groups::scene_depth_view(culling.as_ref(), &esm_texture);
        let inject_groups = [0, 1].map(|p| {
            let (output, temporal) = inject_output(&scattering_view, fused, culling.as_ref(), p);
            inject_bind_group(
                device,
                &inject,
                &buffers,
                &esm_view,
                output,
                InjectTextures {
                    density: density.as_ref(),
                    culling: inject_culling(culling.as_ref(), p),
                    noise: noise.as_ref(),
                    clouds: clouds.as_ref(),
                    local_shadows: local_shadows.as_ref(),
                    temporal,
                    scene_depth: Some(&scene_depth),
                    medium_shadow: medium_shadows.as_ref(),
                },
            )
        });

        let fog_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volfog fog (volfog::bindings)"),
            entries: &fog_layout_entries(
                config.apply_filtering,
                wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            ),
        });
        let fog_sampler = fog_sampler(device);
        let integrated_view = view(integrated.as_ref().unwrap_or(&scattering));
        let fog_group = fog_bind_group(
            device,
            &fog_layout,
            config.apply_filtering,
            &FogResources {
                froxels: &buffers.froxels,
                integrated: &integrated_view,
                tail: &buffers.tail,
                view: &buffers.view,
                sampler: &fog_sampler,
            },
        );
        let timestamps = config
            .timestamps
            .then(|| TimestampPairs::new(device, "volfog timestamps", timings::TIMESTAMP_PAIRS));
        Ok(Self {
            config: config.clone(),
            esm,
            inject,
            inject_shadowed: None,
            scan,
            scan_transient,
            buffers,
            scattering,
            integrated,
            temporal,
            esm_texture,
            esm_scratch,
            blur_groups,
            density,
            culling,
            noise,
            clouds,
            local_shadows,
            medium_shadows,
            inject_groups,
            scan_groups,
            transient_lights: 0,
            shadow_map: None,
            fog_layout,
            fog_group,
            integrated_view,
            fog_sampler,
            timestamps,
            frames: 0,
            tail: crate::pipeline::apply::Tail::Analytic,
            shadows_enabled: false,
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &FogConfig {
        &self.config
    }

    /// Replaces the configuration, recreating every resource; the history starts over.
    /// The shadow map, density texture and scene depth set before are kept (checked
    /// against the new configuration; the last two only where it still uses them). On
    /// error nothing changes.
    pub fn reconfigure(
        &mut self,
        device: &wgpu::Device,
        config: &FogConfig,
    ) -> Result<(), FogError> {
        let mut next = Self::new(device, config)?;
        if let Some(shadow) = &self.shadow_map {
            next.set_shadow_map(device, &shadow.texture)?;
        }
        if let Some(density) = self.density.as_ref().filter(|d| d.user)
            && config.density_texture
        {
            next.set_density_texture(device, &density.texture)?;
        }
        if let Some(clouds) = self.clouds.as_ref().filter(|c| c.user)
            && config.cloud_shadow
        {
            next.set_cloud_map(device, &clouds.map)?;
        }
        if let Some((texture, mip_level, _)) = self.culling.as_ref().and_then(|c| c.depth.as_ref())
            && config.depth_cull
        {
            next.set_scene_depth(device, texture, *mip_level)?;
        }
        if let Some(local) = &self.local_shadows
            && config.local_shadows.is_some()
        {
            let [spot, point, cookies] = local.user_textures();
            if let Some(t) = spot {
                next.set_spot_shadow_maps(device, t)?;
            }
            if let Some(t) = point {
                next.set_point_shadow_maps(device, t)?;
            }
            if let Some(t) = cookies {
                next.set_cookies(device, t)?;
            }
        }
        *self = next;
        Ok(())
    }
}
