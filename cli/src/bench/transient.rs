//! Short-lived lights over the bench scene (`FrameInputs::transient_lights`): the
//! baseline fog's scan without transient lights (the plain scan), with one (a muzzle
//! flash in front of the camera) and with eight (flashes, explosions and a lightning
//! strike over the colonnade), the order rotating from frame to frame. The transient
//! lights cost nothing outside the scan: inject and the temporal blend never see them.
//! The alternative, a pass between the blend and the scan that writes a volume of the
//! lights for the scan to add, would move at least a copy of the volume on top of the
//! same arithmetic; the run's copy floor stands beside the scan's growth for that
//! comparison.

use super::*;
use glam::Vec3;
use volfog::uniforms::FogLight;

/// Eight short-lived lights over the bench scene: a muzzle flash 1.5 m in front of the
/// camera first, then flashes and explosions along the colonnade, a spot-lit flare and
/// a lightning strike (a directional light).
pub(super) fn flashes() -> [FogLight; 8] {
    let point = |x: f32, y: f32, z: f32, color: Vec3, range: f32| {
        FogLight::point(Vec3::new(x, y, z), color, range)
    };
    [
        point(0.4, 1.6, 4.5, Vec3::new(400.0, 260.0, 90.0), 12.0),
        point(-3.0, 1.2, -8.0, Vec3::new(300.0, 200.0, 80.0), 10.0),
        point(3.5, 1.4, -20.0, Vec3::new(900.0, 500.0, 150.0), 16.0),
        point(-2.0, 2.5, -31.0, Vec3::new(600.0, 380.0, 120.0), 14.0),
        point(1.0, 0.8, -44.0, Vec3::new(1200.0, 700.0, 200.0), 20.0),
        point(4.0, 1.5, -52.0, Vec3::new(300.0, 180.0, 60.0), 10.0),
        FogLight::spot(
            Vec3::new(0.0, 8.5, -26.0),
            Vec3::new(0.1, -1.0, 0.05),
            Vec3::new(500.0, 150.0, 120.0),
            18.0,
            0.3,
            0.5,
        ),
        FogLight::directional(Vec3::new(-0.3, 1.0, -0.2).normalize(), Vec3::splat(2.5)),
    ]
}

/// Transient lights in each timed scan: none, one, eight.
const COUNTS: [usize; 3] = [0, 1, 8];

/// The baseline fog that runs the scans.
pub(super) struct TransientLights {
    screen: Screen,
    lights: [FogLight; 8],
}

/// One frame's scans: without transient lights, with one, with eight.
pub(super) struct TransientSamples {
    pub(super) none: Sample,
    pub(super) one: Sample,
    pub(super) eight: Sample,
}

impl TransientLights {
    /// A fog of the baseline configuration over the main screen, whose two
    /// stabilised volumes (the scan's input by frame parity) hold the scene's fog.
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        let mut screen = Screen::new(gpu, config, shadow_map, depth, SCREEN)?;
        for f in 0..2 {
            screen
                .fog
                .prepare(&gpu.queue, &scene.inputs(f as f32 / 60.0, cascades))?;
            screen.passes(gpu, &FogPass::ALL, false)?;
        }
        Ok(Self {
            screen,
            lights: flashes(),
        })
    }

    /// Times the scan of frame `f`'s inputs with none, one and eight transient lights.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        inputs: &volfog::pipeline::FrameInputs<'_>,
        f: u32,
    ) -> Result<TransientSamples, BenchError> {
        let mut samples = [Sample::default(); 3];
        for k in 0..COUNTS.len() {
            let which = (k + f as usize) % COUNTS.len();
            let lit = volfog::pipeline::FrameInputs {
                transient_lights: &self.lights[..COUNTS[which]],
                ..inputs.clone()
            };
            self.screen.fog.prepare(&gpu.queue, &lit)?;
            let (t, wall) = self.screen.passes(gpu, &[FogPass::Scan], false)?;
            samples[which] = Sample {
                gpu: t.scan,
                cpu: wall.scan,
            };
        }
        let [none, one, eight] = samples;
        Ok(TransientSamples { none, one, eight })
    }
}

/// What the transient lights cost in the run.
#[derive(Debug, Clone, Serialize)]
pub struct TransientCost {
    /// Median scan of the baseline fog without transient lights (ms).
    pub scan_ms: f64,
    /// The same with one transient light (a muzzle flash).
    pub scan_1_ms: f64,
    /// The same with eight.
    pub scan_8_ms: f64,
    /// Median scan with one transient light minus without (ms).
    pub added_1_ms: f64,
    /// Median scan with eight transient lights minus without (ms).
    pub added_8_ms: f64,
    /// Scan with one transient light / without, per frame.
    pub scan_1_vs_none: PairedRatio,
    /// Scan with eight transient lights / without, per frame.
    pub scan_8_vs_none: PairedRatio,
    /// Median copy of the volume (ms): what a separate pass writing a volume of the
    /// lights for the scan would move at least, besides the same arithmetic.
    pub separate_pass_floor_ms: f64,
}

/// The transient lights' figures from the medians of the run and its per-frame ratios.
pub(super) fn transient_cost(
    median: &dyn Fn(&str) -> f64,
    per_frame: &dyn Fn(&str, &'static str) -> PairedRatio,
) -> TransientCost {
    let none = median("scan_transient_0");
    TransientCost {
        scan_ms: none,
        scan_1_ms: median("scan_transient_1"),
        scan_8_ms: median("scan_transient_8"),
        added_1_ms: median("scan_transient_1") - none,
        added_8_ms: median("scan_transient_8") - none,
        scan_1_vs_none: per_frame(
            "transient_1_vs_none",
            "scan with 1 transient light / without, per frame",
        ),
        scan_8_vs_none: per_frame(
            "transient_8_vs_none",
            "scan with 8 transient lights / without, per frame",
        ),
        separate_pass_floor_ms: median("copy"),
    }
}

/// The transient lights' lines of the table.
pub(super) fn transient_table(out: &mut String, t: &TransientCost) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "\nshort-lived lights (the scan adds them; inject and temporal never see them):\n  \
         scan {:.3} ms; with 1 transient light {:.3} ms (+{:.3} ms, x{:.2} per frame); with 8 \
         {:.3} ms (+{:.3} ms, x{:.2} per frame); a separate pass would move at least a copy of \
         the volume, {:.3} ms, on top of the same arithmetic",
        t.scan_ms,
        t.scan_1_ms,
        t.added_1_ms,
        t.scan_1_vs_none.median,
        t.scan_8_ms,
        t.added_8_ms,
        t.scan_8_vs_none.median,
        t.separate_pass_floor_ms
    );
}
