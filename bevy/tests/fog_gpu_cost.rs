//! Bevy 0.20's own `VolumetricFog` beside volfog's froxel fog on the GPU model, in
//! `fog_bench`'s scene at 1920x1080: the `fog_gpu_cost` example's capture, loop
//! counts and model, modelled for gfx1100 only (the RX 7900 XTX model, where the
//! target is set); Bevy's fog pipelines are compiled for all three chips. A test
//! binary with its own `main` (`harness = false`): started as `fog_gpu_cost
//! radv-worker` it is the worker that compiles on RADV's null device.
//! Needs lavapipe and RADV (`apt-get install -y mesa-vulkan-drivers libvulkan1`).
//!
//! Checked (figures of the model and counts, no wall time):
//! - the capture is complete: Bevy created every fog pipeline it queued for the scene
//!   (two: the fog without and with a density texture, for the scene's one view), and
//!   each, its shader composed as Bevy composes it and its SPIR-V written as wgpu
//!   writes a trusted module, compiles on RADV for bonaire, navi21 and gfx1100; the
//!   modelled one (the scene's volume has no density texture) has the defs the scene
//!   implies (Bevy's hardware 2x2 shadow filter; no MSAA, density texture or
//!   atmosphere);
//! - the loop counts against what the scene's figures imply without them: the camera
//!   is inside the fog volume, so every wave marches; the volume's diagonal is too
//!   short for the transmittance to fall below Bevy's 0.001, so every march runs all
//!   `step_count` steps, and the model counts both marches at 64 iterations a wave;
//!   one volumetric directional light; the cascade search between 1 and the sun's 4
//!   cascades; Bevy's clusters list at least the lights that reach each sample (the
//!   check of the cluster index the count reads) and at most the scene's 5;
//! - the memory floor: the depth buffer, the sun's four 2048² Depth32Float cascades
//!   and the colour target read and written;
//! - volfog's frame is the plugin's default grid at 1080p (160 x 90 x 128);
//! - Bevy's fog costs more than volfog's frame on the RX 7900 XTX model, even with the
//!   loop over a cluster's lights counted at its volumetric lights only (none in the
//!   scene: the lower of the model's two figures for Bevy). The target there,
//!   10 times, is printed, not asserted: the model gives 2.4x to 5.5x
//!   (`docs/benchmark.md`, "Bevy's fog on the model").

#[path = "../examples/fog_gpu_cost/capture.rs"]
mod capture;
#[path = "../examples/fog_gpu_cost/model.rs"]
mod model;
#[path = "../examples/fog_gpu_cost/run.rs"]
mod run;
#[path = "../examples/fog_scene/scene.rs"]
mod scene;
#[path = "../examples/fog_gpu_cost/trips.rs"]
mod trips;

use std::process::ExitCode;
use std::time::Instant;

use volfog_bevy::FroxelFog;
use volfog_cost::Chip;
use volfog_cost::worker::Worker;

const WORKER: &str = "radv-worker";
const SCREEN: (u32, u32) = (1920, 1080);

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
    let start = Instant::now();
    let worker = Worker::new(std::env::current_exe().expect("the test's path"), &[WORKER]);
    let outcome = run::run(SCREEN.0, SCREEN.1, &[Chip::Gfx1100], &Chip::ALL, &worker)
        .unwrap_or_else(|e| panic!("the comparison did not run: {e}"));
    eprint!(
        "{}",
        model::table(&outcome.plan, &outcome.trips, &outcome.rows)
    );
    every_fog_pipeline_compiles_on_three_chips(&outcome);
    captured_as_the_scene_implies(&outcome);
    loops_counted_as_the_scene_implies(&outcome);
    memory_floor(&outcome);
    volfog_at_the_plugins_default_grid(&outcome);
    bevy_costs_more_than_volfog_on_rdna3(&outcome);
    eprintln!(
        "fog_gpu_cost: 6 checks passed in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    ExitCode::SUCCESS
}

fn every_fog_pipeline_compiles_on_three_chips(o: &run::Outcome) {
    // `run` fails unless every pipeline compiled on every chip; here, that they are
    // the scene's and that each chip compiled each. Bevy specializes the fog for the view's layout, its target's format and whether
    // a volume has a density texture: in the scene, the pipelines without and with one.
    let pipelines = &o.fog.pipelines;
    let defs: Vec<&[String]> = pipelines.iter().map(|p| p.shader_defs.as_slice()).collect();
    assert_eq!(pipelines.len(), 2, "{defs:?}");
    assert!(pipelines.iter().all(|p| p.created), "{defs:?}");
    let modelled: Vec<_> = pipelines.iter().filter(|p| p.wgsl == o.fog.wgsl).collect();
    assert_eq!(modelled.len(), 1, "{defs:?}");
    assert_eq!(modelled[0].shader_defs, o.fog.shader_defs);
    let density = pipelines
        .iter()
        .filter(|p| p.shader_defs.iter().any(|d| d == "DENSITY_TEXTURE"));
    assert_eq!(density.count(), 1, "{defs:?}");
    for chip in Chip::ALL {
        let on: Vec<_> = o.pipelines.iter().filter(|p| p.chip == chip).collect();
        assert_eq!(on.len(), pipelines.len(), "{chip:?}");
        for (p, fog) in on.iter().zip(pipelines) {
            assert_eq!(p.shader_defs, fog.shader_defs);
        }
    }
    for p in &o.pipelines {
        assert!(p.stats.instructions > 0 && p.stats.vgprs > 0, "{p:?}");
        eprintln!(
            "Bevy's fog pipeline [{}] on {}: {} VGPRs, {} instructions, {} / {} spilled VGPRs / SGPRs",
            p.shader_defs.last().map_or("", String::as_str),
            p.chip.family(),
            p.stats.vgprs,
            p.stats.instructions,
            p.stats.spilled_vgprs,
            p.stats.spilled_sgprs
        );
    }
}

fn captured_as_the_scene_implies(o: &run::Outcome) {
    let defs = &o.fog.shader_defs;
    assert!(
        defs.iter()
            .any(|d| d == "SHADOW_FILTER_METHOD_HARDWARE_2X2"),
        "{defs:?}"
    );
    for absent in ["MULTISAMPLED", "DENSITY_TEXTURE", "ATMOSPHERE"] {
        assert!(!defs.iter().any(|d| d == absent), "{absent} in {defs:?}");
    }
    assert!(!o.fog.density_texture);
    let bevy = &o.rows[0].bevy;
    assert!(
        bevy.stats.instructions > 0 && bevy.stats.vgprs > 0,
        "{:?}",
        bevy.stats
    );
}

fn loops_counted_as_the_scene_implies(o: &run::Outcome) {
    let (t, fog) = (&o.trips, &o.fog);
    // The scene's FogVolume: a 120 x 20 x 120 m box of extinction 0.035 * (0.1 + 0.9).
    let diagonal = (120f32 * 120.0 + 20.0 * 20.0 + 120.0 * 120.0).sqrt();
    let extinction = 0.035 * (0.1 + 0.9);
    assert!(
        (fog.extinction - extinction).abs() < 1e-6,
        "{}",
        fog.extinction
    );
    assert!(extinction * diagonal < 1000f32.ln());
    assert_eq!(t.marching_waves, t.waves, "the camera is inside the volume");
    let steps = f64::from(fog.step_count);
    assert_eq!(fog.step_count, 64);
    assert_eq!((t.sun_steps, t.light_steps), (steps, steps));
    assert_eq!(t.directional_lights, 1.0);
    assert!(
        t.cascade_search >= 1.0 && t.cascade_search <= 4.0,
        "{}",
        t.cascade_search
    );
    let lights = fog.lights.len() as f64;
    assert_eq!(lights, 5.0);
    assert!(
        t.cluster_lights >= t.lights_reaching && t.cluster_lights <= lights,
        "{t:?}"
    );
    assert!(t.lights_reaching > 0.0, "{t:?}");
    // No point or spot light of the scene is volumetric.
    assert_eq!(t.volumetric_reaching, 0.0);
    assert_eq!(
        t.under_listed, 0,
        "samples whose cluster lacks a light that reaches them: {t:?}"
    );
    // Both marches run 64 iterations a wave in the model (one sun).
    let terms = &o.rows[0].bevy.corrected.loops;
    for label in [
        "fragment: step < step_count",
        "fragment: step < step_count #2",
    ] {
        let term = terms
            .iter()
            .find(|l| l.label == label)
            .unwrap_or_else(|| panic!("no loop {label} in the code: {terms:?}"));
        assert_eq!(term.iterations, steps, "{label}");
    }
}

fn memory_floor(o: &run::Outcome) {
    let pixels = u64::from(SCREEN.0) * u64::from(SCREEN.1);
    let shadow = 2048 * 2048 * 4 * 4;
    let traffic = &o.rows[0].bevy.traffic;
    assert_eq!(
        traffic.bytes_read,
        pixels * 4 + shadow + pixels * 8,
        "{traffic:?}"
    );
    assert_eq!(traffic.bytes_written, pixels * 8, "{traffic:?}");
}

fn volfog_at_the_plugins_default_grid(o: &run::Outcome) {
    let tile = FroxelFog::default().tile_size;
    let grid = o.plan.config.volume_size.to_array();
    assert_eq!(
        grid,
        [
            SCREEN.0.div_ceil(tile),
            SCREEN.1.div_ceil(tile),
            FroxelFog::default().slices
        ]
    );
    assert_eq!(grid, [160, 90, 128]);
    let names: Vec<&str> = o.rows[0]
        .volfog
        .iter()
        .map(|m| m.pass.variant.pass)
        .collect();
    for pass in ["inject", "scan", "apply"] {
        assert!(names.contains(&pass), "{names:?}");
    }
}

fn bevy_costs_more_than_volfog_on_rdna3(o: &run::Outcome) {
    let row = &o.rows[0];
    assert_eq!(row.gpu.chip, Chip::Gfx1100);
    assert!(
        row.ratio >= row.ratio_lower,
        "{} < {}",
        row.ratio,
        row.ratio_lower
    );
    assert!(
        row.ratio_lower > 1.0,
        "Bevy {:.3} ms, volfog {:.3} ms: {:.2}x",
        row.bevy_lower.estimate.ms,
        row.volfog_ms,
        row.ratio_lower
    );
    eprintln!(
        "the target, Bevy at least 10x volfog on the RDNA3 model: {} ({:.1}x to {:.1}x)",
        if row.ratio_lower >= 10.0 {
            "met"
        } else {
            "missed"
        },
        row.ratio_lower,
        row.ratio
    );
}
