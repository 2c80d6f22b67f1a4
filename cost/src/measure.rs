//! Compiling a shader and each of its loops taken out on every chip, and turning the
//! figures into a pass's estimate on a GPU model.

use std::collections::BTreeMap;

use serde::Serialize;
use volfog_codegen::manifest::RenderState;

use crate::floor::{Sizes, Traffic, traffic};
use crate::frame::FramePass;
use crate::loops::{self, LoopInfo};
use crate::model::{self, Corrected, Estimate, LoopMeasure};
use crate::pipeline::{Job, RuntimeChecks, job_with_checks, render_state};
use crate::worker::Worker;
use crate::{Chip, CostError, GpuModel, ShaderStats};

/// A shader to measure: an entry point of a composed module.
#[derive(Debug, Clone)]
pub struct Shader {
    /// Its name in reports (`variant.entry`).
    pub label: String,
    /// The composed module.
    pub module: naga::Module,
    /// The entry point (compute, or fragment).
    pub entry: String,
    /// The draw state of a fragment entry point.
    pub render: Option<RenderState>,
}

impl Shader {
    /// Entry point `entry` of the prebuilt or custom variant `pass` + `defines`.
    pub fn of_variant(pass: &str, defines: &[String], entry: &str) -> Result<Shader, CostError> {
        let module = volfog::shaders::compose(pass, defines)?;
        let names: Vec<&str> = defines.iter().map(String::as_str).collect();
        Ok(Shader {
            label: format!(
                "{}.{entry}",
                volfog_codegen::manifest::variant_name(pass, &names)
            ),
            module,
            entry: entry.to_string(),
            render: render_state(pass),
        })
    }
}

/// A shader as one chip's compiler sees it, with each of its loops measured.
#[derive(Debug, Clone, Serialize)]
pub struct Measured {
    /// The shader's label.
    pub label: String,
    /// Its statistics.
    pub stats: ShaderStats,
    /// Its loops (in naga's IR), with what taking each out changed.
    pub loops: Vec<LoopMeasure>,
}

/// The loops of a shader and the jobs that measure them: the whole shader, then one
/// per loop taken out.
fn jobs(shader: &Shader, checks: RuntimeChecks) -> Result<(Vec<LoopInfo>, Vec<Job>), CostError> {
    let missing = || CostError::Invalid {
        field: "entry",
        message: format!("{} has no entry point {}", shader.label, shader.entry),
    };
    // One function per call site, so each copy of a loop is measured in its place.
    let module = loops::unshare(&shader.module, &shader.entry).ok_or_else(missing)?;
    let found = loops::loops(&module, &shader.entry).ok_or_else(missing)?;
    let job = |label: String, m: &naga::Module| {
        job_with_checks(
            &label,
            m,
            &shader.entry,
            shader.render.as_ref(),
            true,
            checks,
        )
    };
    let mut list = vec![job(shader.label.clone(), &module)?];
    for l in &found {
        let without = loops::without(&module, l.id).ok_or_else(missing)?;
        list.push(job(
            format!("{} without `{}`", shader.label, l.label),
            &without,
        )?);
    }
    Ok((found, list))
}

/// Every shader measured on one chip, and the device and driver that compiled them.
#[derive(Debug, Clone, Serialize)]
pub struct ChipMeasured {
    /// The device and its driver.
    pub device: String,
    /// One per shader, in order.
    pub shaders: Vec<Measured>,
}

impl ChipMeasured {
    /// The shader labelled `label`.
    pub fn get(&self, label: &str) -> Option<&Measured> {
        self.shaders.iter().find(|m| m.label == label)
    }
}

/// Compiles every shader, and every shader with each of its loops taken out, on each
/// chip (a worker process per chip, side by side), as volfog's runtime creates its
/// modules ([`RuntimeChecks::Checked`]).
pub fn measure(
    worker: &Worker,
    chips: &[Chip],
    shaders: &[Shader],
) -> Result<BTreeMap<Chip, ChipMeasured>, CostError> {
    measure_with_checks(worker, chips, shaders, |_| RuntimeChecks::Checked)
}

/// [`measure`], each shader written with the runtime checks `checks` gives it (another
/// application's shaders as that application creates them).
pub fn measure_with_checks(
    worker: &Worker,
    chips: &[Chip],
    shaders: &[Shader],
    checks: impl Fn(&Shader) -> RuntimeChecks,
) -> Result<BTreeMap<Chip, ChipMeasured>, CostError> {
    let mut all_jobs = Vec::new();
    let mut plan = Vec::new();
    for s in shaders {
        let (found, list) = jobs(s, checks(s))?;
        plan.push((s.label.clone(), found, all_jobs.len(), list.len()));
        all_jobs.extend(list);
    }
    let results = worker.compile_chips(chips, &all_jobs)?;
    let mut out = BTreeMap::new();
    for chip_results in results {
        let chip = chip_results.chip;
        let stats: Vec<ShaderStats> = chip_results
            .results
            .iter()
            .map(|c| ShaderStats::of_compiled(chip, c))
            .collect::<Result<_, _>>()?;
        let measured = plan
            .iter()
            .map(|(label, found, first, _)| {
                let full = &stats[*first];
                let aco_loops = |s: &ShaderStats| s.aco_loops.unwrap_or(0);
                Measured {
                    label: label.clone(),
                    stats: full.clone(),
                    loops: found
                        .iter()
                        .enumerate()
                        .map(|(i, l)| {
                            let without = &stats[first + 1 + i];
                            LoopMeasure {
                                label: l.label.clone(),
                                parent: l.parent,
                                aco_loops_removed: aco_loops(full)
                                    .saturating_sub(aco_loops(without)),
                                delta_latency: full.latency - without.latency,
                                trips: None,
                            }
                        })
                        .collect(),
                }
            })
            .collect();
        out.insert(
            chip,
            ChipMeasured {
                device: chip_results.device.clone(),
                shaders: measured,
            },
        );
    }
    Ok(out)
}

/// A pass of a frame on a GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct PassModel {
    /// The pass.
    pub pass: FramePass,
    /// The GPU model's name.
    pub gpu: &'static str,
    /// The shader's statistics on the model's chip.
    pub stats: ShaderStats,
    /// ACO's latency with the loops counted by their trip counts.
    pub corrected: Corrected,
    /// The memory floor's traffic.
    pub traffic: Traffic,
    /// The estimate.
    pub estimate: Estimate,
}

/// Gives each loop left in ACO's code its trip count from `pass.trips` (the first
/// entry its label starts with).
pub fn with_trips(
    measured: &Measured,
    pass: &FramePass,
    chip: Chip,
) -> Result<Vec<LoopMeasure>, CostError> {
    measured
        .loops
        .iter()
        .map(|l| {
            let trips = pass
                .trips
                .iter()
                .find(|(key, _)| l.label.starts_with(key.as_str()))
                .map(|(_, n)| *n);
            if l.in_code() && trips.is_none() {
                return Err(CostError::NoTripCount {
                    pipeline: measured.label.clone(),
                    label: l.label.clone(),
                    chip,
                    given: pass.trips.iter().map(|(k, _)| k.clone()).collect(),
                });
            }
            Ok(LoopMeasure { trips, ..l.clone() })
        })
        .collect()
}

/// The model of `pass` on `gpu` from its measured shader, its traffic sized by `sizes`.
pub fn model_pass(
    measured: &Measured,
    shader: &Shader,
    pass: &FramePass,
    gpu: &GpuModel,
    sizes: &Sizes,
) -> Result<PassModel, CostError> {
    let loops = with_trips(measured, pass, gpu.chip)?;
    let corrected =
        model::correct(measured.stats.latency, &loops).map_err(|label| CostError::NoTripCount {
            pipeline: measured.label.clone(),
            label,
            chip: gpu.chip,
            given: pass.trips.iter().map(|(k, _)| k.clone()).collect(),
        })?;
    let traffic = traffic(
        &shader.module,
        &[shader.entry.as_str()],
        &|name| {
            pass.binding_bytes
                .iter()
                .find(|(n, _)| n == name)
                .map_or_else(|| sizes.of(name, pass.culled), |(_, b)| *b)
        },
        pass.target,
    );
    let estimate = model::estimate(
        gpu,
        &measured.stats,
        corrected.latency,
        pass.invocations,
        traffic.bytes() as f64,
    );
    Ok(PassModel {
        pass: pass.clone(),
        gpu: gpu.name,
        stats: measured.stats.clone(),
        corrected,
        traffic,
        estimate,
    })
}
