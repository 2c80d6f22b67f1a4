//! Fog for alpha-transparent objects the way Wenzel 2007 ("Fog and Alpha-Transparent
//! Objects") does it where per-pixel fog is not available: fog volumes per object on
//! the CPU, the global fog per vertex (`volfog::height_fog::height_fog_vertex`).
//!
//! A transparent object is shaded and fogged in the same pass, and the fog passes that
//! read the depth buffer never see it. [`object_fog`] gives one fog value, `(in-scatter
//! rgb, T)`, for the whole object, to pass as a uniform and apply with
//! `volfog::apply::apply_fog`: the fog volumes between the camera and the object,
//! processed back to front along each ray and averaged with weights over seven points
//! of its bounding sphere (the centre, weight 1/4, and the six points at `radius` along
//! the camera's right, up and view axes, 1/8 each). Keep such objects small and the
//! fog gradients soft, as the seed says; `tests/host/transparent.rs` measures the
//! error against per-pixel fog.
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use volfog::cpu::transparent::object_fog;
//! use volfog::uniforms::{FogVolume, VolumeShape};
//!
//! let bank = FogVolume::new(Mat4::from_scale(Vec3::splat(10.0)), VolumeShape::Ellipsoid, Vec3::ONE, 0.05).unwrap();
//! let camera = Vec3::new(0.0, 0.0, 30.0);
//! // A glass sphere behind the fog bank sees its whole width: 20 m at 0.05 / m.
//! let fog = object_fog(&[bank], camera, Vec3::new(0.0, 0.0, -20.0), 0.5);
//! assert!((fog.w - (-1.0f32).exp()).abs() < 0.01);
//! // In front of it, no fog.
//! assert_eq!(object_fog(&[bank], camera, Vec3::new(0.0, 0.0, 20.0), 0.5).w, 1.0);
//! ```

use glam::{Vec3, Vec4};

use super::fog_volume::fog_volumes_along;
use crate::uniforms::FogVolume;

/// Weight of the bounding sphere's centre in [`object_fog`]; the six axis points share
/// the rest equally.
pub const OBJECT_FOG_CENTER_WEIGHT: f32 = 0.25;

/// The seven points [`object_fog`] averages over, with their weights: the centre and
/// `center +- radius` along the camera's right, up and view axes (`up` is world +Y
/// unless the view is vertical, then +Z).
pub fn object_fog_points(camera_pos: Vec3, center: Vec3, radius: f32) -> [(Vec3, f32); 7] {
    let view = (center - camera_pos).normalize_or(Vec3::NEG_Z);
    let helper = if view.y.abs() > 0.999 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    let right = view.cross(helper).normalize();
    let up = right.cross(view);
    let r = radius.max(0.0);
    let side = (1.0 - OBJECT_FOG_CENTER_WEIGHT) / 6.0;
    [
        (center, OBJECT_FOG_CENTER_WEIGHT),
        (center + right * r, side),
        (center - right * r, side),
        (center + up * r, side),
        (center - up * r, side),
        (center - view * r, side),
        (center + view * r, side),
    ]
}

/// Fog `(in-scatter rgb, T)` of the fog volumes for a transparent object with
/// bounding sphere (`center`, `radius`) seen from `camera_pos`: per point of
/// [`object_fog_points`], the volumes the ray crosses composited back to front in the
/// order the ray enters them ([`fog_volumes_along`]), then the weighted mean.
pub fn object_fog(volumes: &[FogVolume], camera_pos: Vec3, center: Vec3, radius: f32) -> Vec4 {
    object_fog_points(camera_pos, center, radius)
        .iter()
        .map(|(p, w)| fog_volumes_along(volumes, camera_pos, *p) * *w)
        .sum()
}
