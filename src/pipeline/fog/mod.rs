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

mod cascades;
mod config;
mod error;
mod inputs;
mod resources;

pub use cascades::{cascade_projection, cascade_splits};
pub use config::FogConfig;
pub use error::FogError;
pub use inputs::{FogPass, FrameInputs, FrameUniforms, PassTimings};
pub use resources::{SCENE_DEPTH_FORMATS, SHADOW_MAP_FORMATS, VOLUME_FORMAT, check_device};

use super::apply::{ApplyPipeline, FogResources, fog_bind_group, fog_layout_entries, fog_sampler};
use super::cull::{FroxelCullPass, LiveBlocks, live_slices_texture, write_all_live};
use super::esm::EsmPasses;
use super::inject::{InjectPass, InjectResources};
use super::noise::{NoiseBake, noise_sampler};
use super::scan::ScanPass;
use super::temporal::{TemporalPass, TemporalResources};
use super::timestamps::TimestampPairs;
use crate::uniforms::{
    self, CloudLayer, FogFrame, FogLight, FogLighting, FogMedium, FogView, Froxels, HeightFog,
    HistoryState, LocalVolume, ShadowCascades,
};
pub(crate) use resources::{
    array_view, check_cloud_map, check_density_texture, check_scene_depth, check_shadow_map,
    esm_texture, storage_buffer, texture_bytes, uniform_buffer, volume_texture,
};

/// The uniform and storage buffers of the fog.
#[derive(Debug)]
struct Buffers {
    froxels: wgpu::Buffer,
    frame: wgpu::Buffer,
    medium: wgpu::Buffer,
    lighting: wgpu::Buffer,
    cascades: wgpu::Buffer,
    tail: wgpu::Buffer,
    view: wgpu::Buffer,
    lights: wgpu::Buffer,
    local_volumes: wgpu::Buffer,
}

impl Buffers {
    fn new(device: &wgpu::Device, config: &FogConfig) -> Self {
        let uniform = |label, bytes: Vec<u8>| uniform_buffer(device, label, bytes.len());
        let lights = uniforms::to_storage_bytes(&vec![
            FogLight::default();
            config.max_lights.max(1) as usize
        ]);
        let volumes = uniforms::to_storage_bytes(&vec![
            LocalVolume::default();
            config.max_local_volumes.max(1) as usize
        ]);
        Self {
            froxels: uniform("volfog froxels", Froxels::default().to_bytes()),
            frame: uniform(
                "volfog frame",
                uniforms::to_uniform_bytes(&FogFrame::default()),
            ),
            medium: uniform(
                "volfog medium",
                uniforms::to_uniform_bytes(&FogMedium::default()),
            ),
            lighting: uniform(
                "volfog lighting",
                uniforms::to_uniform_bytes(&FogLighting::default()),
            ),
            cascades: uniform(
                "volfog cascades",
                uniforms::to_uniform_bytes(&ShadowCascades::default()),
            ),
            tail: uniform("volfog tail", HeightFog::none().to_bytes()),
            view: uniform(
                "volfog view",
                uniforms::to_uniform_bytes(&FogView::default()),
            ),
            lights: storage_buffer(device, "volfog lights", lights.len()),
            local_volumes: storage_buffer(device, "volfog local volumes", volumes.len()),
        }
    }

    fn all(&self) -> [&wgpu::Buffer; 9] {
        [
            &self.froxels,
            &self.frame,
            &self.medium,
            &self.lighting,
            &self.cascades,
            &self.tail,
            &self.view,
            &self.lights,
            &self.local_volumes,
        ]
    }
}

/// Temporal reprojection: its pass, the two history volumes with their states, and
/// the bind groups of both parities.
#[derive(Debug)]
struct Temporal {
    pass: TemporalPass,
    volumes: [wgpu::Texture; 2],
    states: [wgpu::Buffer; 2],
    groups: [wgpu::BindGroup; 2],
}

/// The density multiplier texture of the density-texture variant.
#[derive(Debug)]
struct Density {
    /// The user's texture, or a 1x1x1 unit texture until one is set.
    texture: wgpu::Texture,
    user: bool,
    unit_written: bool,
    sampler: wgpu::Sampler,
}

/// The cloud shadow of the cloud-shadow variant: the layer's uniform and its density
/// map (the user's, or an empty 1x1 map until one is set).
#[derive(Debug)]
struct CloudShadow {
    layer: wgpu::Buffer,
    map: wgpu::Texture,
    user: bool,
    empty_written: bool,
    sampler: wgpu::Sampler,
}

/// Depth culling: the cull pass, the live-slice textures of both parities (the one of
/// parity p is written with the history volume p), and the cull bind groups of the
/// scene depth when one is set.
#[derive(Debug)]
struct Culling {
    pass: FroxelCullPass,
    live: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    /// The live blocks and the indirect dispatch arguments of this frame.
    blocks: LiveBlocks,
    /// The scene depth, its mip level and the cull groups of both parities.
    depth: Option<(wgpu::Texture, u32, [wgpu::BindGroup; 2])>,
    /// Whether both textures hold "every slice live" (written by `prepare` while no
    /// scene depth is set).
    all_live: bool,
}

/// The baked noise texture of the noise-texture variant: baked by the first `prepare`
/// (one submission of its own), then only read.
#[derive(Debug)]
struct Noise {
    device: wgpu::Device,
    pass: NoiseBake,
    texture: wgpu::Texture,
    sampler: wgpu::Sampler,
    baked: bool,
}

/// The shadow map and the downsample bind group reading it.
#[derive(Debug)]
struct ShadowMap {
    texture: wgpu::Texture,
    group: wgpu::BindGroup,
}

/// The froxel volumetric fog pipeline.
pub struct VolumetricFog {
    config: FogConfig,
    esm: EsmPasses,
    inject: InjectPass,
    scan: ScanPass,
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
    /// Inject bind groups by frame parity (they differ in the live-slice texture).
    inject_groups: [wgpu::BindGroup; 2],
    scan_groups: [wgpu::BindGroup; 2],
    shadow_map: Option<ShadowMap>,
    fog_layout: wgpu::BindGroupLayout,
    fog_group: wgpu::BindGroup,
    integrated_view: wgpu::TextureView,
    fog_sampler: wgpu::Sampler,
    timestamps: Option<TimestampPairs>,
    /// Frames prepared so far; the prepared frame is `frames - 1`.
    frames: u32,
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
        let inject = InjectPass::new(device, config.inject_options())?;
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
        let live_view = |p: usize| culling.as_ref().map(|c| &c.views[p]);
        let live_blocks = culling.as_ref().map(|c| &c.blocks.blocks);

        let scattering = volume_texture(device, "volfog scattering", size);
        let scattering_view = view(&scattering);
        let temporal = if config.temporal {
            let pass = TemporalPass::new(device, config.depth_cull)?;
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
            // Frame parity p reads history 1 - p and writes history p.
            let groups = [0, 1].map(|p| {
                pass.bind_group(
                    device,
                    &TemporalResources {
                        froxels: &buffers.froxels,
                        frame: &buffers.frame,
                        current: &scattering_view,
                        history: &views[1 - p],
                        history_state: &states[1 - p],
                        stabilised: &views[p],
                        stabilised_state: &states[p],
                        culling: live_view(p)
                            .zip(live_view(1 - p))
                            .zip(live_blocks)
                            .map(|((a, b), c)| (a, b, c)),
                    },
                )
                .expect("the fog binds live slices whenever it culls")
            });
            Some(Temporal {
                pass,
                volumes,
                states,
                groups,
            })
        } else {
            None
        };
        let integrated =
            (!config.temporal).then(|| volume_texture(device, "volfog integrated", size));
        // Parity p scans stabilised volume p (or the scattering volume) with live
        // slices p.
        let scan_groups = [0, 1].map(|p| {
            let (input, output) = match (&temporal, &integrated) {
                (Some(t), _) => (view(&t.volumes[p]), scattering_view.clone()),
                (None, Some(out)) => (scattering_view.clone(), view(out)),
                (None, None) => unreachable!("the integrated volume exists without temporal"),
            };
            scan.bind_group(device, &buffers.froxels, &input, &output, live_view(p))
                .expect("the fog binds live slices whenever it culls")
        });

        let esm_texture = esm_texture(device, "volfog esm", config.esm_resolution, config.cascades);
        let esm_scratch = esm_texture_scratch(device, config);
        let (esm_view, scratch_view) = (array_view(&esm_texture), array_view(&esm_scratch));
        let blur_groups = [
            esm.blur_bind_group(device, &esm_view, &scratch_view),
            esm.blur_bind_group(device, &scratch_view, &esm_view),
        ];
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
        let inject_groups = [0, 1].map(|p| {
            inject_bind_group(
                device,
                &inject,
                &buffers,
                &esm_view,
                &scattering_view,
                InjectTextures {
                    density: density.as_ref(),
                    culling: live_view(p).zip(live_blocks),
                    noise: noise.as_ref(),
                    clouds: clouds.as_ref(),
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
            .then(|| TimestampPairs::new(device, "volfog timestamps", inputs::TIMESTAMP_PAIRS));
        Ok(Self {
            config: config.clone(),
            esm,
            inject,
            scan,
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
            inject_groups,
            scan_groups,
            shadow_map: None,
            fog_layout,
            fog_group,
            integrated_view,
            fog_sampler,
            timestamps,
            frames: 0,
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
        *self = next;
        Ok(())
    }

    /// Uses the sun's cascaded shadow map for the ESM passes: a 2D texture with
    /// `4 * esm_resolution` texels per side and a layer per cascade, in one of
    /// [`SHADOW_MAP_FORMATS`], with `TEXTURE_BINDING` usage. Set it once (and again when
    /// the texture is recreated); every frame with `cascades.count > 0` reads it.
    pub fn set_shadow_map(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        check_shadow_map(texture, &self.config)?;
        let group = self.esm.downsample_bind_group(
            device,
            &self.buffers.cascades,
            &array_view(texture),
            &array_view(&self.esm_texture),
        );
        self.shadow_map = Some(ShadowMap {
            texture: texture.clone(),
            group,
        });
        Ok(())
    }

    /// Stops reading the shadow map (frames must then have `cascades.count` 0).
    pub fn clear_shadow_map(&mut self) {
        self.shadow_map = None;
    }

    /// Uses a 3D texture (r channel, filterable format, `TEXTURE_BINDING` usage) as
    /// density multiplier, sampled with repeat addressing at
    /// `world * texture_scale + texture_offset`; needs `FogConfig::density_texture`.
    pub fn set_density_texture(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let Some(density) = self.density.as_mut() else {
            return Err(option_off("FogConfig.density_texture", "a density texture"));
        };
        check_density_texture(texture, device)?;
        density.texture = texture.clone();
        density.user = true;
        self.rebuild_inject_groups(device);
        Ok(())
    }

    /// Uses a 2D texture (red channel, filterable, `TEXTURE_BINDING` usage) as the
    /// density map of the cloud layer whose shadow the sun's light passes in the fog;
    /// needs `FogConfig::cloud_shadow`. The layer comes with each frame
    /// ([`FrameInputs::clouds`]).
    pub fn set_cloud_map(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
    ) -> Result<(), FogError> {
        let Some(clouds) = self.clouds.as_mut() else {
            return Err(option_off("FogConfig.cloud_shadow", "a cloud map"));
        };
        check_cloud_map(texture, device)?;
        clouds.map = texture.clone();
        clouds.user = true;
        self.rebuild_inject_groups(device);
        Ok(())
    }

    fn rebuild_inject_groups(&mut self, device: &wgpu::Device) {
        let live = |p: usize| {
            self.culling
                .as_ref()
                .map(|c| (&c.views[p], &c.blocks.blocks))
        };
        self.inject_groups = [0, 1].map(|p| {
            inject_bind_group(
                device,
                &self.inject,
                &self.buffers,
                &array_view(&self.esm_texture),
                &view(&self.scattering),
                InjectTextures {
                    density: self.density.as_ref(),
                    culling: live(p),
                    noise: self.noise.as_ref(),
                    clouds: self.clouds.as_ref(),
                },
            )
        });
    }

    /// Culls froxels by the scene depth (needs `FogConfig::depth_cull`): every frame,
    /// before injection, the `froxel_cull` pass finds for each froxel column how many
    /// slices lie in front of the farthest opaque surface over the column's screen
    /// footprint, and inject, temporal and scan skip the others. `texture` holds
    /// depth-buffer values of this frame's camera (standard, reversed or infinite
    /// projection), written before [`VolumetricFog::encode`] runs: the depth buffer
    /// itself (a depth format, single-sampled) or any R32Float texture covering the
    /// screen that is no nearer than it, such as a farthest-depth level of a
    /// hierarchical depth buffer; `mip_level` picks the level read. Needs
    /// `TEXTURE_BINDING` usage. Transparent surfaces, which lie in front of the opaque
    /// depth, read live froxels through the forward snippet as before.
    pub fn set_scene_depth(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
        mip_level: u32,
    ) -> Result<(), FogError> {
        let Some(culling) = self.culling.as_mut() else {
            return Err(FogError::Invalid(crate::limits::InvalidValue {
                field: "FogConfig.depth_cull",
                value: "false".to_string(),
                expected: "true to cull froxels by a scene depth".into(),
            }));
        };
        check_scene_depth(texture, mip_level)?;
        let depth_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            aspect: if texture.format().has_depth_aspect() {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            },
            base_mip_level: mip_level,
            mip_level_count: Some(1),
            ..Default::default()
        });
        let groups = [0, 1].map(|p| {
            culling.pass.bind_group(
                device,
                &self.buffers.froxels,
                &depth_view,
                &culling.views[p],
                &culling.blocks,
            )
        });
        culling.depth = Some((texture.clone(), mip_level, groups));
        culling.all_live = false;
        Ok(())
    }

    /// Stops culling: from the next `prepare` every froxel is live again.
    pub fn clear_scene_depth(&mut self) {
        if let Some(c) = self.culling.as_mut() {
            c.depth = None;
            c.all_live = false;
        }
    }

    /// Checks one frame's inputs and uploads them; starts the next frame.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        inputs: &FrameInputs<'_>,
    ) -> Result<(), FogError> {
        let u = inputs.uniforms(&self.config, self.frames)?;
        if inputs.cascades.count > 0 && self.shadow_map.is_none() {
            return Err(FogError::Invalid(crate::limits::InvalidValue {
                field: "ShadowCascades.count",
                value: inputs.cascades.count.to_string(),
                expected: "0 while no shadow map is set (VolumetricFog::set_shadow_map)".into(),
            }));
        }
        let b = &self.buffers;
        queue.write_buffer(&b.froxels, 0, &u.froxels.to_bytes());
        queue.write_buffer(&b.frame, 0, &uniforms::to_uniform_bytes(&u.frame));
        queue.write_buffer(&b.medium, 0, &uniforms::to_uniform_bytes(&u.medium));
        queue.write_buffer(&b.lighting, 0, &uniforms::to_uniform_bytes(&u.lighting));
        queue.write_buffer(&b.cascades, 0, &uniforms::to_uniform_bytes(&u.cascades));
        queue.write_buffer(&b.tail, 0, &u.tail.to_bytes());
        queue.write_buffer(&b.view, 0, &uniforms::to_uniform_bytes(&u.view));
        if !inputs.lights.is_empty() {
            queue.write_buffer(&b.lights, 0, &uniforms::to_storage_bytes(inputs.lights));
        }
        if !inputs.local_volumes.is_empty() {
            queue.write_buffer(
                &b.local_volumes,
                0,
                &uniforms::to_storage_bytes(inputs.local_volumes),
            );
        }
        if let Some(density) = self.density.as_mut().filter(|d| !d.user && !d.unit_written) {
            write_unit_density(queue, &density.texture);
            density.unit_written = true;
        }
        if let Some(clouds) = self.clouds.as_mut() {
            queue.write_buffer(&clouds.layer, 0, &inputs.clouds.to_bytes());
            if !clouds.user && !clouds.empty_written {
                write_texel(queue, &clouds.map, 0);
                clouds.empty_written = true;
            }
        }
        if let Some(c) = self
            .culling
            .as_mut()
            .filter(|c| c.depth.is_none() && !c.all_live)
        {
            for texture in &c.live {
                write_all_live(queue, texture, self.config.volume_size.z);
            }
            c.blocks
                .write_all(queue, self.config.volume_size.to_array());
            c.all_live = true;
        }
        if let Some(n) = self.noise.as_mut().filter(|n| !n.baked) {
            let mut encoder = n
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("volfog noise_bake"),
                });
            n.pass.encode(&n.device, &mut encoder, &n.texture);
            queue.submit([encoder.finish()]);
            n.baked = true;
        }
        self.shadows_enabled = inputs.cascades.count > 0;
        self.frames = self.frames.wrapping_add(1).max(1);
        Ok(())
    }

    /// The index of the prepared frame (frames prepared before it), `None` before
    /// the first `prepare`.
    pub fn frame_index(&self) -> Option<u32> {
        self.frames.checked_sub(1)
    }

    fn timestamp_writes(&self, pass: FogPass) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.timestamps
            .as_ref()
            .map(|t| t.compute(pass.timestamp_pair()))
    }

    /// Records ESM downsample -> blur -> inject -> temporal -> scan for the prepared
    /// frame.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), FogError> {
        for pass in FogPass::ALL {
            self.encode_pass(encoder, pass)?;
        }
        Ok(())
    }

    /// Records one pass of [`VolumetricFog::encode`], e.g. to submit and time each
    /// pass on its own. Passes that do not run in this configuration or frame (ESM
    /// without cascades, temporal when disabled) record nothing.
    pub fn encode_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: FogPass,
    ) -> Result<(), FogError> {
        let index = self.frame_index().ok_or(FogError::NotPrepared)?;
        let parity = (index % 2) as usize;
        let c = &self.config;
        let size = c.volume_size.to_array();
        let label = match pass {
            FogPass::EsmDownsample => "volfog esm_downsample",
            FogPass::EsmBlur => "volfog esm_blur",
            FogPass::Inject => "volfog inject",
            FogPass::Temporal => "volfog temporal",
            FogPass::Scan => "volfog scan",
            FogPass::Cull => "volfog froxel_cull",
        };
        // With culling, inject and temporal run over the listed live blocks.
        let indirect = self.culling.as_ref().map(|c| &c.blocks.dispatch);
        let cull = self
            .culling
            .as_ref()
            .and_then(|c| Some(&c.pass).zip(c.depth.as_ref()));
        let shadow = self.shadow_map.as_ref().filter(|_| self.shadows_enabled);
        let runs = match pass {
            FogPass::EsmDownsample | FogPass::EsmBlur => shadow.is_some(),
            FogPass::Temporal => self.temporal.is_some(),
            FogPass::Inject | FogPass::Scan => true,
            FogPass::Cull => cull.is_some(),
        };
        if !runs {
            return Ok(());
        }
        let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: self.timestamp_writes(pass),
        });
        match pass {
            FogPass::EsmDownsample => {
                let group = &shadow.expect("checked above").group;
                self.esm
                    .encode_downsample(&mut compute, group, c.esm_resolution, c.cascades);
            }
            FogPass::EsmBlur => {
                for (axis, group) in self.blur_groups.iter().enumerate() {
                    self.esm.encode_blur(
                        &mut compute,
                        group,
                        axis as u32,
                        c.esm_resolution,
                        c.cascades,
                    );
                }
            }
            FogPass::Inject => {
                self.inject
                    .encode(&mut compute, &self.inject_groups[parity], size, indirect)
            }
            FogPass::Temporal => {
                let t = self.temporal.as_ref().expect("checked above");
                t.pass
                    .encode(&mut compute, &t.groups[parity], size, indirect);
            }
            FogPass::Scan => {
                self.scan
                    .encode(&mut compute, &self.scan_groups[parity], [size[0], size[1]]);
            }
            FogPass::Cull => {
                let (pass, (_, _, groups)) = cull.expect("checked above");
                pass.encode(&mut compute, &groups[parity], size);
            }
        }
        Ok(())
    }

    /// The fullscreen apply pass for colour targets of `format`, reading this fog's
    /// group (create one per format; it stays valid until the fog is reconfigured
    /// with another `apply_filtering`).
    pub fn create_apply(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::Depth)
    }

    /// The fullscreen apply pass reading `input` at group 1 (the forms of
    /// [`VolumetricFog::create_apply`], [`VolumetricFog::create_apply_resolved`] and
    /// [`VolumetricFog::create_apply_far_field`]).
    pub fn create_apply_with(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        input: crate::options::ApplyInput,
    ) -> Result<ApplyPipeline, FogError> {
        Ok(ApplyPipeline::with_input(
            device,
            &self.fog_layout,
            self.config.apply_filtering,
            format,
            input,
        )?)
    }

    /// The fullscreen apply pass for a multisampled scene: it reads the resolved MSAA
    /// fog layout ([`crate::options::FOG_LAYOUT_FORMAT`]) instead of the depth buffer.
    /// Lay out each sample with `volfog::apply::fog_layout` (the fog of the sample,
    /// from the fog group) into a multisampled target of that format, resolve it, and
    /// bind the resolved view with [`ApplyPipeline::depth_bind_group`].
    pub fn create_apply_resolved(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::ResolvedLayout)
    }

    /// The fullscreen apply pass with the far field of epipolar sun shafts: beyond the
    /// far plane the tail's sun light is shadowed by the lit fraction of an
    /// [`EpipolarShafts`](crate::pipeline::epipolar::EpipolarShafts) prepared with
    /// `start_depth` = `FogConfig::far`, the frame's tail as its medium and
    /// `max_depth` at least the camera's far plane. Bind its group 1 with
    /// [`ApplyPipeline::far_field_bind_group`].
    pub fn create_apply_far_field(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::FarField)
    }

    fn check_apply(&self, apply: &ApplyPipeline) -> Result<(), FogError> {
        if apply.filtering() != self.config.apply_filtering {
            return Err(FogError::ApplyMismatch {
                pipeline: apply.filtering(),
                fog: self.config.apply_filtering,
            });
        }
        self.frame_index().map(|_| ()).ok_or(FogError::NotPrepared)
    }

    /// Draws the fullscreen apply into the caller's render pass (its colour
    /// attachment is the lit scene in `apply`'s format, loaded): `depth_group` comes
    /// from [`ApplyPipeline::depth_bind_group`].
    pub fn draw_apply(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        apply: &ApplyPipeline,
        depth_group: &wgpu::BindGroup,
    ) -> Result<(), FogError> {
        self.check_apply(apply)?;
        apply.draw(pass, &self.fog_group, depth_group);
        Ok(())
    }

    /// Records the fullscreen apply in a render pass of its own that loads `color`
    /// (timed when timestamps are on).
    pub fn record_apply(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &ApplyPipeline,
        color: &wgpu::TextureView,
        depth_group: &wgpu::BindGroup,
    ) -> Result<(), FogError> {
        self.check_apply(apply)?;
        let timestamps = self
            .timestamps
            .as_ref()
            .map(|t| t.render(inputs::APPLY_PAIR, true, true));
        apply.record(encoder, color, &self.fog_group, depth_group, timestamps);
        Ok(())
    }

    /// The integrated volume (rgb in-scatter, a transmittance) after `encode`.
    pub fn integrated_texture(&self) -> &wgpu::Texture {
        self.integrated.as_ref().unwrap_or(&self.scattering)
    }

    /// The live-slice texture of the prepared frame (R32Uint, one value per froxel
    /// column: how many leading slices inject, temporal and scan process), with
    /// `FogConfig::depth_cull`; `None` without culling or before the first `prepare`.
    pub fn live_slices_texture(&self) -> Option<&wgpu::Texture> {
        let parity = (self.frame_index()? % 2) as usize;
        self.culling.as_ref().map(|c| &c.live[parity])
    }

    /// The scattering volume written by inject (before temporal and scan; with
    /// temporal reprojection the scan overwrites it with the integrated volume).
    pub fn scattering_texture(&self) -> &wgpu::Texture {
        &self.scattering
    }

    /// The stabilised volume of the prepared frame (after `encode`), when temporal
    /// reprojection is on.
    pub fn stabilised_texture(&self) -> Option<&wgpu::Texture> {
        let parity = (self.frame_index()? % 2) as usize;
        self.temporal.as_ref().map(|t| &t.volumes[parity])
    }

    /// The `HistoryState` buffer beside [`VolumetricFog::stabilised_texture`].
    pub fn stabilised_state(&self) -> Option<&wgpu::Buffer> {
        let parity = (self.frame_index()? % 2) as usize;
        self.temporal.as_ref().map(|t| &t.states[parity])
    }

    /// The filtered ESM array (one layer per cascade).
    pub fn esm_texture(&self) -> &wgpu::Texture {
        &self.esm_texture
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

    /// The resources of the fog group, for a group of the caller's own that holds
    /// them (a material's group in an engine whose bind groups are all taken, at the
    /// bindings of `volfog::bindings`). They stay the same until the fog is
    /// reconfigured.
    pub fn fog_resources(&self) -> FogResources<'_> {
        FogResources {
            froxels: &self.buffers.froxels,
            integrated: &self.integrated_view,
            tail: &self.buffers.tail,
            view: &self.buffers.view,
            sampler: &self.fog_sampler,
        }
    }

    /// GPU memory of every texture and buffer this object owns (the user's shadow map
    /// and density texture excluded), in bytes.
    pub fn memory_bytes(&self) -> u64 {
        let mut textures = vec![&self.scattering, &self.esm_texture, &self.esm_scratch];
        textures.extend(&self.integrated);
        if let Some(t) = &self.temporal {
            textures.extend(&t.volumes);
        }
        if let Some(d) = self.density.as_ref().filter(|d| !d.user) {
            textures.push(&d.texture);
        }
        if let Some(c) = &self.culling {
            textures.extend(&c.live);
        }
        if let Some(n) = &self.noise {
            textures.push(&n.texture);
        }
        if let Some(c) = self.clouds.as_ref().filter(|c| !c.user) {
            textures.push(&c.map);
        }
        let mut buffers: Vec<&wgpu::Buffer> = self.buffers.all().to_vec();
        if let Some(c) = &self.culling {
            buffers.extend([&c.blocks.blocks, &c.blocks.dispatch]);
        }
        if let Some(t) = &self.temporal {
            buffers.extend(&t.states);
        }
        textures.into_iter().map(texture_bytes).sum::<u64>()
            + buffers.iter().map(|b| b.size()).sum::<u64>()
            + self
                .timestamps
                .as_ref()
                .map(TimestampPairs::buffer_bytes)
                .unwrap_or(0)
    }

    /// Resolves the timestamps of the recorded frame into the readback buffer; call
    /// after `encode` and `record_apply`, before submitting.
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
        Some(PassTimings::from_ms(&ms))
    }
}

fn esm_texture_scratch(device: &wgpu::Device, config: &FogConfig) -> wgpu::Texture {
    esm_texture(
        device,
        "volfog esm scratch",
        config.esm_resolution,
        config.cascades,
    )
}

fn unit_density_texture(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
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
    })
}

/// The error of a texture set for an option the configuration has off.
fn option_off(field: &'static str, what: &str) -> FogError {
    FogError::Invalid(crate::limits::InvalidValue {
        field,
        value: "false".to_string(),
        expected: format!("true to use {what}").into(),
    })
}

fn empty_cloud_map(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("volfog empty cloud map"),
        size: wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// Writes the one texel of a 1x1 R8Unorm texture.
fn write_texel(queue: &wgpu::Queue, texture: &wgpu::Texture, value: u8) {
    queue.write_texture(
        texture.as_image_copy(),
        &[value],
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: None,
            rows_per_image: None,
        },
        texture.size(),
    );
}

fn write_unit_density(queue: &wgpu::Queue, texture: &wgpu::Texture) {
    queue.write_texture(
        texture.as_image_copy(),
        &[255],
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: None,
            rows_per_image: None,
        },
        texture.size(),
    );
}

fn density_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog density"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// The optional textures an inject variant reads.
struct InjectTextures<'a> {
    density: Option<&'a Density>,
    culling: Option<(&'a wgpu::TextureView, &'a wgpu::Buffer)>,
    noise: Option<&'a Noise>,
    clouds: Option<&'a CloudShadow>,
}

fn inject_bind_group(
    device: &wgpu::Device,
    inject: &InjectPass,
    buffers: &Buffers,
    esm: &wgpu::TextureView,
    scattering: &wgpu::TextureView,
    textures: InjectTextures<'_>,
) -> wgpu::BindGroup {
    let InjectTextures {
        density,
        culling,
        noise,
        clouds,
    } = textures;
    let density_view = density.map(|d| view(&d.texture));
    let noise_view = noise.map(|n| view(&n.texture));
    let cloud_view = clouds.map(|c| view(&c.map));
    inject
        .bind_group(
            device,
            &InjectResources {
                froxels: &buffers.froxels,
                frame: &buffers.frame,
                medium: &buffers.medium,
                lighting: &buffers.lighting,
                cascades: &buffers.cascades,
                esm,
                lights: &buffers.lights,
                local_volumes: &buffers.local_volumes,
                scattering,
                density_texture: density_view.as_ref().zip(density.map(|d| &d.sampler)),
                culling,
                noise_texture: noise_view.as_ref().zip(noise.map(|n| &n.sampler)),
                cloud_shadow: clouds
                    .zip(cloud_view.as_ref())
                    .map(|(c, v)| (&c.layer, v, &c.sampler)),
            },
        )
        .expect("the fog binds every texture its inject variant reads")
}
