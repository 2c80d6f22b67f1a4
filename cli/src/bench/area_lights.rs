//! Area lights over the bench scene (`FrameInputs::area_lights`): the baseline fog
//! with room for eight area lights (the `VOLFOG_INJECT_AREA_LIGHTS` variant) times its
//! inject with the scene's own lights only, with four point lights added, with four
//! rectangle lights and with four disk lights at the same places, the order rotating
//! from frame to frame. The cost of one light of each kind is the growth over the
//! scene's own lights divided by four.

use super::*;
use glam::Vec3;
use volfog::uniforms::{AreaLight, FogLight};

/// Where the four added lights hang: over the colonnade's aisle, 4.5 m up.
const PLACES: [(f32, f32); 4] = [(-2.0, -12.0), (2.0, -22.0), (-2.0, -32.0), (2.0, -42.0)];
/// Their range (m).
const RANGE: f32 = 12.0;
/// Radiance of the area lights (W / (m^2 sr)).
const RADIANCE: Vec3 = Vec3::new(60.0, 50.0, 40.0);

/// The added point lights: the rectangles' intensity straight down (`L A`, 2 m^2).
fn points() -> Vec<FogLight> {
    PLACES
        .iter()
        .map(|&(x, z)| FogLight::point(Vec3::new(x, 4.5, z), RADIANCE * 2.0, RANGE))
        .collect()
}

/// Four 2 m x 1 m panels facing down, or four disks of radius 0.8 m.
fn emitters(disk: bool) -> Vec<AreaLight> {
    PLACES
        .iter()
        .map(|&(x, z)| {
            let center = Vec3::new(x, 4.5, z);
            if disk {
                AreaLight::disk(center, Vec3::NEG_Y, 0.8, RADIANCE, RANGE)
            } else {
                AreaLight::rect(center, Vec3::X, Vec3::Z, 1.0, 0.5, RADIANCE, RANGE)
            }
        })
        .collect()
}

/// The fog with room for the area lights, and the lights it adds.
pub(super) struct AreaLights {
    screen: Screen,
    points: Vec<FogLight>,
    rects: Vec<AreaLight>,
    disks: Vec<AreaLight>,
}

/// One frame's injects: the scene's lights, plus four points, rectangles, disks.
pub(super) struct AreaSamples {
    pub(super) none: Sample,
    pub(super) points: Sample,
    pub(super) rects: Sample,
    pub(super) disks: Sample,
}

impl AreaLights {
    /// A fog of the baseline configuration with `max_area_lights` 8 over the main
    /// screen, run twice untimed with the scene's inputs and the rectangles (so the first
    /// timed inject pays no first use).
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        let config = FogConfig {
            max_area_lights: 8,
            max_lights: config.max_lights.max(32),
            ..config.clone()
        };
        let mut screen = Screen::new(gpu, &config, shadow_map, depth, SCREEN)?;
        let rects = emitters(false);
        for f in 0..2 {
            let inputs = scene.inputs(f as f32 / 60.0, cascades);
            screen.fog.prepare(
                &gpu.queue,
                &volfog::pipeline::FrameInputs {
                    area_lights: &rects,
                    ..inputs
                },
            )?;
            screen.passes(gpu, &FogPass::ALL, false)?;
        }
        Ok(Self {
            screen,
            points: points(),
            rects,
            disks: emitters(true),
        })
    }

    /// Times the inject of frame `f`'s inputs with each set of added lights.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        inputs: &volfog::pipeline::FrameInputs<'_>,
        f: u32,
    ) -> Result<AreaSamples, BenchError> {
        let with_points: Vec<FogLight> =
            inputs.lights.iter().chain(&self.points).copied().collect();
        let mut samples = [Sample::default(); 4];
        for k in 0..4 {
            let which = (k + f as usize) % 4;
            let lit = match which {
                1 => volfog::pipeline::FrameInputs {
                    lights: &with_points,
                    ..inputs.clone()
                },
                2 | 3 => volfog::pipeline::FrameInputs {
                    area_lights: if which == 2 { &self.rects } else { &self.disks },
                    ..inputs.clone()
                },
                _ => inputs.clone(),
            };
            self.screen.fog.prepare(&gpu.queue, &lit)?;
            let (t, wall) = self.screen.passes(gpu, &[FogPass::Inject], false)?;
            samples[which] = Sample {
                gpu: t.inject,
                cpu: wall.inject,
            };
        }
        let [none, points, rects, disks] = samples;
        Ok(AreaSamples {
            none,
            points,
            rects,
            disks,
        })
    }
}

/// What an area light costs in the run, against a point light.
#[derive(Debug, Clone, Serialize)]
pub struct AreaLightCost {
    /// Median inject with the scene's own lights, the area-light variant (ms).
    pub inject_ms: f64,
    /// Median inject with four point lights added, minus that, per light (ms).
    pub point_ms: f64,
    /// The same with four rectangle lights.
    pub rect_ms: f64,
    /// The same with four disk lights.
    pub disk_ms: f64,
    /// A rectangle light's cost over a point light's.
    pub rect_vs_point: f64,
    /// A disk light's cost over a point light's.
    pub disk_vs_point: f64,
}

/// The area lights' figures from the medians of the run.
pub(super) fn area_light_cost(median: &dyn Fn(&str) -> f64) -> AreaLightCost {
    let none = median("inject_area_none");
    let per = |key: &str| (median(key) - none) / PLACES.len() as f64;
    let point = per("inject_area_points");
    AreaLightCost {
        inject_ms: none,
        point_ms: point,
        rect_ms: per("inject_area_rects"),
        disk_ms: per("inject_area_disks"),
        rect_vs_point: per("inject_area_rects") / point,
        disk_vs_point: per("inject_area_disks") / point,
    }
}

/// The area lights' line of the table.
pub(super) fn area_light_table(out: &mut String, a: &AreaLightCost) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "\narea lights (inject, the area-light variant, 4 lights added to the scene's):\n  \
         inject {:.3} ms; per point light +{:.4} ms; per rectangle light +{:.4} ms (x{:.1} a \
         point light); per disk light +{:.4} ms (x{:.1})",
        a.inject_ms, a.point_ms, a.rect_ms, a.rect_vs_point, a.disk_ms, a.disk_vs_point
    );
}
