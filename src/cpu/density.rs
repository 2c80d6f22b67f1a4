//! Mirror of `volfog::density`: extinction and emission of the medium at a point.
//!
//! ```
//! use volfog::cpu::density::height_density;
//! // b e^(-c (h - h0)): 0.1 / m at the base height, e times less 1 / c higher.
//! assert!((height_density(0.0, 0.1, 0.5, 0.0) - 0.1).abs() < 1e-7);
//! assert!((height_density(2.0, 0.1, 0.5, 0.0) - 0.1 / std::f32::consts::E).abs() < 1e-7);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::height_fog::{height_fog_light_optical_depth, height_fog_optical_depth_below};
use crate::uniforms::{FogMedium, FogSample, LocalVolume};

/// Exponents are clamped to this magnitude.
pub const DENSITY_MAX_EXPONENT: f32 = 80.0;

/// Exponential height profile `b e^(-c (h - h0))`.
pub fn height_density(h: f32, b: f32, c: f32, h0: f32) -> f32 {
    b * (-c * (h - h0))
        .clamp(-DENSITY_MAX_EXPONENT, DENSITY_MAX_EXPONENT)
        .exp()
}

/// `LocalVolume.shape` of a box (WGSL `LOCAL_VOLUME_BOX`).
pub const LOCAL_VOLUME_BOX: u32 = 0;
/// `LocalVolume.shape` of an ellipsoid (WGSL `LOCAL_VOLUME_ELLIPSOID`).
pub const LOCAL_VOLUME_ELLIPSOID: u32 = 1;
/// `LocalVolume.shape` of a cylinder (WGSL `LOCAL_VOLUME_CYLINDER`).
pub const LOCAL_VOLUME_CYLINDER: u32 = 3;
/// `LocalVolume.shape` of a cone (WGSL `LOCAL_VOLUME_CONE`).
pub const LOCAL_VOLUME_CONE: u32 = 4;

/// Distance-like measure of a point in unit shape space: below 1 inside, 1 on the
/// surface (box, sphere, cylinder around y with |y| <= 1, cone with its apex at y = 1).
pub fn local_volume_measure(local: Vec3, shape: u32) -> f32 {
    let a = local.abs();
    let radial = Vec2::new(local.x, local.z).length();
    match shape {
        LOCAL_VOLUME_ELLIPSOID => local.length(),
        LOCAL_VOLUME_CYLINDER => a.y.max(radial),
        LOCAL_VOLUME_CONE => a.y.max(radial + 0.5 * (local.y + 1.0)),
        _ => a.max_element(),
    }
}

/// Soft membership of a point in unit shape space (see [`local_volume_measure`]).
pub fn local_volume_weight(local: Vec3, shape: u32, edge: f32) -> f32 {
    ((1.0 - local_volume_measure(local, shape)) / edge.max(1e-4)).clamp(0.0, 1.0)
}

/// `LocalVolume.blend` of an additive volume (WGSL `LOCAL_VOLUME_ADD`).
pub const LOCAL_VOLUME_ADD: u32 = 0;
/// `LocalVolume.blend` of a subtractive volume (WGSL `LOCAL_VOLUME_SUBTRACT`).
pub const LOCAL_VOLUME_SUBTRACT: u32 = 1;
/// `LocalVolume.blend` of a multiplying volume (WGSL `LOCAL_VOLUME_MULTIPLY`).
pub const LOCAL_VOLUME_MULTIPLY: u32 = 2;
/// `LocalVolume.blend` of a capping volume (WGSL `LOCAL_VOLUME_MIN`).
pub const LOCAL_VOLUME_MIN: u32 = 3;
/// `LocalVolume.blend` of a raising volume (WGSL `LOCAL_VOLUME_MAX`).
pub const LOCAL_VOLUME_MAX: u32 = 4;
/// `LocalVolume.blend` of an overwriting volume (WGSL `LOCAL_VOLUME_OVERWRITE`).
pub const LOCAL_VOLUME_OVERWRITE: u32 = 5;

/// The change `blend(m, v) - m` a local volume makes to the medium `m` (rgb emission,
/// a extinction) where it holds fully, for its value `v` (rgb emission, a density) and
/// blend code (see [`BlendMode`](crate::uniforms::BlendMode); an unknown code adds).
pub fn local_volume_blend_delta(m: Vec4, v: Vec4, blend: u32) -> Vec4 {
    match blend {
        LOCAL_VOLUME_SUBTRACT => -v.min(m),
        LOCAL_VOLUME_MULTIPLY => m * (v.w - 1.0),
        LOCAL_VOLUME_MIN => (v - m).min(Vec4::ZERO),
        LOCAL_VOLUME_MAX => (v - m).max(Vec4::ZERO),
        LOCAL_VOLUME_OVERWRITE => v - m,
        _ => v,
    }
}

/// The medium (rgb emission per metre, a extinction) after a local volume at a world
/// position: its blend mode faded in by its edge weight (WGSL `local_volume_blend`).
///
/// ```
/// use glam::{Mat4, Vec3, Vec4};
/// use volfog::cpu::density::local_volume_blend;
/// use volfog::uniforms::{BlendMode, LocalVolume, VolumeShape};
///
/// let room = LocalVolume::new(Mat4::from_scale(Vec3::splat(2.0)), VolumeShape::Box, 0.5, 0.1)
///     .unwrap()
///     .with_blend(BlendMode::Subtract)
///     .unwrap();
/// let fog = Vec4::new(0.0, 0.0, 0.0, 0.2);
/// // Inside, 0.2 - 0.5 is clamped at 0; outside the fog stays.
/// assert_eq!(local_volume_blend(fog, &room, Vec3::ZERO), Vec4::ZERO);
/// assert_eq!(local_volume_blend(fog, &room, Vec3::splat(3.0)), fog);
/// ```
pub fn local_volume_blend(medium: Vec4, volume: &LocalVolume, world: Vec3) -> Vec4 {
    local_volume_blend_textured(medium, volume, world, 1.0)
}

/// [`local_volume_blend`] with the density texture's factor, which scales a textured
/// volume's value (WGSL `local_volume_blend_textured`).
pub fn local_volume_blend_textured(
    medium: Vec4,
    volume: &LocalVolume,
    world: Vec3,
    texture_factor: f32,
) -> Vec4 {
    let local = volume.local_from_world.transform_point3(world);
    let w = local_volume_weight(local, volume.shape, volume.edge);
    let factor = if volume.textured != 0 {
        texture_factor.max(0.0)
    } else {
        1.0
    };
    let value = volume.emission.extend(volume.density) * factor;
    medium + w * local_volume_blend_delta(medium, value, volume.blend)
}

/// Extinction an additive local volume adds at a world position (its density times
/// its edge weight, whatever its blend mode).
pub fn local_volume_density(volume: &LocalVolume, world: Vec3) -> f32 {
    let local = volume.local_from_world.transform_point3(world);
    volume.density * local_volume_weight(local, volume.shape, volume.edge)
}

/// What an additive local volume adds at a world position: rgb the emission per metre,
/// a the extinction (its value times its edge weight, whatever its blend mode).
pub fn local_volume_sample(volume: &LocalVolume, world: Vec3) -> Vec4 {
    let local = volume.local_from_world.transform_point3(world);
    let w = local_volume_weight(local, volume.shape, volume.edge);
    volume.emission.extend(volume.density) * w
}

/// The density texture's coordinate in a local volume at a world position (see
/// `volfog::density::local_volume_texture_coord`).
pub fn local_volume_texture_coord(volume: &LocalVolume, world: Vec3) -> Vec3 {
    volume.local_from_world.transform_point3(world) * 0.5 + Vec3::splat(0.5) + volume.texture_offset
}

/// [`local_volume_sample`] scaled by the density texture's factor for a textured
/// volume (see `volfog::density::local_volume_sample_textured`).
pub fn local_volume_sample_textured(
    volume: &LocalVolume,
    world: Vec3,
    texture_factor: f32,
) -> Vec4 {
    let factor = if volume.textured != 0 {
        texture_factor.max(0.0)
    } else {
        1.0
    };
    local_volume_sample(volume, world) * factor
}

/// Whether a local volume can add extinction anywhere in the world-space sphere
/// (`center`, `radius`): conservative (see `volfog::density`).
pub fn local_volume_touches_sphere(volume: &LocalVolume, center: Vec3, radius: f32) -> bool {
    let m = volume.local_from_world;
    let local = m.transform_point3(center);
    let scale = (m.x_axis.truncate().length_squared()
        + m.y_axis.truncate().length_squared()
        + m.z_axis.truncate().length_squared())
    .sqrt();
    let outside = (local.abs() - Vec3::ONE).max(Vec3::ZERO);
    outside.length() <= radius * scale
}

/// The medium's shape factor at a world position (height profile times noise
/// modulation times texture factor), which scales its density and its emission.
pub fn medium_shape(medium: &FogMedium, world: Vec3, noise: f32, texture_factor: f32) -> f32 {
    let h = world.dot(medium.up);
    let profile = if h > medium.top_height {
        0.0
    } else {
        height_density(h, 1.0, medium.height_falloff, medium.base_height)
    };
    let modulation = (1.0 + medium.noise_strength * noise).max(0.0);
    profile * modulation * texture_factor.max(0.0)
}

/// Global extinction at a world position for a noise value and texture factor.
pub fn medium_extinction(medium: &FogMedium, world: Vec3, noise: f32, texture_factor: f32) -> f32 {
    medium.density * medium_shape(medium, world, noise, texture_factor)
}

/// The largest extinction (1/m) of a custom density's sample (WGSL
/// `FOG_SAMPLE_MAX_EXTINCTION`).
pub const FOG_SAMPLE_MAX_EXTINCTION: f32 = 1.0e3;
/// The largest emission per channel of a custom density's sample (WGSL
/// `FOG_SAMPLE_MAX_EMISSION`).
pub const FOG_SAMPLE_MAX_EMISSION: f32 = 1.0e6;

/// `x` if above 0 (at most `max`), else 0 (NaN included).
fn positive_at_most(x: f32, max: f32) -> f32 {
    if x > 0.0 { x.min(max) } else { 0.0 }
}

/// A custom density's sample brought into range (WGSL `fog_sample_clamped`):
/// extinction in [0, 1e3], albedo in [0, 1], emission in [0, 1e6] per channel; a value
/// not above 0 (NaN too) reads 0.
///
/// ```
/// use glam::Vec3;
/// use volfog::cpu::density::fog_sample_clamped;
/// use volfog::uniforms::FogSample;
///
/// let wild = FogSample { albedo: Vec3::new(2.0, -1.0, f32::NAN), extinction: f32::INFINITY, emission: Vec3::NAN };
/// let c = fog_sample_clamped(&wild);
/// assert_eq!((c.albedo, c.extinction, c.emission), (Vec3::new(1.0, 0.0, 0.0), 1.0e3, Vec3::ZERO));
/// ```
pub fn fog_sample_clamped(s: &FogSample) -> FogSample {
    let channels = |v: Vec3, max: f32| v.to_array().map(|c| positive_at_most(c, max)).into();
    FogSample {
        albedo: channels(s.albedo, 1.0),
        extinction: positive_at_most(s.extinction, FOG_SAMPLE_MAX_EXTINCTION),
        emission: channels(s.emission, FOG_SAMPLE_MAX_EMISSION),
    }
}

/// The medium (rgb emission per metre, a extinction) with a custom density's sample
/// (clamped) added (WGSL `medium_with_sample`).
pub fn medium_with_sample(prior: Vec4, s: &FogSample) -> Vec4 {
    let c = fog_sample_clamped(s);
    prior + c.emission.extend(c.extinction)
}

/// The albedo of the medium `prior` (albedo `albedo`) with a custom density's sample
/// (clamped) added: the extinction-weighted mean of the two, the medium's where both
/// are 0 (WGSL `albedo_with_sample`).
pub fn albedo_with_sample(prior: Vec4, albedo: Vec3, s: &FogSample) -> Vec3 {
    let c = fog_sample_clamped(s);
    let own = prior.w.max(0.0);
    let total = own + c.extinction;
    if total <= 0.0 {
        return albedo;
    }
    (albedo * own + c.albedo * c.extinction) / total
}

/// Transmittance of the medium's height profile (no noise, texture or local volume)
/// from `world` towards a light infinitely far along the unit direction `towards`,
/// entering at the medium's top (WGSL `medium_light_transmittance`).
pub fn medium_light_transmittance(medium: &FogMedium, world: Vec3, towards: Vec3) -> f32 {
    (-height_fog_light_optical_depth(
        medium.density,
        medium.height_falloff,
        medium.base_height,
        medium.up,
        medium.top_height,
        world,
        towards,
    ))
    .exp()
}

/// Transmittance of the medium's height profile along the segment from `world` to a
/// light at `light` (m) (WGSL `medium_segment_transmittance`).
pub fn medium_segment_transmittance(medium: &FogMedium, world: Vec3, light: Vec3) -> f32 {
    (-height_fog_optical_depth_below(
        medium.density,
        medium.height_falloff,
        medium.base_height,
        medium.up,
        medium.top_height,
        world,
        light - world,
    ))
    .exp()
}
