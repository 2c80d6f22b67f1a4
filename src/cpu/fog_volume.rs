//! Mirror of `volfog::fog_volume`: analytic box, ellipsoid and plane fog volumes (Wenzel
//! 2007, "Fog Volumes"), ray traced in local space and integrated in closed form.
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use volfog::cpu::fog_volume::{fog_over, fog_volume, fog_volume_entry_exit, FOG_NONE};
//! use volfog::uniforms::{FogVolume, VolumeShape};
//!
//! // A 10 m cube of uniform fog (0.1 / m) centred at the origin.
//! let cube = FogVolume::new(
//!     Mat4::from_scale(Vec3::splat(5.0)),
//!     VolumeShape::Box,
//!     Vec3::ONE,
//!     0.1,
//! )
//! .unwrap();
//! let eye = Vec3::new(-20.0, 0.0, 0.0);
//! let wall = Vec3::new(20.0, 0.0, 0.0);
//! // The segment eye -> wall enters at x = -5 (t = 0.375) and leaves at x = 5.
//! let t = fog_volume_entry_exit(&cube, eye, wall);
//! assert!((t.x - 0.375).abs() < 1e-6 && (t.y - 0.625).abs() < 1e-6);
//! // 10 m of fog at 0.1 / m: transmittance exp(-1).
//! let fog = fog_volume(&cube, eye, wall);
//! assert!((fog.w - (-1.0f32).exp()).abs() < 1e-6);
//! // A point in front of the cube sees no fog; compositing starts from FOG_NONE.
//! let near = fog_volume(&cube, eye, Vec3::new(-10.0, 0.0, 0.0));
//! assert_eq!(fog_over(near, FOG_NONE), FOG_NONE);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::height_fog::{fog_inscatter, height_fog_optical_depth};
use crate::limits::FOG_POSITION_LIMIT;
use crate::uniforms::FogVolume;

/// Shape code of a box (`FogVolume.shape`).
pub const FOG_VOLUME_BOX: u32 = 0;
/// Shape code of an ellipsoid (`FogVolume.shape`).
pub const FOG_VOLUME_ELLIPSOID: u32 = 1;
/// Shape code of a plane volume, fog below a plane (`FogVolume.shape`).
pub const FOG_VOLUME_PLANE: u32 = 2;
/// No fog: no in-scattering, transmittance 1.
pub const FOG_NONE: Vec4 = Vec4::new(0.0, 0.0, 0.0, 1.0);
/// Direction components below this magnitude are replaced by it in the slab test.
pub const FOG_VOLUME_MIN_DIRECTION: f32 = 1e-12;

/// Line parameters `(t_near, t_far)` of `ro + t rd` through the box `[-1, 1]^3`;
/// `t_near > t_far` on a miss.
pub fn ray_unit_box(ro: Vec3, rd: Vec3) -> Vec2 {
    let safe = Vec3::select(
        rd.abs().cmplt(Vec3::splat(FOG_VOLUME_MIN_DIRECTION)),
        Vec3::splat(FOG_VOLUME_MIN_DIRECTION),
        rd,
    );
    let inv = 1.0 / safe;
    let ta = (Vec3::NEG_ONE - ro) * inv;
    let tb = (Vec3::ONE - ro) * inv;
    let lo = ta.min(tb);
    let hi = ta.max(tb);
    Vec2::new(lo.x.max(lo.y.max(lo.z)), hi.x.min(hi.y.min(hi.z)))
}

/// Line parameters `(t_near, t_far)` of `ro + t rd` through the unit sphere;
/// `t_near > t_far` on a miss or for a zero `rd`.
pub fn ray_unit_sphere(ro: Vec3, rd: Vec3) -> Vec2 {
    let s = rd.x.abs().max(rd.y.abs().max(rd.z.abs()));
    let du = rd / s.max(1e-30);
    let lu = du.length();
    let dn = du / lu.max(1e-30);
    let len = (s * lu).max(1e-30);
    let tc = -ro.dot(dn);
    let closest = (ro + tc * dn).clamp(Vec3::splat(-2.0), Vec3::splat(2.0));
    let h2 = 1.0 - closest.dot(closest);
    let h = h2.max(0.0).sqrt();
    if h2 >= 0.0 && s > 1e-30 {
        Vec2::new(tc - h, tc + h) / len
    } else {
        Vec2::new(1.0, 0.0)
    }
}

/// Line parameters `(t_near, t_far)` of `ro + t rd` in the half-space `y <= 0`
/// (unbounded ends are +-1e30); `t_near > t_far` on a miss. A line in the plane `y = 0`
/// lies inside.
pub fn ray_half_space(ro: Vec3, rd: Vec3) -> Vec2 {
    let far = 1e30;
    if rd.y.abs() < FOG_VOLUME_MIN_DIRECTION {
        return if ro.y <= 0.0 {
            Vec2::new(-far, far)
        } else {
            Vec2::new(1.0, 0.0)
        };
    }
    let t = -ro.y / rd.y;
    if rd.y > 0.0 {
        Vec2::new(-far, t)
    } else {
        Vec2::new(t, far)
    }
}

fn clamped_segment(camera_pos: Vec3, point: Vec3) -> (Vec3, Vec3) {
    let lim = Vec3::splat(FOG_POSITION_LIMIT);
    let eye = camera_pos.clamp(-lim, lim);
    (eye, point.clamp(-lim, lim) - eye)
}

/// Ray parameters `[t0, t1]` within `[0, 1]` of the part of the segment from
/// `camera_pos` (t = 0) to `point` (t = 1, the scene depth) inside the volume;
/// `t0 == t1` on a miss.
pub fn fog_volume_entry_exit(volume: &FogVolume, camera_pos: Vec3, point: Vec3) -> Vec2 {
    let (eye, seg) = clamped_segment(camera_pos, point);
    let ro = (volume.local_from_world * eye.extend(1.0)).truncate();
    let rd = (volume.local_from_world * seg.extend(0.0)).truncate();
    let t = if volume.shape == FOG_VOLUME_ELLIPSOID {
        ray_unit_sphere(ro, rd)
    } else if volume.shape == FOG_VOLUME_PLANE {
        ray_half_space(ro, rd)
    } else {
        ray_unit_box(ro, rd)
    };
    let t0 = t.x.clamp(0.0, 1.0);
    Vec2::new(t0, t.y.clamp(t0, 1.0))
}

/// Optical depth of the volume's fog between `camera_pos` and `point`.
pub fn fog_volume_optical_depth(volume: &FogVolume, camera_pos: Vec3, point: Vec3) -> f32 {
    let t = fog_volume_entry_exit(volume, camera_pos, point);
    let (eye, seg) = clamped_segment(camera_pos, point);
    let entry = eye + t.x * seg;
    height_fog_optical_depth(
        volume.density,
        volume.falloff,
        volume.offset,
        volume.gradient,
        entry - volume.center,
        (t.y - t.x) * seg,
    )
}

/// Fog of one volume between `camera_pos` and `point`: `(in-scatter rgb, T)`.
pub fn fog_volume(volume: &FogVolume, camera_pos: Vec3, point: Vec3) -> Vec4 {
    fog_inscatter(
        volume.color,
        fog_volume_optical_depth(volume, camera_pos, point),
    )
}

/// Composites the fog of a volume in front over fog accumulated behind it.
pub fn fog_over(front: Vec4, behind: Vec4) -> Vec4 {
    (front.truncate() + front.w * behind.truncate()).extend(front.w * behind.w)
}

/// Fog of several volumes between `camera_pos` and `point`, composited back to front
/// (volumes sorted by the distance of their centres from the camera, farthest first).
/// Exact when the volumes do not overlap along the segment.
pub fn fog_volumes(volumes: &[FogVolume], camera_pos: Vec3, point: Vec3) -> Vec4 {
    let mut order: Vec<&FogVolume> = volumes.iter().collect();
    order.sort_by(|a, b| {
        let da = a.center.distance_squared(camera_pos);
        let db = b.center.distance_squared(camera_pos);
        db.total_cmp(&da)
    });
    order.into_iter().fold(FOG_NONE, |acc, v| {
        fog_over(fog_volume(v, camera_pos, point), acc)
    })
}

/// Fog of several volumes between `camera_pos` and `point`, composited back to front
/// in the order the segment enters them (the volume entered last first): exact for
/// volumes that do not overlap along the segment, whatever their sizes (a plane volume
/// has no meaningful centre). Volumes the segment misses are skipped.
pub fn fog_volumes_along(volumes: &[FogVolume], camera_pos: Vec3, point: Vec3) -> Vec4 {
    let mut hits: Vec<(f32, &FogVolume)> = volumes
        .iter()
        .map(|v| (fog_volume_entry_exit(v, camera_pos, point), v))
        .filter(|(t, _)| t.y > t.x)
        .map(|(t, v)| (t.x, v))
        .collect();
    hits.sort_by(|a, b| b.0.total_cmp(&a.0));
    hits.into_iter().fold(FOG_NONE, |acc, (_, v)| {
        fog_over(fog_volume(v, camera_pos, point), acc)
    })
}
