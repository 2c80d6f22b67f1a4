//! Mirror of the temporal pass: this frame's scattering blended with the history
//! reprojected from the froxel's centre through the camera the history was written
//! with.

use glam::{UVec3, Vec2, Vec3, Vec4};

use super::apply::Volume;
use super::froxel::{slice_coord, uv_from_ndc};
use super::inject::froxel_world_position;
use crate::uniforms::{FogFrame, Froxels, HistoryState};

/// The temporal pass for froxel `id`: `now` blended with `history` (the volume
/// described by `previous`) when the froxel's centre reprojects inside it.
pub fn temporal_blend(
    froxels: &Froxels,
    frame: &FogFrame,
    previous: &HistoryState,
    id: UVec3,
    now: Vec4,
    history: &Volume,
) -> Vec4 {
    let (world, _) = froxel_world_position(froxels, frame, id, false);
    let clip = previous.clip_from_world * world.extend(1.0);
    if frame.history_enabled == 0 || previous.valid == 0 || clip.w <= 1e-6 {
        return now;
    }
    let uv = uv_from_ndc(Vec2::new(clip.x, clip.y) / clip.w);
    let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
    let uvw = Vec3::new(uv.x, uv.y, w);
    if uvw.cmplt(Vec3::ZERO).any() || uvw.cmpgt(Vec3::ONE).any() {
        return now;
    }
    let past = history.sample(uvw);
    now.lerp(past, frame.history_weight.clamp(0.0, 1.0))
}

/// The history state the temporal pass writes for `frame`.
pub fn written_state(frame: &FogFrame) -> HistoryState {
    HistoryState {
        clip_from_world: frame.clip_from_world,
        valid: 1,
    }
}
