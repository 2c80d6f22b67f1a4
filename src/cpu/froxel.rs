//! Mirror of `volfog::froxel`: depth slices and screen mapping.
//!
//! ```
//! use volfog::cpu::froxel::{slice_coord, slice_depth};
//! let (near, far, curve) = (0.5, 128.0, (128.0f32 / 0.5).ln());
//! // With curve = ln(far / near) the slices have a constant depth ratio.
//! assert!((slice_depth(0.5, near, far, curve) - 8.0).abs() < 1e-3);
//! assert!((slice_coord(8.0, near, far, curve) - 0.5).abs() < 1e-5);
//! ```

use glam::{Mat4, UVec2, UVec3, Vec2, Vec3, Vec4};

/// Below this curve the distribution uses its series in `curve`.
pub const CURVE_LINEAR_LIMIT: f32 = 1e-3;

/// View depth (m) at normalised slice coordinate `t`.
pub fn slice_depth(t: f32, near: f32, far: f32, curve: f32) -> f32 {
    let span = far - near;
    if curve < CURVE_LINEAR_LIMIT {
        return near + span * (t + 0.5 * curve * t * (t - 1.0));
    }
    near + ((curve * t).exp() - 1.0) * (span / (curve.exp() - 1.0))
}

/// The slice boundaries of a volume of `slices` slices as a walk (`slice_walk`, the
/// scan pass): `(a, b)` such that with `d_0 = 0` and `d_(k+1) = a d_k + b` the back
/// of slice `k` lies at view depth `near + d_(k+1)`.
///
/// ```
/// use volfog::cpu::froxel::{slice_depth, slice_walk};
/// let (near, far, slices) = (0.5f32, 128.0f32, 256u32);
/// for curve in [(far / near).ln(), 3.0, 1e-4, 0.0] {
///     let (a, b) = slice_walk(slices, near, far, curve);
///     let mut d = 0.0f32;
///     for k in 1..=slices {
///         d = d * a + b;
///         let want = slice_depth(k as f32 / slices as f32, near, far, curve);
///         assert!((near + d - want).abs() <= 3e-5 * want, "curve {curve} slice {k}");
///     }
/// }
/// ```
pub fn slice_walk(slices: u32, near: f32, far: f32, curve: f32) -> (f32, f32) {
    let step = 1.0 / slices as f32;
    let a = (curve * step).exp();
    let span = far - near;
    if curve < CURVE_LINEAR_LIMIT {
        return (a, span * step * (1.0 + 0.5 * curve * (step - 1.0)));
    }
    (a, span * ((a - 1.0) / (curve.exp() - 1.0)))
}

/// Normalised slice coordinate of view depth `z` (clamped to `z >= near`).
pub fn slice_coord(z: f32, near: f32, far: f32, curve: f32) -> f32 {
    let s = (z - near).max(0.0) / (far - near);
    if curve < CURVE_LINEAR_LIMIT {
        return s - 0.5 * curve * s * (s - 1.0);
    }
    (1.0 + s * (curve.exp() - 1.0)).ln() / curve
}

/// Normalised device x, y (y up) of screen uv (v down).
pub fn ndc_from_uv(uv: Vec2) -> Vec2 {
    Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0)
}

/// Screen uv (v down) of normalised device x, y (y up).
pub fn uv_from_ndc(ndc: Vec2) -> Vec2 {
    Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
}

/// View-space position of a point in normalised device coordinates.
pub fn view_from_ndc(ndc: Vec3, view_from_clip: Mat4) -> Vec3 {
    let p = view_from_clip * Vec4::new(ndc.x, ndc.y, ndc.z, 1.0);
    let w = if p.w.abs() < 1e-30 { 1e-30 } else { p.w };
    (p.truncate() / w).clamp(Vec3::splat(-3.0e38), Vec3::splat(3.0e38))
}

/// Path length per metre of view depth of the ray through screen uv.
pub fn ray_scale(uv: Vec2, view_from_clip: Mat4) -> f32 {
    let n = ndc_from_uv(uv);
    let p = view_from_ndc(Vec3::new(n.x, n.y, 0.5), view_from_clip);
    p.length() / p.z.abs().max(1e-30)
}

/// Radical inverse of `index` in `base` (Halton sequence), in [0, 1).
pub fn halton(index: u32, base: u32) -> f32 {
    let mut f = 1.0f32;
    let mut r = 0.0f32;
    let mut i = index;
    let inv = 1.0 / base as f32;
    while i > 0 {
        f *= inv;
        r += f * (i % base) as f32;
        i /= base;
    }
    r
}

/// Sample offset inside a froxel for a frame: Halton (2, 3, 5) of `frame % 16 + 1`,
/// minus 0.5 (froxel units).
pub fn froxel_jitter(frame: u32) -> Vec3 {
    let i = frame % 16 + 1;
    Vec3::new(halton(i, 2), halton(i, 3), halton(i, 5)) - 0.5
}

/// The jitter of frame `index` for a fog that amortises its injection over two frames
/// when `checkerboard` is 1 ([`froxel_injected`]): each froxel is injected every other
/// frame, so the sequence advances every two frames and each froxel still visits all
/// 16 points. With the frame's own index, the froxels of one parity would see only
/// every other point of the sequence, and the base-2 Halton digit of those puts all of
/// one parity's samples in one half of the froxel in x.
pub fn froxel_jitter_amortised(index: u32, checkerboard: u32) -> Vec3 {
    froxel_jitter(if checkerboard != 0 { index / 2 } else { index })
}

/// View-space position of a point inside froxel `id` at `offset` from its centre.
pub fn froxel_view_position(
    id: glam::UVec3,
    offset: Vec3,
    size: glam::UVec3,
    view_from_clip: Mat4,
    near: f32,
    far: f32,
    curve: f32,
) -> Vec3 {
    let cell = (id.as_vec3() + 0.5 + offset) / size.as_vec3();
    let depth = slice_depth(cell.z, near, far, curve);
    let n = ndc_from_uv(Vec2::new(cell.x, cell.y));
    let ray = view_from_ndc(Vec3::new(n.x, n.y, 0.5), view_from_clip);
    ray * (depth / ray.z.abs().max(1e-30))
}

/// Leading slices (2..=`slices`) of a froxel column that can be read when its farthest
/// opaque surface lies at view depth `max_depth` (m).
pub fn froxel_live_slices(max_depth: f32, slices: u32, near: f32, far: f32, curve: f32) -> u32 {
    let s = slice_coord(max_depth, near, far, curve) * slices as f32;
    let first = s.floor().clamp(0.0, slices as f32) as u32;
    (first + 2).min(slices)
}

/// The texels (inclusive `[min_x, min_y, max_x, max_y]`) of a depth texture of size
/// `texels` that overlap cell `cell` of a grid of `cells` cells (half a column each).
pub fn froxel_cull_cell(cell: UVec2, cells: UVec2, texels: UVec2) -> [u32; 4] {
    let scale = texels.as_vec2() / cells.as_vec2();
    let top = texels.as_vec2() - 1.0;
    let lo = (cell.as_vec2() * scale).floor().clamp(Vec2::ZERO, top);
    let hi = ((cell + 1).as_vec2() * scale)
        .floor()
        .clamp(Vec2::ZERO, top);
    [lo.x as u32, lo.y as u32, hi.x as u32, hi.y as u32]
}

/// Whether froxel `id` is injected in frame `index` (3D checkerboard amortisation
/// when `checkerboard` is 1).
pub fn froxel_injected(id: UVec3, index: u32, checkerboard: u32) -> bool {
    checkerboard == 0 || (id.x + id.y + id.z + index) & 1 == 0
}

/// The froxel_cull pass: live slices per column (x fastest) of a grid from a depth
/// buffer of `width` x `height` depth-buffer values (x fastest): the farthest view
/// depth per cell of half a column, then per column over its 4 x 4 cells.
pub fn live_slices_from_depth(
    froxels: &crate::uniforms::Froxels,
    depth: &[f32],
    width: u32,
    height: u32,
) -> Vec<u32> {
    let grid = froxels.size.truncate();
    let cells = 2 * grid;
    let texels = UVec2::new(width, height);
    let view_depth = |d: f32| {
        view_from_ndc(Vec3::new(0.0, 0.0, d), froxels.view_from_clip)
            .z
            .abs()
    };
    let mut farthest = Vec::with_capacity((cells.x * cells.y) as usize);
    for cy in 0..cells.y {
        for cx in 0..cells.x {
            let [x0, y0, x1, y1] = froxel_cull_cell(UVec2::new(cx, cy), cells, texels);
            let (mut lo, mut hi) = (1.0f32, 0.0f32);
            for ty in y0..=y1 {
                for tx in x0..=x1 {
                    // As the pass's max-then-min: a NaN texel reads as 0.
                    let v = depth[(ty * width + tx) as usize];
                    let d = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
                    lo = lo.min(d);
                    hi = hi.max(d);
                }
            }
            farthest.push(view_depth(lo).max(view_depth(hi)));
        }
    }
    let mut out = Vec::with_capacity((grid.x * grid.y) as usize);
    for y in 0..grid.y {
        for x in 0..grid.x {
            let first = (2 * UVec2::new(x, y)).max(UVec2::ONE) - 1;
            let last = (2 * UVec2::new(x, y) + 2).min(cells - 1);
            let mut deepest = 0.0f32;
            for cy in first.y..=last.y {
                for cx in first.x..=last.x {
                    deepest = deepest.max(farthest[(cy * cells.x + cx) as usize]);
                }
            }
            out.push(froxel_live_slices(
                deepest,
                froxels.size.z,
                froxels.near,
                froxels.far,
                froxels.curve,
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under checkerboard amortisation a froxel of either parity visits all 16 jitter
    /// points in 32 frames, and its samples average as the sequence does; with the
    /// frame's own index a parity would see 8 of them, all in one half in x.
    #[test]
    fn amortised_jitter_covers_the_froxel_for_each_parity() {
        for parity in [UVec3::ZERO, UVec3::X] {
            let seen = |jitter: fn(u32) -> Vec3| {
                let mut points: Vec<Vec3> = (0..32)
                    .filter(|&f| froxel_injected(parity, f, 1))
                    .map(jitter)
                    .collect();
                let mean = points.iter().sum::<Vec3>() / points.len() as f32;
                points.sort_by(|a, b| a.x.total_cmp(&b.x));
                points.dedup();
                (points.len(), mean)
            };
            // The 16 points' own mean (Halton points are not balanced at 16 in base 3
            // and 5): each parity's samples average to it.
            let all = (0..16).map(froxel_jitter).sum::<Vec3>() / 16.0;
            let (count, mean) = seen(|f| froxel_jitter_amortised(f, 1));
            assert_eq!(count, 16, "parity {parity}");
            assert!(
                (mean - all).abs().max_element() < 1e-6,
                "parity {parity}: mean {mean} against {all}"
            );
            let (count, mean) = seen(froxel_jitter);
            assert_eq!(count, 8, "parity {parity}");
            assert!(mean.x.abs() > 0.2, "parity {parity}: mean {mean}");
            assert_eq!(froxel_jitter_amortised(7, 0), froxel_jitter(7));
        }
    }
}
