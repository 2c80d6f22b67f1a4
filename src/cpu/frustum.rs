//! Mirror of `volfog::frustum`: world positions from depth through rays interpolated
//! from the screen's corners (Wenzel 2007, "Recovering World Space Position from
//! Depth").
//!
//! ```
//! use glam::{Mat4, Vec2, Vec3, Vec4};
//! use volfog::cpu::frustum::{frustum_ray, frustum_view_depth, frustum_world_position};
//! use volfog::uniforms::FrustumRays;
//!
//! let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
//! let world_from_view = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
//! let rays = FrustumRays::new(world_from_view, proj).unwrap();
//! // A point 10 m in front of the camera, through the screen centre.
//! let clip = proj * Vec4::new(0.0, 0.0, -10.0, 1.0);
//! let depth = clip.z / clip.w;
//! let p = frustum_world_position(&rays, frustum_ray(&rays, Vec2::splat(0.5)), frustum_view_depth(&rays, depth));
//! assert!(p.distance(Vec3::new(1.0, 2.0, -7.0)) < 1e-4);
//! ```

use glam::{Vec2, Vec3, Vec4};

use crate::uniforms::FrustumRays;

/// The world ray (to view depth 1) through screen `uv` (v down).
pub fn frustum_ray(rays: &FrustumRays, uv: Vec2) -> Vec3 {
    let c = rays.corners.map(|c| c.truncate());
    let top = c[0].lerp(c[1], uv.x);
    let bottom = c[2].lerp(c[3], uv.x);
    top.lerp(bottom, uv.y)
}

/// Vertex `index` of the fullscreen triangle: its clip position and ray.
pub fn frustum_vertex(rays: &FrustumRays, index: u32) -> (Vec4, Vec3) {
    let xy = Vec2::new(((index << 1) & 2) as f32, (index & 2) as f32);
    let clip = (xy * 2.0 - 1.0).extend(0.0).extend(1.0);
    let uv = Vec2::new(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5);
    (clip, frustum_ray(rays, uv))
}

/// View depth (m) of a depth value given a projection's depth terms
/// (`-(t.x d + t.y) / (t.z d + t.w)`); at most 1e30.
pub fn frustum_depth_from_terms(t: Vec4, depth: f32) -> f32 {
    let w = t.z * depth + t.w;
    let w = if w.abs() < 1e-30 { 1e-30 } else { w };
    (-(t.x * depth + t.y) / w).min(1e30)
}

/// View depth (m) of a depth-buffer value; at most 1e30.
pub fn frustum_view_depth(rays: &FrustumRays, depth: f32) -> f32 {
    frustum_depth_from_terms(rays.depth_terms, depth)
}

/// Is a pixel at this view depth the sky (at or beyond the far plane)?
pub fn frustum_is_sky(rays: &FrustumRays, view_depth: f32) -> bool {
    view_depth >= 0.9999 * rays.camera.w
}

/// World position of the pixel with `ray` at `view_depth`: one multiply-add.
pub fn frustum_world_position(rays: &FrustumRays, ray: Vec3, view_depth: f32) -> Vec3 {
    rays.camera.truncate() + ray * view_depth
}
