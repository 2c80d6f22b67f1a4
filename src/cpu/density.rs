//! Mirror of `volfog::density`: extinction of the medium at a point.
//!
//! ```
//! use volfog::cpu::density::height_density;
//! // b e^(-c (h - h0)): 0.1 / m at the base height, e times less 1 / c higher.
//! assert!((height_density(0.0, 0.1, 0.5, 0.0) - 0.1).abs() < 1e-7);
//! assert!((height_density(2.0, 0.1, 0.5, 0.0) - 0.1 / std::f32::consts::E).abs() < 1e-7);
//! ```

use glam::Vec3;

use crate::uniforms::{FogMedium, LocalVolume};

/// Exponents are clamped to this magnitude.
pub const DENSITY_MAX_EXPONENT: f32 = 80.0;

/// Exponential height profile `b e^(-c (h - h0))`.
pub fn height_density(h: f32, b: f32, c: f32, h0: f32) -> f32 {
    b * (-c * (h - h0))
        .clamp(-DENSITY_MAX_EXPONENT, DENSITY_MAX_EXPONENT)
        .exp()
}

/// Soft membership of a point in unit shape space (0 box, 1 ellipsoid).
pub fn local_volume_weight(local: Vec3, shape: u32, edge: f32) -> f32 {
    let d = if shape == 0 {
        local.abs().max_element()
    } else {
        local.length()
    };
    ((1.0 - d) / edge.max(1e-4)).clamp(0.0, 1.0)
}

/// Extinction a local volume adds at a world position.
pub fn local_volume_density(volume: &LocalVolume, world: Vec3) -> f32 {
    let local = volume.local_from_world.transform_point3(world);
    volume.density * local_volume_weight(local, volume.shape, volume.edge)
}

/// Whether a local volume can add extinction anywhere in the world-space sphere
/// (`center`, `radius`): conservative (see `volfog::density`).
pub fn local_volume_touches_sphere(volume: &LocalVolume, center: Vec3, radius: f32) -> bool {
    let m = volume.local_from_world;
    let local = m.transform_point3(center);
    let scale = (m.x_axis.truncate().length_squared()
        + m.y_axis.truncate().length_squared()
        + m.z_axis.truncate().length_squared())
    .sqrt();
    let outside = (local.abs() - Vec3::ONE).max(Vec3::ZERO);
    outside.length() <= radius * scale
}

/// Global extinction at a world position for a noise value and texture factor.
pub fn medium_extinction(medium: &FogMedium, world: Vec3, noise: f32, texture_factor: f32) -> f32 {
    let h = world.dot(medium.up);
    let profile = height_density(h, medium.density, medium.height_falloff, medium.base_height);
    let modulation = (1.0 + medium.noise_strength * noise).max(0.0);
    profile * modulation * texture_factor.max(0.0)
}
