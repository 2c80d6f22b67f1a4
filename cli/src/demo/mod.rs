//! `volfog demo`: renders the demo scene headless with the real `VolumetricFog`
//! pipeline and writes PNGs.
//!
//! Once: the sky texture for the sun (`volfog::sky`, sky_solve). Per frame: shadow
//! cascades (depth-only, one pass per layer) -> lit opaque pass and sky (sampled from
//! the sky texture, the phase per pixel) -> the clouds' shadow on the lit scene and the
//! distance clouds (`volfog::clouds`) -> fog prepare/encode (its sun term under the same
//! cloud shadow) (froxel culling by this frame's depth buffer, ESM
//! downsample, blur, inject, temporal, scan) -> fullscreen fog apply -> semi-transparent sphere fogged by the forward snippet ->
//! tonemap. The camera moves along a short path so the temporal reprojection works on
//! a moving view; the last frame is written as `DIR/demo.png`. The pool's water
//! (`volfog::water`) is shaded in the opaque pass; then a second camera under water
//! renders `DIR/underwater.png` (the froxel apply is skipped there: the opaque pass
//! fogs what lies beyond the surface with the medium's analytic height fog).
//!
//! `--probe` also writes `DIR/probe/`: linear float images of the last frame (before
//! the apply, after it, after the transparent pass, and with every surface black, which
//! leaves only the fog's in-scattering), the depth buffer, and `probe.json` (camera,
//! pass list, timings, volume statistics) for tests.

mod render;
mod scene;

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Mat4, UVec3, Vec3, Vec4};
use serde_json::json;
use volfog::limits::InvalidValue;
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::clouds::{CloudDraw, CloudPasses, cloud_map_texture};
use volfog::pipeline::sky::SkyLight;
use volfog::pipeline::{
    FogConfig, FogError, FrameInputs, PassTimings, VolumetricFog, cascade_splits,
};
use volfog::uniforms::{CloudLayer, FrustumRays, ShadowCascades};
use volfog_testkit::{Gpu, GpuError};

use render::{HDR_FORMAT, Renderer, SceneUniform};

/// Options of `volfog demo`.
#[derive(Debug, Clone, clap::Args)]
pub struct DemoArgs {
    /// Destination folder (created); the final frame is DIR/demo.png.
    #[arg(long, short)]
    pub out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1920)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 1080)]
    pub height: u32,
    /// Frames of the camera path (the last one is written).
    #[arg(long, default_value_t = 12)]
    pub frames: u32,
    /// Froxel volume size, WxHxD.
    #[arg(long, default_value = "160x90x128", value_parser = parse_volume)]
    pub volume: UVec3,
    /// Exposure applied before the tonemap.
    #[arg(long, default_value_t = 0.6)]
    pub exposure: f32,
    /// Also write every frame as DIR/frames/frame_NNN.png.
    #[arg(long)]
    pub save_frames: bool,
    /// Also write linear float images and probe.json of the last frame to DIR/probe.
    #[arg(long)]
    pub probe: bool,
}

fn parse_volume(s: &str) -> Result<UVec3, String> {
    let parts: Vec<&str> = s.split('x').collect();
    let values: Result<Vec<u32>, _> = parts.iter().map(|p| p.trim().parse::<u32>()).collect();
    match values {
        Ok(v) if v.len() == 3 => Ok(UVec3::new(v[0], v[1], v[2])),
        _ => Err(format!("expected WxHxD (e.g. 160x90x128), got {s:?}")),
    }
}

/// Errors of the demo.
#[derive(Debug, thiserror::Error)]
pub enum DemoError {
    /// An option is out of range.
    #[error("{0}")]
    Args(String),
    /// No adapter or device.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The fog pipeline refused the configuration or a frame's inputs.
    #[error(transparent)]
    Fog(#[from] FogError),
    /// A scene value is invalid.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// A demo shader or pipeline failed.
    #[error("demo pipeline: {0}")]
    Pipeline(String),
    /// Writing an output file failed.
    #[error("writing {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The reason.
        message: String,
    },
}

const FOV_Y: f32 = 55.0;
const NEAR: f32 = 0.1;
const FAR: f32 = 500.0;
/// Seconds between frames (fog animation).
const FRAME_TIME: f32 = 1.0 / 24.0;
/// Names of every timed pass, in frame order.
const PASS_NAMES: [&str; 11] = [
    "shadow maps",
    "opaque + sky",
    "froxel cull",
    "esm downsample",
    "esm blur",
    "inject",
    "temporal",
    "scan",
    "fog apply",
    "transparent",
    "tonemap",
];

/// The fog configuration of the demo. The ESM is 512 texels per cascade with a
/// 3-tap blur: an exponential shadow map erodes occluders by its filter footprint
/// (any unoccluded texel far behind the receiver dominates the filtered exponential),
/// and the pillars must keep their shadows in the farther cascades. Log-space
/// filtering allows the exponent of 200 (a leak band of 1.5 % of a cascade's depth
/// range).
fn fog_config(args: &DemoArgs, timestamps: bool) -> FogConfig {
    FogConfig {
        volume_size: args.volume,
        near: 0.5,
        far: 128.0,
        slice_curve: 4.0,
        esm_resolution: 512,
        cascades: 4,
        esm_exponent: 200.0,
        esm_log_space: true,
        esm_blur_radius: 1,
        max_lights: 8,
        max_local_volumes: 4,
        noise_octaves: 2,
        cloud_shadow: true,
        timestamps,
        ..FogConfig::default()
    }
}

/// Per-pass GPU milliseconds of one frame, in `PASS_NAMES` order.
fn frame_times(
    fog: Option<PassTimings>,
    demo: Option<[f64; render::DEMO_PASSES.len()]>,
) -> Option<[f64; 11]> {
    let (f, d) = (fog?, demo?);
    Some([
        d[0],
        d[1],
        f.cull,
        f.esm_downsample,
        f.esm_blur,
        f.inject,
        f.temporal,
        f.scan,
        f.apply,
        d[2],
        d[3],
    ])
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

fn write_error(path: &Path, e: impl std::fmt::Display) -> DemoError {
    DemoError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), DemoError> {
    let file = std::fs::File::create(path).map_err(|e| write_error(path, e))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(|e| write_error(path, e))?;
    writer
        .write_image_data(rgba)
        .map_err(|e| write_error(path, e))?;
    writer.finish().map_err(|e| write_error(path, e))
}

fn write_f32(path: &Path, values: &[f32]) -> Result<(), DemoError> {
    std::fs::write(path, bytemuck::cast_slice(values)).map_err(|e| write_error(path, e))
}

fn flat(v: &[Vec4]) -> Vec<f32> {
    v.iter().flat_map(|t| t.to_array()).collect()
}

fn check_args(args: &DemoArgs) -> Result<(), DemoError> {
    if args.width == 0 || args.height == 0 || args.width > 8192 || args.height > 8192 {
        return Err(DemoError::Args(format!(
            "--width and --height must be 1..=8192, got {}x{}",
            args.width, args.height
        )));
    }
    if args.frames == 0 {
        return Err(DemoError::Args("--frames must be at least 1".to_string()));
    }
    if !(args.exposure.is_finite() && args.exposure > 0.0) {
        return Err(DemoError::Args(format!(
            "--exposure must be a finite value > 0, got {}",
            args.exposure
        )));
    }
    Ok(())
}

/// One frame's camera, scene uniform and shadow cascades.
struct FrameSetup {
    /// The camera's corner rays (the clouds' passes).
    rays: FrustumRays,
    /// The cloud layer at this frame's time.
    clouds: CloudLayer,
    /// The froxel fog is applied fullscreen (false for the camera under water, whose
    /// view rays start in the water: the opaque pass fogs what lies beyond the
    /// surface with the medium's analytic height fog instead).
    froxel_apply: bool,
    eye: Vec3,
    view_from_world: Mat4,
    time: f32,
    uniform: SceneUniform,
    cascades: ShadowCascades,
}

/// Everything the demo holds while it renders.
struct Demo<'a> {
    args: &'a DemoArgs,
    gpu: Gpu,
    scene: scene::Scene,
    config: FogConfig,
    fog: VolumetricFog,
    renderer: Renderer,
    apply: ApplyPipeline,
    depth_group: wgpu::BindGroup,
    clip_from_view: Mat4,
    splits: Vec4,
    /// Copies of the HDR target before and after the apply (with `--probe`).
    probe_textures: Option<[wgpu::Texture; 3]>,
    /// The sky light, solved once for the scene's sun.
    sky: SkyLight,
    /// The cloud passes (shadow on the lit scene, distance clouds), their map and bind
    /// group.
    clouds: CloudPasses,
    cloud_group: wgpu::BindGroup,
}

impl<'a> Demo<'a> {
    fn new(args: &'a DemoArgs) -> Result<Self, DemoError> {
        let gpu = Gpu::with_features(wgpu::Features::TIMESTAMP_QUERY)?;
        let timestamps = gpu
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY);
        println!("adapter: {}", gpu.describe());
        println!(
            "rendering {}x{}, {} frames, froxel volume {}x{}x{}{}",
            args.width,
            args.height,
            args.frames,
            args.volume.x,
            args.volume.y,
            args.volume.z,
            if timestamps {
                ""
            } else {
                " (no TIMESTAMP_QUERY: no GPU times)"
            }
        );
        let scene = scene::build()?;
        let config = fog_config(args, timestamps);
        let mut fog = VolumetricFog::new(&gpu.device, &config)?;
        let mut sky = SkyLight::new(&gpu.device, HDR_FORMAT)
            .map_err(|e| DemoError::Pipeline(e.to_string()))?;
        sky.set_atmosphere(scene.atmosphere)?;
        let renderer = gpu
            .checked(|| {
                Renderer::new(
                    &gpu.device,
                    args.width,
                    args.height,
                    &scene,
                    &fog,
                    &sky,
                    timestamps,
                )
            })
            .map_err(|e| DemoError::Pipeline(e.to_string()))?
            .map_err(DemoError::Pipeline)?;
        fog.set_shadow_map(&gpu.device, renderer.shadow_map())?;
        // The opaque pass lays the depth out before the fog runs, so the fog culls the
        // froxels behind this frame's opaque surfaces.
        fog.set_scene_depth(&gpu.device, &renderer.depth, 0)?;
        // The sky for the scene's (fixed) sun, solved once; the cloud map for the
        // clouds' passes and for the fog's cloud shadow.
        let aspect0 = args.width as f32 / args.height as f32;
        let proj0 =
            glam::camera::rh::proj::directx::perspective(FOV_Y.to_radians(), aspect0, NEAR, FAR);
        sky.prepare(&gpu.queue, &FrustumRays::new(Mat4::IDENTITY, proj0)?, 64)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        sky.encode_solve(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let size = (scene::CLOUD_MAP_SIZE, scene::CLOUD_MAP_SIZE);
        let cloud_map = cloud_map_texture(&gpu.device, &gpu.queue, size, &scene.cloud_map)?;
        fog.set_cloud_map(&gpu.device, &cloud_map)?;
        let clouds = CloudPasses::new(&gpu.device, HDR_FORMAT)
            .map_err(|e| DemoError::Pipeline(e.to_string()))?;
        let cloud_group = clouds.bind_group(
            &gpu.device,
            &cloud_map.create_view(&Default::default()),
            renderer.depth_view(),
        );
        let apply = fog.create_apply(&gpu.device, HDR_FORMAT)?;
        let depth_group = apply.depth_bind_group(&gpu.device, renderer.depth_view());
        println!(
            "fog pipeline: {:.1} MiB of GPU memory; sky {:.0} KiB",
            fog.memory_bytes() as f64 / (1024.0 * 1024.0),
            sky.memory_bytes() as f64 / 1024.0
        );
        let aspect = args.width as f32 / args.height as f32;
        let clip_from_view =
            glam::camera::rh::proj::directx::perspective(FOV_Y.to_radians(), aspect, NEAR, FAR);
        let splits = cascade_splits(config.cascades, config.near, config.far, 0.7);
        let probe_textures = args.probe.then(|| {
            [
                renderer.hdr_like(&gpu.device, "probe surface"),
                renderer.hdr_like(&gpu.device, "probe clouded"),
                renderer.hdr_like(&gpu.device, "probe fogged"),
            ]
        });
        Ok(Self {
            args,
            gpu,
            scene,
            config,
            fog,
            renderer,
            apply,
            depth_group,
            clip_from_view,
            splits,
            probe_textures,
            sky,
            clouds,
            cloud_group,
        })
    }

    /// Camera, uniforms and cascades of frame `frame` along the camera path.
    fn setup(&self, frame: u32) -> FrameSetup {
        let frames = self.args.frames;
        let t = if frames > 1 {
            frame as f32 / (frames - 1) as f32
        } else {
            1.0
        };
        self.setup_camera(frame, scene::camera(t))
    }

    /// Uniforms and cascades of frame `frame` seen by the camera `(eye, view_from_world)`.
    fn setup_camera(&self, frame: u32, (eye, view_from_world): (Vec3, Mat4)) -> FrameSetup {
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
    fn dry_surface(&self, setup: &FrameSetup) -> Result<Vec<Vec4>, DemoError> {
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
    fn render(&mut self, setup: &FrameSetup, probe: bool) -> Result<Option<[f64; 11]>, DemoError> {
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
                local_volumes: &scene.local_volumes,
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

/// Runs the demo.
pub fn run(args: &DemoArgs) -> Result<(), DemoError> {
    check_args(args)?;
    let started = Instant::now();
    std::fs::create_dir_all(&args.out).map_err(|e| write_error(&args.out, e))?;
    let frames_dir = args.out.join("frames");
    if args.save_frames {
        std::fs::create_dir_all(&frames_dir).map_err(|e| write_error(&frames_dir, e))?;
    }
    let mut demo = Demo::new(args)?;
    let mut times: Vec<[f64; 11]> = Vec::new();
    let mut last = None;
    for frame in 0..args.frames {
        let frame_started = Instant::now();
        let is_last = frame + 1 == args.frames;
        let setup = demo.setup(frame);
        let frame_ms = demo.render(&setup, is_last)?;
        times.extend(frame_ms);
        let mut line = format!(
            "frame {:>3}/{}  camera ({:+.2}, {:.2}, {:+.2})  wall {:>7.1} ms",
            frame + 1,
            args.frames,
            setup.eye.x,
            setup.eye.y,
            setup.eye.z,
            frame_started.elapsed().as_secs_f64() * 1e3
        );
        if let Some(ms) = frame_ms {
            line += &format!("  GPU {:>7.1} ms", ms.iter().sum::<f64>());
        }
        println!("{line}");
        if args.save_frames || is_last {
            let rgba = demo.gpu.read_texture_raw(&demo.renderer.ldr, 4)?;
            if args.save_frames {
                let path = frames_dir.join(format!("frame_{frame:03}.png"));
                write_png(&path, args.width, args.height, &rgba)?;
            }
            if is_last {
                last = Some((rgba, setup));
            }
        }
    }
    let (rgba, setup) = last.expect("at least one frame");
    let png_path = args.out.join("demo.png");
    write_png(&png_path, args.width, args.height, &rgba)?;

    print_timings(&times, args.frames);
    if !times.is_empty() && demo.gpu.info.device_type == wgpu::DeviceType::Cpu {
        println!(
            "  (a software adapter: its timestamps are CPU clock readings and can miss\n   \
             work it runs asynchronously, notably compute dispatches; the wall time per\n   \
             frame above is the reliable figure)"
        );
    }
    if let Some(live) = volfog_testkit::scene::live_fraction(&demo.gpu, &demo.fog)? {
        println!(
            "depth culling: {:.1} % of the froxels live in the last frame",
            100.0 * live
        );
    }
    if demo.probe_textures.is_some() {
        write_probe(&mut demo, &setup, &times)?;
    }
    render_underwater(&mut demo)?;
    println!(
        "wrote {} ({:.1} s)",
        png_path.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Frames the second camera renders (the first reprojects the main camera's history).
const UNDERWATER_FRAMES: u32 = 2;

/// The second camera, under water in the pool: `DIR/underwater.png`, and with
/// `--probe` its linear images (`underwater_surface.f32` the lit opaque pass and sky
/// seen through the water, `underwater_dry.f32` the same with the pool dry,
/// `underwater_water.f32` with every surface black (the in-scattering of the water,
/// and beyond the surface of the air), `underwater_final.f32`,
/// `underwater_depth.f32`) and `underwater.json`.
fn render_underwater(demo: &mut Demo<'_>) -> Result<(), DemoError> {
    let mut setup = None;
    for k in 0..UNDERWATER_FRAMES {
        let frame = demo.args.frames + k;
        let s = demo.setup_camera(frame, scene::underwater_camera());
        demo.render(&s, k + 1 == UNDERWATER_FRAMES)?;
        setup = Some(s);
    }
    let setup = setup.expect("at least one frame");
    let (args, gpu) = (demo.args, &demo.gpu);
    let rgba = gpu.read_texture_raw(&demo.renderer.ldr, 4)?;
    let png_path = args.out.join("underwater.png");
    write_png(&png_path, args.width, args.height, &rgba)?;
    println!("wrote {} (the camera under water)", png_path.display());
    let Some([surface, _, _]) = demo.probe_textures.as_ref() else {
        return Ok(());
    };
    let dir = args.out.join("probe");
    let surface_hdr = gpu.read_texture_rgba16f(surface)?;
    let final_hdr = gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    let depth_raw = gpu.read_texture_raw(&demo.renderer.depth, 4)?;
    let dry = demo.dry_surface(&setup)?;
    let black = SceneUniform {
        surface_scale: 0.0,
        ..setup.uniform
    };
    demo.renderer
        .upload(&gpu.queue, &black, &setup.cascades, args.exposure);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    demo.renderer.encode_opaque(&mut encoder, false);
    gpu.queue.submit([encoder.finish()]);
    let water_hdr = gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    for (name, data) in [
        ("underwater_water.f32", flat(&water_hdr)),
        ("underwater_surface.f32", flat(&surface_hdr)),
        ("underwater_dry.f32", flat(&dry)),
        ("underwater_final.f32", flat(&final_hdr)),
        (
            "underwater_depth.f32",
            bytemuck::cast_slice(&depth_raw).to_vec(),
        ),
    ] {
        write_f32(&dir.join(name), &data)?;
    }
    let info = json!({
        "camera": {
            "position": setup.uniform.camera_position.to_array(),
            "world_from_clip": setup.uniform.world_from_clip.to_cols_array().to_vec(),
        },
        "water": water_json(&demo.scene.water),
    });
    let path = dir.join("underwater.json");
    let text = serde_json::to_string_pretty(&info).map_err(|e| write_error(&path, e))?;
    std::fs::write(&path, text).map_err(|e| write_error(&path, e))?;
    Ok(())
}

/// The pool's water and footprint for the probe files.
fn water_json(water: &volfog::uniforms::Water) -> serde_json::Value {
    json!({
        "uniform": water,
        "pool_min": scene::POOL_MIN.to_array(),
        "pool_max": scene::POOL_MAX.to_array(),
    })
}

fn print_timings(times: &[[f64; 11]], frames: u32) {
    if times.is_empty() {
        println!("per-pass GPU times: unavailable (the adapter lacks TIMESTAMP_QUERY)");
        return;
    }
    // The first frame pays for pipeline compilation and first use: leave it out when
    // there are others.
    let measured = if times.len() > 1 { &times[1..] } else { times };
    println!(
        "\nper-pass GPU time, median of {} frame(s) (of {frames}):",
        measured.len()
    );
    println!(
        "  {:<16} {:>10} {:>10} {:>10}",
        "pass", "median ms", "min ms", "max ms"
    );
    let mut total = 0.0;
    for (i, name) in PASS_NAMES.iter().enumerate() {
        let mut v: Vec<f64> = measured.iter().map(|t| t[i]).collect();
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = v.iter().copied().fold(0.0, f64::max);
        let m = median(&mut v);
        total += m;
        println!("  {name:<16} {m:>10.3} {min:>10.3} {max:>10.3}");
    }
    println!("  {:<16} {:>10.3}", "total", total);
}

fn write_probe(
    demo: &mut Demo<'_>,
    setup: &FrameSetup,
    times: &[[f64; 11]],
) -> Result<(), DemoError> {
    let final_hdr = demo.gpu.read_texture_rgba16f(&demo.renderer.hdr)?;
    let dry_hdr = demo.dry_surface(setup)?;
    let Demo {
        args,
        gpu,
        renderer,
        fog,
        apply,
        depth_group,
        clip_from_view,
        scene,
        probe_textures,
        sky,
        ..
    } = demo;
    let [surface, clouded, fogged] = probe_textures.as_ref().expect("called with --probe");
    let (uniform, cascades, clip_from_view, medium) = (
        &setup.uniform,
        &setup.cascades,
        *clip_from_view,
        &scene.medium,
    );
    let dir = args.out.join("probe");
    std::fs::create_dir_all(&dir).map_err(|e| write_error(&dir, e))?;
    let surface_hdr = gpu.read_texture_rgba16f(surface)?;
    let fogged_hdr = gpu.read_texture_rgba16f(fogged)?;
    let clouded_hdr = gpu.read_texture_rgba16f(clouded)?;
    let depth_raw = gpu.read_texture_raw(&renderer.depth, 4)?;
    let depth: Vec<f32> = bytemuck::cast_slice(&depth_raw).to_vec();

    // Black surfaces under the same fog volume: what remains is the in-scattering.
    let black = SceneUniform {
        surface_scale: 0.0,
        ..*uniform
    };
    renderer.upload(&gpu.queue, &black, cascades, args.exposure);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode_opaque(&mut encoder, false);
    gpu.queue.submit([encoder.finish()]);
    // Before the air's fog: only the pool's underwater in-scattering remains.
    let water_hdr = gpu.read_texture_rgba16f(&renderer.hdr)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.record_apply(&mut encoder, apply, renderer.hdr_view(), depth_group)?;
    gpu.queue.submit([encoder.finish()]);
    let inscatter_hdr = gpu.read_texture_rgba16f(&renderer.hdr)?;

    let integrated = gpu.read_texture_rgba16f(fog.integrated_texture())?;
    let size = fog.config().volume_size;
    let last_slice = &integrated[((size.z - 1) * size.x * size.y) as usize..];
    let mean_far_t =
        last_slice.iter().map(|t| f64::from(t.w)).sum::<f64>() / last_slice.len() as f64;
    let finite_volume = integrated.iter().all(|t| t.is_finite());
    let esm_raw = gpu.read_texture_raw(fog.esm_texture(), 4)?;
    let esm: &[f32] = bytemuck::cast_slice(&esm_raw);
    let (esm_min, esm_max) = esm
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });

    for (name, data) in [
        ("surface.f32", flat(&surface_hdr)),
        ("surface_dry.f32", flat(&dry_hdr)),
        ("clouded.f32", flat(&clouded_hdr)),
        ("cloud_map.f32", scene.cloud_map.clone()),
        ("fogged.f32", flat(&fogged_hdr)),
        ("final.f32", flat(&final_hdr)),
        ("inscatter.f32", flat(&inscatter_hdr)),
        ("water.f32", flat(&water_hdr)),
        ("depth.f32", depth),
        ("integrated.f32", flat(&integrated)),
        ("esm.f32", esm.to_vec()),
    ] {
        write_f32(&dir.join(name), &data)?;
    }
    let measured = if times.len() > 1 { &times[1..] } else { times };
    let passes: Vec<serde_json::Value> = PASS_NAMES
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let mut v: Vec<f64> = measured.iter().map(|t| t[i]).collect();
            json!({
                "name": name,
                "frames_with_gpu_time": times.iter().filter(|t| t[i] > 0.0).count(),
                "gpu_ms_median": if v.is_empty() { None } else { Some(median(&mut v)) },
                "gpu_ms_min": v.iter().copied().reduce(f64::min),
            })
        })
        .collect();
    let mat = |m: glam::Mat4| m.to_cols_array().to_vec();
    let info = json!({
        "width": args.width,
        "height": args.height,
        "frames": args.frames,
        "adapter": gpu.describe(),
        "timestamps": !times.is_empty(),
        "images": {
            "layout": "rgba f32 little-endian, rows top to bottom; depth.f32: one f32 per pixel (depth buffer, 0 near .. 1 far)",
            "surface": "surface.f32: lit opaque pass and sky before the fog (alpha: sun visibility of the surface, 1 for the sky), seen through the pool's water",
            "surface_dry": "surface_dry.f32: the same with the pool dry",
            "clouded": "clouded.f32: after the clouds' shadow and the distance clouds, before the fog",
            "cloud_map": "cloud_map.f32: the cloud density map, one f32 per texel, rows of cloud_map_size",
            "fogged": "fogged.f32: after the fullscreen fog apply (alpha kept)",
            "final": "final.f32: after the semi-transparent pass, before the tonemap",
            "inscatter": "inscatter.f32: every surface and the sky black, then the fog applied: the in-scattered radiance",
            "water": "water.f32: every surface and the sky black, before the fog: the pool's underwater in-scattering",
            "integrated": "integrated.f32: the integrated froxel volume (rgb in-scatter, a transmittance), x fastest, then y, then z",
            "esm": "esm.f32: the filtered ESM, one esm_resolution^2 layer per cascade",
        },
        "camera": {
            "position": uniform.camera_position.to_array(),
            "view_from_world": mat(uniform.view_from_world),
            "clip_from_view": mat(clip_from_view),
            "world_from_clip": mat(uniform.world_from_clip),
        },
        "sun_direction": uniform.sun_direction.to_array(),
        "water": water_json(&scene.water),
        "sky": {
            "atmosphere": scene.atmosphere,
            "memory_bytes": sky.memory_bytes(),
        },
        "clouds": {
            "layer": setup.clouds,
            "map_size": scene::CLOUD_MAP_SIZE,
        },
        "medium": {
            "density": medium.density,
            "height_falloff": medium.height_falloff,
            "base_height": medium.base_height,
            "noise_strength": medium.noise_strength,
        },
        "fog": {
            "volume_size": fog.config().volume_size.to_array(),
            "near": fog.config().near,
            "far": fog.config().far,
            "slice_curve": fog.config().slice_curve,
            "memory_bytes": fog.memory_bytes(),
            "frames_prepared": fog.frame_index().map_or(0, |i| i + 1),
            "integrated_finite": finite_volume,
            "mean_transmittance_far": mean_far_t,
            "esm_min": esm_min,
            "esm_max": esm_max,
            "esm_resolution": fog.config().esm_resolution,
            "esm_log_space": fog.config().esm_log_space,
            "live_fraction": volfog_testkit::scene::live_fraction(gpu, fog)?,
        },
        "cascades": {
            "light_from_world": cascades.light_from_world.iter().map(|m| mat(*m)).collect::<Vec<_>>(),
            "splits": cascades.splits.to_array(),
            "count": cascades.count,
            "exponent": cascades.exponent,
        },
        "passes": passes,
    });
    let path = dir.join("probe.json");
    let text = serde_json::to_string_pretty(&info).map_err(|e| write_error(&path, e))?;
    std::fs::write(&path, text).map_err(|e| write_error(&path, e))?;
    println!("wrote probe images and {}", path.display());
    Ok(())
}
