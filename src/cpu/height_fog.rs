//! Mirror of `volfog::height_fog`: closed-form global height fog (Wenzel 2007, eq. 2).
//!
//! The extinction `f(p) = b exp(-c (dot(p, up) - h0))` is integrated in closed form
//! along a straight segment, so gameplay code can ask how much fog lies between two
//! points without touching the GPU:
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::height_fog::{height_fog, height_fog_transmittance};
//! use volfog::uniforms::HeightFog;
//!
//! // Valley fog: 0.05 / m at sea level, halving every ~14 m of height (+Y up).
//! let fog = HeightFog::new(Vec3::splat(0.6), 0.05, Vec3::Y, 0.05, 0.0).unwrap();
//! let eye = Vec3::new(0.0, 2.0, 0.0);
//! let target = Vec3::new(120.0, 40.0, 0.0);
//! let seen = height_fog(&fog, eye, target - eye);
//! // Fraction of the target's light that reaches the eye, and the fog colour added.
//! let visibility = seen.w;
//! assert!(visibility > 0.0 && visibility < 1.0);
//! assert!((seen.x - 0.6 * (1.0 - visibility)).abs() < 1e-6);
//!
//! // The same query through the scalar core (b, c, h0, up, origin, segment).
//! let t = height_fog_transmittance(0.05, 0.05, 0.0, Vec3::Y, eye, target - eye);
//! assert_eq!(t, visibility);
//!
//! // Light crosses the same fog in either direction along a segment.
//! let back = height_fog(&fog, target, eye - target);
//! assert!((back.w - visibility).abs() < 1e-6);
//! ```

use glam::{Vec3, Vec4};

use super::phase::phase_hg;
use crate::limits::{FOG_DENSITY_LIMIT, FOG_FALLOFF_LIMIT, FOG_POSITION_LIMIT};
use crate::uniforms::HeightFog;

/// Below this `|x|` the mean `E(x)` uses its Taylor series.
pub const FOG_SERIES_LIMIT: f32 = 1.0;
/// Exponent arguments are clamped to `+-FOG_EXPONENT_LIMIT`.
pub const FOG_EXPONENT_LIMIT: f32 = 80.0;
/// Largest peak density (1/m).
pub const FOG_PEAK_LIMIT: f32 = 1e20;

/// `E(x) = (1 - exp(-x)) / x`, the mean of `exp(-x s)` over `s` in `[0, 1]`; `E(0) = 1`.
/// Taylor series through `x^10 / 11!` for `|x| < 1`; `x` is clamped to `>= -80`.
pub fn exp_segment_average(x_in: f32) -> f32 {
    let x = x_in.max(-FOG_EXPONENT_LIMIT);
    if x.abs() < FOG_SERIES_LIMIT {
        let mut s = 1.0 - x / 11.0;
        s = 1.0 - x / 10.0 * s;
        s = 1.0 - x / 9.0 * s;
        s = 1.0 - x / 8.0 * s;
        s = 1.0 - x / 7.0 * s;
        s = 1.0 - x / 6.0 * s;
        s = 1.0 - x / 5.0 * s;
        s = 1.0 - x / 4.0 * s;
        s = 1.0 - x / 3.0 * s;
        return 1.0 - x / 2.0 * s;
    }
    (1.0 - (-x).exp()) / x
}

/// Optical depth of `b exp(-c (dot(p, up) - h0))` along the segment from `origin` to
/// `origin + segment` (m); `b`, `c` in 1/m, `up` a unit vector. Finite for every
/// finite input; zero for a zero-length segment.
pub fn height_fog_optical_depth(
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    origin: Vec3,
    segment: Vec3,
) -> f32 {
    let lim = Vec3::splat(FOG_POSITION_LIMIT);
    let o = origin.clamp(-lim, lim);
    let d = segment.clamp(-lim, lim);
    let u = up.clamp(Vec3::NEG_ONE, Vec3::ONE);
    let k = c.clamp(-FOG_FALLOFF_LIMIT, FOG_FALLOFF_LIMIT);
    let h = o.dot(u) - h0.clamp(-FOG_POSITION_LIMIT, FOG_POSITION_LIMIT);
    let x = k * d.dot(u);
    let e0 = -k * h;
    let e1 = e0 - x;
    let e = e0.max(e1).clamp(-FOG_EXPONENT_LIMIT, FOG_EXPONENT_LIMIT);
    let peak = (b.clamp(0.0, FOG_DENSITY_LIMIT) * e.exp()).min(FOG_PEAK_LIMIT);
    peak * (d.length() * exp_segment_average(x.abs()))
}

/// The part of the segment from `origin` to `origin + segment` below the height `top`
/// (m along `up`) as fractions `(t0, t1)`; `t1 <= t0` when none of it is below.
pub fn height_fog_below_top(up: Vec3, top: f32, origin: Vec3, segment: Vec3) -> (f32, f32) {
    let h = origin.dot(up);
    let dh = segment.dot(up);
    if dh == 0.0 {
        return if h <= top { (0.0, 1.0) } else { (0.0, 0.0) };
    }
    let t = ((top - h) / dh).clamp(0.0, 1.0);
    if dh > 0.0 { (0.0, t) } else { (t, 1.0) }
}

/// [`height_fog_optical_depth`] of the segment's part below `top` (m along `up`): the
/// optical depth of a profile whose medium ends at its top.
pub fn height_fog_optical_depth_below(
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    top: f32,
    origin: Vec3,
    segment: Vec3,
) -> f32 {
    let (t0, t1) = height_fog_below_top(up, top, origin, segment);
    if t1 <= t0 {
        return 0.0;
    }
    height_fog_optical_depth(b, c, h0, up, origin + segment * t0, segment * (t1 - t0))
}

/// Optical depth from `origin` towards a light infinitely far along the unit direction
/// `towards` (the sun) through the profile below `top`: the light enters the medium at
/// its top, `(top - h) / dot(towards, up)` metres away (for `c > 0` and a far top,
/// Wenzel's `b exp(-c (h - h0)) / (c dot(towards, up))`). A light at or below the
/// horizon is followed for [`FOG_POSITION_LIMIT`] metres (the transmittance falls
/// smoothly to 0). 0 at and above the top.
///
/// ```
/// use glam::Vec3;
/// use volfog::cpu::height_fog::height_fog_light_optical_depth;
/// use volfog::limits::NO_TOP;
///
/// // 0.05 / m at the ground, e times thinner every 10 m, the sun 30 degrees high.
/// let sun = Vec3::new(30f32.to_radians().cos(), 0.5, 0.0);
/// let od = height_fog_light_optical_depth(0.05, 0.1, 0.0, Vec3::Y, NO_TOP, Vec3::ZERO, sun);
/// assert!((od - 0.05 / (0.1 * 0.5)).abs() < 1e-5);
/// // Uniform fog 20 m deep: the sun crosses 40 m of it.
/// let od = height_fog_light_optical_depth(0.05, 0.0, 0.0, Vec3::Y, 20.0, Vec3::ZERO, sun);
/// assert!((od - 2.0).abs() < 1e-5);
/// ```
pub fn height_fog_light_optical_depth(
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    top: f32,
    origin: Vec3,
    towards: Vec3,
) -> f32 {
    let h = origin.dot(up);
    if h >= top {
        return 0.0;
    }
    let mu = towards.dot(up);
    let reach = if mu > 0.0 {
        ((top - h) / mu.max(1e-30)).min(FOG_POSITION_LIMIT)
    } else {
        FOG_POSITION_LIMIT
    };
    height_fog_optical_depth(b, c, h0, up, origin, towards * reach)
}

/// Light scattered along a segment from a light infinitely far along `towards`, per
/// unit of its radiance times phase (albedo 1): the integral of
/// `sigma(t) exp(-tau_view(t)) exp(-tau_light(t)) dt` over the part below `top`, in
/// closed form `exp(-min(F0, F1)) tau E(|r| tau)` with `F = tau_view + tau_light`,
/// `r = 1 - v / mu` (WGSL `height_fog_lit_integral`). 0 for a light at or below the
/// horizon; `1 - T` is its value without the light's transmittance.
#[allow(clippy::too_many_arguments)]
pub fn height_fog_lit_integral(
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    top: f32,
    origin: Vec3,
    segment: Vec3,
    towards: Vec3,
) -> f32 {
    let mu = towards.dot(up);
    let (t0, t1) = height_fog_below_top(up, top, origin, segment);
    if mu <= 0.0 || t1 <= t0 {
        return 0.0;
    }
    let o = origin + segment * t0;
    let d = segment * (t1 - t0);
    let tau = height_fog_optical_depth(b, c, h0, up, o, d);
    let f0 = height_fog_light_optical_depth(b, c, h0, up, top, o, towards);
    let f1 = tau + height_fog_light_optical_depth(b, c, h0, up, top, o + d, towards);
    let v = d.dot(up) / d.length().max(1e-30);
    let r = (1.0 - v / mu).clamp(-1e20, 1e20);
    (-f0.min(f1)).exp() * tau * exp_segment_average((r.abs() * tau).min(1e30))
}

/// Transmittance `exp(-OD)` along the segment (arguments as
/// [`height_fog_optical_depth`]): the fraction of light that crosses it.
pub fn height_fog_transmittance(
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    origin: Vec3,
    segment: Vec3,
) -> f32 {
    (-height_fog_optical_depth(b, c, h0, up, origin, segment)).exp()
}

/// Fog of optical depth `od` lit by a constant radiance: `(radiance (1 - T), T)`.
pub fn fog_inscatter(radiance: Vec3, od_in: f32) -> Vec4 {
    let od = od_in.max(0.0);
    let t = (-od).exp();
    let absorbed = if od < FOG_SERIES_LIMIT {
        od * exp_segment_average(od)
    } else {
        1.0 - t
    };
    (radiance * absorbed).extend(t)
}

/// Height fog along the segment from `origin` to `origin + segment` (world space, m):
/// rgb the in-scattered radiance, w the transmittance, as `volfog::apply` expects.
pub fn height_fog(fog: &HeightFog, origin: Vec3, segment: Vec3) -> Vec4 {
    height_fog_from_vertex(height_fog_vertex(fog, origin, segment))
}

/// The fog of [`height_fog`] before its exponential, for per-vertex fog (Wenzel 2007,
/// "Fog and Alpha-Transparent Objects"): `(in-scattered radiance rgb, optical depth)`.
/// Interpolate it across a primitive and finish with [`height_fog_from_vertex`].
///
/// ```
/// use glam::Vec3;
/// use volfog::cpu::height_fog::{height_fog, height_fog_from_vertex, height_fog_vertex};
/// use volfog::uniforms::HeightFog;
///
/// let fog = HeightFog::new(Vec3::splat(0.5), 0.02, Vec3::Y, 0.1, 0.0).unwrap();
/// let eye = Vec3::new(0.0, 2.0, 0.0);
/// let (a, b) = (Vec3::new(-2.5, 0.0, -40.0), Vec3::new(2.5, 0.0, -40.0));
/// // Halfway between two vertices 5 m apart, 40 m away: the interpolated vertex fog
/// // against per-pixel fog.
/// let mid = (height_fog_vertex(&fog, eye, a - eye) + height_fog_vertex(&fog, eye, b - eye)) / 2.0;
/// let per_pixel = height_fog(&fog, eye, (a + b) / 2.0 - eye);
/// assert!((height_fog_from_vertex(mid) - per_pixel).abs().max_element() < 1e-3);
/// ```
pub fn height_fog_vertex(fog: &HeightFog, origin: Vec3, segment: Vec3) -> Vec4 {
    let od = height_fog_optical_depth_below(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        fog.top_height,
        origin,
        segment,
    );
    let d = segment.clamp(
        Vec3::splat(-FOG_POSITION_LIMIT),
        Vec3::splat(FOG_POSITION_LIMIT),
    );
    let view_dir = d / d.length().max(1e-30);
    let cos_theta = view_dir.dot(fog.sun_direction).clamp(-1.0, 1.0);
    let lobe = phase_hg(cos_theta, fog.sun_g.clamp(-0.999, 0.999));
    let sun = height_fog_sun_share(fog, origin, segment, od);
    (fog.color + fog.sun_color * (lobe * sun)).extend(od)
}

/// The share in `[0, 1]` of the sun's light that reaches a segment through the fog, per
/// unit of the light it absorbs: [`height_fog_lit_integral`] / `(1 - T)` with
/// `fog.sun_transmittance`, 1 without it (or where nothing is absorbed); `od` is the
/// segment's optical depth below the top (WGSL `height_fog_sun_share`).
pub fn height_fog_sun_share(fog: &HeightFog, origin: Vec3, segment: Vec3, od: f32) -> f32 {
    if fog.sun_transmittance == 0 {
        return 1.0;
    }
    let absorbed = fog_inscatter(Vec3::ONE, od).x;
    let lit = height_fog_lit_integral(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        fog.top_height,
        origin,
        segment,
        fog.sun_direction,
    );
    if absorbed > 0.0 {
        (lit / absorbed).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Fog `(in-scatter rgb, T)` from an interpolated [`height_fog_vertex`] value.
pub fn height_fog_from_vertex(vertex_fog: Vec4) -> Vec4 {
    fog_inscatter(vertex_fog.truncate(), vertex_fog.w)
}
