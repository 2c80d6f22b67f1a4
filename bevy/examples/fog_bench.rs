//! `cargo run -p volfog-bevy --release --example fog_bench [-- --width W --height H]`:
//! the fog scene in four apps one after the other in this process, at the same size:
//! without fog, with volfog's froxel fog (`FroxelFog` at the plugin's default tile
//! size, and at 8-pixel tiles, 2.25 times the froxels) and with Bevy's built-in
//! ray-marched `VolumetricFog` (its default 64 steps, one `FogVolume` around the
//! scene, the sun as its volumetric light). Each frame is timed from the start of
//! `App::update` to the GPU going idle; the report gives the median frame of each,
//! the fog's cost over the fog-free frame and their ratio, the difference of the two
//! volfog images, and writes the fogged images as PNGs next to a JSON report.

#[path = "fog_scene/scene.rs"]
mod scene;

use std::path::PathBuf;
use std::time::Instant;

use bevy::diagnostic::DiagnosticsStore;
use bevy::prelude::{Entity, Vec4, With};
use bevy::render::RenderApp;
use bevy::render::renderer::RenderDevice;
use clap::Parser;
use scene::{FogKind, SceneCamera, SceneOptions};
use volfog_bevy::FroxelFog;

/// Times the scene without fog, with volfog and with Bevy's fog.
#[derive(Parser)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../out/bevy"))]
    out: PathBuf,
    #[arg(long, default_value_t = 1920)]
    width: u32,
    #[arg(long, default_value_t = 1080)]
    height: u32,
    /// Frames before timing (pipelines compile, history fills).
    #[arg(long, default_value_t = 3)]
    warmup: u32,
    /// Frames timed per configuration.
    #[arg(long, default_value_t = 5)]
    frames: u32,
}

struct Timed {
    name: &'static str,
    frames_ms: Vec<f64>,
    median_ms: f64,
    /// GPU time of each render span over the timed frames (ms, median), by path.
    gpu_spans: Vec<(String, f64)>,
    /// The last frame, linear rgba.
    pixels: Vec<Vec4>,
}

/// (median, 95th percentile, mean) of the per-pixel relative differences of two
/// images.
fn image_difference(a: &[Vec4], b: &[Vec4]) -> (f32, f32, f32) {
    let d = scene::relative_differences(a, b);
    let mean = d.iter().sum::<f32>() / d.len() as f32;
    (d[d.len() / 2], d[d.len() * 95 / 100], mean)
}

/// The median of the last `n` values of every `render/.../elapsed_gpu` diagnostic.
fn gpu_spans(app: &bevy::app::App, n: usize) -> Vec<(String, f64)> {
    let store = app.world().resource::<DiagnosticsStore>();
    let mut spans: Vec<(String, f64)> = store
        .iter()
        .filter(|d| d.path().as_str().ends_with("/elapsed_gpu"))
        .filter_map(|d| {
            let mut values: Vec<f64> = d.values().copied().collect();
            let start = values.len().saturating_sub(n);
            let mut last = values.split_off(start);
            last.sort_by(f64::total_cmp);
            (!last.is_empty()).then(|| (d.path().as_str().to_string(), last[last.len() / 2]))
        })
        .collect();
    spans.sort_by(|a, b| a.0.cmp(&b.0));
    spans
}

/// Runs the scene with `kind` of fog; `tile_size` replaces the froxel fog's tile size
/// (the scene's 8) with another.
fn run(
    kind: FogKind,
    name: &'static str,
    tile_size: Option<u32>,
    args: &Args,
) -> Result<Timed, Box<dyn std::error::Error>> {
    let options = SceneOptions {
        width: args.width,
        height: args.height,
        fog: kind,
        gpu_timings: true,
        ..SceneOptions::default()
    };
    let mut app = scene::app(&options);
    if let Some(tile_size) = tile_size {
        app.update();
        let world = app.world_mut();
        let mut cameras = world.query_filtered::<Entity, With<SceneCamera>>();
        let camera = cameras.single(world)?;
        world
            .get_mut::<FroxelFog>(camera)
            .ok_or("the scene camera has a FroxelFog")?
            .tile_size = tile_size;
    }
    let idle = |app: &bevy::app::App| {
        let device = app.sub_app(RenderApp).world().resource::<RenderDevice>();
        device
            .wgpu_device()
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
    };
    for _ in 0..args.warmup {
        app.update();
        idle(&app)?;
    }
    let mut frames_ms = Vec::new();
    for _ in 0..args.frames {
        let start = Instant::now();
        app.update();
        idle(&app)?;
        frames_ms.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let gpu_spans = gpu_spans(&app, args.frames as usize);
    let pixels = scene::capture(&mut app, 0);
    if pixels.iter().any(|p| !p.is_finite()) {
        return Err(format!("{name}: NaN or infinite pixels").into());
    }
    scene::write_png(
        &args.out.join(format!("bench_{name}.png")),
        args.width,
        args.height,
        &pixels,
    )?;
    let mut sorted = frames_ms.clone();
    sorted.sort_by(f64::total_cmp);
    let median_ms = sorted[sorted.len() / 2];
    eprintln!(
        "{name}: median frame {median_ms:.1} ms over {} frames",
        frames_ms.len()
    );
    for (path, ms) in &gpu_spans {
        eprintln!("  GPU {path}: {ms:.1} ms");
    }
    Ok(Timed {
        name,
        frames_ms,
        median_ms,
        gpu_spans,
        pixels,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    std::fs::create_dir_all(&args.out)?;
    let default_tile = FroxelFog::default().tile_size;
    let runs = [
        run(FogKind::None, "no_fog", None, &args)?,
        run(FogKind::Froxel, "volfog", Some(default_tile), &args)?,
        run(FogKind::BevyBuiltIn, "bevy_volumetric_fog", None, &args)?,
        run(FogKind::Froxel, "volfog_tile8", Some(8), &args)?,
    ];
    let span = |t: &Timed, key: &str| {
        t.gpu_spans
            .iter()
            .find(|(p, _)| p.contains(key))
            .map(|(_, ms)| *ms)
    };
    let gpu_volfog = span(&runs[1], "volfog");
    let gpu_bevy = span(&runs[2], "volumetric_lighting");
    let gpu_tile8 = span(&runs[3], "volfog");
    let (median, p95, mean) = image_difference(&runs[1].pixels, &runs[3].pixels);
    let base = runs[0].median_ms;
    let cost = |t: &Timed| (t.median_ms - base).max(0.0);
    let (ours, bevys) = (cost(&runs[1]), cost(&runs[2]));
    let frame_ratio = runs[2].median_ms / runs[1].median_ms;
    let cost_ratio = bevys / ours.max(1e-3);
    let report = serde_json::json!({
        "width": args.width,
        "height": args.height,
        "frames": args.frames,
        "runs": runs.iter().map(|t| serde_json::json!({
            "name": t.name,
            "median_frame_ms": t.median_ms,
            "frames_ms": t.frames_ms,
            "gpu_spans_ms": t.gpu_spans.iter().map(|(p, ms)| (p.clone(), *ms)).collect::<std::collections::BTreeMap<_, _>>(),
        })).collect::<Vec<_>>(),
        "default_tile_size": default_tile,
        "fog_gpu_ms": { "volfog": gpu_volfog, "bevy_volumetric_fog": gpu_bevy, "volfog_tile8": gpu_tile8 },
        "fog_gpu_ratio_bevy_over_volfog": gpu_volfog.zip(gpu_bevy).map(|(a, b)| b / a),
        "fog_gpu_ratio_bevy_over_volfog_tile8": gpu_tile8.zip(gpu_bevy).map(|(a, b)| b / a),
        "image_difference_default_vs_tile8": { "median": median, "p95": p95, "mean": mean },
        "fog_cost_ms": { "volfog": ours, "bevy_volumetric_fog": bevys },
        "frame_ratio_bevy_over_volfog": frame_ratio,
        "fog_cost_ratio_bevy_over_volfog": cost_ratio,
    });
    let path = args.out.join("fog_bench.json");
    std::fs::write(&path, serde_json::to_string_pretty(&report)?)?;
    if let (Some(a), Some(b), Some(t)) = (gpu_volfog, gpu_bevy, gpu_tile8) {
        println!(
            "GPU time of the fog (timestamp queries): volfog {a:.1} ms (tile {default_tile}), Bevy's VolumetricFog {b:.1} ms ({:.1}x, target 10x: {}); volfog at tile 8 {t:.1} ms ({:.1}x)",
            b / a,
            if b / a >= 10.0 { "met" } else { "missed" },
            b / t
        );
    }
    println!(
        "image at tile {default_tile} against tile 8: relative difference median {median:.2e}, p95 {p95:.2e}, mean {mean:.2e}"
    );
    println!(
        "{}x{}: frame {:.1} ms without fog, {:.1} ms with volfog, {:.1} ms with Bevy's VolumetricFog; fog cost {ours:.1} ms vs {bevys:.1} ms ({cost_ratio:.1}x); report {}",
        args.width,
        args.height,
        runs[0].median_ms,
        runs[1].median_ms,
        runs[2].median_ms,
        path.display()
    );
    Ok(())
}
