// volfog::sky — sky light from single Rayleigh and Mie scattering (Nishita et al. 1993),
// solved per direction of a hemisphere texture, the phase applied per pixel.
//
// Use:      pass sky_solve fills the texture (two layers: Rayleigh, Mie) for the sun of
//           the SkyAtmosphere uniform, optionally a band of rows per frame; then
//           #import volfog::sky::sky_sample
//           let sky = sky_sample(sky_texture, sky_sampler, view_dir, atmosphere);
//           Height fog that matches the sky at the horizon: sky_horizon averages the
//           lowest row; sky_height_fog(fog, horizon, atmosphere, origin, segment) is
//           volfog::height_fog's density lit by sky_radiance(horizon, dot(view_dir,
//           sun), atmosphere) (Wenzel: "average in-scattering samples along the
//           horizon ... combine with the per-pixel phase function").
// Defines:  none
// Model:    Wenzel 2007, eq. 1: I_v = I_s K F(theta, g) int_Pa^Pb e^(-h / H)
//           e^(-t(P Pc) - t(P Pa)) ds, for Rayleigh (K = beta_R(lambda), H_R, F the
//           Rayleigh phase) and Mie (K = beta_M, H_M, F Cornette-Shanks), the camera
//           on the ground at altitude h_c, a spherical planet, +Y up. t(P Pc) is the
//           optical depth from P towards the sun (infinite where the planet blocks the
//           sun: no light), t(P Pa) from P back to the camera; the Mie extinction is
//           mie_extinction_ratio times its scattering. The texture stores the two
//           integrals times K, without I_s and F: the sun's spot, F at high frequency,
//           is applied per pixel (the seed's move of F to the GPU).
// Quadrature: view_samples midpoints along the view ray and light_samples along each
//           sun ray, spaced exponentially, s(u) = H (e^(a u) - 1), a = ln(1 + L / H)
//           with H the geometric mean of the scale heights, dense where the air is.
//           Heights along a ray are evaluated in a form without cancellation, so f32
//           keeps metres at planet radius.
// Texture:  SKY_TEXTURE_WIDTH x SKY_TEXTURE_HEIGHT (128 x 64, the seed's size), x the
//           azimuth atan2(z, x) over [0, 2 pi), y the elevation e = (pi / 2) v^2 (rows
//           dense near the horizon). Directions below the horizon read the horizon row.
//           Sample with a linear sampler, repeat in u, clamp in v.
// Units:    metres; scattering coefficients 1/m; the radiance is I_s times (1/sr).
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "Sky
//           Light Rendering" (eq. 1); Nishita, Sirai, Tadamura & Nakamae 1993.
#define_import_path volfog::sky

#import volfog::types::{SkyAtmosphere, HeightFog}
#import volfog::phase::{phase_rayleigh, phase_cornette_shanks}
#import volfog::height_fog::{height_fog_optical_depth, fog_inscatter, FOG_POSITION_LIMIT}

const SKY_TEXTURE_WIDTH: u32 = 128u;
const SKY_TEXTURE_HEIGHT: u32 = 64u;
const SKY_PI: f32 = 3.14159265358979;
// Optical depth of a sun ray that the planet blocks.
const SKY_OPAQUE: f32 = 1e9;

// The two integrals of eq. 1 for one direction (times K, without I_s and F).
struct SkyScattering {
    rayleigh: vec3<f32>,
    mie: vec3<f32>,
}

// A SkyScattering, field by field (a constructor expression becomes a helper function
// in HLSL, outside the snippets' volfog_ names).
fn sky_scattering(rayleigh: vec3<f32>, mie: vec3<f32>) -> SkyScattering {
    var s: SkyScattering;
    s.rayleigh = rayleigh;
    s.mie = mie;
    return s;
}

// Quadrature point i of n over [0, length]: (position s, weight ds), exponential
// spacing with scale height `scale` (m).
fn sky_quadrature(i: u32, n: u32, length: f32, scale: f32) -> vec2<f32> {
    let a = log(1.0 + max(length, 0.0) / scale);
    let u = (f32(i) + 0.5) / f32(n);
    let e = exp(a * u);
    return vec2<f32>(scale * (e - 1.0), scale * a * e / f32(n));
}

// Height above the ground (m) of the point at distance s along a ray that starts at
// height h0 with cosine mu to the local vertical, over a planet of radius planet.
fn sky_height(h0: f32, mu: f32, s: f32, planet: f32) -> f32 {
    let r0 = planet + h0;
    let r = sqrt(max(r0 * r0 + s * s + 2.0 * r0 * s * mu, 0.0));
    return (s * (s + 2.0 * r0 * mu) + h0 * (r0 + planet)) / (r + planet);
}

// Does the ray from height h0 with cosine mu hit the planet?
fn sky_hits_planet(h0: f32, mu: f32, planet: f32) -> bool {
    let r0 = planet + h0;
    return mu < 0.0 && (r0 * mu) * (r0 * mu) > h0 * (r0 + planet);
}

// Distance (m) from height h0 along cosine mu to the top of the atmosphere (radius
// top), or to the ground where the ray hits the planet.
fn sky_ray_length(h0: f32, mu: f32, planet: f32, top: f32) -> f32 {
    let r0 = planet + h0;
    if sky_hits_planet(h0, mu, planet) {
        let disc = (r0 * mu) * (r0 * mu) - h0 * (r0 + planet);
        return h0 * (r0 + planet) / max(-r0 * mu + sqrt(max(disc, 0.0)), 1e-30);
    }
    let rise = (top - r0) * (top + r0);
    let disc = (r0 * mu) * (r0 * mu) + rise;
    if mu >= 0.0 {
        return rise / max(r0 * mu + sqrt(max(disc, 0.0)), 1e-30);
    }
    return -r0 * mu + sqrt(max(disc, 0.0));
}

// The quadrature's scale height: the geometric mean of the two.
fn sky_scale(atmosphere: SkyAtmosphere) -> f32 {
    return sqrt(atmosphere.rayleigh_height * atmosphere.mie_height);
}

// Optical depths (Rayleigh, Mie; in units of the ground densities, m) from height h
// towards the sun at cosine mu; SKY_OPAQUE where the planet blocks the sun.
fn sky_light_depth(atmosphere: SkyAtmosphere, h: f32, mu: f32) -> vec2<f32> {
    let planet = atmosphere.planet_radius;
    if sky_hits_planet(h, mu, planet) {
        return vec2<f32>(SKY_OPAQUE);
    }
    let length = sky_ray_length(h, mu, planet, atmosphere.atmosphere_radius);
    let n = clamp(atmosphere.light_samples, 1u, 256u);
    let scale = sky_scale(atmosphere);
    var depth = vec2<f32>(0.0);
    for (var j = 0u; j < n; j++) {
        let q = sky_quadrature(j, n, length, scale);
        let hj = sky_height(h, mu, q.x, planet);
        depth += vec2<f32>(exp(-hj / atmosphere.rayleigh_height), exp(-hj / atmosphere.mie_height)) * q.y;
    }
    return depth;
}

// Eq. 1 without I_s and F for one view direction (unit, +Y up) from the camera.
fn sky_single_scattering(atmosphere: SkyAtmosphere, view_dir: vec3<f32>) -> SkyScattering {
    let planet = atmosphere.planet_radius;
    let top = atmosphere.atmosphere_radius;
    let h0 = clamp(atmosphere.camera_height, 0.0, 0.999 * (top - planet));
    let r0 = planet + h0;
    let mu = clamp(view_dir.y, -1.0, 1.0);
    let sun = atmosphere.sun_direction;
    let cos_view_sun = dot(view_dir, sun);
    let length = sky_ray_length(h0, mu, planet, top);
    let n = clamp(atmosphere.view_samples, 1u, 256u);
    let scale = sky_scale(atmosphere);
    let mie_extinction = atmosphere.mie * atmosphere.mie_extinction_ratio;
    var view_depth = vec2<f32>(0.0);
    var sum_r = vec3<f32>(0.0);
    var sum_m = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let q = sky_quadrature(i, n, length, scale);
        let h = sky_height(h0, mu, q.x, planet);
        let density = vec2<f32>(exp(-h / atmosphere.rayleigh_height), exp(-h / atmosphere.mie_height));
        let half_step = density * (0.5 * q.y);
        view_depth += half_step;
        // Cosine of the sun to the vertical at the sample.
        let mu_sun = clamp((r0 * sun.y + q.x * cos_view_sun) / (planet + h), -1.0, 1.0);
        let light = sky_light_depth(atmosphere, h, mu_sun);
        let depth = view_depth + light;
        let t = exp(-(atmosphere.rayleigh * depth.x + vec3<f32>(mie_extinction * depth.y)));
        sum_r += t * (density.x * q.y);
        sum_m += t * (density.y * q.y);
        view_depth += half_step;
    }
    return sky_scattering(atmosphere.rayleigh * sum_r, atmosphere.mie * sum_m);
}

// Radiance of the sky for its scattering integrals and the cosine between the view
// direction and the sun: I_s (R F_Rayleigh + M F_Cornette-Shanks(g)).
fn sky_radiance(scattering: SkyScattering, cos_theta: f32, atmosphere: SkyAtmosphere) -> vec3<f32> {
    let c = clamp(cos_theta, -1.0, 1.0);
    let g = clamp(atmosphere.mie_g, 0.0, 0.999);
    return atmosphere.sun_intensity
        * (scattering.rayleigh * phase_rayleigh(c) + scattering.mie * phase_cornette_shanks(c, g));
}

// Unit direction of the centre of texel (x, y) of the sky texture.
fn sky_texel_direction(texel: vec2<u32>) -> vec3<f32> {
    let u = (f32(texel.x) + 0.5) / f32(SKY_TEXTURE_WIDTH);
    let v = (f32(texel.y) + 0.5) / f32(SKY_TEXTURE_HEIGHT);
    let azimuth = 2.0 * SKY_PI * u;
    let elevation = 0.5 * SKY_PI * v * v;
    return vec3<f32>(cos(elevation) * cos(azimuth), sin(elevation), cos(elevation) * sin(azimuth));
}

// Texture coordinates of a direction (unit, +Y up; below the horizon: the horizon).
fn sky_texture_uv(dir: vec3<f32>) -> vec2<f32> {
    var azimuth = atan2(dir.z, dir.x);
    azimuth = select(azimuth, azimuth + 2.0 * SKY_PI, azimuth < 0.0);
    let elevation = asin(clamp(dir.y, 0.0, 1.0));
    return vec2<f32>(azimuth / (2.0 * SKY_PI), sqrt(elevation / (0.5 * SKY_PI)));
}

// Sky radiance in a direction from the solved texture (layer 0 Rayleigh, 1 Mie) with
// the phase applied per pixel.
fn sky_sample(sky: texture_2d_array<f32>, sky_sampler: sampler, dir: vec3<f32>, atmosphere: SkyAtmosphere) -> vec3<f32> {
    let uv = sky_texture_uv(dir);
    let r = textureSampleLevel(sky, sky_sampler, uv, 0, 0.0).rgb;
    let m = textureSampleLevel(sky, sky_sampler, uv, 1, 0.0).rgb;
    return sky_radiance(sky_scattering(r, m), dot(dir, atmosphere.sun_direction), atmosphere);
}

// Height fog (the density of `fog`; its colours are not used) lit by the sky: the
// in-scattered radiance is the horizon's average scattering (pass sky_horizon) with
// the phase of the view direction, so dense fog takes the colour of the sky at the
// horizon around it. vec4(in-scatter rgb, transmittance) along origin -> origin +
// segment (m, world space).
fn sky_height_fog(fog: HeightFog, horizon: SkyScattering, atmosphere: SkyAtmosphere,
                  origin: vec3<f32>, segment: vec3<f32>) -> vec4<f32> {
    let od = height_fog_optical_depth(fog.density, fog.falloff, fog.base_height, fog.up, origin, segment);
    let d = clamp(segment, vec3<f32>(-FOG_POSITION_LIMIT), vec3<f32>(FOG_POSITION_LIMIT));
    let view_dir = d / max(length(d), 1e-30);
    return fog_inscatter(sky_radiance(horizon, dot(view_dir, atmosphere.sun_direction), atmosphere), od);
}
