//! [`StereoFog`]: one fog for the two eyes of a head-mounted display.
//!
//! The work that does not depend on the eye runs once: the shadow maps and their
//! filtering, the local-light shadow atlas, the noise texture, and the density and
//! lighting of world points, injected and temporally stabilised in one volume aligned
//! with a centre eye whose frustum encloses both eyes' frusta
//! ([`centre_eye`](crate::cpu::stereo::centre_eye): the eyes' orientation, the widest of
//! their side planes, the apex just behind them). Each eye then has its own froxel
//! volume: the scan (`VOLFOG_SCAN_RESAMPLE`, one dispatch for both eyes) reads the
//! shared volume trilinearly at the world position of each of the eye's froxels'
//! centres and integrates along the eye's own rays, and each eye's apply reads its own integrated volume, so each eye sees the fog where
//! its camera puts it. Both eyes share the temporal history and so its jitter sequence:
//! they converge alike.
//!
//! What the shared volume cannot hold per eye: the phase function's view direction is
//! the centre eye's, off by at most [`CentreEye::eye_distance`] / d radians at distance
//! d (about 1.3 degrees at 2 m for eyes 64 mm apart with 90-degree frusta), and detail
//! finer than one froxel of the shared grid, e.g. a shadow edge, spreads over about one
//! froxel of it.
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, target: &wgpu::Texture, depth: [&wgpu::TextureView; 2], eyes: [volfog::cpu::stereo::StereoEye; 2]) -> Result<(), volfog::pipeline::FogError> {
//! use volfog::pipeline::{FogConfig, FrameInputs, StereoFog};
//!
//! let mut fog = StereoFog::new(device, &FogConfig::default())?;
//! let apply = fog.shared().create_apply(device, wgpu::TextureFormat::Rgba16Float)?;
//! let depth_groups = depth.map(|d| apply.depth_bind_group(device, d));
//! // every frame, with the eyes' cameras from the XR runtime:
//! let inputs = FrameInputs::new(glam::Mat4::IDENTITY, eyes[0].clip_from_view, 0.0);
//! fog.prepare(queue, &eyes, &inputs)?;
//! let mut encoder = device.create_command_encoder(&Default::default());
//! fog.encode(&mut encoder)?;
//! // `target`: a two-layer array texture, layer 0 the left eye, layer 1 the right.
//! fog.record_apply(&mut encoder, &apply, target, [&depth_groups[0], &depth_groups[1]])?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

use super::{FogConfig, FogError, FogPass, FrameInputs, VolumetricFog, uniform_buffer, view};
use crate::cpu::stereo::{CentreEye, StereoEye, centre_eye};
use crate::limits::{InvalidValue, check};
use crate::pipeline::apply::{ApplyPipeline, FogResources, Tail, fog_bind_group, fog_sampler};
use crate::pipeline::scan::{ResampleEye, ResampleScanResources, ScanPass};
use crate::uniforms::{self, FogView, Froxels, HeightFog, TransientLighting};

mod multiview;

/// One eye's volume and the uniforms its scan and apply read.
#[derive(Debug)]
struct EyeVolume {
    froxels: wgpu::Buffer,
    view: wgpu::Buffer,
    tail: wgpu::Buffer,
    rays: wgpu::Buffer,
    integrated: wgpu::Texture,
    integrated_view: wgpu::TextureView,
    fog_group: wgpu::BindGroup,
    tail_kind: Tail,
}

/// Stereo fog: a shared volume for both eyes and a froxel volume per eye (see the
/// module documentation).
#[derive(Debug)]
pub struct StereoFog {
    config: FogConfig,
    shared: VolumetricFog,
    scan: ScanPass,
    eyes: [EyeVolume; 2],
    /// The scan's bind groups (both eyes) by frame parity: they read the shared
    /// stabilised volume of that parity.
    scan_groups: [wgpu::BindGroup; 2],
    centre: Option<CentreEye>,
    /// Both eyes' fog in one group, for multiview shaders (`multiview.rs`).
    stereo: multiview::StereoGroup,
}

impl StereoFog {
    /// The shared fog and both eyes' volumes for `config` (each eye's volume has
    /// `config.volume_size` froxels from `config.near` to `config.far` of that eye).
    /// Stereo fog neither culls froxels by depth (the shared volume serves both eyes'
    /// depths) nor runs transient lights: `FogConfig::depth_cull` and
    /// `FogConfig::max_transient_lights` are not used, and a frame with transient
    /// lights is an error.
    pub fn new(device: &wgpu::Device, config: &FogConfig) -> Result<Self, FogError> {
        let config = &FogConfig {
            depth_cull: false,
            max_transient_lights: 0,
            ..config.clone()
        };
        let shared = VolumetricFog::new(device, config)?;
        let scan = ScanPass::resampling(device, config.scan_step, false)?;
        let sampler = fog_sampler(device);
        let eyes = [0, 1].map(|i| {
            let name = ["left", "right"][i];
            let buffer = |what: &str, bytes: Vec<u8>| {
                uniform_buffer(device, &format!("volfog stereo {name} {what}"), bytes.len())
            };
            let froxels = buffer("froxels", Froxels::default().to_bytes());
            let view_buffer = buffer("view", uniforms::to_uniform_bytes(&FogView::default()));
            let tail = buffer("tail", HeightFog::none().to_bytes());
            let rays = buffer(
                "rays",
                uniforms::to_uniform_bytes(&TransientLighting::default()),
            );
            let integrated = super::volume_texture(
                device,
                &format!("volfog stereo {name} integrated"),
                config.volume_size,
            );
            let integrated_view = view(&integrated);
            let fog_group = fog_bind_group(
                device,
                &shared.fog_layout,
                config.apply_filtering,
                &FogResources {
                    froxels: &froxels,
                    integrated: &integrated_view,
                    tail: &tail,
                    view: &view_buffer,
                    sampler: &shared.fog_sampler,
                },
            );
            EyeVolume {
                froxels,
                view: view_buffer,
                tail,
                rays,
                integrated,
                integrated_view,
                fog_group,
                tail_kind: Tail::Analytic,
            }
        });
        let scan_groups = [0, 1].map(|p| {
            scan.resample_bind_group(
                device,
                &shared.stabilised_view(p),
                [0, 1].map(|i| ResampleEye {
                    froxels: &eyes[i].froxels,
                    rays: &eyes[i].rays,
                    integrated: &eyes[i].integrated_view,
                    live_slices: None,
                }),
                ResampleScanResources {
                    sampler: &sampler,
                    shared_frame: &shared.buffers.frame,
                    shared_froxels: &shared.buffers.froxels,
                },
            )
            .expect("the resampling scan without culling")
        });
        let stereo = multiview::StereoGroup::new(device, config.apply_filtering, &shared, &eyes);
        Ok(Self {
            config: config.clone(),
            shared,
            scan,
            eyes,
            scan_groups,
            centre: None,
            stereo,
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &FogConfig {
        &self.config
    }

    /// The shared fog: set its shadow map, density texture, cloud map or local-light
    /// shadow maps there, read its timings, create apply pipelines from it. Its own
    /// scan and fog group are not used by stereo fog.
    pub fn shared(&self) -> &VolumetricFog {
        &self.shared
    }

    /// The shared fog, to set its textures (see [`StereoFog::shared`]).
    pub fn shared_mut(&mut self) -> &mut VolumetricFog {
        &mut self.shared
    }

    /// The centre eye of the prepared frame, `None` before the first `prepare`.
    pub fn centre_eye(&self) -> Option<&CentreEye> {
        self.centre.as_ref()
    }

    /// Checks one frame's inputs and uploads them: `eyes` are the left and the right
    /// eye's cameras; the camera of `inputs` (`view_from_world`, `clip_from_view`) is
    /// not read, everything else of it is (the medium, lights, shadows, tail...).
    /// Errors name the field: a non-finite or singular eye matrix, a projection that
    /// is not perspective, eyes whose orientations differ (canted displays), anything
    /// [`VolumetricFog::prepare`] rejects. On error nothing is uploaded.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        eyes: &[StereoEye; 2],
        inputs: &FrameInputs<'_>,
    ) -> Result<(), FogError> {
        let centre = centre_eye(eyes)?;
        check(
            inputs.transient_lights.is_empty(),
            "FrameInputs.transient_lights",
            inputs.transient_lights.len(),
            "none for StereoFog",
        )?;
        let index = self.shared.frames;
        let eye_uniforms = [0, 1].map(|i| {
            FrameInputs {
                view_from_world: eyes[i].view_from_world,
                clip_from_view: eyes[i].clip_from_view,
                ..inputs.clone()
            }
            .uniforms(&self.config, index)
        });
        let [left, right] = eye_uniforms;
        let eye_uniforms = [left?, right?];
        // The shared grid: an eye's view depth z is the centre eye's z + apex_offset,
        // so its slices from near + offset to far + offset lie where the eyes' do.
        let mut shared_config = self.config.clone();
        shared_config.near += centre.apex_offset;
        shared_config.far += centre.apex_offset;
        shared_config.validate()?;
        let previous = std::mem::replace(&mut self.shared.config, shared_config);
        let shared_inputs = FrameInputs {
            view_from_world: centre.view_from_world,
            clip_from_view: centre.clip_from_view,
            ..inputs.clone()
        };
        let prepared = self.shared.prepare(queue, &shared_inputs);
        self.shared.config = previous;
        prepared?;
        for (eye, u) in self.eyes.iter_mut().zip(&eye_uniforms) {
            queue.write_buffer(&eye.froxels, 0, &u.froxels.to_bytes());
            queue.write_buffer(&eye.view, 0, &uniforms::to_uniform_bytes(&u.view));
            queue.write_buffer(&eye.tail, 0, &u.tail.to_bytes());
            queue.write_buffer(&eye.rays, 0, &uniforms::to_uniform_bytes(&u.transient));
            eye.tail_kind = Tail::of(&u.tail);
        }
        self.centre = Some(centre);
        Ok(())
    }

    /// Records the shared passes (shadows, inject, temporal) and both eyes' scans.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), FogError> {
        for pass in FogPass::ALL {
            if pass != FogPass::Scan {
                self.shared.encode_pass(encoder, pass)?;
            }
        }
        self.encode_scans(encoder)
    }

    /// Records both eyes' scans of the shared volume alone (after the shared passes,
    /// e.g. to time them on their own).
    pub fn encode_scans(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), FogError> {
        let index = self.shared.frame_index().ok_or(FogError::NotPrepared)?;
        let parity = (index % 2) as usize;
        let size = self.config.volume_size;
        let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("volfog stereo scan"),
            timestamp_writes: None,
        });
        self.scan
            .encode(&mut compute, &self.scan_groups[parity], [size.x, size.y]);
        Ok(())
    }

    /// The fog group of eye `eye` (0 left, 1 right) at the bindings of
    /// `volfog::bindings` (layout [`VolumetricFog::fog_bind_group_layout`] of the shared
    /// fog): what a forward shader drawing that eye's view reads. Errors on another
    /// index, naming `eye`.
    pub fn eye_fog_bind_group(&self, eye: usize) -> Result<&wgpu::BindGroup, FogError> {
        Ok(&self.eye(eye)?.fog_group)
    }

    /// The integrated volume of eye `eye` (0 left, 1 right).
    pub fn eye_integrated_texture(&self, eye: usize) -> Result<&wgpu::Texture, FogError> {
        Ok(&self.eye(eye)?.integrated)
    }

    fn eye(&self, eye: usize) -> Result<&EyeVolume, FogError> {
        self.eyes.get(eye).ok_or_else(|| {
            FogError::Invalid(InvalidValue {
                field: "StereoFog eye",
                value: eye.to_string(),
                expected: "0 (left) or 1 (right)".into(),
            })
        })
    }

    /// Blends each eye's fog onto its layer of `target`, a two-layer array texture
    /// (layer 0 the left eye, layer 1 the right, as an XR swapchain image holds them),
    /// with that eye's scene depth group (from [`ApplyPipeline::depth_bind_group`]).
    /// Errors when `target` has fewer than two layers.
    pub fn record_apply(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &ApplyPipeline,
        target: &wgpu::Texture,
        depth_groups: [&wgpu::BindGroup; 2],
    ) -> Result<(), FogError> {
        if target.depth_or_array_layers() < 2 {
            return Err(FogError::Texture {
                texture: "the stereo target",
                property: "array layers",
                found: target.depth_or_array_layers().to_string(),
                expected: "2 or more (layer 0 the left eye, layer 1 the right)".into(),
            });
        }
        self.record_apply_eyes(encoder, apply, [target, target], [0, 1], depth_groups)
    }

    /// Blends each eye's fog onto a layer of a target of its own (`targets[i]` layer
    /// `layers[i]` for eye i). Errors, naming the texture and property, when the two
    /// targets' sizes differ (both eyes render at one resolution) or a layer does not
    /// exist.
    pub fn record_apply_eyes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &ApplyPipeline,
        targets: [&wgpu::Texture; 2],
        layers: [u32; 2],
        depth_groups: [&wgpu::BindGroup; 2],
    ) -> Result<(), FogError> {
        self.check_apply(apply)?;
        let size = |t: &wgpu::Texture| (t.width(), t.height());
        if size(targets[1]) != size(targets[0]) {
            return Err(FogError::Texture {
                texture: "the right eye's target",
                property: "size",
                found: format!("{:?}", size(targets[1])),
                expected: format!("the left eye's, {:?}", size(targets[0])),
            });
        }
        for (i, (t, layer)) in targets.iter().zip(layers).enumerate() {
            if layer >= t.depth_or_array_layers() {
                return Err(FogError::Texture {
                    texture: ["the left eye's target", "the right eye's target"][i],
                    property: "array layer",
                    found: layer.to_string(),
                    expected: format!("below its {} layers", t.depth_or_array_layers()),
                });
            }
        }
        for (i, eye) in self.eyes.iter().enumerate() {
            let color = targets[i].create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layers[i],
                array_layer_count: Some(1),
                ..Default::default()
            });
            apply.record_tail(
                encoder,
                &color,
                &eye.fog_group,
                depth_groups[i],
                None,
                eye.tail_kind,
            );
        }
        Ok(())
    }

    fn check_apply(&self, apply: &ApplyPipeline) -> Result<(), FogError> {
        if apply.filtering() != self.config.apply_filtering {
            return Err(FogError::ApplyMismatch {
                pipeline: apply.filtering(),
                fog: self.config.apply_filtering,
            });
        }
        self.shared
            .frame_index()
            .map(|_| ())
            .ok_or(FogError::NotPrepared)
    }
}

impl VolumetricFog {
    /// The volume a scan of frame parity `parity` reads: the stabilised volume of that
    /// parity, or the scattering volume without temporal reprojection.
    fn stabilised_view(&self, parity: usize) -> wgpu::TextureView {
        match &self.temporal {
            Some(t) => t.views[parity].clone(),
            None => view(&self.scattering),
        }
    }
}
