//! Particles over the bench scene (`FrameInputs::particles`): the baseline fog with
//! room for 10,000 particles (the `VOLFOG_INJECT_PARTICLES` variant) times its inject
//! with none, 1,000 and 10,000 particles, the order rotating from frame to frame; the
//! baseline's own inject (without the variant) is the `inject` series.

use super::*;
use glam::Vec3;
use volfog::uniforms::FogParticle;

/// The most particles timed, and the fog's capacity.
const MOST: usize = 10_000;
/// The smaller count timed.
const SOME: usize = 1_000;

/// `MOST` particles of dust and smoke over the colonnade's aisle, 11 to 51 m ahead of
/// the camera and up to 5 m high: radius 0.3 to 1.2 m, extinction 0.05 to 0.5 /m,
/// smooth; one in eight glowing. Deterministic (a 64-bit LCG); the first `SOME` are
/// spread over the same region.
fn dust() -> Vec<FogParticle> {
    let mut state = 41u64;
    let mut unit = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..MOST)
        .map(|i| FogParticle {
            position: Vec3::new(-6.0 + 12.0 * unit(), 5.0 * unit(), -5.0 - 40.0 * unit()),
            radius: 0.3 + 0.9 * unit(),
            albedo: Vec3::splat(0.5 + 0.4 * unit()),
            extinction: 0.05 + 0.45 * unit(),
            emission: if i % 8 == 0 {
                Vec3::new(2.0, 0.8, 0.2) * unit()
            } else {
                Vec3::ZERO
            },
            falloff: 1.0,
        })
        .collect()
}

/// The fog with room for the particles, and the particles.
pub(super) struct Particles {
    screen: Screen,
    particles: Vec<FogParticle>,
}

/// One frame's injects: no particle, 1,000 and 10,000.
pub(super) struct ParticleSamples {
    pub(super) none: Sample,
    pub(super) some: Sample,
    pub(super) most: Sample,
}

impl Particles {
    /// A fog of the baseline configuration with `max_particles` 10,000 over the main
    /// screen, run twice untimed with the scene's inputs and every particle (so the
    /// first timed inject pays no first use).
    pub(super) fn new(
        gpu: &Gpu,
        config: &FogConfig,
        scene: &Scene,
        cascades: volfog::uniforms::ShadowCascades,
        shadow_map: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<Self, BenchError> {
        let config = FogConfig {
            max_particles: MOST as u32,
            ..config.clone()
        };
        let mut screen = Screen::new(gpu, &config, shadow_map, depth, SCREEN)?;
        let particles = dust();
        for f in 0..2 {
            let inputs = scene.inputs(f as f32 / 60.0, cascades);
            screen.fog.prepare(
                &gpu.queue,
                &volfog::pipeline::FrameInputs {
                    particles: &particles,
                    ..inputs
                },
            )?;
            screen.passes(gpu, &FogPass::ALL, false)?;
        }
        Ok(Self { screen, particles })
    }

    /// Times the inject of frame `f`'s inputs with each particle count.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        inputs: &volfog::pipeline::FrameInputs<'_>,
        f: u32,
    ) -> Result<ParticleSamples, BenchError> {
        let counts = [0, SOME, MOST];
        let mut samples = [Sample::default(); 3];
        for k in 0..3 {
            let which = (k + f as usize) % 3;
            self.screen.fog.prepare(
                &gpu.queue,
                &volfog::pipeline::FrameInputs {
                    particles: &self.particles[..counts[which]],
                    ..inputs.clone()
                },
            )?;
            let (t, wall) = self.screen.passes(gpu, &[FogPass::Inject], false)?;
            samples[which] = Sample {
                gpu: t.inject,
                cpu: wall.inject,
            };
        }
        let [none, some, most] = samples;
        Ok(ParticleSamples { none, some, most })
    }
}

/// What particles cost in the run.
#[derive(Debug, Clone, Serialize)]
pub struct ParticleCost {
    /// Median inject of the baseline, without the particle variant (ms).
    pub baseline_inject_ms: f64,
    /// Median inject of the particle variant with no particle (ms).
    pub inject_0_ms: f64,
    /// The same with 1,000 particles.
    pub inject_1000_ms: f64,
    /// The same with 10,000 particles.
    pub inject_10000_ms: f64,
    /// 1,000 particles' inject over none's.
    pub ratio_1000_vs_0: f64,
    /// 10,000 particles' inject over none's.
    pub ratio_10000_vs_0: f64,
}

/// The particles' figures from the medians of the run.
pub(super) fn particle_cost(median: &dyn Fn(&str) -> f64) -> ParticleCost {
    let none = median("inject_particles_0");
    ParticleCost {
        baseline_inject_ms: median("inject"),
        inject_0_ms: none,
        inject_1000_ms: median("inject_particles_1000"),
        inject_10000_ms: median("inject_particles_10000"),
        ratio_1000_vs_0: median("inject_particles_1000") / none,
        ratio_10000_vs_0: median("inject_particles_10000") / none,
    }
}

/// The particles' line of the table.
pub(super) fn particle_table(out: &mut String, p: &ParticleCost) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "\nparticles (inject, the particle variant with room for 10,000):\n  \
         baseline inject {:.3} ms; 0 particles {:.3} ms; 1,000 particles {:.3} ms (x{:.2}); \
         10,000 particles {:.3} ms (x{:.2})",
        p.baseline_inject_ms,
        p.inject_0_ms,
        p.inject_1000_ms,
        p.ratio_1000_vs_0,
        p.inject_10000_ms,
        p.ratio_10000_vs_0
    );
}
