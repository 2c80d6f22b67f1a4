//! Mirror of `volfog::fog_lit`: particles and translucent surfaces lit by the fog's
//! light at their position, read back from the lit volume
//! ([`VolumetricFog::lit_texture`](crate::pipeline::VolumetricFog::lit_texture): rgb
//! `sigma_s L_in`, a `sigma_t` per froxel).
//!
//! ```
//! use volfog::cpu::fog_lit::fog_lit_light;
//! use volfog::glam::{Vec3, Vec4};
//!
//! // 0.02 /m of fog of albedo 0.9 lit by 5 W / (m^2 sr) after its phase.
//! let source = Vec4::new(0.09, 0.09, 0.09, 0.02);
//! let light = fog_lit_light(source, Vec3::splat(0.9), Vec3::ZERO);
//! assert!((light - Vec3::splat(5.0)).abs().max_element() < 1e-5);
//! // Clear air carries no light: the fallback.
//! assert_eq!(fog_lit_light(Vec4::ZERO, Vec3::splat(0.9), Vec3::ONE), Vec3::ONE);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::froxel::{slice_coord, uv_from_ndc};
use crate::uniforms::Froxels;

/// Extinction (1/m) below which the lit volume carries no light.
pub const FOG_LIT_MIN_EXTINCTION: f32 = 1e-4;

/// Texture coordinate in the lit volume of the point at screen `uv` (v down) and view
/// depth `depth` (m).
pub fn fog_lit_coord(uv: Vec2, depth: f32, froxels: &Froxels) -> Vec3 {
    let n = froxels.size.z as f32;
    let t = slice_coord(depth, froxels.near, froxels.far, froxels.curve);
    uv.extend(t.clamp(0.5 / n, 1.0 - 0.5 / n))
}

/// Texture coordinate in the lit volume of a view-space position (m).
pub fn fog_lit_coord_from_view(view_pos: Vec3, froxels: &Froxels) -> Vec3 {
    let clip = froxels.clip_from_view * view_pos.extend(1.0);
    let w = if clip.w.abs() < 1e-30 { 1e-30 } else { clip.w };
    fog_lit_coord(
        uv_from_ndc(Vec2::new(clip.x, clip.y) / w),
        view_pos.z.abs(),
        froxels,
    )
}

/// The fog's light at a point from the lit volume's sample there and the medium's
/// albedo: `L_in` per channel, or `fallback` where the sample holds no extinction or
/// the albedo's channel is 0.
pub fn fog_lit_light(source: Vec4, albedo: Vec3, fallback: Vec3) -> Vec3 {
    if source.w < FOG_LIT_MIN_EXTINCTION {
        return fallback;
    }
    let scattering = albedo * source.w;
    let light = source.truncate().max(Vec3::ZERO) / scattering.max(Vec3::splat(1e-30));
    Vec3::select(albedo.cmpgt(Vec3::ZERO), light, fallback)
}
