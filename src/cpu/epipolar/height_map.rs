//! A slice's 1D height map in light space: the shadow and colour layers it reads, view
//! rays and their projection onto the map.

use glam::{Mat4, Vec2, Vec3, Vec3Swizzles, Vec4, Vec4Swizzles};

use super::LIT_DEPTH;
use super::lines::exit_point;
use crate::cpu::froxel::view_from_ndc;
use crate::uniforms::EpipolarFrame;

/// One layer of the shadow map (light depth in [0, 1] per texel, row-major,
/// `depths[y * size + x]`): the layer `frame.cascade` the WGSL reads from its
/// `texture_2d_array<f32>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowLayer<'a> {
    /// Side of the layer in texels (`EpipolarFrame::shadow_size`).
    pub size: u32,
    /// `size * size` depths, row-major (v down, as the texture).
    pub depths: &'a [f32],
}

impl ShadowLayer<'_> {
    /// The depth of texel (x, y), as WGSL `textureLoad` (both below `size`).
    pub fn load(&self, x: u32, y: u32) -> f32 {
        self.depths[(y * self.size + x) as usize]
    }
}

/// The light-space colour texture of coloured shafts (`VOLFOG_EPIPOLAR_COLORED`): the
/// light's colour after stained glass per texel of the cascade, row-major
/// (`colors[y * size + x]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorLayer<'a> {
    /// Side in texels (`EpipolarFrame::shadow_size`).
    pub size: u32,
    /// `size * size` colours (linear rgb), row-major, v down.
    pub colors: &'a [Vec3],
}

/// Colour of the light at height-map entry `k` of a slice (white off the map, or
/// without colours); mirror of `volfog::epipolar::epipolar_color`.
pub fn color(colors: Option<&ColorLayer>, map: Vec4, k: u32) -> Vec3 {
    let Some(c) = colors else {
        return Vec3::ONE;
    };
    let q = (map.xy() + (k as f32 + 0.5) * map.zw()).floor();
    if q.cmplt(Vec2::ZERO).any() || q.cmpge(Vec2::splat(c.size as f32)).any() {
        return Vec3::ONE;
    }
    c.colors[(q.y as u32 * c.size + q.x as u32) as usize]
}

/// A view ray's segment set up for the march: view-space start and extent (m), its
/// projection onto the slice's 1D height map (texels) and its light depths at both
/// ends; mirror of `volfog::epipolar::EpipolarRay`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EpipolarRay {
    /// View-space start of the segment (m).
    pub origin: Vec3,
    /// View-space extent of the segment (m).
    pub segment: Vec3,
    /// Height-map position (texels) of the start.
    pub start: f32,
    /// Height-map position (texels) of the end.
    pub end: f32,
    /// Light depth of the start.
    pub light_start: f32,
    /// Light depth of the end.
    pub light_end: f32,
}

/// View-space point at view depth 1 (m) on the ray through normalised device `ndc`;
/// mirror of `volfog::epipolar::epipolar_view_ray`.
pub fn view_ray(view_from_clip: Mat4, ndc: Vec2) -> Vec3 {
    let p = view_from_ndc(ndc.extend(0.5), view_from_clip);
    p / p.z.abs().max(1e-30)
}

/// Light-space texel position (xy, in `shadow_size` texels, v down) and light depth (z)
/// of a view-space point (m); mirror of `volfog::epipolar::epipolar_light_texel`.
pub fn light_texel(frame: &EpipolarFrame, view: Vec3) -> Vec3 {
    let clip = frame.light_from_view * view.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let uv = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    (uv * frame.shadow_size as f32).extend(ndc.z)
}

/// The 1D height map of `slice`: `(origin.xy, dir.xy)` in texels, origin the camera's
/// texel and dir the projection of the slice's rays, one texel long in its larger axis;
/// mirror of `volfog::epipolar::epipolar_slice_map`.
pub fn slice_map(frame: &EpipolarFrame, slice: u32) -> Vec4 {
    let s = (slice as f32 + 0.5) / frame.slices as f32;
    let ray = view_ray(frame.view_from_clip, exit_point(s));
    let o = light_texel(frame, Vec3::ZERO);
    let d = light_texel(frame, ray).xy() - o.xy();
    let m = d.x.abs().max(d.y.abs());
    let dir = if m > 1e-12 { d / m } else { Vec2::X };
    Vec4::new(o.x, o.y, dir.x, dir.y)
}

/// h(k): the shadow depth under entry `k` of a slice's height map `map`
/// ([`LIT_DEPTH`] off the map, side `shadow.size`); mirror of
/// `volfog::epipolar::epipolar_height`.
pub fn height(shadow: &ShadowLayer, map: Vec4, k: u32, bias: f32) -> f32 {
    let size = shadow.size;
    let q = (map.xy() + (k as f32 + 0.5) * map.zw()).floor();
    if q.cmplt(Vec2::ZERO).any() || q.cmpge(Vec2::splat(size as f32)).any() {
        return LIT_DEPTH;
    }
    shadow.load(q.x as u32, q.y as u32) + bias
}

/// The segment of the view ray through `ndc` from view depth `depth0` to `depth1` (m) on
/// a slice's height map `map`; mirror of `volfog::epipolar::epipolar_ray`.
pub fn ray(frame: &EpipolarFrame, map: Vec4, ndc: Vec2, depth0: f32, depth1: f32) -> EpipolarRay {
    let dir = view_ray(frame.view_from_clip, ndc);
    let p0 = dir * depth0;
    let p1 = dir * depth1.max(depth0);
    let l0 = light_texel(frame, p0);
    let l1 = light_texel(frame, p1);
    let dd = map.zw().dot(map.zw());
    EpipolarRay {
        origin: p0,
        segment: p1 - p0,
        start: (l0.xy() - map.xy()).dot(map.zw()) / dd,
        end: (l1.xy() - map.xy()).dot(map.zw()) / dd,
        light_start: l0.z,
        light_end: l1.z,
    }
}
