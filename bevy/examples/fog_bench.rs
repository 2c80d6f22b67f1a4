//! `cargo run -p volfog-bevy --release --example fog_bench [-- --width W --height H]`:
//! the fog scene in three apps one after the other in this process, at the same size:
//! without fog, with volfog's froxel fog (`FroxelFog`) and with Bevy's built-in
//! ray-marched `VolumetricFog` (its default 64 steps, one `FogVolume` around the
//! scene, the sun as its volumetric light). Each frame is timed from the start of
//! `App::update` to the GPU going idle; the report gives the median frame of each,
//! the fog's cost over the fog-free frame and their ratio, and writes both fogged
//! images as PNGs next to a JSON report.

#[path = "fog_scene/scene.rs"]
mod scene;

use std::path::PathBuf;
use std::time::Instant;

use bevy::diagnostic::DiagnosticsStore;
use bevy::render::RenderApp;
use bevy::render::renderer::RenderDevice;
use clap::Parser;
use scene::{FogKind, SceneOptions};

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

fn run(
    kind: FogKind,
    name: &'static str,
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
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    std::fs::create_dir_all(&args.out)?;
    let runs = [
        run(FogKind::None, "no_fog", &args)?,
        run(FogKind::Froxel, "volfog", &args)?,
        run(FogKind::BevyBuiltIn, "bevy_volumetric_fog", &args)?,
    ];
    let span = |t: &Timed, key: &str| {
        t.gpu_spans
            .iter()
            .find(|(p, _)| p.contains(key))
            .map(|(_, ms)| *ms)
    };
    let gpu_volfog = span(&runs[1], "volfog");
    let gpu_bevy = span(&runs[2], "volumetric_lighting");
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
        "fog_gpu_ms": { "volfog": gpu_volfog, "bevy_volumetric_fog": gpu_bevy },
        "fog_gpu_ratio_bevy_over_volfog": gpu_volfog.zip(gpu_bevy).map(|(a, b)| b / a),
        "fog_cost_ms": { "volfog": ours, "bevy_volumetric_fog": bevys },
        "frame_ratio_bevy_over_volfog": frame_ratio,
        "fog_cost_ratio_bevy_over_volfog": cost_ratio,
    });
    let path = args.out.join("fog_bench.json");
    std::fs::write(&path, serde_json::to_string_pretty(&report)?)?;
    if let (Some(a), Some(b)) = (gpu_volfog, gpu_bevy) {
        println!(
            "GPU time of the fog (timestamp queries): volfog {a:.1} ms, Bevy's VolumetricFog {b:.1} ms ({:.1}x)",
            b / a
        );
    }
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
