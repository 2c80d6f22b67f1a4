// volfog::soft_particles — depth fade of camera-facing particles treated as volumes.
//
// Use:      #import volfog::soft_particles::soft_particle_fade
//           let fade = soft_particle_fade(particle_view_depth, scene_view_depth, thickness);
//           color.a *= fade;
// Defines:  none
// Model:    a billboard at view depth z_p stands for a view-aligned box spanning view
//           depths [z_p - thickness / 2, z_p + thickness / 2]. The view ray travels
//           through the part of it in front of both the scene depth (opaque geometry
//           behind the particle) and behind the eye (depth 0); the fade is that part's
//           share of the whole box. As the box faces are perpendicular to the view axis,
//           the share of ray length equals the share of view depth, for any ray.
//           The fade is 1 with nothing near, 1/2 where the billboard plane meets the
//           geometry (the hard intersection line of a plain billboard), 0 where the box
//           is entirely behind the geometry, and falls as the eye enters the box.
// Units:    view depths in metres along the view axis, positive in front of the eye
//           (the linear depth the froxel modules use); clamped to +-1e9 m.
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "Soft
//           Particles" (a camera aligned volume box rather than a sphere).
#define_import_path volfog::soft_particles

// A box thinner than this (m) is treated as a plane: the fade is a hard depth test.
const SOFT_PARTICLE_MIN_THICKNESS: f32 = 1e-6;
// View depths (m) are clamped to +-SOFT_PARTICLE_DEPTH_LIMIT.
const SOFT_PARTICLE_DEPTH_LIMIT: f32 = 1e9;

// Share in [0, 1] of the view-aligned box spanning view depths [front, back] that lies
// in front of scene_depth and behind the eye.
fn soft_particle_box_fade(front: f32, back: f32, scene_depth: f32) -> f32 {
    let f = clamp(front, -SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    let b = clamp(back, f, SOFT_PARTICLE_DEPTH_LIMIT);
    let s = clamp(scene_depth, -SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    let thickness = b - f;
    if thickness < SOFT_PARTICLE_MIN_THICKNESS {
        let plane = 0.5 * (f + b);
        return select(0.0, 1.0, s > plane && plane >= 0.0);
    }
    return clamp((min(s, b) - max(f, 0.0)) / thickness, 0.0, 1.0);
}

// Fade factor in [0, 1] of a particle at view depth particle_depth standing for a box of
// the given thickness (m) centred on it, with the opaque scene at view depth scene_depth.
fn soft_particle_fade(particle_depth: f32, scene_depth: f32, thickness: f32) -> f32 {
    let half = 0.5 * clamp(thickness, 0.0, SOFT_PARTICLE_DEPTH_LIMIT);
    let z = clamp(particle_depth, -SOFT_PARTICLE_DEPTH_LIMIT, SOFT_PARTICLE_DEPTH_LIMIT);
    return soft_particle_box_fade(z - half, z + half, scene_depth);
}
