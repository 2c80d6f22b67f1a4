//! Shadow cascades for a directional light: projections and split depths.

use glam::{Mat4, Vec3, Vec4};

/// A world-space orthographic light projection for one cascade: the light looks
/// along `-direction` (direction towards the light) at `center`, covering a square of
/// `half_extent` metres and `depth_range` metres of depth centred on `center`.
pub fn cascade_projection(
    direction: Vec3,
    center: Vec3,
    half_extent: f32,
    depth_range: f32,
) -> Mat4 {
    let dir = direction.normalize();
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let eye = center + dir * (depth_range * 0.5);
    let view = glam::camera::rh::view::look_at_mat4(eye, center, up);
    let proj = glam::camera::rh::proj::directx::orthographic(
        -half_extent,
        half_extent,
        -half_extent,
        half_extent,
        0.0,
        depth_range,
    );
    proj * view
}

/// Splits of `count` cascades between `near` and `far` (m), blending logarithmic and
/// uniform splits by `lambda` in [0, 1] (the practical split scheme).
pub fn cascade_splits(count: u32, near: f32, far: f32, lambda: f32) -> Vec4 {
    let mut splits = [far; 4];
    for (i, split) in splits.iter_mut().enumerate().take(count as usize) {
        let f = (i + 1) as f32 / count as f32;
        let log = near * (far / near).powf(f);
        let uniform = near + (far - near) * f;
        *split = lambda * log + (1.0 - lambda) * uniform;
    }
    Vec4::from_array(splits)
}
