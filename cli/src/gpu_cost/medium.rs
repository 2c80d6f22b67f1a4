//! The medium's shadows on the GPU models: the bench frame with
//! `FogConfig::medium_shadows` at `MediumShadowConfig::default()` (the `medium_shadow`
//! pass and inject's `VOLFOG_INJECT_MEDIUM_SHADOW` variant) against the same frame
//! without them, each compiled by RADV for the model's chip.

use std::fmt::Write as _;

use serde::Serialize;
use volfog_cost::Chip;
use volfog_cost::measure::{Measured, PassModel};

use super::{FrameModel, FramePlan, GpuCostError};

/// The bench frame with the medium's shadows on a GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct MediumShadowModel {
    /// The GPU model's name.
    pub gpu: &'static str,
    /// The grid.
    pub grid: [u32; 3],
    /// The frame's inject without the medium's shadows (ms).
    pub plain_inject_ms: f64,
    /// The `medium_shadow` pass.
    pub pass: PassModel,
    /// Inject reading its volume.
    pub inject: PassModel,
    /// The whole frame without them and with them (ms).
    pub frame_ms: (f64, f64),
}

/// The models of `plans` (the frames with the medium's shadows), beside `frames` (the
/// same frames without them, in the same order).
pub(super) fn models<'a>(
    plans: &[FramePlan],
    frames: &[FrameModel],
    find: impl Fn(Chip, &str) -> &'a Measured,
) -> Result<Vec<MediumShadowModel>, GpuCostError> {
    let mut out = Vec::new();
    for (p, plain) in plans.iter().zip(frames) {
        let passes = super::model_passes(p, &find)?;
        let named = |name: &str| {
            passes
                .iter()
                .find(|m| m.pass.name == name)
                .cloned()
                .expect("the frame has the pass")
        };
        let plain_inject = plain
            .passes
            .iter()
            .find(|m| m.pass.name == "inject")
            .expect("every frame injects");
        out.push(MediumShadowModel {
            gpu: p.gpu.name,
            grid: p.config.volume_size.to_array(),
            plain_inject_ms: plain_inject.estimate.ms,
            pass: named("medium shadow"),
            inject: named("inject"),
            frame_ms: (plain.total_ms, passes.iter().map(|m| m.estimate.ms).sum()),
        });
    }
    Ok(out)
}

/// The frames' models as a table.
pub(super) fn table(out: &mut String, rows: &[MediumShadowModel]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Medium shadows: the bench frame with FogConfig::medium_shadows (64^3, ms)\n\n\
         | GPU model | grid | inject | medium_shadow pass | inject with | frame | frame with | \
         pass VGPRs | pass waves/SIMD |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {}x{}x{} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {} |",
            r.gpu,
            r.grid[0],
            r.grid[1],
            r.grid[2],
            r.plain_inject_ms,
            r.pass.estimate.ms,
            r.inject.estimate.ms,
            r.frame_ms.0,
            r.frame_ms.1,
            r.pass.stats.vgprs,
            r.pass.stats.waves_per_simd
        );
    }
}
