//! `volfog truth`: every path-tracer comparison scene rendered by the froxel pipeline
//! and by Mitsuba 3 (`volfog_testkit::truth`), at three grids (64, 128 and 256 slices):
//! the converged image (a still camera over `--frames` jittered frames blended with the
//! history), the first frame's and the grid floor (a perfect shadow term at the same
//! grid, on the CPU), as a Markdown table on stdout and, with `--out`, the whole report
//! as JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use glam::UVec3;
use volfog_testkit::truth::mitsuba::MitsubaOptions;
use volfog_testkit::truth::report::{SPP, grids, markdown, report};
use volfog_testkit::truth::scenes;
use volfog_testkit::truth::volfog::{CONVERGED_FRAMES, VolfogOptions};

/// Options of `volfog truth`.
#[derive(Debug, Clone, clap::Args)]
pub struct TruthArgs {
    /// Mitsuba's samples per pixel of each radiance render.
    #[arg(long, default_value_t = SPP)]
    pub spp: u32,
    /// Only the scenes named (repeatable; default every scene).
    #[arg(long)]
    pub scene: Vec<String>,
    /// Only these slice counts (repeatable; default 64, 128 and 256).
    #[arg(long)]
    pub slices: Vec<u32>,
    /// Frames of the still camera; the converged figures are the last frame's.
    #[arg(long, default_value_t = CONVERGED_FRAMES)]
    pub frames: u32,
    /// Also render each scene with the blurred exponential shadow maps at 256 texels
    /// (`VolfogOptions::esm_256`), a row beside the default's.
    #[arg(long)]
    pub esm: bool,
    /// Write the report as JSON here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs the comparison and prints the table.
pub fn main(args: &TruthArgs) -> ExitCode {
    let gpu = match volfog_testkit::Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let all = scenes::all();
    let unknown: Vec<&String> = args
        .scene
        .iter()
        .filter(|n| !all.iter().any(|s| &s.name == *n))
        .collect();
    if !unknown.is_empty() {
        let names: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
        eprintln!(
            "error: unknown scene {unknown:?}; the scenes are {}",
            names.join(", ")
        );
        return ExitCode::FAILURE;
    }
    let chosen: Vec<_> = all
        .into_iter()
        .filter(|s| args.scene.is_empty() || args.scene.contains(&s.name))
        .collect();
    let grids: Vec<UVec3> = if args.slices.is_empty() {
        grids().to_vec()
    } else {
        let d = VolfogOptions::default().config.volume_size;
        args.slices
            .iter()
            .map(|&z| UVec3::new(d.x, d.y, z))
            .collect()
    };
    let default = VolfogOptions {
        frames: args.frames,
        ..VolfogOptions::default()
    };
    let mut configurations = vec![("default".to_string(), default.clone())];
    if args.esm {
        configurations.push(("ESM 256".to_string(), default.esm_256()));
    }
    eprintln!(
        "rendering {} scenes with Mitsuba ({} spp) and volfog ({} frames) on {}...",
        chosen.len(),
        args.spp,
        args.frames,
        gpu.describe()
    );
    let options = MitsubaOptions {
        spp: args.spp,
        ..MitsubaOptions::default()
    };
    let report = match report(&gpu, &chosen, &options, &grids, &configurations) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("adapter: {}\n", report.adapter);
    print!("{}", markdown(&report));
    if let Some(out) = &args.out {
        let json = serde_json::to_string_pretty(&report).expect("the report serializes");
        // Written beside the destination and renamed: never a half-written report.
        let partial = out.with_extension("partial");
        if let Err(e) = std::fs::write(&partial, json).and_then(|()| std::fs::rename(&partial, out))
        {
            eprintln!("error: cannot write {}: {e}", out.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
