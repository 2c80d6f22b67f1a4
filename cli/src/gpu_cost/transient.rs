//! Short-lived lights on the GPU models: the bench frame's scan with 1 and 8 transient
//! lights (the scan's `VOLFOG_SCAN_TRANSIENT_LIGHTS` variant, which the runtime runs on
//! frames with transient lights) against its plain scan, each compiled by RADV for the
//! model's chip with every loop counted by its trip count.

use std::fmt::Write as _;

use serde::Serialize;
use volfog_cost::frame::FramePass;
use volfog_cost::measure::{Measured, PassModel, Shader, model_pass};
use volfog_cost::transient::transient_scan;
use volfog_cost::{Chip, CostError};

use super::{FramePlan, GpuCostError, SCREEN};

/// The transient light counts the report models.
pub const TRANSIENT_LIGHT_COUNTS: [u32; 2] = [1, 8];

/// The scan of the bench frame with transient lights on a GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct TransientModel {
    /// The GPU model's name.
    pub gpu: &'static str,
    /// The grid.
    pub grid: [u32; 3],
    /// The frame's plain scan (ms).
    pub scan_ms: f64,
    /// The scan with each count of [`TRANSIENT_LIGHT_COUNTS`] transient lights.
    pub scans: Vec<PassModel>,
}

impl TransientModel {
    /// What the transient lights add to the frame (ms), per count.
    pub fn extra_ms(&self) -> Vec<f64> {
        self.scans
            .iter()
            .map(|m| m.estimate.ms - self.scan_ms)
            .collect()
    }
}

/// The transient scans of a frame plan and their shaders.
pub(super) struct TransientPlan {
    plan: usize,
    scans: Vec<(FramePass, Shader)>,
}

/// The transient scans of `plans[i]` (none where the configuration builds no
/// transient scan).
pub(super) fn plan(plans: &[FramePlan]) -> Result<Vec<TransientPlan>, GpuCostError> {
    let mut out = Vec::new();
    for (i, p) in plans.iter().enumerate() {
        let scans = TRANSIENT_LIGHT_COUNTS
            .iter()
            .filter_map(|&n| transient_scan(&p.config, &p.workload, n))
            .map(|pass| {
                let shader =
                    Shader::of_variant(pass.variant.pass, &pass.variant.defines, &pass.entry)?;
                Ok((pass, shader))
            })
            .collect::<Result<Vec<_>, CostError>>()?;
        if !scans.is_empty() {
            out.push(TransientPlan { plan: i, scans });
        }
    }
    Ok(out)
}

/// The shaders the transient scans add to the measured ones.
pub(super) fn shaders(plans: &[TransientPlan]) -> impl Iterator<Item = &Shader> {
    plans.iter().flat_map(|t| t.scans.iter().map(|(_, s)| s))
}

/// The models of the transient scans, with the plain scan of the same frame.
pub(super) fn models<'a>(
    transient: &[TransientPlan],
    plans: &[FramePlan],
    find: impl Fn(Chip, &str) -> &'a Measured,
) -> Result<Vec<TransientModel>, GpuCostError> {
    let mut out = Vec::new();
    for t in transient {
        let p = &plans[t.plan];
        let sizes = volfog_cost::floor::Sizes::new(&p.config, SCREEN, p.workload.live_fraction);
        let model = |(pass, shader): &(FramePass, Shader)| {
            model_pass(
                find(p.gpu.chip, &shader.label),
                shader,
                pass,
                &p.gpu,
                &sizes,
            )
        };
        let plain = p
            .passes
            .iter()
            .find(|(pass, _)| pass.name == "scan")
            .expect("every frame scans");
        out.push(TransientModel {
            gpu: p.gpu.name,
            grid: p.config.volume_size.to_array(),
            scan_ms: model(plain)?.estimate.ms,
            scans: t.scans.iter().map(model).collect::<Result<_, _>>()?,
        });
    }
    Ok(out)
}

/// The transient scans as a table.
pub(super) fn table(out: &mut String, rows: &[TransientModel]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Short-lived lights: the bench frame's scan with transient lights (ms)\n\n\
         | GPU model | grid | scan | lights | scan with them | added | VGPRs | waves/SIMD |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for r in rows {
        for (m, extra) in r.scans.iter().zip(r.extra_ms()) {
            let lights = m.pass.trips.last().map_or(0.0, |(_, n)| *n);
            let _ = writeln!(
                out,
                "| {} | {}x{}x{} | {:.3} | {lights} | {:.3} | {:.3} | {} | {} |",
                r.gpu,
                r.grid[0],
                r.grid[1],
                r.grid[2],
                r.scan_ms,
                m.estimate.ms,
                extra,
                m.stats.vgprs,
                m.stats.waves_per_simd
            );
        }
    }
}
