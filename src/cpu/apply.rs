//! Mirror of `volfog::apply`: fog coordinates, filtered look-ups of the integrated
//! volume, and applying fog to a colour.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::froxel::{ndc_from_uv, slice_coord, uv_from_ndc, view_from_ndc};
use crate::uniforms::{Froxels, HeightFog};

/// Fog coordinate (xyz texture coordinate, w weight) of screen uv and view depth.
pub fn fog_coord(uv: Vec2, depth: f32, froxels: &Froxels) -> Vec4 {
    let n = froxels.size.z as f32;
    let slices = slice_coord(depth, froxels.near, froxels.far, froxels.curve) * n;
    let w = ((slices - 0.5) / n).clamp(0.5 / n, 1.0 - 0.5 / n);
    Vec4::new(uv.x, uv.y, w, slices.clamp(0.0, 1.0))
}

/// Fog coordinate of a view-space position.
pub fn fog_coord_from_view(view_pos: Vec3, froxels: &Froxels) -> Vec4 {
    let clip = froxels.clip_from_view * view_pos.extend(1.0);
    let w = if clip.w.abs() < 1e-30 { 1e-30 } else { clip.w };
    let ndc = Vec2::new(clip.x, clip.y) / w;
    fog_coord(uv_from_ndc(ndc), view_pos.z.abs(), froxels)
}

/// View-space position of a world-space position with the camera's world -> view
/// transform.
pub fn fog_view_position(world_pos: Vec3, view_from_world: Mat4) -> Vec3 {
    (view_from_world * world_pos.extend(1.0)).truncate()
}

/// Fog coordinate of a world-space position.
pub fn fog_coord_from_world(world_pos: Vec3, view_from_world: Mat4, froxels: &Froxels) -> Vec4 {
    fog_coord_from_view(fog_view_position(world_pos, view_from_world), froxels)
}

/// Fog coordinate of a point in normalised device coordinates.
pub fn fog_coord_from_ndc(ndc: Vec3, froxels: &Froxels) -> Vec4 {
    let view = view_from_ndc(ndc, froxels.view_from_clip);
    fog_coord(uv_from_ndc(Vec2::new(ndc.x, ndc.y)), view.z.abs(), froxels)
}

/// An integrated volume in CPU memory: `size.x * size.y * size.z` texels, x fastest.
#[derive(Debug, Clone)]
pub struct Volume {
    /// Size in texels.
    pub size: [u32; 3],
    /// Texels (rgb in-scatter, a transmittance).
    pub texels: Vec<Vec4>,
}

impl Volume {
    /// The texel at integer coordinates, clamped to the edge.
    pub fn load(&self, x: i32, y: i32, z: i32) -> Vec4 {
        let c = |v: i32, n: u32| v.clamp(0, n as i32 - 1) as usize;
        let [sx, sy, sz] = self.size;
        let (x, y, z) = (c(x, sx), c(y, sy), c(z, sz));
        self.texels[(z * sy as usize + y) * sx as usize + x]
    }

    /// Trilinear filtering with clamp-to-edge at texture coordinate `uvw`.
    pub fn sample(&self, uvw: Vec3) -> Vec4 {
        let size = Vec3::new(
            self.size[0] as f32,
            self.size[1] as f32,
            self.size[2] as f32,
        );
        let texel = uvw * size - 0.5;
        let base = texel.floor();
        let f = texel - base;
        let (x, y, z) = (base.x as i32, base.y as i32, base.z as i32);
        let lerp = |a: Vec4, b: Vec4, t: f32| a + (b - a) * t;
        let y0 = lerp(
            lerp(self.load(x, y, z), self.load(x + 1, y, z), f.x),
            lerp(self.load(x, y + 1, z), self.load(x + 1, y + 1, z), f.x),
            f.y,
        );
        let y1 = lerp(
            lerp(self.load(x, y, z + 1), self.load(x + 1, y, z + 1), f.x),
            lerp(
                self.load(x, y + 1, z + 1),
                self.load(x + 1, y + 1, z + 1),
                f.x,
            ),
            f.y,
        );
        lerp(y0, y1, f.z)
    }

    /// Fog at a fog coordinate (same result as `fog_sample` / `fog_load`).
    pub fn fog(&self, coord: Vec4) -> Vec4 {
        let none = Vec4::new(0.0, 0.0, 0.0, 1.0);
        none + (self.sample(coord.truncate()) - none) * coord.w
    }
}

/// Analytic fog between the far plane and a view-space position beyond it (the
/// height fog in view space); no fog within the volume.
pub fn fog_tail(froxels: &Froxels, tail: &HeightFog, view_pos: Vec3) -> Vec4 {
    let depth = view_pos.z.abs();
    if depth <= froxels.far {
        return Vec4::new(0.0, 0.0, 0.0, 1.0);
    }
    let start = view_pos * (froxels.far / depth);
    super::height_fog::height_fog(tail, start, view_pos - start)
}

/// `fog_tail` with the sun's light shadowed by the epipolar lit fraction `shafts` (the
/// far field; mirror of `volfog::apply::fog_tail_shafts`): the tail's sun colour scaled
/// by `shafts` in [0, 1] per channel.
pub fn fog_tail_shafts(froxels: &Froxels, tail: &HeightFog, view_pos: Vec3, shafts: Vec3) -> Vec4 {
    let shadowed = HeightFog {
        sun_color: tail.sun_color * shafts.clamp(Vec3::ZERO, Vec3::ONE),
        ..*tail
    };
    fog_tail(froxels, &shadowed, view_pos)
}

/// The volume's fog followed by the tail behind it.
pub fn fog_with_tail(fog: Vec4, tail: Vec4) -> Vec4 {
    (fog.truncate() + fog.w * tail.truncate()).extend(fog.w * tail.w)
}

/// A lit colour seen through fog: `color * T + L`.
pub fn apply_fog(color: Vec3, fog: Vec4) -> Vec3 {
    color * fog.w + fog.truncate()
}

/// View-space position (m) of the point at screen `uv` and view depth `depth` (m).
pub fn fog_view_from_depth(uv: Vec2, depth: f32, view_from_clip: Mat4) -> Vec3 {
    let p = view_from_ndc(ndc_from_uv(uv).extend(0.5), view_from_clip);
    p * (depth / p.z.abs().max(1e-30))
}

/// Below this fog amount at the resolved depth, [`fog_resolved`] keeps its colour.
pub const FOG_RESOLVED_MIN_AMOUNT: f32 = 1e-4;

/// The MSAA layout of one sample: `(view depth, 1 - T)` (Wenzel 2007, "Scene depth
/// based rendering and MSAA: Fog").
pub fn fog_layout(fog: Vec4, view_depth: f32) -> Vec2 {
    Vec2::new(view_depth, 1.0 - fog.w)
}

/// Fog of a pixel from its resolved layout: the colour of `fog` (the fog at the
/// resolved depth), the resolved `amount`.
///
/// ```
/// use glam::Vec4;
/// use volfog::cpu::apply::fog_resolved;
///
/// let fog = Vec4::new(0.3, 0.3, 0.3, 0.4); // fog colour 0.5, amount 0.6
/// assert!((fog_resolved(fog, 0.6) - fog).abs().max_element() < 1e-6);
/// assert!((fog_resolved(fog, 0.2) - Vec4::new(0.1, 0.1, 0.1, 0.8)).abs().max_element() < 1e-6);
/// ```
pub fn fog_resolved(fog: Vec4, amount: f32) -> Vec4 {
    let a = amount.clamp(0.0, 1.0);
    let scale = a / (1.0 - fog.w).max(FOG_RESOLVED_MIN_AMOUNT);
    (fog.truncate() * scale).extend(1.0 - a)
}
