//! Mirror of the temporal pass: this frame's scattering blended with the history
//! reprojected from the froxel's centre through the camera the history was written
//! with; with depth culling and checkerboard amortisation as the pass does them.

use glam::{UVec3, Vec2, Vec3, Vec4};

use super::apply::Volume;
use super::froxel::{froxel_injected, slice_coord, uv_from_ndc};
use super::inject::froxel_world_position;
use crate::uniforms::{FogFrame, Froxels, HistoryState};

/// The history at `uvw` with culling (`live`: the live slices it was written with, per
/// column): the filtered sample when every texel the look-up can touch was live, else
/// the trilinear weights of the texels that were not live dropped and the rest
/// renormalised; `None` when those carry less than half the weight.
pub fn history_at(froxels: &Froxels, history: &Volume, uvw: Vec3, live: &[u32]) -> Option<Vec4> {
    let size = froxels.size;
    let texel = uvw * size.as_vec3() - 0.5;
    let base = texel.floor();
    let f = texel - base;
    let top = (size - 1).as_vec3();
    let lo = base.clamp(Vec3::ZERO, top).as_uvec3();
    let hi = (lo + 1).min(size - 1);
    let at = |x: u32, y: u32| live[(y * size.x + x) as usize];
    let reach = at(lo.x, lo.y)
        .min(at(hi.x, lo.y))
        .min(at(lo.x, hi.y))
        .min(at(hi.x, hi.y));
    if hi.z < reach {
        return Some(history.sample(uvw));
    }
    let (mut sum, mut weight) = (Vec4::ZERO, 0.0);
    for k in 0..8u32 {
        let corner = UVec3::new(k & 1, (k >> 1) & 1, k >> 2);
        let pick = |c: u32, f: f32| if c == 1 { f } else { 1.0 - f };
        let w = pick(corner.x, f.x) * pick(corner.y, f.y) * pick(corner.z, f.z);
        let p = (base + corner.as_vec3()).clamp(Vec3::ZERO, top).as_uvec3();
        if w > 0.0 && p.z < at(p.x, p.y) {
            sum += w * history.load(p.x as i32, p.y as i32, p.z as i32);
            weight += w;
        }
    }
    (weight >= 0.5).then(|| sum / weight)
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
    let (world, _) = froxel_world_position(froxels, frame, id, false);
    let clip = previous.clip_from_world * world.extend(1.0);
    if frame.history_enabled == 0 || previous.valid == 0 || clip.w <= 1e-6 {
        return None;
    }
    let uv = uv_from_ndc(Vec2::new(clip.x, clip.y) / clip.w);
    let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
    let uvw = Vec3::new(uv.x, uv.y, w);
    if uvw.cmplt(Vec3::ZERO).any() || uvw.cmpgt(Vec3::ONE).any() {
        return None;
    }
    match history_live_slices {
        Some(live) => history_at(froxels, history, uvw, live),
        None => Some(history.sample(uvw)),
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
        Some(past) => now.lerp(past, frame.history_weight.clamp(0.0, 1.0)),
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
    /// This frame's scattering volume (read at injected froxels only).
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
    let live = |x: u32, y: u32| {
        t.live_slices
            .map_or(size.z, |(live, _)| live[(y * size.x + x) as usize])
    };
    if id.z >= live(id.x, id.y) {
        return None;
    }
    let past = reproject(
        t.froxels,
        t.frame,
        t.previous,
        id,
        t.history,
        t.live_slices.map(|(_, history)| history),
    );
    let load = |p: UVec3| t.current.load(p.x as i32, p.y as i32, p.z as i32);
    if froxel_injected(id, t.frame.index, t.frame.checkerboard) {
        let now = load(id);
        return Some(match past {
            Some(past) => now.lerp(past, t.frame.history_weight.clamp(0.0, 1.0)),
            None => now,
        });
    }
    if past.is_some() {
        return past;
    }
    // The mean of the live face neighbours (injected this frame).
    let (mut sum, mut count) = (Vec4::ZERO, 0.0);
    for k in 0..6u32 {
        let step = if k & 1 == 1 { 1 } else { -1 };
        let offset = match k / 2 {
            0 => glam::IVec3::new(step, 0, 0),
            1 => glam::IVec3::new(0, step, 0),
            _ => glam::IVec3::new(0, 0, step),
        };
        let n = id.as_ivec3() + offset;
        if n.cmpge(glam::IVec3::ZERO).all() && n.cmplt(size.as_ivec3()).all() {
            let m = n.as_uvec3();
            if m.z < live(m.x, m.y) {
                sum += load(m);
                count += 1.0;
            }
        }
    }
    Some(sum / f32::max(count, 1.0))
}

/// The history state the temporal pass writes for `frame`.
pub fn written_state(frame: &FogFrame) -> HistoryState {
    HistoryState {
        clip_from_world: frame.clip_from_world,
        valid: 1,
    }
}
