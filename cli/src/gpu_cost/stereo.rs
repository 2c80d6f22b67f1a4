//! Stereo fog on the GPU models: the bench frame of `StereoFog` (the eyes of the bench's
//! stereo comparison, 64 mm apart, each with a 1920x1080 view) against one mono view
//! and two, on each model's grid. The shared passes run once over the centre eye's
//! volume; the scan's `VOLFOG_SCAN_RESAMPLE` variant runs once for both eyes, then each
//! eye's apply.
//! Stereo fog culls no froxels by depth, so its mono reference is the same
//! configuration without culling (as in the bench); the report's culled mono frame
//! stands beside it.

use std::fmt::Write as _;

use serde::Serialize;
use volfog_cost::frame::{FramePass, frame_passes};
use volfog_cost::measure::{Measured, PassModel, Shader, model_pass};
use volfog_cost::stereo::{stereo_config, stereo_frame_passes};
use volfog_cost::{Chip, CostError};

use super::{FramePlan, GpuCostError, SCREEN, inputs};

/// Stereo fog's bench frame on a GPU model, beside one mono view.
#[derive(Debug, Clone, Serialize)]
pub struct StereoModel {
    /// The GPU model's name.
    pub gpu: &'static str,
    /// The grid (each eye's, and the shared volume's).
    pub grid: [u32; 3],
    /// One mono view of stereo fog's configuration (no culling), its whole frame with
    /// the apply (ms).
    pub mono_ms: f64,
    /// The report's mono frame, which culls froxels by depth (ms).
    pub culled_mono_ms: f64,
    /// The stereo frame, both eyes' scans and applies included (ms).
    pub stereo_ms: f64,
    /// `stereo_ms / mono_ms`.
    pub stereo_ratio: f64,
    /// Two mono fogs against one mono view: 2.
    pub two_mono_ratio: f64,
    /// The mono view's passes.
    pub mono: Vec<PassModel>,
    /// The stereo frame's passes.
    pub stereo: Vec<PassModel>,
}

/// The stereo frame and its mono reference for one frame plan, with their shaders.
pub(super) struct StereoPlan {
    plan: usize,
    mono: Vec<(FramePass, Shader)>,
    stereo: Vec<(FramePass, Shader)>,
}

fn with_shaders(passes: Vec<FramePass>) -> Result<Vec<(FramePass, Shader)>, CostError> {
    passes
        .into_iter()
        .map(|p| {
            let shader = Shader::of_variant(p.variant.pass, &p.variant.defines, &p.entry)?;
            Ok((p, shader))
        })
        .collect()
}

/// The stereo frames of `plans` in the bench scene (`depth`: its 1080p depth buffer).
pub(super) fn plan(
    plans: &[FramePlan],
    scene: &crate::bench::scene::Scene,
    depth: &[f32],
) -> Result<Vec<StereoPlan>, GpuCostError> {
    let mut out = Vec::new();
    for (i, p) in plans.iter().enumerate() {
        let config = stereo_config(&p.config);
        let mono_work = inputs::workload(scene, depth, &config)?;
        let shared_work = inputs::stereo_workload(scene, &p.config)?;
        out.push(StereoPlan {
            plan: i,
            mono: with_shaders(frame_passes(&config, &mono_work))?,
            stereo: with_shaders(stereo_frame_passes(&p.config, &shared_work))?,
        });
    }
    Ok(out)
}

/// The shaders the stereo frames add to the measured ones.
pub(super) fn shaders(plans: &[StereoPlan]) -> impl Iterator<Item = &Shader> {
    plans
        .iter()
        .flat_map(|s| s.mono.iter().chain(&s.stereo).map(|(_, s)| s))
}

/// The models of the stereo frames, with the mono frame of the same plan.
pub(super) fn models<'a>(
    stereo: &[StereoPlan],
    plans: &[FramePlan],
    culled_mono_ms: &[f64],
    find: impl Fn(Chip, &str) -> &'a Measured,
) -> Result<Vec<StereoModel>, GpuCostError> {
    let mut out = Vec::new();
    for s in stereo {
        let p = &plans[s.plan];
        // No pass of either frame culls: the live share does not enter.
        let sizes = volfog_cost::floor::Sizes::new(&stereo_config(&p.config), SCREEN, 1.0);
        let model = |list: &[(FramePass, Shader)]| -> Result<Vec<PassModel>, CostError> {
            list.iter()
                .map(|(pass, shader)| {
                    model_pass(
                        find(p.gpu.chip, &shader.label),
                        shader,
                        pass,
                        &p.gpu,
                        &sizes,
                    )
                })
                .collect()
        };
        let mono = model(&s.mono)?;
        let stereo = model(&s.stereo)?;
        let total = |m: &[PassModel]| m.iter().map(|m| m.estimate.ms).sum::<f64>();
        let (mono_ms, stereo_ms) = (total(&mono), total(&stereo));
        out.push(StereoModel {
            gpu: p.gpu.name,
            grid: p.config.volume_size.to_array(),
            mono_ms,
            culled_mono_ms: culled_mono_ms[s.plan],
            stereo_ms,
            stereo_ratio: stereo_ms / mono_ms,
            two_mono_ratio: 2.0,
            mono,
            stereo,
        });
    }
    Ok(out)
}

/// The stereo frames as tables: the frames, then the stereo frame's passes.
pub(super) fn table(out: &mut String, rows: &[StereoModel]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Stereo fog: the bench frame for two 1920x1080 eyes against one mono view (ms)\n\n\
         | GPU model | grid | mono (no culling) | mono (culled) | stereo | stereo / mono | two mono / mono |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: |"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {}x{}x{} | {:.3} | {:.3} | {:.3} | {:.2}x | {:.2}x |",
            r.gpu,
            r.grid[0],
            r.grid[1],
            r.grid[2],
            r.mono_ms,
            r.culled_mono_ms,
            r.stereo_ms,
            r.stereo_ratio,
            r.two_mono_ratio
        );
    }
    let _ = writeln!(
        out,
        "\n| GPU model | stereo pass | ms | VGPRs | waves/SIMD |\n| --- | --- | ---: | ---: | ---: |"
    );
    for r in rows {
        for m in &r.stereo {
            let _ = writeln!(
                out,
                "| {} | {} | {:.3} | {} | {} |",
                r.gpu, m.pass.name, m.estimate.ms, m.stats.vgprs, m.stats.waves_per_simd
            );
        }
    }
}
