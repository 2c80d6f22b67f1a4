//! Mirror of `volfog::clouds`: cloud shadows, distance clouds and the lit cloud layer
//! from a wind-scrolled 2D density map (Wenzel 2007, "Clouds", "Cloud Shadows",
//! "Distance Clouds").
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::clouds::{CloudMap, cloud_shadow};
//! use volfog::uniforms::CloudLayer;
//!
//! // Uniform clouds of density 1: 400 m at 0.005 / m straight overhead.
//! let map = CloudMap::uniform(1.0);
//! let layer = CloudLayer::new(1000.0, 400.0, 0.005, 5000.0).unwrap();
//! let t = cloud_shadow(&map, &layer, Vec3::ZERO);
//! assert!((t - (-2.0f32).exp()).abs() < 1e-6);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::phase::phase_hg;
use super::soft_particles::soft_particle_box_fade;
use crate::uniforms::CloudLayer;

/// Below this sun height clouds cast no shadow.
pub const CLOUD_MIN_SUN_HEIGHT: f32 = 0.01;
/// View rays are cut at this distance (m).
pub const CLOUD_MAX_DISTANCE: f32 = 1e5;
/// No clouds.
pub const CLOUD_NONE: Vec4 = Vec4::new(0.0, 0.0, 0.0, 1.0);

/// A cloud density map (red channel), sampled as the GPU samples it with a linear,
/// repeat sampler.
#[derive(Debug, Clone, PartialEq)]
pub struct CloudMap {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Densities in [0, 1], row-major.
    pub texels: Vec<f32>,
}

impl CloudMap {
    /// A 1 x 1 map of one density.
    pub fn uniform(density: f32) -> Self {
        Self {
            width: 1,
            height: 1,
            texels: vec![density],
        }
    }

    /// Bilinear look-up with repeat addressing at `uv` (texel centres at
    /// `(i + 0.5) / width`).
    pub fn sample(&self, uv: Vec2) -> f32 {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = uv.x * w as f32 - 0.5;
        let y = uv.y * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| self.texels[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
        let (i, j) = (x0 as i64, y0 as i64);
        let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// Map coordinates of world (x, z), scrolled by the wind, wrapped into [0, 1).
pub fn cloud_map_uv(layer: &CloudLayer, xz: Vec2) -> Vec2 {
    let uv = (xz - layer.wind * layer.time) / layer.map_size.max(1e-6);
    uv - uv.floor()
}

/// Map density in [0, 1] at world (x, z).
pub fn cloud_density(map: &CloudMap, layer: &CloudLayer, xz: Vec2) -> f32 {
    map.sample(cloud_map_uv(layer, xz)).clamp(0.0, 1.0)
}

fn xz(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.z)
}

/// Transmittance of the sun's light at `p` through the cloud layer.
pub fn cloud_shadow(map: &CloudMap, layer: &CloudLayer, p: Vec3) -> f32 {
    let sun = layer.sun_direction;
    let middle = layer.base_height + 0.5 * layer.thickness;
    let rise = middle - p.y;
    if sun.y < CLOUD_MIN_SUN_HEIGHT || rise <= 0.0 {
        return 1.0;
    }
    let q = xz(p) + xz(sun) * (rise.min(CLOUD_MAX_DISTANCE) / sun.y);
    let m = cloud_density(map, layer, q);
    (-(layer.extinction * m * layer.thickness / sun.y).min(80.0)).exp()
}

/// Ray parameters `[t0, t1]` of the slab along the unit `dir` from `eye`, cut to
/// `[0, min(max_distance, CLOUD_MAX_DISTANCE)]`.
pub fn cloud_slab(layer: &CloudLayer, eye: Vec3, dir: Vec3, max_distance: f32) -> Vec2 {
    let far = max_distance.min(CLOUD_MAX_DISTANCE);
    let bottom = layer.base_height;
    let top = layer.base_height + layer.thickness;
    if dir.y.abs() < 1e-6 {
        let inside = eye.y >= bottom && eye.y <= top;
        return if inside {
            Vec2::new(0.0, far)
        } else {
            Vec2::new(1.0, 0.0)
        };
    }
    let ta = (bottom - eye.y) / dir.y;
    let tb = (top - eye.y) / dir.y;
    Vec2::new(ta.min(tb).clamp(0.0, far), ta.max(tb).clamp(0.0, far))
}

/// Distance clouds along the unit `dir` from `eye` up to `max_distance`:
/// `(in-scatter rgb, T)`.
pub fn distance_clouds(
    map: &CloudMap,
    layer: &CloudLayer,
    eye: Vec3,
    dir: Vec3,
    max_distance: f32,
) -> Vec4 {
    let t = cloud_slab(layer, eye, dir, max_distance);
    if t.y <= t.x {
        return CLOUD_NONE;
    }
    let n = layer.view_samples.clamp(1, 64);
    let m = layer.sun_samples.clamp(1, 64);
    let sun = layer.sun_direction;
    let ds = (t.y - t.x) / n as f32;
    let lobe = phase_hg(dir.dot(sun).clamp(-1.0, 1.0), layer.g.clamp(-0.999, 0.999));
    let top = layer.base_height + layer.thickness;
    let mut transmittance = 1.0f32;
    let mut inscatter = Vec3::ZERO;
    for i in 0..n {
        let p = eye + dir * (t.x + (i as f32 + 0.5) * ds);
        let sigma = layer.extinction * cloud_density(map, layer, xz(p));
        let mut sun_light = 0.0;
        if sun.y >= CLOUD_MIN_SUN_HEIGHT {
            let dl = ((top - p.y).max(0.0) / sun.y).min(CLOUD_MAX_DISTANCE) / m as f32;
            let mut depth = 0.0;
            for j in 0..m {
                let q = p + sun * ((j as f32 + 0.5) * dl);
                depth += layer.extinction * cloud_density(map, layer, xz(q)) * dl;
            }
            sun_light = (-depth.min(80.0_f32)).exp();
        }
        let step_t = (-(sigma * ds).min(80.0)).exp();
        inscatter += transmittance
            * (1.0 - step_t)
            * (layer.sun_color * (sun_light * lobe) + layer.sky_color);
        transmittance *= step_t;
    }
    inscatter.extend(transmittance)
}

/// The cloud layer lit per pixel along the unit `dir` from `eye`, the scene
/// `max_distance` along the ray: `(in-scatter rgb, T)`, soft-clipped at the scene.
pub fn cloud_layer(
    map: &CloudMap,
    layer: &CloudLayer,
    eye: Vec3,
    dir: Vec3,
    max_distance: f32,
    map_texels: u32,
) -> Vec4 {
    let whole = cloud_slab(layer, eye, dir, CLOUD_MAX_DISTANCE);
    if whole.y <= whole.x {
        return CLOUD_NONE;
    }
    let fade = soft_particle_box_fade(whole.x, whole.y, max_distance);
    let t_mid = 0.5 * (whole.x + whole.y.min(max_distance.max(whole.x)));
    let p = eye + dir * t_mid;
    let m = cloud_density(map, layer, xz(p));
    let texel = layer.map_size.max(1e-6) / map_texels as f32;
    let d = |dx: f32, dz: f32| cloud_density(map, layer, xz(p) + Vec2::new(dx, dz));
    let grad = Vec2::new(
        d(texel, 0.0) - d(-texel, 0.0),
        d(0.0, texel) - d(0.0, -texel),
    ) / (2.0 * texel);
    let normal = Vec3::new(-grad.x * layer.thickness, 1.0, -grad.y * layer.thickness).normalize();
    let sun = layer.sun_direction;
    let diffuse = 0.5 + 0.5 * normal.dot(sun);
    let lobe = phase_hg(dir.dot(sun).clamp(-1.0, 1.0), layer.g.clamp(-0.999, 0.999));
    let rim = layer.rim * (1.0 - m) * (1.0 - m) * lobe;
    let color = layer.sun_color * (diffuse + rim) + layer.sky_color;
    let opacity = (1.0 - (-(layer.extinction * m * (whole.y - whole.x)).min(80.0)).exp()) * fade;
    (color * opacity).extend(1.0 - opacity)
}
