//! `Froxels`: where a camera-aligned froxel volume lies.

use encase::ShaderType;
use glam::{Mat4, UVec3};

use crate::limits::{self, InvalidValue, check};

/// Placement of a camera-aligned froxel volume (WGSL `volfog::types::Froxels`).
/// `Default` is a placeholder for layout probes, not a valid placement: build one
/// with [`Froxels::new`].
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Froxels {
    /// Projection (view -> clip).
    pub clip_from_view: Mat4,
    /// Its inverse (clip -> view).
    pub view_from_clip: Mat4,
    /// Volume size in froxels.
    pub size: UVec3,
    /// View depth of the first slice's front, metres.
    pub near: f32,
    /// View depth of the last slice's back, metres.
    pub far: f32,
    /// Slice distribution curve (0 = linear, ln(far / near) = exponential).
    pub curve: f32,
}

/// Checks a perspective projection: finite and invertible, with clip w proportional
/// to view z (last row `0, 0, ±1, 0` up to scale), which is what the froxel mapping
/// (slices by view depth, rays through the eye) assumes. Orthographic projections are
/// rejected.
pub(crate) fn check_perspective(
    field: &'static str,
    clip_from_view: Mat4,
) -> Result<(), InvalidValue> {
    let w = clip_from_view.row(3);
    let perspective = w.z.abs() > 0.0
        && w.x.abs() <= 1e-6 * w.z.abs()
        && w.y.abs() <= 1e-6 * w.z.abs()
        && w.w.abs() <= 1e-6 * w.z.abs();
    check(
        clip_from_view.is_finite() && clip_from_view.determinant().abs() > 0.0 && perspective,
        field,
        clip_from_view,
        "a finite, invertible perspective projection (last row 0, 0, ±1, 0 up to scale; \
         orthographic projections are not supported)",
    )
}

/// Checks the volume size, near and far depths and slice curve; `fields` names them
/// in the error (as members of `Froxels` or of `FogConfig`).
pub(crate) fn check_slices(
    fields: [&'static str; 4],
    size: UVec3,
    near: f32,
    far: f32,
    curve: f32,
) -> Result<(), InvalidValue> {
    check(
        size.to_array()
            .iter()
            .all(|a| limits::VOLUME_AXIS.contains(*a))
            && u64::from(size.x) * u64::from(size.y) * u64::from(size.z) <= limits::MAX_FROXELS,
        fields[0],
        size,
        format!(
            "{} and at most {} froxels in all",
            limits::VOLUME_AXIS.describe(),
            limits::MAX_FROXELS
        ),
    )?;
    check(
        near.is_finite() && near > 0.0,
        fields[1],
        near,
        "a finite depth > 0 m",
    )?;
    check(
        far.is_finite() && far > near,
        fields[2],
        far,
        "a finite depth > near",
    )?;
    limits::SLICE_CURVE.check(fields[3], curve)
}

impl Froxels {
    /// Checks the values and builds the uniform; `view_from_clip` is the inverse
    /// of `clip_from_view`, which must be a perspective projection.
    pub fn new(
        clip_from_view: Mat4,
        size: UVec3,
        near: f32,
        far: f32,
        curve: f32,
    ) -> Result<Self, InvalidValue> {
        check_perspective("Froxels.clip_from_view", clip_from_view)?;
        check_slices(
            [
                "Froxels.size",
                "Froxels.near",
                "Froxels.far",
                "Froxels.curve",
            ],
            size,
            near,
            far,
            curve,
        )?;
        Ok(Self {
            clip_from_view,
            view_from_clip: clip_from_view.inverse(),
            size,
            near,
            far,
            curve,
        })
    }

    /// The uniform buffer bytes (std140-compatible uniform layout).
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
