//! Mirror of `volfog::soft_particles`: depth fade of a particle treated as a
//! view-aligned volume box (Wenzel 2007, "Soft Particles").
//!
//! ```
//! use volfog::cpu::soft_particles::soft_particle_fade;
//! // A 1 m thick particle 10 m away.
//! assert_eq!(soft_particle_fade(10.0, 100.0, 1.0), 1.0); // nothing near: opaque
//! assert_eq!(soft_particle_fade(10.0, 10.0, 1.0), 0.5); // the hard intersection line
//! assert_eq!(soft_particle_fade(10.0, 9.75, 1.0), 0.25); // a wall a bit in front of it
//! assert_eq!(soft_particle_fade(10.0, 9.5, 1.0), 0.0); // hidden behind the wall
//! ```

/// A box thinner than this (m) is treated as a plane: the fade is a hard depth test.
pub const SOFT_PARTICLE_MIN_THICKNESS: f32 = 1e-6;
/// View depths (m) are clamped to `+-SOFT_PARTICLE_DEPTH_LIMIT`.
pub const SOFT_PARTICLE_DEPTH_LIMIT: f32 = 1e9;

/// Share in `[0, 1]` of the view-aligned box spanning view depths `[front, back]` that
/// lies in front of `scene_depth` and behind the eye (view depth 0).
pub fn soft_particle_box_fade(front: f32, back: f32, scene_depth: f32) -> f32 {
    let f = front.clamp(-SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    let b = back.clamp(f, SOFT_PARTICLE_DEPTH_LIMIT);
    let s = scene_depth.clamp(-SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    let thickness = b - f;
    if thickness < SOFT_PARTICLE_MIN_THICKNESS {
        let plane = 0.5 * (f + b);
        return if s > plane && plane >= 0.0 { 1.0 } else { 0.0 };
    }
    ((s.min(b) - f.max(0.0)) / thickness).clamp(0.0, 1.0)
}

/// Fade factor in `[0, 1]` of a particle at view depth `particle_depth` standing for a
/// box of `thickness` metres centred on it, with the opaque scene at `scene_depth`.
pub fn soft_particle_fade(particle_depth: f32, scene_depth: f32, thickness: f32) -> f32 {
    let half = 0.5 * thickness.clamp(0.0, SOFT_PARTICLE_DEPTH_LIMIT);
    let z = particle_depth.clamp(-SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    soft_particle_box_fade(z - half, z + half, scene_depth)
}
