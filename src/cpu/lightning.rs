//! Mirror of `volfog::lightning`: closed-form volumetric light of a point source
//! (Wenzel 2007, eq. 3), evaluated through a stable arctangent difference.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::lightning::volumetric_lightning;
//!
//! // A flash 2 m off a 100 m view ray: most of the glow is gathered near the flash.
//! let flash = Vec3::new(50.0, 2.0, 0.0);
//! let eye = Vec3::ZERO;
//! let all = volumetric_lightning(1.0, 1.0, flash, eye, Vec3::new(100.0, 0.0, 0.0));
//! let half = volumetric_lightning(1.0, 1.0, flash, eye, Vec3::new(50.0, 0.0, 0.0));
//! assert!((half / all - 0.5).abs() < 1e-3); // symmetric about the flash
//! // With a = 1 and the flash r = 2 m off the ray this is the integral of
//! // 1 / (1 + r^2 + s^2) over s in [-50, 50], i.e. (2 / sqrt(5)) atan(50 / sqrt(5)).
//! let exact = 2.0 / 5f32.sqrt() * (50.0 / 5f32.sqrt()).atan();
//! assert!((all - exact).abs() < 1e-5 * exact);
//! ```

use glam::Vec3;

/// Positions (m) are clamped to `+-LIGHTNING_POSITION_LIMIT`.
pub const LIGHTNING_POSITION_LIMIT: f32 = 1e9;
/// Largest attenuation control `a` (1/m^2).
pub const LIGHTNING_ATTENUATION_LIMIT: f32 = 1e6;
/// Largest intensity `i`.
pub const LIGHTNING_INTENSITY_LIMIT: f32 = 1e18;
/// Below `Y / X` = this the ratio `atan2(Y, X) / Y` uses its series.
pub const LIGHTNING_SERIES_LIMIT: f32 = 1e-2;

const LIGHTNING_PI: f32 = std::f32::consts::PI;

/// `arctan(a)` for `a` in `[0, 1]` (Cephes atanf: reduction at tan(pi / 8), odd
/// polynomial; relative error < 2e-7), the same arithmetic as the shader.
pub fn lightning_atan_unit(a: f32) -> f32 {
    let high = a > 0.414_213_56;
    let x = if high { (a - 1.0) / (a + 1.0) } else { a };
    let z = x * x;
    let p =
        (((8.053_744_5e-2 * z - 1.387_768_6e-1) * z + 1.997_771_1e-1) * z - 3.333_295e-1) * z * x
            + x;
    if high {
        std::f32::consts::FRAC_PI_4 + p
    } else {
        p
    }
}

/// `atan2(y, x)` in `[0, pi]` for `y >= 0`, from [`lightning_atan_unit`].
pub fn lightning_atan2(y: f32, x: f32) -> f32 {
    let ax = x.abs();
    let steep = y > ax;
    let a = if steep {
        ax / y.max(1e-30)
    } else {
        y / ax.max(1e-30)
    };
    let r = if steep {
        0.5 * LIGHTNING_PI - lightning_atan_unit(a)
    } else {
        lightning_atan_unit(a)
    };
    if x < 0.0 { LIGHTNING_PI - r } else { r }
}

/// The light density `i / (1 + a |l - p|^2)` at one point.
pub fn lightning_density(i: f32, a: f32, light: Vec3, p: Vec3) -> f32 {
    let lim = Vec3::splat(LIGHTNING_POSITION_LIMIT);
    let q = p.clamp(-lim, lim) - light.clamp(-lim, lim);
    let k = a.clamp(0.0, LIGHTNING_ATTENUATION_LIMIT);
    i.clamp(0.0, LIGHTNING_INTENSITY_LIMIT) / (1.0 + k * q.dot(q))
}

/// Integral (m) of `1 / (1 + a |l - p|^2)` over the segment from `origin` to
/// `origin + segment`.
pub fn lightning_integral(a: f32, light: Vec3, origin: Vec3, segment: Vec3) -> f32 {
    let lim = Vec3::splat(LIGHTNING_POSITION_LIMIT);
    let l = light.clamp(-lim, lim);
    let q0 = origin.clamp(-lim, lim) - l;
    let d = segment.clamp(-lim, lim);
    let k = a.clamp(0.0, LIGHTNING_ATTENUATION_LIMIT);
    let len = d.length();
    let perp = q0.cross(d / len.max(1e-30));
    let y = len * (k * (1.0 + k * perp.dot(perp))).sqrt();
    let x = 1.0 + k * q0.dot(q0 + d);
    let z = y / x.max(1e-30);
    let z2 = z * z;
    let series = (1.0 - z2 * (1.0 / 3.0 - z2 / 5.0)) / x.max(1e-30);
    let direct = lightning_atan2(y, x) / y.max(1e-30);
    let ratio = if x > 0.0 && y < LIGHTNING_SERIES_LIMIT * x {
        series
    } else {
        direct
    };
    len * ratio
}

/// Light gathered along the segment from `origin` to `origin + segment` from a point
/// source at `light` of intensity `i` (radiance / m) and attenuation control `a`
/// (1/m^2): the integral of `i / (1 + a |l - p|^2)`.
pub fn volumetric_lightning(i: f32, a: f32, light: Vec3, origin: Vec3, segment: Vec3) -> f32 {
    i.clamp(0.0, LIGHTNING_INTENSITY_LIMIT) * lightning_integral(a, light, origin, segment)
}
