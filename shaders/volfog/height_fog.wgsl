// volfog::height_fog — closed-form global height fog: optical depth, transmittance and
// in-scattering of an exponential density along a straight segment.
//
// Use:      #import volfog::height_fog::{height_fog, height_fog_optical_depth, ...}
//           let fog = height_fog(params, camera_pos, shaded_pos - camera_pos);
//           color = apply_fog(color, fog);          // volfog::apply::apply_fog
// Defines:  none
// Density:  f(p) = b * exp(-c * (dot(p, up) - h0))   (extinction, 1/m)
//           b  density on the reference plane dot(p, up) = h0, 1/m, in [0, 1e3]
//           c  falloff along up, 1/m (c > 0: thinner upwards; c = 0: uniform fog)
//           up unit axis the density falls along (any direction, not only +Y or +Z)
// Integral: along p(t) = o + t d, t in [0, 1] (Wenzel 2007, eq. 2, generalised):
//           OD = b |d| exp(-c (dot(o, up) - h0)) * E(c dot(d, up)),
//           E(x) = (1 - exp(-x)) / x, the mean of exp(-x s) over s in [0, 1].
//           It is evaluated as b |d| exp(max(e0, e1)) * E(|x|) with e0, e1 the exponents
//           at the two ends: the exponential is the density at the densest end and
//           E(|x|) lies in (0, 1], so nothing overflows for a steep segment either way.
//           E uses its Taylor series for |x| < 1 (no threshold on the slope, no seam:
//           both forms agree to f32 rounding where they meet).
// Output:   vec4(in-scattered radiance rgb, transmittance a), the same convention as the
//           integrated froxel volume, so volfog::apply::apply_fog consumes it directly.
// Robustness: every finite input gives a finite result. Positions, heights and the
//           falloff are clamped to FOG_POSITION_LIMIT / FOG_FALLOFF_LIMIT, b to
//           [0, FOG_DENSITY_LIMIT], exponents to [-FOG_EXPONENT_LIMIT,
//           FOG_EXPONENT_LIMIT] and the peak density to FOG_PEAK_LIMIT; inside those
//           ranges the clamps change nothing (transmittance is 0 long before).
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "Global
//           Volumetric Fog" (eq. 2) and "Fog Volumes" (arbitrary gradient direction,
//           gradient shifted along it).
#define_import_path volfog::height_fog

#import volfog::types::HeightFog
#import volfog::phase::phase_hg

// Below this |x| the mean E(x) is evaluated by its Taylor series through x^10 / 11!
// (truncation < 2.1e-9 relative); above it the direct form loses < 3e-7 to rounding.
const FOG_SERIES_LIMIT: f32 = 1.0;
// Exponent arguments are clamped to +-FOG_EXPONENT_LIMIT (exp(80) = 5.5e34).
const FOG_EXPONENT_LIMIT: f32 = 80.0;
// Largest base density b, 1/m (fog this dense is opaque within a millimetre).
const FOG_DENSITY_LIMIT: f32 = 1e3;
// Largest falloff |c|, 1/m.
const FOG_FALLOFF_LIMIT: f32 = 1e3;
// Positions, segments and heights are clamped to +-FOG_POSITION_LIMIT metres.
const FOG_POSITION_LIMIT: f32 = 1e9;
// Largest peak density b * exp(e), 1/m; keeps the optical depth finite.
const FOG_PEAK_LIMIT: f32 = 1e20;

// E(x) = (1 - exp(-x)) / x, the mean of exp(-x s) over s in [0, 1]; E(0) = 1.
// Exact to f32 rounding for every x >= -FOG_EXPONENT_LIMIT (smaller x are clamped).
fn exp_segment_average(x_in: f32) -> f32 {
    let x = max(x_in, -FOG_EXPONENT_LIMIT);
    if abs(x) < FOG_SERIES_LIMIT {
        // sum_k (-x)^k / (k + 1)!, k = 0..10, in Horner form.
        var s = 1.0 - x / 11.0;
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
    return (1.0 - exp(-x)) / x;
}

// Optical depth (dimensionless) of f(p) = b exp(-c (dot(p, up) - h0)) along the segment
// from origin to origin + segment (m). b in 1/m, c in 1/m, h0 in m, up a unit vector.
// Zero for a zero-length segment; finite for every finite input.
fn height_fog_optical_depth(b: f32, c: f32, h0: f32, up: vec3<f32>, origin: vec3<f32>, segment: vec3<f32>) -> f32 {
    let lim = vec3<f32>(FOG_POSITION_LIMIT);
    let o = clamp(origin, -lim, lim);
    let d = clamp(segment, -lim, lim);
    let u = clamp(up, vec3<f32>(-1.0), vec3<f32>(1.0));
    let k = clamp(c, -FOG_FALLOFF_LIMIT, FOG_FALLOFF_LIMIT);
    let h = dot(o, u) - clamp(h0, -FOG_POSITION_LIMIT, FOG_POSITION_LIMIT);
    // Exponents of the density at both ends and their difference x = c dot(d, up).
    let x = k * dot(d, u);
    let e0 = -k * h;
    let e1 = e0 - x;
    let e = clamp(max(e0, e1), -FOG_EXPONENT_LIMIT, FOG_EXPONENT_LIMIT);
    let peak = min(clamp(b, 0.0, FOG_DENSITY_LIMIT) * exp(e), FOG_PEAK_LIMIT);
    return peak * (length(d) * exp_segment_average(abs(x)));
}

// The part of the segment from origin to origin + segment (m) below the height top
// (m along the unit axis up), as fractions vec2(t0, t1) of the segment; t1 <= t0 when
// none of it is below (the medium is empty above its top).
fn height_fog_below_top(up: vec3<f32>, top: f32, origin: vec3<f32>, segment: vec3<f32>) -> vec2<f32> {
    let h = dot(origin, up);
    let dh = dot(segment, up);
    if dh == 0.0 {
        return select(vec2<f32>(0.0), vec2<f32>(0.0, 1.0), h <= top);
    }
    let t = clamp((top - h) / dh, 0.0, 1.0);
    return select(vec2<f32>(t, 1.0), vec2<f32>(0.0, t), dh > 0.0);
}

// height_fog_optical_depth of the segment's part below top (m along up): the optical
// depth of a profile whose medium ends at its top.
fn height_fog_optical_depth_below(b: f32, c: f32, h0: f32, up: vec3<f32>, top: f32, origin: vec3<f32>, segment: vec3<f32>) -> f32 {
    let part = height_fog_below_top(up, top, origin, segment);
    if part.y <= part.x {
        return 0.0;
    }
    return height_fog_optical_depth(b, c, h0, up, origin + segment * part.x, segment * (part.y - part.x));
}

// Optical depth from origin (m) towards a light infinitely far along the unit
// direction towards (the sun) through the profile below top (m along up): the path
// leaves the medium at its top after (top - h) / dot(towards, up) metres, which for
// c > 0 and top far above is Wenzel's integral towards infinity,
// b exp(-c (h - h0)) / (c dot(towards, up)). A light at or below the horizon
// (dot(towards, up) <= 0) is followed for FOG_POSITION_LIMIT metres, so its optical
// depth grows without bound as it sinks: the transmittance falls smoothly to 0 with no
// division by zero. 0 at and above the top.
fn height_fog_light_optical_depth(b: f32, c: f32, h0: f32, up: vec3<f32>, top: f32, origin: vec3<f32>, towards: vec3<f32>) -> f32 {
    let h = dot(origin, up);
    if h >= top {
        return 0.0;
    }
    let mu = dot(towards, up);
    let reach = select(FOG_POSITION_LIMIT, min((top - h) / max(mu, 1e-30), FOG_POSITION_LIMIT), mu > 0.0);
    return height_fog_optical_depth(b, c, h0, up, origin, towards * reach);
}

// Light scattered along a segment from a light infinitely far along the unit direction
// towards, per unit of the light's radiance times phase (albedo 1):
//   I = integral over the segment of sigma(t) exp(-tau_view(t)) exp(-tau_light(t)) dt,
// with tau_view the optical depth from the segment's start and tau_light that of
// height_fog_light_optical_depth, for the profile below top. With no sun
// transmittance I would be 1 - T. Closed form: along the segment both depths change
// with sigma alone, d(tau_view + tau_light)/dt = sigma (1 - v / mu) with v and mu the
// up components of the unit segment direction and of towards, so with
// F = tau_view + tau_light and r = 1 - v / mu,
//   I = exp(-min(F(start), F(end))) tau E(|r| tau),   tau = tau_view(end),
// E the mean of volfog::height_fog::exp_segment_average: exact for any slope, and
// finite where r -> 0 (the segment climbs as steeply as the light) or r -> -inf (a
// low light). 0 for a light at or below the horizon.
fn height_fog_lit_integral(b: f32, c: f32, h0: f32, up: vec3<f32>, top: f32, origin: vec3<f32>, segment: vec3<f32>, towards: vec3<f32>) -> f32 {
    let mu = dot(towards, up);
    let part = height_fog_below_top(up, top, origin, segment);
    if mu <= 0.0 || part.y <= part.x {
        return 0.0;
    }
    // Above the top there is no medium: the part below starts with tau_view = 0.
    let o = origin + segment * part.x;
    let d = segment * (part.y - part.x);
    let tau = height_fog_optical_depth(b, c, h0, up, o, d);
    let f0 = height_fog_light_optical_depth(b, c, h0, up, top, o, towards);
    let f1 = tau + height_fog_light_optical_depth(b, c, h0, up, top, o + d, towards);
    let v = dot(d, up) / max(length(d), 1e-30);
    let r = clamp(1.0 - v / mu, -1e20, 1e20);
    return exp(-min(f0, f1)) * tau * exp_segment_average(min(abs(r) * tau, 1e30));
}

// Transmittance exp(-OD) in (0, 1] along the same segment (arguments as above).
fn height_fog_transmittance(b: f32, c: f32, h0: f32, up: vec3<f32>, origin: vec3<f32>, segment: vec3<f32>) -> f32 {
    return exp(-height_fog_optical_depth(b, c, h0, up, origin, segment));
}

// Fog of optical depth od >= 0 lit by a constant in-scattered radiance (albedo 1):
// vec4(radiance * (1 - T), T) with T = exp(-od). For thin fog (od below the series
// limit) 1 - T is evaluated as od * E(od), which keeps its relative precision.
fn fog_inscatter(radiance: vec3<f32>, od_in: f32) -> vec4<f32> {
    let od = max(od_in, 0.0);
    let t = exp(-od);
    let absorbed = select(1.0 - t, od * exp_segment_average(od), od < FOG_SERIES_LIMIT);
    return vec4<f32>(radiance * absorbed, t);
}

// Height fog along the segment from origin to origin + segment (m, world space) with
// the parameters of a HeightFog uniform: rgb the in-scattered radiance
// (fog.color + fog.sun_color * HG(dot(view_dir, fog.sun_direction), fog.sun_g)) * (1 - T),
// a the transmittance T. view_dir is the direction of segment (eye to shaded point).
fn height_fog(fog: HeightFog, origin: vec3<f32>, segment: vec3<f32>) -> vec4<f32> {
    return height_fog_from_vertex(height_fog_vertex(fog, origin, segment));
}

// The fog of height_fog before its exponential: vec4(in-scattered radiance rgb of the
// fog seen along segment, optical depth a). Wenzel 2007 ("Fog and Alpha-Transparent
// Objects") approximates the global fog per vertex for transparent objects; call this
// in the vertex stage with origin the camera and segment the vertex minus the camera,
// interpolate the result (perspective-correct) and finish each fragment with
// height_fog_from_vertex. Pure arithmetic, no texture: for vertex stages, older
// hardware or passes where per-pixel fog costs too much. The interpolated optical
// depth is exact for uniform fog along straight view rays and otherwise errs by the
// curvature of the optical depth across the triangle.
fn height_fog_vertex(fog: HeightFog, origin: vec3<f32>, segment: vec3<f32>) -> vec4<f32> {
    let od = height_fog_optical_depth_below(fog.density, fog.falloff, fog.base_height, fog.up, fog.top_height, origin, segment);
    let d = clamp(segment, vec3<f32>(-FOG_POSITION_LIMIT), vec3<f32>(FOG_POSITION_LIMIT));
    let view_dir = d / max(length(d), 1e-30);
    let cos_theta = clamp(dot(view_dir, fog.sun_direction), -1.0, 1.0);
    let lobe = phase_hg(cos_theta, clamp(fog.sun_g, -0.999, 0.999));
    let sun = height_fog_sun_share(fog, origin, segment, od);
    return vec4<f32>(fog.color + fog.sun_color * (lobe * sun), od);
}

// The share in [0, 1] of the sun's light that reaches a segment through the fog, per
// unit of the light it absorbs: height_fog_lit_integral / (1 - T) with fog.
// sun_transmittance, 1 without it (or where nothing is absorbed). od is the segment's
// optical depth below the top (height_fog_optical_depth_below).
fn height_fog_sun_share(fog: HeightFog, origin: vec3<f32>, segment: vec3<f32>, od: f32) -> f32 {
    if fog.sun_transmittance == 0u {
        return 1.0;
    }
    let absorbed = fog_inscatter(vec3<f32>(1.0), od).r;
    let lit = height_fog_lit_integral(fog.density, fog.falloff, fog.base_height, fog.up,
        fog.top_height, origin, segment, fog.sun_direction);
    return select(1.0, clamp(lit / absorbed, 0.0, 1.0), absorbed > 0.0);
}

// Fog (rgb in-scatter, a transmittance) from the interpolated output of
// height_fog_vertex.
fn height_fog_from_vertex(vertex_fog: vec4<f32>) -> vec4<f32> {
    return fog_inscatter(vertex_fog.rgb, vertex_fog.a);
}
