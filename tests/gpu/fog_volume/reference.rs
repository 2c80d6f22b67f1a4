//! The f64 reference of one volume along a segment: entry and exit by bisection of the
//! shape's distance function, the optical depth by Simpson's rule.

use glam::{Mat4, Vec3};
use volfog::cpu::fog_volume::{FOG_VOLUME_CONE, FOG_VOLUME_CYLINDER, FOG_VOLUME_ELLIPSOID};
use volfog::uniforms::FogVolume;

pub(super) type M64 = [[f64; 4]; 4];

pub(super) fn m64(m: &Mat4) -> M64 {
    m.to_cols_array_2d().map(|c| c.map(|v| v as f64))
}

pub(super) fn xform(m: &M64, p: [f64; 3], w: f64) -> [f64; 3] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r] * w)
}

pub(super) fn v64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

pub(super) fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Distance-like function of the shape in local space: <= 0 inside.
pub(super) fn phi(shape: u32, p: [f64; 3]) -> f64 {
    let radial = p[0].hypot(p[2]);
    match shape {
        FOG_VOLUME_ELLIPSOID => norm(p) - 1.0,
        FOG_VOLUME_CYLINDER => p[1].abs().max(radial) - 1.0,
        FOG_VOLUME_CONE => p[1].abs().max(radial + 0.5 * (p[1] + 1.0)) - 1.0,
        _ => p[0].abs().max(p[1].abs()).max(p[2].abs()) - 1.0,
    }
}

/// Magnitude of the terms summed into the local-space ray origin and direction: f32
/// rounding of the transform is a few ulp of this (local units).
pub(super) fn local_magnitude(v: &FogVolume, eye: Vec3, point: Vec3) -> f64 {
    let m = m64(&v.local_from_world);
    let abs_m: M64 = m.map(|c| c.map(f64::abs));
    let e = v64(eye).map(f64::abs);
    let d = [0, 1, 2].map(|i| (point[i] as f64 - eye[i] as f64).abs());
    norm(xform(&abs_m, e, 1.0)) + norm(xform(&abs_m, d, 0.0))
}

pub(super) struct Reference {
    /// Clipped interval [t0, t1] (t0 == t1 when empty).
    pub(super) t: (f64, f64),
    /// The line passes within 1e-4 (local units) of tangency, or meets the surface at
    /// a cosine below 1e-3: its chord is ill-posed.
    pub(super) grazing: bool,
    /// Length of the segment in local units.
    pub(super) local_len: f64,
    /// Conditioning of t0 and t1: 1 / |cos| of the angle between the line and the
    /// surface normal where it enters / leaves (1 where the end is the camera or the
    /// point). A distance error e to the surface moves the end by e * amp along the line.
    pub(super) amp: (f64, f64),
}

/// 1 / |cos| between the line direction and the shape's normal at local point p (the
/// worst face for a box point near an edge or corner).
fn incidence(shape: u32, p: [f64; 3], rd: [f64; 3]) -> f64 {
    let len = norm(rd);
    let dot = |n: [f64; 3]| (n[0] * rd[0] + n[1] * rd[1] + n[2] * rd[2]).abs();
    let radial = p[0].hypot(p[2]).max(1e-300);
    if shape == FOG_VOLUME_ELLIPSOID {
        let n = norm(p);
        len * n / (p[0] * rd[0] + p[1] * rd[1] + p[2] * rd[2]).abs()
    } else if shape == FOG_VOLUME_CYLINDER || shape == FOG_VOLUME_CONE {
        // The side (its unit normal) and the caps, those within 1e-3 of the surface.
        let (side, side_normal) = if shape == FOG_VOLUME_CYLINDER {
            (radial, [p[0] / radial, 0.0, p[2] / radial])
        } else {
            let k = 1.25f64.sqrt();
            (
                radial + 0.5 * (p[1] + 1.0),
                [p[0] / radial / k, 0.5 / k, p[2] / radial / k],
            )
        };
        let m = side.max(p[1].abs());
        let mut amp = 1.0f64;
        if side >= m - 1e-3 {
            amp = amp.max(len / dot(side_normal));
        }
        if p[1].abs() >= m - 1e-3 {
            amp = amp.max(len / rd[1].abs());
        }
        amp
    } else {
        let m = p[0].abs().max(p[1].abs()).max(p[2].abs());
        (0..3)
            .filter(|&k| p[k].abs() >= m - 1e-3)
            .map(|k| len / rd[k].abs())
            .fold(1.0, f64::max)
    }
}

/// Entry and exit by minimising the convex phi along the line (ternary search) and
/// bisecting phi = 0 on both sides of the minimum, all in f64.
pub(super) fn reference(v: &FogVolume, eye: Vec3, point: Vec3) -> Reference {
    let m = m64(&v.local_from_world);
    let e = v64(eye);
    let seg = [0, 1, 2].map(|i| point[i] as f64 - e[i]);
    let ro = xform(&m, e, 1.0);
    let rd = xform(&m, seg, 0.0);
    let local_len = norm(rd);
    let empty = |grazing| Reference {
        t: (0.0, 0.0),
        grazing,
        local_len,
        amp: (1.0, 1.0),
    };
    if local_len == 0.0 {
        return empty(false);
    }
    let at = |t: f64| [0, 1, 2].map(|i| ro[i] + t * rd[i]);
    let f = |t: f64| phi(v.shape, at(t));
    let reach = (norm(ro) + 2.0) / local_len;
    let (mut lo, mut hi) = (-reach, reach);
    for _ in 0..400 {
        let a = lo + (hi - lo) / 3.0;
        let b = hi - (hi - lo) / 3.0;
        if f(a) <= f(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let tm = 0.5 * (lo + hi);
    let fm = f(tm);
    if fm > 0.0 {
        return empty(fm < 1e-4);
    }
    let bisect = |mut outside: f64, mut inside: f64| {
        for _ in 0..200 {
            let mid = 0.5 * (outside + inside);
            if f(mid) > 0.0 {
                outside = mid;
            } else {
                inside = mid;
            }
        }
        0.5 * (outside + inside)
    };
    let ta = bisect(-reach, tm);
    let tb = bisect(reach, tm);
    let t0 = ta.clamp(0.0, 1.0);
    let t1 = tb.clamp(t0, 1.0);
    if t1 <= t0 {
        return empty(fm > -1e-4);
    }
    let amp0 = if ta > 0.0 {
        incidence(v.shape, at(ta), rd)
    } else {
        1.0
    };
    let amp1 = if tb < 1.0 {
        incidence(v.shape, at(tb), rd)
    } else {
        1.0
    };
    Reference {
        t: (t0, t1),
        grazing: fm > -1e-4 || amp0.max(amp1) > 1e3,
        local_len,
        amp: (amp0, amp1),
    }
}

/// Extinction of a volume at a world point (f64), ignoring its shape.
pub(super) fn density64(v: &FogVolume, p: [f64; 3]) -> f64 {
    let c = v64(v.center);
    let g = v64(v.gradient);
    let h = (0..3).map(|i| (p[i] - c[i]) * g[i]).sum::<f64>();
    v.density as f64 * (-(v.falloff as f64) * (h - v.offset as f64)).exp()
}

/// Optical depth over [t0, t1] of the segment by Simpson's rule (2048 intervals).
pub(super) fn reference_od(v: &FogVolume, eye: Vec3, point: Vec3, t: (f64, f64)) -> f64 {
    let e = v64(eye);
    let seg = [0, 1, 2].map(|i| point[i] as f64 - e[i]);
    let len = norm(seg);
    if t.1 <= t.0 {
        return 0.0;
    }
    let n = 2048;
    let h = (t.1 - t.0) / n as f64;
    let at = |s: f64| density64(v, [0, 1, 2].map(|i| e[i] + s * seg[i]));
    let mut sum = at(t.0) + at(t.1);
    for i in 1..n {
        sum += at(t.0 + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0 * len
}
