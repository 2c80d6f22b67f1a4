//! Mirror of `volfog::sky`: single Rayleigh and Mie scattering of the sky (Nishita et
//! al. 1993; Wenzel 2007, eq. 1), per direction, with the phase applied per pixel.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::sky::{sky_radiance, sky_single_scattering};
//! use volfog::uniforms::SkyAtmosphere;
//!
//! let noon = SkyAtmosphere::earth(Vec3::new(0.0, 0.95, -0.31).normalize()).unwrap();
//! let zenith = sky_single_scattering(&noon, Vec3::Y);
//! let sky = sky_radiance(&zenith, Vec3::Y.dot(noon.sun_direction), &noon);
//! // Rayleigh scattering makes the clear zenith blue.
//! assert!(sky.z > sky.y && sky.y > sky.x);
//! ```

use glam::{UVec2, Vec2, Vec3};

use super::height_fog::{fog_inscatter, height_fog_optical_depth};
use super::phase::{phase_cornette_shanks, phase_rayleigh};
use crate::limits::FOG_POSITION_LIMIT;
use crate::uniforms::{HeightFog, SkyAtmosphere};

/// Width of the sky texture (azimuth).
pub const SKY_TEXTURE_WIDTH: u32 = 128;
/// Height of the sky texture (elevation, dense near the horizon).
pub const SKY_TEXTURE_HEIGHT: u32 = 64;
/// π as the shader writes it.
pub const SKY_PI: f32 = std::f32::consts::PI;
/// Optical depth of a sun ray that the planet blocks.
pub const SKY_OPAQUE: f32 = 1e9;

/// The two integrals of eq. 1 for one direction (times K, without I_s and F).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkyScattering {
    /// Rayleigh (rgb).
    pub rayleigh: Vec3,
    /// Mie (rgb).
    pub mie: Vec3,
}

/// Quadrature point `i` of `n` over `[0, length]`: `(s, ds)`, exponential spacing.
pub fn sky_quadrature(i: u32, n: u32, length: f32, scale: f32) -> Vec2 {
    let a = (1.0 + length.max(0.0) / scale).ln();
    let u = (i as f32 + 0.5) / n as f32;
    let e = (a * u).exp();
    Vec2::new(scale * (e - 1.0), scale * a * e / n as f32)
}

/// Height (m) of the point at distance `s` along a ray from height `h0` with cosine
/// `mu` to the vertical.
pub fn sky_height(h0: f32, mu: f32, s: f32, planet: f32) -> f32 {
    let r0 = planet + h0;
    let r = (r0 * r0 + s * s + 2.0 * r0 * s * mu).max(0.0).sqrt();
    (s * (s + 2.0 * r0 * mu) + h0 * (r0 + planet)) / (r + planet)
}

/// Does the ray from height `h0` with cosine `mu` hit the planet?
pub fn sky_hits_planet(h0: f32, mu: f32, planet: f32) -> bool {
    let r0 = planet + h0;
    mu < 0.0 && (r0 * mu) * (r0 * mu) > h0 * (r0 + planet)
}

/// Distance (m) to the top of the atmosphere, or to the ground where the ray hits it.
pub fn sky_ray_length(h0: f32, mu: f32, planet: f32, top: f32) -> f32 {
    let r0 = planet + h0;
    if sky_hits_planet(h0, mu, planet) {
        let disc = (r0 * mu) * (r0 * mu) - h0 * (r0 + planet);
        return h0 * (r0 + planet) / (-r0 * mu + disc.max(0.0).sqrt()).max(1e-30);
    }
    let rise = (top - r0) * (top + r0);
    let disc = (r0 * mu) * (r0 * mu) + rise;
    if mu >= 0.0 {
        return rise / (r0 * mu + disc.max(0.0).sqrt()).max(1e-30);
    }
    -r0 * mu + disc.max(0.0).sqrt()
}

/// The quadrature's scale height: the geometric mean of the two.
pub fn sky_scale(atmosphere: &SkyAtmosphere) -> f32 {
    (atmosphere.rayleigh_height * atmosphere.mie_height).sqrt()
}

/// Optical depths (Rayleigh, Mie) from height `h` towards the sun at cosine `mu`.
pub fn sky_light_depth(atmosphere: &SkyAtmosphere, h: f32, mu: f32) -> Vec2 {
    let planet = atmosphere.planet_radius;
    if sky_hits_planet(h, mu, planet) {
        return Vec2::splat(SKY_OPAQUE);
    }
    let length = sky_ray_length(h, mu, planet, atmosphere.atmosphere_radius);
    let n = atmosphere.light_samples.clamp(1, 256);
    let scale = sky_scale(atmosphere);
    let mut depth = Vec2::ZERO;
    for j in 0..n {
        let q = sky_quadrature(j, n, length, scale);
        let hj = sky_height(h, mu, q.x, planet);
        depth += Vec2::new(
            (-hj / atmosphere.rayleigh_height).exp(),
            (-hj / atmosphere.mie_height).exp(),
        ) * q.y;
    }
    depth
}

/// Eq. 1 without I_s and F for one unit view direction.
pub fn sky_single_scattering(atmosphere: &SkyAtmosphere, view_dir: Vec3) -> SkyScattering {
    let planet = atmosphere.planet_radius;
    let top = atmosphere.atmosphere_radius;
    let h0 = atmosphere.camera_height.clamp(0.0, 0.999 * (top - planet));
    let r0 = planet + h0;
    let mu = view_dir.y.clamp(-1.0, 1.0);
    let sun = atmosphere.sun_direction;
    let cos_view_sun = view_dir.dot(sun);
    let length = sky_ray_length(h0, mu, planet, top);
    let n = atmosphere.view_samples.clamp(1, 256);
    let scale = sky_scale(atmosphere);
    let mie_extinction = atmosphere.mie * atmosphere.mie_extinction_ratio;
    let mut view_depth = Vec2::ZERO;
    let (mut sum_r, mut sum_m) = (Vec3::ZERO, Vec3::ZERO);
    for i in 0..n {
        let q = sky_quadrature(i, n, length, scale);
        let h = sky_height(h0, mu, q.x, planet);
        let density = Vec2::new(
            (-h / atmosphere.rayleigh_height).exp(),
            (-h / atmosphere.mie_height).exp(),
        );
        let half_step = density * (0.5 * q.y);
        view_depth += half_step;
        let mu_sun = ((r0 * sun.y + q.x * cos_view_sun) / (planet + h)).clamp(-1.0, 1.0);
        let light = sky_light_depth(atmosphere, h, mu_sun);
        let depth = view_depth + light;
        let t = (-(atmosphere.rayleigh * depth.x + Vec3::splat(mie_extinction * depth.y))).exp();
        sum_r += t * (density.x * q.y);
        sum_m += t * (density.y * q.y);
        view_depth += half_step;
    }
    SkyScattering {
        rayleigh: atmosphere.rayleigh * sum_r,
        mie: atmosphere.mie * sum_m,
    }
}

/// Radiance of the sky: `I_s (R F_Rayleigh + M F_Cornette-Shanks(g))`.
pub fn sky_radiance(
    scattering: &SkyScattering,
    cos_theta: f32,
    atmosphere: &SkyAtmosphere,
) -> Vec3 {
    let c = cos_theta.clamp(-1.0, 1.0);
    let g = atmosphere.mie_g.clamp(0.0, 0.999);
    atmosphere.sun_intensity
        * (scattering.rayleigh * phase_rayleigh(c) + scattering.mie * phase_cornette_shanks(c, g))
}

/// Unit direction of the centre of texel `(x, y)` of the sky texture.
pub fn sky_texel_direction(texel: UVec2) -> Vec3 {
    let u = (texel.x as f32 + 0.5) / SKY_TEXTURE_WIDTH as f32;
    let v = (texel.y as f32 + 0.5) / SKY_TEXTURE_HEIGHT as f32;
    let azimuth = 2.0 * SKY_PI * u;
    let elevation = 0.5 * SKY_PI * v * v;
    Vec3::new(
        elevation.cos() * azimuth.cos(),
        elevation.sin(),
        elevation.cos() * azimuth.sin(),
    )
}

/// Texture coordinates of a direction (below the horizon: the horizon).
pub fn sky_texture_uv(dir: Vec3) -> Vec2 {
    let mut azimuth = dir.z.atan2(dir.x);
    if azimuth < 0.0 {
        azimuth += 2.0 * SKY_PI;
    }
    let elevation = dir.y.clamp(0.0, 1.0).asin();
    Vec2::new(
        azimuth / (2.0 * SKY_PI),
        (elevation / (0.5 * SKY_PI)).sqrt(),
    )
}

/// The sky's scattering averaged along the horizon (row 0 of the texture's
/// directions), as the `sky_horizon` pass computes it: the colour of fog that matches
/// the sky there, with [`sky_radiance`] and the view's phase.
pub fn sky_horizon(atmosphere: &SkyAtmosphere) -> SkyScattering {
    let n = SKY_TEXTURE_WIDTH;
    let (mut r, mut m) = (Vec3::ZERO, Vec3::ZERO);
    for x in 0..n {
        let s = sky_single_scattering(atmosphere, sky_texel_direction(UVec2::new(x, 0)));
        r += s.rayleigh;
        m += s.mie;
    }
    SkyScattering {
        rayleigh: r / n as f32,
        mie: m / n as f32,
    }
}

/// Height fog (the density of `fog`) lit by the sky's horizon average `horizon` with
/// the view's phase: `(in-scatter rgb, T)` along `origin -> origin + segment`.
pub fn sky_height_fog(
    fog: &HeightFog,
    horizon: &SkyScattering,
    atmosphere: &SkyAtmosphere,
    origin: Vec3,
    segment: Vec3,
) -> glam::Vec4 {
    let od = height_fog_optical_depth(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        origin,
        segment,
    );
    let d = segment.clamp(
        Vec3::splat(-FOG_POSITION_LIMIT),
        Vec3::splat(FOG_POSITION_LIMIT),
    );
    let view_dir = d / d.length().max(1e-30);
    fog_inscatter(
        sky_radiance(horizon, view_dir.dot(atmosphere.sun_direction), atmosphere),
        od,
    )
}
