//! `cargo run -p volfog-bevy --example fog_gpu_cost [-- --chips gfx1100]`: Bevy 0.20's
//! own `VolumetricFog` and volfog's froxel fog in `fog_bench`'s scene, on volfog's GPU
//! model (the model of `volfog gpu-cost`, `docs/benchmark.md`, "On a GPU compiler").
//!
//! Both fogs are captured from Bevy apps of the scene on this machine's Vulkan device
//! (lavapipe will do; a frame or two each): Bevy's fog pipeline as Bevy built it (its
//! shader composed by Bevy's own shader cache with the pipeline's defs) and the scene
//! its loops run over (Bevy's light clusters, the sun's cascades, the fog volume, the
//! depth of every pixel), and volfog's fog as the plugin extracts it. Each pipeline
//! is then compiled by Mesa's RADV (ACO) on its null device for bonaire, navi21 and
//! gfx1100 (no GPU needed: this program starts itself as the compiling worker, one
//! process per chip), its loops counted by their trip counts in the scene, and its
//! time modelled against its memory floor on the Xbox One, RX 6800 XT and RX 7900 XTX
//! models. Prints the tables, and writes `fog_gpu_cost.json` and the captured shader
//! (`bevy_volumetric_fog.wgsl`) to `--out`.
//!
//! Needs `apt-get install -y mesa-vulkan-drivers libvulkan1` (lavapipe and RADV).

#[path = "../fog_scene/scene.rs"]
mod scene;

mod capture;
mod model;
mod run;
mod trips;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use volfog_cost::Chip;
use volfog_cost::worker::Worker;

/// The argument that makes this program a RADV worker.
const WORKER: &str = "radv-worker";

/// Bevy's fog and volfog's in `fog_bench`'s scene on the GPU model.
#[derive(Parser)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../out/bevy"))]
    out: PathBuf,
    #[arg(long, default_value_t = 1920)]
    width: u32,
    #[arg(long, default_value_t = 1080)]
    height: u32,
    /// Chips to compile for (bonaire, navi21, gfx1100) [default: all three].
    #[arg(long, value_delimiter = ',')]
    chips: Vec<String>,
}

fn main() -> ExitCode {
    if std::env::args().nth(1).as_deref() == Some(WORKER) {
        return match volfog_cost::worker::serve(std::io::stdin().lock(), std::io::stdout().lock()) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        };
    }
    match report(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn report(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let mut chips = Vec::new();
    for name in &args.chips {
        chips.push(
            Chip::from_family(name)
                .ok_or_else(|| format!("--chips: {name:?} is not bonaire, navi21 or gfx1100"))?,
        );
    }
    if chips.is_empty() {
        chips = Chip::ALL.to_vec();
    }
    chips.sort();
    chips.dedup();
    let worker = Worker::new(std::env::current_exe()?, &[WORKER]);
    let outcome = run::run(args.width, args.height, &chips, &chips, &worker)?;
    print!(
        "{}",
        model::table(&outcome.plan, &outcome.trips, &outcome.rows)
    );
    for p in &outcome.pipelines {
        println!(
            "Bevy's fog pipeline [{}] compiles on {}: {} VGPRs, {} instructions, {} waves per SIMD",
            p.shader_defs.join(", "),
            p.chip.family(),
            p.stats.vgprs,
            p.stats.instructions,
            p.stats.waves_per_simd
        );
    }
    std::fs::create_dir_all(&args.out)?;
    let shader = args.out.join("bevy_volumetric_fog.wgsl");
    std::fs::write(&shader, &outcome.fog.wgsl)?;
    let json = serde_json::json!({
        "screen": [args.width, args.height],
        "bevy": {
            "shader": capture::SHADER_PATH,
            "shader_defs": outcome.fog.shader_defs,
            "step_count": outcome.fog.step_count,
            "clusters": outcome.fog.clusters.dimensions.to_array(),
            "shadow_texture": [outcome.fog.shadow_texture.0, outcome.fog.shadow_texture.1, outcome.fog.shadow_texture.2],
            "trips": outcome.trips,
        },
        "volfog": { "grid": outcome.plan.config.volume_size.to_array(), "workload": outcome.plan.workload },
        "models": outcome.rows,
        "pipelines": outcome.pipelines,
    });
    let path = args.out.join("fog_gpu_cost.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json)? + "\n")?;
    eprintln!("wrote {} and {}", path.display(), shader.display());
    Ok(())
}
