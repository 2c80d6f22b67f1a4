//! Mirror of the temporal pass: this frame's scattering blended with the history
//! reprojected from the froxel's centre through the camera the history was written
//! with; with depth culling and checkerboard amortisation as the pass does them.

use glam::{Mat4, UVec2, UVec3, Vec2, Vec3, Vec4};

use super::apply::Volume;
use super::froxel::{
    froxel_injected, ndc_from_uv, slice_coord, slice_depth, uv_from_ndc, view_from_ndc,
};
use crate::uniforms::{FogFrame, Froxels, HistoryState};

/// Below this trilinear weight (per axis) a history texel is not required to be live
/// (`TEMPORAL_HISTORY_REACH` of `volfog::temporal`).
pub const HISTORY_REACH: f32 = 0.015625;

/// Whether every texel the trilinear look-up of a volume at `uvw` weighs by
/// [`HISTORY_REACH`] or more lies within the live slices `live` (per column, x
/// fastest) it was written with.
pub fn history_live(froxels: &Froxels, uvw: Vec3, live: &[u32]) -> bool {
    let size = froxels.size;
    let texel = uvw * size.as_vec3() - 0.5;
    let base = texel.floor();
    let f = texel - base;
    let top = (size - 1).as_vec3();
    let lo = base.clamp(Vec3::ZERO, top).as_uvec3();
    let hi = (base + 1.0).clamp(Vec3::ZERO, top).as_uvec3();
    let pick = |lo: u32, hi: u32, wants_hi: bool| if wants_hi { hi } else { lo };
    let x0 = pick(hi.x, lo.x, 1.0 - f.x >= HISTORY_REACH);
    let x1 = pick(lo.x, hi.x, f.x >= HISTORY_REACH);
    let y0 = pick(hi.y, lo.y, 1.0 - f.y >= HISTORY_REACH);
    let y1 = pick(lo.y, hi.y, f.y >= HISTORY_REACH);
    let deepest = pick(lo.z, hi.z, f.z >= HISTORY_REACH);
    let at = |x: u32, y: u32| live[(y * size.x + x) as usize];
    let reach = at(x0, y0).min(at(x1, y0)).min(at(x0, y1)).min(at(x1, y1));
    deepest < reach
}

/// The history camera's clip coordinates along the centre ray of froxel column `xy`
/// (WGSL `temporal_history_column`): the point of the ray at view depth `z` (m) lands
/// at `column[0] * z + column[1]`.
pub fn history_column(
    froxels: &Froxels,
    world_from_view: Mat4,
    previous: &HistoryState,
    xy: UVec2,
) -> [Vec4; 2] {
    let cell = (xy.as_vec2() + 0.5) / froxels.size.truncate().as_vec2();
    let n = ndc_from_uv(cell);
    let ray = view_from_ndc(Vec3::new(n.x, n.y, 0.5), froxels.view_from_clip);
    let step = ray / ray.z.abs().max(1e-30);
    [
        previous.clip_from_world * (world_from_view * step.extend(0.0)),
        previous.clip_from_world * world_from_view.w_axis,
    ]
}

/// The history volume's texture coordinates of the centre of the froxel in slice
/// `slice` of `column` ([`history_column`]; WGSL `temporal_history_slice_uvw`): `None`
/// where the history is not usable (disabled, never written, behind the history's
/// camera, outside its volume).
pub fn history_slice_uvw(
    froxels: &Froxels,
    column: [Vec4; 2],
    slice: u32,
    valid: u32,
    history_enabled: u32,
) -> Option<Vec3> {
    let t = (slice as f32 + 0.5) / froxels.size.z as f32;
    let depth = slice_depth(t, froxels.near, froxels.far, froxels.curve);
    let clip = column[0] * depth + column[1];
    if history_enabled == 0 || valid == 0 || clip.w <= 1e-6 {
        return None;
    }
    let uv = uv_from_ndc(Vec2::new(clip.x, clip.y) / clip.w);
    let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
    let uvw = Vec3::new(uv.x, uv.y, w);
    if uvw.cmplt(Vec3::ZERO).any() || uvw.cmpgt(Vec3::ONE).any() {
        return None;
    }
    Some(uvw)
}

/// The history of froxel `id` reprojected through the camera of `previous`: `None`
/// when there is no usable history (disabled, invalid, behind the camera, outside the
/// volume, or touching texels outside `history_live` when given).
pub fn reproject(
    froxels: &Froxels,
    frame: &FogFrame,
    previous: &HistoryState,
    id: UVec3,
    history: &Volume,
    history_live_slices: Option<&[u32]>,
) -> Option<Vec4> {
    let column = history_column(froxels, frame.world_from_view, previous, id.truncate());
    let uvw = history_slice_uvw(froxels, column, id.z, previous.valid, frame.history_enabled)?;
    if history_live_slices.is_some_and(|live| !history_live(froxels, uvw, live)) {
        return None;
    }
    Some(history.sample(uvw))
}

/// This frame's value of a froxel with its reprojected history (WGSL
/// `temporal_blend`): an injected froxel blends them with `history_weight` (clamped to
/// [0, 1]); one the checkerboard skipped takes the history alone.
pub fn blend_history(now: Vec4, past: Vec4, injected: bool, history_weight: f32) -> Vec4 {
    if injected {
        now.lerp(past, history_weight.clamp(0.0, 1.0))
    } else {
        past
    }
}

/// The temporal pass for an injected froxel `id` without culling: `now` blended with
/// `history` (the volume described by `previous`) when the froxel's centre reprojects
/// inside it.
pub fn temporal_blend(
    froxels: &Froxels,
    frame: &FogFrame,
    previous: &HistoryState,
    id: UVec3,
    now: Vec4,
    history: &Volume,
) -> Vec4 {
    match reproject(froxels, frame, previous, id, history, None) {
        Some(past) => blend_history(now, past, true, frame.history_weight),
        None => now,
    }
}

/// Everything the temporal pass reads.
#[derive(Debug, Clone, Copy)]
pub struct TemporalInputs<'a> {
    /// Froxel placement.
    pub froxels: &'a Froxels,
    /// This frame.
    pub frame: &'a FogFrame,
    /// The state of the history volume.
    pub previous: &'a HistoryState,
    /// This frame's scattering volume as inject wrote it (with the checkerboard, both
    /// froxels of a pair hold the injected one's value).
    pub current: &'a Volume,
    /// The history volume.
    pub history: &'a Volume,
    /// Live slices of this frame and of the history (depth culling), per column.
    pub live_slices: Option<(&'a [u32], &'a [u32])>,
}

/// The temporal pass for froxel `id`: `None` when the pass skips it (behind its
/// column's live slices), else the value it writes.
pub fn temporal_froxel(t: &TemporalInputs<'_>, id: UVec3) -> Option<Vec4> {
    let size = t.froxels.size;
    let live = t
        .live_slices
        .map_or(size.z, |(live, _)| live[(id.y * size.x + id.x) as usize]);
    if id.z >= live {
        return None;
    }
    let now = t.current.load(id.x as i32, id.y as i32, id.z as i32);
    let past = reproject(
        t.froxels,
        t.frame,
        t.previous,
        id,
        t.history,
        t.live_slices.map(|(_, history)| history),
    );
    Some(match past {
        None => now,
        Some(past) => blend_history(
            now,
            past,
            froxel_injected(id, t.frame.index, t.frame.checkerboard),
            t.frame.history_weight,
        ),
    })
}

/// The history state the temporal pass writes for `frame`.
pub fn written_state(frame: &FogFrame) -> HistoryState {
    HistoryState {
        clip_from_world: frame.clip_from_world,
        valid: 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, DVec3, DVec4, Quat};

    /// A froxel centre reprojected through its column lands where the froxel's world
    /// position projects through the history's camera, computed apart in f64 (the
    /// depth from the slice distribution, the point from the pixel's ray in view
    /// space, then world and clip): every froxel of a 16 x 9 x 64 volume, for an
    /// exponential, a mild and a linear slice curve, a moved and turned camera and an
    /// off-centre (jittered) projection. Within 5e-6 of the clip vector's length, and
    /// the texture coordinates within 2e-6 (measured: 1.1e-6 and 3.5e-7 at worst).
    #[test]
    fn a_column_reprojects_every_slice_as_the_froxel_positions_do() {
        let size = UVec3::new(16, 9, 64);
        let (near, far) = (0.5f32, 96.0f32);
        let mut projection =
            glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 500.0);
        projection.z_axis.x = 0.003;
        projection.z_axis.y = -0.002;
        let world_from_view = Mat4::from_rotation_translation(
            Quat::from_euler(glam::EulerRot::YXZ, 0.4, -0.1, 0.02),
            Vec3::new(3.0, 2.0, -1.0),
        );
        let history_world_from_view = Mat4::from_rotation_translation(
            Quat::from_euler(glam::EulerRot::YXZ, 0.37, -0.09, 0.0),
            Vec3::new(2.8, 2.1, -0.7),
        );
        let previous = HistoryState {
            clip_from_world: projection * history_world_from_view.inverse(),
            valid: 1,
        };
        let clip_from_world = previous.clip_from_world.as_dmat4();
        let view_from_clip = projection.inverse().as_dmat4();
        let world_from_view_d: DMat4 = world_from_view.as_dmat4();
        for curve in [(far / near).ln(), 1.5, 0.0] {
            let froxels = Froxels::new(projection, size, near, far, curve).unwrap();
            let (mut worst_clip, mut worst_uvw, mut usable) = (0.0f64, 0.0f64, 0);
            for y in 0..size.y {
                for x in 0..size.x {
                    let column =
                        history_column(&froxels, world_from_view, &previous, UVec2::new(x, y));
                    for z in 0..size.z {
                        // The reference, in f64.
                        let t = (z as f64 + 0.5) / size.z as f64;
                        let (n, f, c) = (near as f64, far as f64, curve as f64);
                        let depth = if c == 0.0 {
                            n + (f - n) * t
                        } else {
                            n + (f - n) * ((c * t).exp() - 1.0) / (c.exp() - 1.0)
                        };
                        let u = (x as f64 + 0.5) / size.x as f64;
                        let v = (y as f64 + 0.5) / size.y as f64;
                        let p = view_from_clip * DVec4::new(2.0 * u - 1.0, 1.0 - 2.0 * v, 0.5, 1.0);
                        let ray: DVec3 = p.truncate() / p.w;
                        let view = ray * (depth / ray.z.abs());
                        let want = clip_from_world * (world_from_view_d * view.extend(1.0));
                        let got = column[0] * slice_depth(t as f32, near, far, curve) + column[1];
                        let error = (got.as_dvec4() - want).length() / want.length();
                        worst_clip = worst_clip.max(error);
                        if let Some(uvw) = history_slice_uvw(&froxels, column, z, 1, 1) {
                            // The slice coordinate of the history's view depth.
                            let s = (want.w - n).max(0.0) / (f - n);
                            let want_w = if c == 0.0 {
                                s
                            } else {
                                (1.0 + s * (c.exp() - 1.0)).ln() / c
                            };
                            let want_uvw = DVec3::new(
                                want.x / want.w * 0.5 + 0.5,
                                0.5 - want.y / want.w * 0.5,
                                want_w,
                            );
                            let e = (uvw.as_dvec3() - want_uvw).abs().max_element();
                            worst_uvw = worst_uvw.max(e);
                            usable += 1;
                        }
                    }
                }
            }
            assert!(
                worst_clip < 5e-6,
                "curve {curve}: clip off by {worst_clip:e}"
            );
            assert!(worst_uvw < 2e-6, "curve {curve}: uv off by {worst_uvw:e}");
            assert!(usable > 16 * 9 * 64 / 2, "curve {curve}: {usable} usable");
        }
    }

    /// Without a usable history (a camera cut, a history never written, a point
    /// behind the history's camera) a column gives no texture coordinates.
    #[test]
    fn an_unusable_history_gives_no_coordinates() {
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
        let froxels = Froxels::new(projection, UVec3::new(4, 4, 8), 0.5, 32.0, 2.0).unwrap();
        let previous = HistoryState {
            clip_from_world: projection,
            valid: 1,
        };
        let column = history_column(&froxels, Mat4::IDENTITY, &previous, UVec2::new(1, 2));
        assert!(history_slice_uvw(&froxels, column, 3, 1, 1).is_some());
        assert!(history_slice_uvw(&froxels, column, 3, 0, 1).is_none());
        assert!(history_slice_uvw(&froxels, column, 3, 1, 0).is_none());
        // The history's camera turned round: every point is behind it.
        let behind = HistoryState {
            clip_from_world: projection * Mat4::from_rotation_y(std::f32::consts::PI),
            valid: 1,
        };
        let column = history_column(&froxels, Mat4::IDENTITY, &behind, UVec2::new(1, 2));
        assert!((0..8).all(|z| history_slice_uvw(&froxels, column, z, 1, 1).is_none()));
    }
}
