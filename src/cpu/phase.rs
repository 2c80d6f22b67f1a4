//! Mirror of `volfog::phase`: phase functions normalised over the sphere.
//!
//! `cos_theta` is the cosine of the scattering angle, `dot(view_dir, to_light)`;
//! `g` is the mean cosine in (-1, 1). See the WGSL module for references.
//!
//! ```
//! use volfog::cpu::phase;
//! // Forward-scattering HG is brighter looking towards the light than away from it.
//! assert!(phase::phase_hg(1.0, 0.6) > phase::phase_hg(-1.0, 0.6));
//! ```

use glam::{Vec3, Vec4};

/// pi in f32.
pub const PI: f32 = std::f32::consts::PI;
/// 1 / (4 pi).
pub const INV_4PI: f32 = 0.079_577_47;
/// Real SH basis constant of band 0, 1 / (2 sqrt(pi)).
pub const SH_Y0: f32 = 0.282_094_8;
/// Real SH basis constant of band 1, sqrt(3 / (4 pi)).
pub const SH_Y1: f32 = 0.488_602_51;
/// sqrt(5 / (4 pi)), the zonal band-2 constant.
pub const SH_Y2: f32 = 0.630_783_1;

/// Isotropic scattering, 1 / (4 pi).
pub fn phase_isotropic() -> f32 {
    INV_4PI
}

/// Henyey-Greenstein phase function.
pub fn phase_hg(cos_theta: f32, g: f32) -> f32 {
    let g2 = g * g;
    let d = (1.0 + g2 - 2.0 * g * cos_theta).max(1e-12);
    INV_4PI * (1.0 - g2) / (d * d.sqrt())
}

/// Schlick's approximation of HG with parameter `k` (see [`schlick_k`]).
pub fn phase_schlick(cos_theta: f32, k: f32) -> f32 {
    let d = (1.0 - k * cos_theta).max(1e-6);
    INV_4PI * (1.0 - k * k) / (d * d)
}

/// The Schlick parameter matching HG of mean cosine `g` (Blasi et al. 1993),
/// clamped to `[-0.999, 0.999]` where the fit would leave `(-1, 1)`.
pub fn schlick_k(g: f32) -> f32 {
    ((1.55 - 0.55 * g * g) * g).clamp(-0.999, 0.999)
}

/// Cornette-Shanks phase function.
pub fn phase_cornette_shanks(cos_theta: f32, g: f32) -> f32 {
    let g2 = g * g;
    let d = (1.0 + g2 - 2.0 * g * cos_theta).max(1e-12);
    let num = 3.0 * (1.0 - g2) * (1.0 + cos_theta * cos_theta);
    num / (8.0 * PI * (2.0 + g2) * d * d.sqrt())
}

/// Rayleigh phase function.
pub fn phase_rayleigh(cos_theta: f32) -> f32 {
    3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta)
}

/// Two HG lobes blended by `w`: `(1 - w) HG(g0) + w HG(g1)`.
pub fn phase_hg_two_lobe(cos_theta: f32, g0: f32, g1: f32, w: f32) -> f32 {
    let a = phase_hg(cos_theta, g0);
    let b = phase_hg(cos_theta, g1);
    a + (b - a) * w
}

/// Zonal SH coefficients of HG for bands 0, 1, 2.
pub fn phase_hg_zonal_sh(g: f32) -> Vec3 {
    Vec3::new(SH_Y0, SH_Y1 * g, SH_Y2 * g * g)
}

/// L1 SH coefficients (Y00, Y1-1, Y10, Y11) of HG rotated to unit direction `dir`.
pub fn phase_hg_sh_l1(dir: Vec3, g: f32) -> Vec4 {
    Vec4::new(
        SH_Y0,
        SH_Y1 * g * dir.y,
        SH_Y1 * g * dir.z,
        SH_Y1 * g * dir.x,
    )
}

/// In-scattered radiance from L1 SH radiance per channel: one dot product each.
pub fn phase_sh_l1_radiance(phase_sh: Vec4, sh_r: Vec4, sh_g: Vec4, sh_b: Vec4) -> Vec3 {
    Vec3::new(phase_sh.dot(sh_r), phase_sh.dot(sh_g), phase_sh.dot(sh_b))
}

/// AC4's art-driven two-colour phase: isotropic, tinted from `away` to `toward`.
pub fn phase_two_color(cos_theta: f32, toward: Vec3, away: Vec3) -> Vec3 {
    INV_4PI * away.lerp(toward, 0.5 + 0.5 * cos_theta)
}
