//! Mirror of `volfog::froxel`: depth slices and screen mapping.
//!
//! ```
//! use volfog::cpu::froxel::{slice_coord, slice_depth};
//! let (near, far, curve) = (0.5, 128.0, (128.0f32 / 0.5).ln());
//! // With curve = ln(far / near) the slices have a constant depth ratio.
//! assert!((slice_depth(0.5, near, far, curve) - 8.0).abs() < 1e-3);
//! assert!((slice_coord(8.0, near, far, curve) - 0.5).abs() < 1e-5);
//! ```

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Below this curve the distribution uses its series in `curve`.
pub const CURVE_LINEAR_LIMIT: f32 = 1e-3;

/// View depth (m) at normalised slice coordinate `t`.
pub fn slice_depth(t: f32, near: f32, far: f32, curve: f32) -> f32 {
    let span = far - near;
    if curve < CURVE_LINEAR_LIMIT {
        return near + span * (t + 0.5 * curve * t * (t - 1.0));
    }
    near + span * ((curve * t).exp() - 1.0) / (curve.exp() - 1.0)
}

/// Normalised slice coordinate of view depth `z` (clamped to `z >= near`).
pub fn slice_coord(z: f32, near: f32, far: f32, curve: f32) -> f32 {
    let s = (z - near).max(0.0) / (far - near);
    if curve < CURVE_LINEAR_LIMIT {
        return s - 0.5 * curve * s * (s - 1.0);
    }
    (1.0 + s * (curve.exp() - 1.0)).ln() / curve
}

/// Normalised device x, y (y up) of screen uv (v down).
pub fn ndc_from_uv(uv: Vec2) -> Vec2 {
    Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0)
}

/// Screen uv (v down) of normalised device x, y (y up).
pub fn uv_from_ndc(ndc: Vec2) -> Vec2 {
    Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
}

/// View-space position of a point in normalised device coordinates.
pub fn view_from_ndc(ndc: Vec3, view_from_clip: Mat4) -> Vec3 {
    let p = view_from_clip * Vec4::new(ndc.x, ndc.y, ndc.z, 1.0);
    let w = if p.w.abs() < 1e-30 { 1e-30 } else { p.w };
    (p.truncate() / w).clamp(Vec3::splat(-3.0e38), Vec3::splat(3.0e38))
}

/// Path length per metre of view depth of the ray through screen uv.
pub fn ray_scale(uv: Vec2, view_from_clip: Mat4) -> f32 {
    let n = ndc_from_uv(uv);
    let p = view_from_ndc(Vec3::new(n.x, n.y, 0.5), view_from_clip);
    p.length() / p.z.abs().max(1e-30)
}

/// Radical inverse of `index` in `base` (Halton sequence), in [0, 1).
pub fn halton(index: u32, base: u32) -> f32 {
    let mut f = 1.0f32;
    let mut r = 0.0f32;
    let mut i = index;
    let inv = 1.0 / base as f32;
    while i > 0 {
        f *= inv;
        r += f * (i % base) as f32;
        i /= base;
    }
    r
}

/// Sample offset inside a froxel for a frame: Halton (2, 3, 5) of `frame % 16 + 1`,
/// minus 0.5 (froxel units).
pub fn froxel_jitter(frame: u32) -> Vec3 {
    let i = frame % 16 + 1;
    Vec3::new(halton(i, 2), halton(i, 3), halton(i, 5)) - 0.5
}

/// View-space position of a point inside froxel `id` at `offset` from its centre.
pub fn froxel_view_position(
    id: glam::UVec3,
    offset: Vec3,
    size: glam::UVec3,
    view_from_clip: Mat4,
    near: f32,
    far: f32,
    curve: f32,
) -> Vec3 {
    let cell = (id.as_vec3() + 0.5 + offset) / size.as_vec3();
    let depth = slice_depth(cell.z, near, far, curve);
    let n = ndc_from_uv(Vec2::new(cell.x, cell.y));
    let ray = view_from_ndc(Vec3::new(n.x, n.y, 0.5), view_from_clip);
    ray * (depth / ray.z.abs().max(1e-30))
}
