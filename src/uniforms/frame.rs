//! `FogFrame` (per-frame camera and temporal state), `HistoryState` (what a history
//! volume holds) and `FogView` (the camera of the fog group).

use encase::ShaderType;
use glam::{Mat4, Vec3};

/// Per-frame camera and temporal state (WGSL `volfog::types::FogFrame`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogFrame {
    /// View -> world transform of the current camera.
    pub world_from_view: Mat4,
    /// World -> clip of the current camera (recorded with the history it writes).
    pub clip_from_world: Mat4,
    /// Camera position in world space.
    pub camera_position: Vec3,
    /// Seconds since start.
    pub time: f32,
    /// Sample offset inside each froxel (froxel units, [-0.5, 0.5]^3).
    pub jitter: Vec3,
    /// History weight in [0, 1).
    pub history_weight: f32,
    /// Frames prepared before this one.
    pub index: u32,
    /// 0 to ignore the history this frame (after a camera cut), else 1.
    pub history_enabled: u32,
    /// 1 to amortise injection over two frames in a 3D checkerboard (the froxels with
    /// `x + y + z + index` even are injected, temporal fills the others), else 0.
    pub checkerboard: u32,
}

/// What a history volume holds (WGSL `volfog::types::HistoryState`): written on the
/// GPU by the temporal pass next to the volume it stabilises, so a frame that is never
/// submitted cannot make the next one reproject with the wrong camera. Zeroed
/// buffers read as "no history".
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HistoryState {
    /// World -> clip of the frame whose volume it is.
    pub clip_from_world: Mat4,
    /// 1 once a volume was written.
    pub valid: u32,
}

/// The camera of a frame in the fog group (WGSL `volfog::types::FogView`), for shaders
/// that start from world positions (`volfog::apply::fog_coord_from_world`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogView {
    /// World -> view transform.
    pub view_from_world: Mat4,
}
