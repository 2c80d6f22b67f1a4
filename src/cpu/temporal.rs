//! Mirror of the temporal pass: this frame's scattering blended with the history
//! reprojected from the froxel's centre through the camera the history was written
//! with; with depth culling and checkerboard amortisation as the pass does them.

use glam::{UVec3, Vec2, Vec3, Vec4};

use super::apply::Volume;
use super::froxel::{froxel_injected, slice_coord, uv_from_ndc};
use super::inject::froxel_world_position;
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
