// volfog::phase — phase functions of single scattering, normalised over the sphere.
//
// Use:      #import volfog::phase::{phase_hg, ...}
// Defines:  none
// Convention: cos_theta is the cosine of the scattering angle, the angle between the
//           direction light travels before and after scattering. For a view ray with
//           direction view_dir (from the eye into the scene) and a light in direction
//           to_light (from the scattering point towards the light),
//           cos_theta = dot(view_dir, to_light). Every function integrates to 1 over
//           the sphere (unit 1/sr); g is the mean cosine, valid in (-1, 1): g > 0
//           scatters forward (bright when looking towards the light).
// References: Wronski 2014, "Phase functions", "Analytical phase functions" and the
//           bonus slide "Ambient / GI support" (zonal SH of Henyey-Greenstein);
//           Henyey & Greenstein 1941; Blasi, Le Saec & Schlick 1993 (Schlick
//           approximation, k = 1.55 g - 0.55 g^3); Cornette & Shanks 1992; Rayleigh.
#define_import_path volfog::phase

const PI: f32 = 3.14159265358979;
const INV_4PI: f32 = 0.0795774715459477;
// Real SH basis constants: Y_0^0 = 1 / (2 sqrt(pi)), Y_1^m = sqrt(3 / (4 pi)) * (y, z, x).
const SH_Y0: f32 = 0.282094791773878;
const SH_Y1: f32 = 0.488602511902920;

// Isotropic scattering: 1 / (4 pi).
fn phase_isotropic() -> f32 {
    return INV_4PI;
}

// Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^(3/2)).
fn phase_hg(cos_theta: f32, g: f32) -> f32 {
    let g2 = g * g;
    let d = max(1.0 + g2 - 2.0 * g * cos_theta, 1e-12);
    return INV_4PI * (1.0 - g2) / (d * sqrt(d));
}

// Schlick's rational approximation of HG with the parameter k of schlick_k:
// (1 - k^2) / (4 pi (1 - k cos_theta)^2).
fn phase_schlick(cos_theta: f32, k: f32) -> f32 {
    let d = max(1.0 - k * cos_theta, 1e-6);
    return INV_4PI * (1.0 - k * k) / (d * d);
}

// The Schlick parameter k that best matches HG of mean cosine g (Blasi et al. 1993),
// k = 1.55 g - 0.55 g^3. The fit exceeds |k| = 1 above |g| ~ 0.94, so k is clamped
// to [-0.999, 0.999] to keep the function positive and normalised.
fn schlick_k(g: f32) -> f32 {
    return clamp((1.55 - 0.55 * g * g) * g, -0.999, 0.999);
}

// Cornette-Shanks: 3 (1 - g^2) (1 + cos^2) / (8 pi (2 + g^2) (1 + g^2 - 2 g cos)^(3/2)).
fn phase_cornette_shanks(cos_theta: f32, g: f32) -> f32 {
    let g2 = g * g;
    let d = max(1.0 + g2 - 2.0 * g * cos_theta, 1e-12);
    let num = 3.0 * (1.0 - g2) * (1.0 + cos_theta * cos_theta);
    return num / (8.0 * PI * (2.0 + g2) * d * sqrt(d));
}

// Rayleigh scattering by particles much smaller than the wavelength:
// 3 (1 + cos^2) / (16 pi).
fn phase_rayleigh(cos_theta: f32) -> f32 {
    return 3.0 / (16.0 * PI) * (1.0 + cos_theta * cos_theta);
}

// Two HG lobes blended by weight w in [0, 1]: (1 - w) HG(g0) + w HG(g1); a forward
// lobe plus a weaker backward one fits measured aerosol phase functions well.
fn phase_hg_two_lobe(cos_theta: f32, g0: f32, g1: f32, w: f32) -> f32 {
    return mix(phase_hg(cos_theta, g0), phase_hg(cos_theta, g1), w);
}

// Zonal SH coefficients of HG for bands 0, 1, 2: sqrt((2l + 1) / (4 pi)) g^l
// (HG = sum_l (2l + 1) / (4 pi) g^l P_l(cos_theta)).
fn phase_hg_zonal_sh(g: f32) -> vec3<f32> {
    return vec3<f32>(SH_Y0, SH_Y1 * g, 0.630783130505040 * g * g);
}

// L1 SH coefficients (order Y_0^0, Y_1^-1, Y_1^0, Y_1^1) of the HG lobe rotated to
// direction dir (unit): c_lm = g^l Y_lm(dir), Wronski's float4(1, dir.y, dir.z, dir.x)
// * float4(1, g, g, g) with the basis constants included. With dir the view direction,
// dot(coefficients, radiance SH) gives the in-scattered radiance of an L1 environment.
fn phase_hg_sh_l1(dir: vec3<f32>, g: f32) -> vec4<f32> {
    return vec4<f32>(SH_Y0, SH_Y1 * g * dir.y, SH_Y1 * g * dir.z, SH_Y1 * g * dir.x);
}

// In-scattered radiance (rgb) from an environment given as L1 SH projections of its
// incoming radiance per colour channel (order as above), for a phase function given
// by its rotated L1 SH coefficients: one dot product per channel.
fn phase_sh_l1_radiance(phase_sh: vec4<f32>, sh_r: vec4<f32>, sh_g: vec4<f32>, sh_b: vec4<f32>) -> vec3<f32> {
    return vec3<f32>(dot(phase_sh, sh_r), dot(phase_sh, sh_g), dot(phase_sh, sh_b));
}

// Art-driven two-colour phase of Assassin's Creed 4 (Wronski 2014, "Density estimation
// and volume lighting"): isotropic in shape, tinted from `away` (looking away from the
// light, cos_theta = -1) to `toward` (looking into it, cos_theta = 1). Normalised when
// both tints are 1.
fn phase_two_color(cos_theta: f32, toward: vec3<f32>, away: vec3<f32>) -> vec3<f32> {
    return INV_4PI * mix(away, toward, 0.5 + 0.5 * cos_theta);
}
