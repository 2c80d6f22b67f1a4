//! `volfog demo`: renders the demo scene headless with the real `VolumetricFog`
//! pipeline and writes PNGs.
//!
//! Once: the sky texture for the sun (`volfog::sky`, sky_solve). Per frame: shadow
//! cascades (depth-only, one pass per layer) -> the lamp's cube shadow map (depth-only,
//! one pass per face) -> lit opaque pass and sky (sampled from the sky texture, the
//! phase per pixel) -> the clouds' shadow on the lit scene and the distance clouds
//! (`volfog::clouds`) -> fog prepare/encode (its sun term under the same cloud shadow,
//! the lamp a shadowed light) (froxel culling by this frame's depth buffer, ESM
//! downsample, blur, the local-light atlas from the lamp's cube, inject with the
//! temporal blend fused into it, scan) -> fullscreen fog apply -> semi-transparent sphere fogged by the forward
//! snippet -> tonemap. The camera moves along a short path so the temporal
//! reprojection works on a moving view; the last frame is written as `DIR/demo.png`. The pool's water
//! (`volfog::water`) is shaded in the opaque pass; then a second camera under water
//! renders `DIR/underwater.png` (the froxel apply is skipped there: the opaque pass
//! fogs what lies beyond the surface with the medium's analytic height fog).
//!
//! `--probe` also writes `DIR/probe/`: linear float images of the last frame (before
//! the apply, after it, after the transparent pass, and with every surface black, which
//! leaves only the fog's in-scattering), the depth buffer, the ESM, the lamp's atlas
//! maps, the integrated volume, and `probe.json` (camera, pass list, timings, volume
//! statistics, the lamp and its wall) for tests.

mod passes;
mod report;
mod scene;

use std::path::PathBuf;
use std::time::Instant;

use glam::UVec3;
use volfog::limits::InvalidValue;
use volfog::options::ShadowFilter;
use volfog::pipeline::FogError;
use volfog_testkit::GpuError;

use passes::{Demo, PASS_COUNT};
use report::{print_timings, write_error, write_png, write_probe, write_underwater_probe};

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
    /// How the fog tests the sun's and the lamp's shadows: `compare` (the default: the
    /// shadow maps themselves at one tap per froxel per frame, accumulated by the
    /// temporal blend) or `esm` (exponential shadow maps).
    #[arg(long, default_value = "compare", value_parser = parse_filter)]
    pub shadow_filter: ShadowFilter,
}

/// The fog configuration the demo renders with (`volfog gpu-cost` compiles its
/// pipelines).
pub fn fog_config(args: &DemoArgs) -> volfog::pipeline::FogConfig {
    passes::fog_config(args, false)
}

fn parse_filter(s: &str) -> Result<ShadowFilter, String> {
    match s {
        "compare" => Ok(ShadowFilter::default()),
        "esm" => Ok(ShadowFilter::Esm),
        _ => Err(format!("expected compare or esm, got {s:?}")),
    }
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
    let mut times: Vec<[f64; PASS_COUNT]> = Vec::new();
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
    write_underwater_probe(demo, &setup)
}
