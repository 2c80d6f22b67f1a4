//! Bevy's own volumetric fog held against the path tracer: every truth scene of
//! `volfog_testkit::truth::scenes` rendered by Bevy 0.20's `VolumetricFog` and
//! `FogVolume`s (`render.rs`, the mapping in `mapping.rs`) and by Mitsuba 3, compared as
//! volfog's rows are (per 4 x 4 block, `volfog_testkit::truth::report`), printed as a
//! Markdown table; with `--volfog`, volfog's default rows from the same run beside
//! them; with `--model`, Bevy's shader evaluated on the CPU (`model.rs`) as it is and
//! with its departures from single scattering removed; with `--out`, the rows as JSON.
//!
//! ```text
//! cargo run -p volfog-bevy --example bevy_truth -- --volfog --model --out ../target/bevy-truth.json
//! ```

mod mapping;
mod model;
mod render;
mod rows;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use volfog_testkit::truth::mitsuba::MitsubaOptions;
use volfog_testkit::truth::report::{Reference, SPP, row};
use volfog_testkit::truth::scenes;
use volfog_testkit::truth::volfog::VolfogOptions;

use mapping::{DEFAULT_STEPS, map_scene};
use model::ModelOptions;
use render::BevyTruth;
use rows::{Noise, TruthRow};

/// Options of the example.
#[derive(Debug, Parser)]
struct Args {
    /// Only the scenes named (repeatable; default every scene).
    #[arg(long)]
    scene: Vec<String>,
    /// Bevy's ray-march steps per pixel (repeatable; default 64, Bevy's default, and
    /// 256).
    #[arg(long)]
    steps: Vec<u32>,
    /// Mitsuba's samples per pixel.
    #[arg(long, default_value_t = SPP)]
    spp: u32,
    /// Also volfog's default rows (converged), rendered in the same run.
    #[arg(long)]
    volfog: bool,
    /// Also Bevy's shader on the CPU at the first step count: as it is, and with each
    /// of its three departures from single scattering removed in turn, then all three.
    #[arg(long)]
    model: bool,
    /// Write the rows as JSON here.
    #[arg(long)]
    out: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let all = scenes::all();
    if let Some(unknown) = args
        .scene
        .iter()
        .find(|n| !all.iter().any(|s| &&s.name == n))
    {
        let names: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
        return Err(format!(
            "unknown scene {unknown}; the scenes are {}",
            names.join(", ")
        )
        .into());
    }
    let chosen: Vec<_> = all
        .into_iter()
        .filter(|s| args.scene.is_empty() || args.scene.contains(&s.name))
        .collect();
    let steps = if args.steps.is_empty() {
        vec![DEFAULT_STEPS, 4 * DEFAULT_STEPS]
    } else {
        args.steps.clone()
    };
    let mitsuba = MitsubaOptions {
        spp: args.spp,
        ..MitsubaOptions::default()
    };
    let mut bevy = BevyTruth::new();
    let mut adapters = vec![format!("Bevy: {}", bevy.adapter())];
    let gpu = if args.volfog {
        let gpu = volfog_testkit::Gpu::new()?;
        adapters.push(format!("volfog: {}", gpu.describe()));
        Some(gpu)
    } else {
        None
    };
    eprintln!("{}", adapters.join("; "));
    let (mut table, mut noise) = (Vec::new(), Vec::new());
    for scene in &chosen {
        let reference = Reference::render(scene, &mitsuba)?;
        noise.push(Noise::of(&reference));
        if let Some(gpu) = &gpu {
            let start = Instant::now();
            let r = row(gpu, &reference, "default", &VolfogOptions::default())?;
            eprintln!(
                "{}: volfog in {:.1} s",
                scene.name,
                start.elapsed().as_secs_f32()
            );
            table.push(TruthRow {
                scene: scene.name.clone(),
                renderer: format!("volfog, default, {} frames", r.frames),
                errors: r.converged,
            });
        }
        for &n in &steps {
            let start = Instant::now();
            let image = bevy.render(scene, n)?;
            eprintln!(
                "{}: Bevy at {n} steps in {:.1} s",
                scene.name,
                start.elapsed().as_secs_f32()
            );
            table.push(TruthRow {
                scene: scene.name.clone(),
                renderer: format!("Bevy VolumetricFog, {n} steps"),
                errors: reference.compare(&image),
            });
        }
        if args.model {
            let mapped = map_scene(scene, steps[0])?;
            let variants = [
                ("as written", ModelOptions::default()),
                (
                    "light's path",
                    ModelOptions {
                        path_attenuation: true,
                        ..ModelOptions::default()
                    },
                ),
                (
                    "lamp phase",
                    ModelOptions {
                        lamp_phase: true,
                        ..ModelOptions::default()
                    },
                ),
                (
                    "ray length",
                    ModelOptions {
                        ray_length: true,
                        ..ModelOptions::default()
                    },
                ),
                ("all three", ModelOptions::PHYSICAL),
            ];
            for (label, options) in variants {
                let lamps = !scene.points.is_empty() || !scene.spots.is_empty();
                if label == "lamp phase" && !lamps {
                    continue;
                }
                let image = model::render(scene, &mapped, options);
                table.push(TruthRow {
                    scene: scene.name.clone(),
                    renderer: format!("Bevy's shader on the CPU, {} steps, {label}", steps[0]),
                    errors: reference.compare(&image),
                });
            }
        }
    }
    println!("{}\n", adapters.join("; "));
    print!("{}", rows::markdown(&table, &noise));
    if let Some(out) = &args.out {
        rows::write_atomic(out, &rows::json(&adapters, mitsuba.spp, &table, &noise))?;
    }
    Ok(())
}
