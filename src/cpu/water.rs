//! Mirror of `volfog::water`: underwater fog below a water plane (the river and ocean
//! models of Wenzel 2007), the light reaching a point under water and the shore fade of
//! the water surface.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::water::{water_fog, water_light};
//! use volfog::uniforms::Water;
//!
//! // Ocean: light fades with depth, red first.
//! let sea = Water::ocean(0.0, Vec3::ONE, 0.1, Vec3::new(0.4, 0.1, 0.05)).unwrap();
//! let deep = water_light(&sea, Vec3::new(0.0, -10.0, 0.0));
//! assert!(deep.x < deep.y && deep.y < deep.z);
//! // Looking down from 1 m above the surface to the bed 5 m below it: 5 m of water.
//! let fog = water_fog(&sea, Vec3::Y, Vec3::new(0.0, -5.0, 0.0));
//! assert!((fog.w - (-0.5f32).exp()).abs() < 1e-6);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::height_fog::{FOG_EXPONENT_LIMIT, exp_segment_average};
use super::phase::phase_hg;
use crate::limits::FOG_POSITION_LIMIT;
use crate::uniforms::Water;

/// A shore fade shorter than this (m) is a hard depth test.
pub const WATER_MIN_SHORE_FADE: f32 = 1e-6;

/// Depth (m) of `p` below the surface; negative above it.
pub fn water_depth(water: &Water, p: Vec3) -> f32 {
    let lim = Vec3::splat(FOG_POSITION_LIMIT);
    water.height.clamp(-FOG_POSITION_LIMIT, FOG_POSITION_LIMIT)
        - p.clamp(-lim, lim).dot(water.normal)
}

/// Ray parameters `[t0, t1]` within `[0, 1]` of the part of the segment from
/// `camera_pos` (t = 0) to `point` (t = 1) below the surface; `t0 == t1` above it.
pub fn water_segment(water: &Water, camera_pos: Vec3, point: Vec3) -> Vec2 {
    let d0 = water_depth(water, camera_pos);
    let d1 = water_depth(water, point);
    if d0 < 0.0 && d1 < 0.0 {
        Vec2::new(1.0, 1.0)
    } else if d0 < 0.0 {
        Vec2::new((d0 / (d0 - d1)).clamp(0.0, 1.0), 1.0)
    } else if d1 < 0.0 {
        Vec2::new(0.0, (d0 / (d0 - d1)).clamp(0.0, 1.0))
    } else {
        Vec2::new(0.0, 1.0)
    }
}

/// Light (linear rgb) reaching `p` under water: `light * exp(-attenuation * depth)`.
pub fn water_light(water: &Water, p: Vec3) -> Vec3 {
    let d = water_depth(water, p).max(0.0);
    water.light * (-(water.attenuation * d).min(Vec3::splat(FOG_EXPONENT_LIMIT))).exp()
}

/// `s * exp(e0) * E(x)`, the integral of `exp(e0 - x u / s)` over `u` in `[0, s]`.
pub fn water_exp_integral(s: f32, e0: f32, x: f32) -> f32 {
    let e = e0
        .max(e0 - x)
        .clamp(-FOG_EXPONENT_LIMIT, FOG_EXPONENT_LIMIT);
    s * e.exp() * exp_segment_average(x.abs())
}

/// Underwater fog between `camera_pos` and `point`: `(in-scatter rgb, T)`.
pub fn water_fog(water: &Water, camera_pos: Vec3, point: Vec3) -> Vec4 {
    let lim = Vec3::splat(FOG_POSITION_LIMIT);
    let eye = camera_pos.clamp(-lim, lim);
    let seg = point.clamp(-lim, lim) - eye;
    let t = water_segment(water, eye, eye + seg);
    let length_all = seg.length();
    let s = (t.y - t.x) * length_all;
    let dir = seg / length_all.max(1e-30);
    let entry = eye + t.x * seg;
    let d0 = water_depth(water, entry).max(0.0);
    let up = dir.dot(water.normal).clamp(-1.0, 1.0);
    let sigma = water.extinction.clamp(0.0, 1e3);
    let k = water.attenuation.clamp(Vec3::ZERO, Vec3::splat(1e3));
    let lobe = phase_hg(up, water.g.clamp(-0.999, 0.999));
    let source = water.albedo * water.light * (sigma * lobe);
    let x = (Vec3::splat(sigma) - k * up) * s;
    let e0 = -(k * d0).min(Vec3::splat(FOG_EXPONENT_LIMIT));
    let integral = Vec3::new(
        water_exp_integral(s, e0.x, x.x),
        water_exp_integral(s, e0.y, x.y),
        water_exp_integral(s, e0.z, x.z),
    );
    (source * integral).extend((-sigma * s).exp())
}

/// Opacity factor in `[0, 1]` of a water surface at view depth `surface_depth` in front
/// of the scene at `scene_depth` (m), fading in over `fade` metres.
pub fn water_shore_fade(surface_depth: f32, scene_depth: f32, fade: f32) -> f32 {
    let gap = (scene_depth - surface_depth).clamp(-FOG_POSITION_LIMIT, FOG_POSITION_LIMIT);
    (gap / fade.max(WATER_MIN_SHORE_FADE)).clamp(0.0, 1.0)
}

/// The largest view depth of the texel at `pixel` and its four direct neighbours
/// (clamped to the image) of a `width` x `height` row-major linear depth image.
pub fn water_scene_depth(depths: &[f32], width: usize, height: usize, pixel: (i32, i32)) -> f32 {
    let at = |x: i32, y: i32| {
        let x = x.clamp(0, width as i32 - 1) as usize;
        let y = y.clamp(0, height as i32 - 1) as usize;
        depths[y * width + x]
    };
    let (x, y) = (
        pixel.0.clamp(0, width as i32 - 1),
        pixel.1.clamp(0, height as i32 - 1),
    );
    [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)]
        .iter()
        .map(|(dx, dy)| at(x + dx, y + dy))
        .fold(f32::NEG_INFINITY, f32::max)
}
