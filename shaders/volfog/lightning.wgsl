// volfog::lightning — closed-form volumetric light of a point source along a segment
// (Wenzel's "volumetric lightning": glow around a flash, a lamp in fog).
//
// Use:      #import volfog::lightning::volumetric_lightning
//           let glow = color * volumetric_lightning(i, a, light_pos, eye, shaded - eye);
// Defines:  none
// Model:    f(p) = i / (1 + a |l - p|^2): i the in-scattered radiance per metre at the
//           light (radiance / m), a >= 0 the attenuation control (1/m^2), l the light.
// Integral: along p(t) = o + t d, t in [0, 1] (Wenzel 2007, eq. 3):
//           F = 2 i |d| (atan((v + 2w) / sqrt(D)) - atan(v / sqrt(D))) / sqrt(D),
//           u = 1 + a |o - l|^2, v = 2a (o - l).d, w = a |d|^2, D = 4uw - v^2.
//           With q0 = o - l, q1 = o + d - l and Y = sqrt(D) / 2 this is evaluated as
//               F = i |d| atan2(Y, X) / Y,  X = 1 + a q0.q1,
//               Y = |d| sqrt(a (1 + a r^2)),  r = |q0 x d| / |d|,
//           using atan(A) - atan(B) = atan2(A - B, 1 + A B) (exact for A >= B): no
//           difference of nearly equal arctangents, no division by a small D (which is
//           computed without cancellation from the distance r of the light to the
//           line), and the right branch (beyond pi / 2) when the segment passes through
//           the light. For Y < 1e-2 X (a -> 0, or a short or distant segment) the
//           ratio atan2(Y, X) / Y uses its series (1 - z^2 / 3 + z^4 / 5) / X, z = Y / X;
//           a zero-length segment gives 0, a = 0 gives i |d|.
//           The arctangent is evaluated in the module (lightning_atan2, < 2e-7
//           relative) rather than by the backend's atan2, whose precision varies.
// Robustness: finite for every finite input: positions are clamped to +-1e9 m, a to
//           [0, 1e6] 1/m^2 and i to [0, 1e18].
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited",
//           "Volumetric Lightning Using Per-Pixel Depth" (eq. 3).
#define_import_path volfog::lightning

// Positions (m) are clamped to +-LIGHTNING_POSITION_LIMIT.
const LIGHTNING_POSITION_LIMIT: f32 = 1e9;
// Largest attenuation control a (1/m^2).
const LIGHTNING_ATTENUATION_LIMIT: f32 = 1e6;
// Largest intensity i.
const LIGHTNING_INTENSITY_LIMIT: f32 = 1e18;
// Below Y / X = this the ratio atan2(Y, X) / Y uses its series (truncation < 1.5e-13).
const LIGHTNING_SERIES_LIMIT: f32 = 1e-2;

const LIGHTNING_PI: f32 = 3.14159265358979;

// arctan(a) for a in [0, 1] (Cephes atanf: reduction at tan(pi / 8), odd polynomial;
// relative error < 2e-7). Shader atan precision varies by backend (Vulkan allows
// 4096 ulp), so the closed form carries its own.
fn lightning_atan_unit(a: f32) -> f32 {
    let high = a > 0.414213562373095;
    let x = select(a, (a - 1.0) / (a + 1.0), high);
    let z = x * x;
    let p = (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
        - 3.33329491539e-1) * z * x + x;
    return select(p, 0.785398163397448 + p, high);
}

// atan2(y, x) in [0, pi] for y >= 0, from lightning_atan_unit; atan2(0, 0) = 0.
fn lightning_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let steep = y > ax;
    let a = select(y / max(ax, 1e-30), ax / max(y, 1e-30), steep);
    let r = select(lightning_atan_unit(a), 0.5 * LIGHTNING_PI - lightning_atan_unit(a), steep);
    return select(r, LIGHTNING_PI - r, x < 0.0);
}

// The light density f(p) = i / (1 + a |l - p|^2) at one point.
fn lightning_density(i: f32, a: f32, light: vec3<f32>, p: vec3<f32>) -> f32 {
    let lim = vec3<f32>(LIGHTNING_POSITION_LIMIT);
    let q = clamp(p, -lim, lim) - clamp(light, -lim, lim);
    let k = clamp(a, 0.0, LIGHTNING_ATTENUATION_LIMIT);
    return clamp(i, 0.0, LIGHTNING_INTENSITY_LIMIT) / (1.0 + k * dot(q, q));
}

// Integral (m) of 1 / (1 + a |l - p|^2) over the segment from origin to origin + segment
// (world space, m), a in 1/m^2: the path length weighted by the attenuation.
fn lightning_integral(a: f32, light: vec3<f32>, origin: vec3<f32>, segment: vec3<f32>) -> f32 {
    let lim = vec3<f32>(LIGHTNING_POSITION_LIMIT);
    let l = clamp(light, -lim, lim);
    let q0 = clamp(origin, -lim, lim) - l;
    let d = clamp(segment, -lim, lim);
    let k = clamp(a, 0.0, LIGHTNING_ATTENUATION_LIMIT);
    let len = length(d);
    let perp = cross(q0, d / max(len, 1e-30));
    let y = len * sqrt(k * (1.0 + k * dot(perp, perp)));
    let x = 1.0 + k * dot(q0, q0 + d);
    let z = y / max(x, 1e-30);
    let z2 = z * z;
    let series = (1.0 - z2 * (1.0 / 3.0 - z2 / 5.0)) / max(x, 1e-30);
    let direct = lightning_atan2(y, x) / max(y, 1e-30);
    let ratio = select(direct, series, x > 0.0 && y < LIGHTNING_SERIES_LIMIT * x);
    return len * ratio;
}

// Light gathered along the segment (Wenzel eq. 3): the integral of
// i / (1 + a |l - p|^2) over it, i in radiance / m, so the result is a radiance.
fn volumetric_lightning(i: f32, a: f32, light: vec3<f32>, origin: vec3<f32>, segment: vec3<f32>) -> f32 {
    return clamp(i, 0.0, LIGHTNING_INTENSITY_LIMIT) * lightning_integral(a, light, origin, segment);
}
