//! The medium's shadows over the bench scene (`FogConfig::medium_shadows` at
//! `MediumShadowConfig::default()`): the baseline fog with them times the
//! `medium_shadow` pass (the sun-aligned volume of the noisy medium and the scene's
//! local volumes) and its inject (the `VOLFOG_INJECT_MEDIUM_SHADOW` variant, which reads
//! the volume for the sun and marches it towards the scene's lights), beside the
//! baseline's own inject.

use super::*;
use volfog::uniforms::MediumShadowConfig;

/// The baseline fog with the medium's shadows.
pub(super) struct MediumShadows {
    screen: Screen,
}

/// One frame's samples: the fill pass and the inject that reads it.
pub(super) struct MediumShadowSamples {
    pub(super) pass: Sample,
    pub(super) inject: Sample,
}

impl MediumShadows {
    /// The baseline configuration with the medium's shadows over the main screen, run
    /// twice untimed (so the first timed frame pays no first use).
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        let config = FogConfig {
            medium_shadows: Some(MediumShadowConfig::default()),
            ..config.clone()
        };
        let mut screen = Screen::new(gpu, &config, shadow_map, depth, SCREEN)?;
        for f in 0..2 {
            screen
                .fog
                .prepare(&gpu.queue, &scene.inputs(f as f32 / 60.0, cascades))?;
            screen.passes(gpu, &FogPass::ALL, false)?;
        }
        Ok(Self { screen })
    }

    /// Times the fill and the inject of frame `f`'s inputs.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        inputs: &volfog::pipeline::FrameInputs<'_>,
    ) -> Result<MediumShadowSamples, BenchError> {
        self.screen.fog.prepare(&gpu.queue, inputs)?;
        let (t, wall) =
            self.screen
                .passes(gpu, &[FogPass::MediumShadow, FogPass::Inject], false)?;
        Ok(MediumShadowSamples {
            pass: Sample {
                gpu: t.medium_shadow,
                cpu: wall.medium_shadow,
            },
            inject: Sample {
                gpu: t.inject,
                cpu: wall.inject,
            },
        })
    }
}

/// What the medium's shadows cost in the run.
#[derive(Debug, Clone, Serialize)]
pub struct MediumShadowCost {
    /// Median `medium_shadow` pass (ms): the 64^3 volume, four points a texel.
    pub pass_ms: f64,
    /// Median inject of the medium-shadow variant (ms).
    pub inject_ms: f64,
    /// Median inject of the baseline (ms).
    pub baseline_inject_ms: f64,
    /// (pass + inject) / the baseline's inject.
    pub total_vs_inject: f64,
}

/// The medium's shadows' figures from the medians of the run.
pub(super) fn medium_shadow_cost(median: &dyn Fn(&str) -> f64) -> MediumShadowCost {
    let (pass, inject, base) = (
        median("medium_shadow"),
        median("inject_medium_shadow"),
        median("inject"),
    );
    MediumShadowCost {
        pass_ms: pass,
        inject_ms: inject,
        baseline_inject_ms: base,
        total_vs_inject: (pass + inject) / base,
    }
}

/// The medium's shadows' line of the table.
pub(super) fn medium_shadow_table(out: &mut String, m: &MediumShadowCost) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "\nmedium shadows (FogConfig::medium_shadows, 64^3 volume):\n  medium_shadow pass \
         {:.3} ms; inject reading it {:.3} ms against the baseline's {:.3} ms; together x{:.2} \
         the baseline's inject",
        m.pass_ms, m.inject_ms, m.baseline_inject_ms, m.total_vs_inject
    );
}
