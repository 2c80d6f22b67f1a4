//! The whole comparison: capture both fogs of the scene, count the loops of Bevy's,
//! compile and model both.

use std::time::Instant;

use volfog_cost::Chip;
use volfog_cost::worker::Worker;

use crate::capture::{BevyFog, capture_bevy, capture_volfog};
use crate::model::{Comparison, PipelineCompiled, Plan, compare, compile_pipelines, plan};
use crate::trips::{BevyTrips, bevy_trips, scene_depth};

type Error = Box<dyn std::error::Error>;

/// What a run found.
pub struct Outcome {
    /// Bevy's fog as captured.
    pub fog: BevyFog,
    /// The trips of its loops in the scene.
    pub trips: BevyTrips,
    /// What the model compiles and counts.
    pub plan: Plan,
    /// Both fogs on each GPU model.
    pub rows: Vec<Comparison>,
    /// Every fog pipeline of the scene in Bevy's cache, compiled on each chip.
    pub pipelines: Vec<PipelineCompiled>,
}

/// Captures the scene at `width` x `height` (on the machine's Vulkan device), counts,
/// and models both fogs on the GPU models of `chips` (compiled by workers `worker`
/// starts on RADV's null device); compiles every fog pipeline Bevy created on
/// `compile_chips`. Prints each stage's time to stderr.
pub fn run(
    width: u32,
    height: u32,
    chips: &[Chip],
    compile_chips: &[Chip],
    worker: &Worker,
) -> Result<Outcome, Error> {
    volfog_cost::worker::check_radv()?;
    let start = Instant::now();
    let fog = capture_bevy(width, height)?;
    let volfog = capture_volfog(width, height)?;
    eprintln!(
        "captured both fogs in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let start = Instant::now();
    let depth = scene_depth(fog.world_from_view, fog.clip_from_view, fog.screen);
    let trips = bevy_trips(&fog, &depth);
    let plan = plan(&fog, &trips, &volfog, &depth)?;
    eprintln!(
        "counted the loops in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let start = Instant::now();
    let rows = compare(worker, chips, &plan)?;
    eprintln!(
        "compiled and modelled for {} chips in {:.1} s",
        chips.len(),
        start.elapsed().as_secs_f64()
    );
    let start = Instant::now();
    let pipelines = compile_pipelines(worker, compile_chips, &fog)?;
    eprintln!(
        "compiled Bevy's {} fog pipelines for {} chips in {:.1} s",
        fog.pipelines.len(),
        compile_chips.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(Outcome {
        fog,
        trips,
        plan,
        rows,
        pipelines,
    })
}
