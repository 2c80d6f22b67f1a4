//! Mirror of `volfog::fog_volume`: analytic box, ellipsoid, plane, cylinder and cone fog
//! volumes (Wenzel 2007, "Fog Volumes"), ray traced in local space and integrated in
//! closed form.
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
/// Shape code of a cylinder (`FogVolume.shape`).
pub const FOG_VOLUME_CYLINDER: u32 = 3;
/// Shape code of a cone (`FogVolume.shape`).
pub const FOG_VOLUME_CONE: u32 = 4;
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

/// Line parameters of `ro + t d` in the slab `|y| <= 1` (the caps of the cylinder and
/// the cone); `d` scaled to a largest component of 1.
pub fn ray_unit_slab_y(ro: Vec3, d: Vec3) -> Vec2 {
    let far = 1e30;
    if d.y.abs() < FOG_VOLUME_MIN_DIRECTION {
        return if ro.y.abs() <= 1.0 {
            Vec2::new(-far, far)
        } else {
            Vec2::new(1.0, 0.0)
        };
    }
    let ta = (-1.0 - ro.y) / d.y;
    let tb = (1.0 - ro.y) / d.y;
    Vec2::new(ta.min(tb), ta.max(tb))
}

fn xz(v: Vec3) -> Vec2 {
    Vec2::new(v.x, v.z)
}

/// Line parameters `(t_near, t_far)` of `ro + t rd` through the unit cylinder (radius 1
/// around the y axis, `|y| <= 1`); `t_near > t_far` on a miss.
pub fn ray_unit_cylinder(ro: Vec3, rd: Vec3) -> Vec2 {
    let far = 1e30;
    let none = Vec2::new(1.0, 0.0);
    let s = rd.x.abs().max(rd.y.abs().max(rd.z.abs()));
    if s <= 1e-30 {
        return if ro.y.abs().max(xz(ro).length()) <= 1.0 {
            Vec2::new(-far, far)
        } else {
            none
        };
    }
    let d = rd / s;
    let mut side = Vec2::new(-far, far);
    let l = xz(d).length();
    if l > FOG_VOLUME_MIN_DIRECTION {
        let dn = xz(d) / l;
        let uc = -xz(ro).dot(dn);
        let closest = (xz(ro) + uc * dn).clamp(Vec2::splat(-2.0), Vec2::splat(2.0));
        let h2 = 1.0 - closest.dot(closest);
        let h = h2.max(0.0).sqrt();
        side = if h2 >= 0.0 {
            Vec2::new(uc - h, uc + h) / l
        } else {
            none
        };
    } else if xz(ro).dot(xz(ro)) > 1.0 {
        side = none;
    }
    let caps = ray_unit_slab_y(ro, d);
    Vec2::new(side.x.max(caps.x), side.y.min(caps.y)) / s
}

/// Line parameters `(t_near, t_far)` of `ro + t rd` through the unit cone (apex at
/// `y = 1`, a base of radius 1 at `y = -1`); `t_near > t_far` on a miss.
pub fn ray_unit_cone(ro: Vec3, rd: Vec3) -> Vec2 {
    let far = 1e30;
    let none = Vec2::new(1.0, 0.0);
    let s = rd.x.abs().max(rd.y.abs().max(rd.z.abs()));
    if s <= 1e-30 {
        let inside = ro.y.abs().max(xz(ro).length() + 0.5 * (ro.y + 1.0)) <= 1.0;
        return if inside { Vec2::new(-far, far) } else { none };
    }
    let d = rd / s;
    let k0 = 1.0 - ro.y;
    let a = 4.0 * xz(d).dot(xz(d)) - d.y * d.y;
    let b = 8.0 * xz(ro).dot(xz(d)) + 2.0 * k0 * d.y;
    let c = 4.0 * xz(ro).dot(xz(ro)) - k0 * k0;
    let mut side = none;
    if a.abs() < 1e-6 {
        if b.abs() < 1e-12 {
            side = if c <= 0.0 { Vec2::new(-far, far) } else { none };
        } else {
            let u = -c / b;
            side = if b < 0.0 {
                Vec2::new(u, far)
            } else {
                Vec2::new(-far, u)
            };
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 || a < 0.0 {
            let sign = if b >= 0.0 { 1.0 } else { -1.0 };
            let q = -0.5 * (b + sign * disc.max(0.0).sqrt());
            let (mut u1, mut u2) = (0.0, 0.0);
            if q != 0.0 {
                u1 = q / a;
                u2 = c / q;
            }
            let lo = u1.min(u2);
            let hi = u1.max(u2);
            side = if a > 0.0 {
                if k0 - 0.5 * (lo + hi) * d.y >= 0.0 {
                    Vec2::new(lo, hi)
                } else {
                    none
                }
            } else if d.y > 0.0 {
                Vec2::new(-far, lo)
            } else {
                Vec2::new(hi, far)
            };
        }
    }
    let caps = ray_unit_slab_y(ro, d);
    Vec2::new(side.x.max(caps.x), side.y.min(caps.y)) / s
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
    } else if volume.shape == FOG_VOLUME_CYLINDER {
        ray_unit_cylinder(ro, rd)
    } else if volume.shape == FOG_VOLUME_CONE {
        ray_unit_cone(ro, rd)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::density::{LOCAL_VOLUME_CONE, LOCAL_VOLUME_CYLINDER, local_volume_measure};

    /// The chord of each shape against the membership measure of `volfog::density`
    /// sampled along the line (100,000 steps): the two describe the same solid.
    #[test]
    fn cylinder_and_cone_chords_match_the_local_volume_shapes() {
        let mut rng = crate::cpu::TestRng(11);
        let cases = [
            (
                FOG_VOLUME_CYLINDER,
                LOCAL_VOLUME_CYLINDER,
                ray_unit_cylinder as fn(Vec3, Vec3) -> Vec2,
            ),
            (FOG_VOLUME_CONE, LOCAL_VOLUME_CONE, ray_unit_cone),
        ];
        for (name, shape, chord) in cases {
            let (mut hits, mut worst) = (0, 0.0f32);
            for _ in 0..300 {
                let ro = rng.vec(-3.0, 3.0);
                // Lines through a random point near the shape, some of them steep.
                let target = rng.vec(-1.1, 1.1);
                let rd = (target - ro) * rng.range(0.2, 3.0);
                let t = chord(ro, rd);
                let steps = 100_000;
                let (t_lo, t_hi) = (-2.0f32, 3.0f32);
                let dt = (t_hi - t_lo) / steps as f32;
                let inside: Vec<f32> = (0..steps)
                    .map(|i| t_lo + (i as f32 + 0.5) * dt)
                    .filter(|&t| local_volume_measure(ro + t * rd, shape) <= 1.0)
                    .collect();
                let sampled = inside.len() as f32 * dt;
                let analytic = (t.y.min(t_hi) - t.x.max(t_lo)).max(0.0);
                let err = (sampled - analytic).abs();
                worst = worst.max(err);
                assert!(err <= 3.0 * dt, "shape {name}: {ro} {rd}: {sampled} vs {t}");
                if let (Some(first), Some(last)) = (inside.first(), inside.last()) {
                    hits += 1;
                    let (enter, leave) = (t.x.max(t_lo), t.y.min(t_hi));
                    assert!((first - enter).abs() <= 2.0 * dt && (last - leave).abs() <= 2.0 * dt);
                }
            }
            assert!(hits > 100, "shape {name}: {hits} lines hit");
            eprintln!("shape {name}: {hits} of 300 lines hit, chord error <= {worst:.2e}");
        }
    }

    /// Closed-form chords: along and across the axis, through the cone's side.
    #[test]
    fn cylinder_and_cone_chords_in_closed_form() {
        let t = ray_unit_cylinder(Vec3::new(-5.0, 0.3, 0.0), Vec3::X);
        assert!((t - Vec2::new(4.0, 6.0)).abs().max_element() < 1e-6);
        let t = ray_unit_cylinder(Vec3::new(0.5, -4.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
        assert!((t - Vec2::new(1.5, 2.5)).abs().max_element() < 1e-6);
        assert!({
            let t = ray_unit_cylinder(Vec3::new(-5.0, 1.5, 0.0), Vec3::X);
            t.x > t.y
        });
        // Across the cone at height y the chord through the axis is 2 r(y) = 1 - y.
        for y in [-0.9f32, -0.5, 0.0, 0.6] {
            let t = ray_unit_cone(Vec3::new(-4.0, y, 0.0), Vec3::X);
            assert!(((t.y - t.x) - (1.0 - y)).abs() < 1e-5, "{y}: {t}");
        }
        // Up the axis: from the base (y = -1) to the apex (y = 1).
        let t = ray_unit_cone(Vec3::new(0.0, -3.0, 0.0), Vec3::Y);
        assert!((t - Vec2::new(2.0, 4.0)).abs().max_element() < 1e-5);
        // Down a line steeper than the side from above the apex: it enters at the apex.
        let t = ray_unit_cone(Vec3::new(0.05, 3.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert!(
            (t.x - (2.0 + 0.1)).abs() < 1e-5 && (t.y - 4.0).abs() < 1e-5,
            "{t}"
        );
    }
}
