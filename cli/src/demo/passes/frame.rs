//! One frame of the demo: its camera, scene uniform and shadow cascades
//! (`FrameSetup`), its passes in order (the lamp passed to the fog as a shadowed
//! light), and their GPU times in `PASS_NAMES` order.

use glam::{Mat4, Vec3, Vec4};
use volfog::pipeline::clouds::CloudDraw;
use volfog::pipeline::{FrameInputs, PassTimings};
use volfog::uniforms::{CloudLayer, FrustumRays, ShadowCascades};

use super::{DEMO_PASSES, Demo, SceneUniform};
use crate::demo::DemoError;
use crate::demo::scene::{self, FOV_Y};

/// Seconds between frames (fog animation).
const FRAME_TIME: f32 = 1.0 / 24.0;
/// Number of timed passes.
pub const PASS_COUNT: usize = 12;
/// Names of every timed pass, in frame order.
pub const PASS_NAMES: [&str; PASS_COUNT] = [
    "shadow maps",
    "lamp shadow map",
    "opaque + sky",
    "froxel cull",
    "esm downsample",
    "esm blur",
    "local shadows",
    "inject + temporal",
    "scan",
    "fog apply",
    "transparent",
    "tonemap",
];

/// Per-pass GPU milliseconds of one frame, in `PASS_NAMES` order.
fn frame_times(
    fog: Option<PassTimings>,
    demo: Option<[f64; DEMO_PASSES.len()]>,
) -> Option<[f64; PASS_COUNT]> {
    let (f, d) = (fog?, demo?);
    Some([
        d[0],
        d[1],
        d[2],
        f.cull,
        f.esm_downsample,
        f.esm_blur,
        f.local_shadows,
        // The demo's fog blends the history inside inject (FogConfig::fuse_temporal).
        f.inject + f.temporal,
        f.scan,
        f.apply,
        d[3],
        d[4],
    ])
}

/// One frame's camera, scene uniform and shadow cascades.
pub struct FrameSetup {
    /// The camera's corner rays (the clouds' passes).
    pub rays: FrustumRays,
    /// The cloud layer at this frame's time.
    pub clouds: CloudLayer,
    /// The froxel fog is applied fullscreen (false for the camera under water, whose
    /// view rays start in the water: the opaque pass fogs what lies beyond the
    /// surface with the medium's analytic height fog instead).
    pub froxel_apply: bool,
    pub eye: Vec3,
    pub view_from_world: Mat4,
    pub time: f32,
    pub uniform: SceneUniform,
    pub cascades: ShadowCascades,
}

impl Demo<'_> {
    /// Camera, uniforms and cascades of frame `frame` along the camera path.
    pub fn setup(&self, frame: u32) -> FrameSetup {
        let frames = self.args.frames;
        let t = if frames > 1 {
            frame as f32 / (frames - 1) as f32
        } else {
            1.0
        };
        self.setup_camera(frame, scene::camera(t))
    }

    /// Uniforms and cascades of frame `frame` seen by the camera `(eye, view_from_world)`.
    pub fn setup_camera(&self, frame: u32, (eye, view_from_world): (Vec3, Mat4)) -> FrameSetup {
        let aspect = self.args.width as f32 / self.args.height as f32;
        let (cascades, texels) = scene::fit_cascades(
            view_from_world.inverse(),
            FOV_Y.to_radians(),
            aspect,
            self.config.near,
            self.splits,
            self.config.cascades,
            self.scene.sun.direction,
            self.config.esm_resolution * 4,
            self.config.esm_exponent,
        );
        let clip_from_world = self.clip_from_view * view_from_world;
        let uniform = SceneUniform {
            clip_from_world,
            view_from_world,
            world_from_clip: clip_from_world.inverse(),
            shadow_texel: Vec4::from_array(texels),
            camera_position: eye,
            surface_scale: 1.0,
            sun_direction: self.scene.sun.direction,
            light_count: self.scene.lights.len() as u32,
            sun_color: self.scene.sun.color,
            sun_disk: 40.0,
            sky_zenith: self.scene.sky_zenith,
            sky_horizon: self.scene.ambient_sky,
            glass_alpha: 0.3,
            ambient_ground: self.scene.ambient_ground,
            shadow_bias: 2e-4,
            water: self.scene.water,
            air: self.scene.air,
            atmosphere: self.scene.atmosphere,
            pool_min: scene::POOL_MIN.extend(1.0),
            pool_max: scene::POOL_MAX.extend(0.0),
            lamp_position: self.scene.lights[self.scene.lamp.light as usize].position,
            lamp_index: self.scene.lamp.light,
        };
        let time = 3.0 + frame as f32 * FRAME_TIME;
        FrameSetup {
            rays: FrustumRays::new(view_from_world.inverse(), self.clip_from_view)
                .expect("the demo's camera is a perspective camera"),
            clouds: CloudLayer {
                time,
                ..self.scene.clouds
            },
            froxel_apply: !scene::in_pool(eye),
            eye,
            view_from_world,
            time,
            uniform,
            cascades,
        }
    }

    /// The lit opaque pass and sky of `setup` with the pool dry (the probe's reference
    /// for the water), read back.
    pub fn dry_surface(&self, setup: &FrameSetup) -> Result<Vec<Vec4>, DemoError> {
        let dry = SceneUniform {
            pool_min: setup.uniform.pool_min.truncate().extend(0.0),
            ..setup.uniform
        };
        self.renderer
            .upload(&self.gpu.queue, &dry, &setup.cascades, self.args.exposure);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.renderer.encode_opaque(&mut encoder, false);
        self.gpu.queue.submit([encoder.finish()]);
        Ok(self.gpu.read_texture_rgba16f(&self.renderer.hdr)?)
    }

    /// Renders one frame and returns its per-pass GPU times, if measured.
    pub fn render(
        &mut self,
        setup: &FrameSetup,
        probe: bool,
    ) -> Result<Option<[f64; PASS_COUNT]>, DemoError> {
        let (gpu, scene) = (&self.gpu, &self.scene);
        self.renderer.upload(
            &gpu.queue,
            &setup.uniform,
            &setup.cascades,
            self.args.exposure,
        );
        self.fog.prepare(
            &gpu.queue,
            &FrameInputs {
                medium: scene.medium,
                sun: scene.sun,
                ambient: scene.ambient(),
                lights: &scene.lights,
                shadowed_lights: &self.shadowed_lights,
                local_volumes: &scene.local_volumes,
                particles: &scene::smoke(setup.time),
                cascades: setup.cascades,
                clouds: setup.clouds,
                ..FrameInputs::new(setup.view_from_world, self.clip_from_view, setup.time)
            },
        )?;
        self.clouds
            .prepare(&gpu.queue, &setup.rays, &setup.clouds)?;
        let probe = self.probe_textures.as_ref().filter(|_| probe);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.renderer.encode_shadows(&mut encoder);
        self.renderer.encode_lamp_shadow(&mut encoder);
        self.renderer.encode_opaque(&mut encoder, true);
        self.fog.encode(&mut encoder)?;
        if let Some([surface, _, _]) = probe {
            self.renderer.copy_hdr(&mut encoder, surface);
        }
        if setup.froxel_apply {
            // The clouds' shadow on the lit scene, then the distance clouds.
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("demo clouds"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: self.renderer.hdr_view(),
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.clouds
                .draw(&mut pass, &self.cloud_group, CloudDraw::Shadow);
            self.clouds
                .draw(&mut pass, &self.cloud_group, CloudDraw::Distance);
        }
        if let Some([_, clouded, _]) = probe {
            self.renderer.copy_hdr(&mut encoder, clouded);
        }
        if setup.froxel_apply {
            self.fog.record_apply(
                &mut encoder,
                &self.apply,
                self.renderer.hdr_view(),
                &self.depth_group,
            )?;
        }
        if let Some([_, _, fogged]) = probe {
            self.renderer.copy_hdr(&mut encoder, fogged);
        }
        self.renderer.encode_transparent(&mut encoder, &self.fog);
        self.renderer.encode_tonemap(&mut encoder);
        self.fog.resolve_timestamps(&mut encoder);
        self.renderer.resolve_timestamps(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let fog_times = self.fog.read_timings(&gpu.device, &gpu.queue);
        let demo_times = self.renderer.read_timings(&gpu.device, &gpu.queue);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| DemoError::Pipeline(e.to_string()))?;
        Ok(frame_times(fog_times, demo_times))
    }
}
