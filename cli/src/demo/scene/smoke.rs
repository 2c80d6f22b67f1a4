//! Smoke rising from a fire beyond the pool: the demo's particles
//! (`FrameInputs::particles`), a column of puffs that rise, widen, thin and drift with
//! the wind, glowing at the base where the fire is.

use glam::Vec3;
use volfog::uniforms::FogParticle;

/// Where the fire burns (m): on the ground beyond the pool, left of the glass sphere.
pub const FIRE: Vec3 = Vec3::new(1.6, 0.0, -21.0);
/// Puffs in the column.
pub const PUFFS: usize = 96;
/// How high a puff rises before it is released again (m).
const RISE: f32 = 7.0;
/// Rising speed (m/s).
const SPEED: f32 = 0.9;

/// The column at time `time` (s): puff `i` has risen by `(i RISE / PUFFS + SPEED time)
/// mod RISE` metres; it widens from 0.35 to 1.6 m, its extinction falls from 1.2 to
/// 0.1 /m, it leans with the wind as it rises, and the lowest metre glows.
pub fn smoke(time: f32) -> Vec<FogParticle> {
    (0..PUFFS)
        .map(|i| {
            let h = (i as f32 * RISE / PUFFS as f32 + SPEED * time) % RISE;
            let f = h / RISE;
            // A deterministic sway per puff, and the wind's lean (the medium's wind
            // blows towards +x, -z).
            let phase = i as f32 * 2.399;
            let sway = Vec3::new(phase.cos(), 0.0, phase.sin()) * (0.15 + 0.4 * f);
            let lean = Vec3::new(0.5, 0.0, -0.2) * (h * f);
            let glow = (1.0 - h).max(0.0);
            FogParticle {
                position: FIRE + Vec3::new(0.0, 0.3 + h, 0.0) + sway + lean,
                radius: 0.35 + 1.25 * f,
                albedo: Vec3::splat(0.35 + 0.3 * f),
                extinction: 1.2 * (1.0 - f) * (1.0 - f) + 0.1,
                emission: Vec3::new(3.0, 1.1, 0.25) * glow,
                falloff: 1.0,
            }
        })
        .collect()
}
