//! Rust twins of the WGSL uniform structs (encase `ShaderType` with glam members).
//!
//! Each struct here has the same members, in the same order, as its WGSL twin in
//! `shaders/volfog/types.wgsl`; `tests/layout.rs` compares every member offset and
//! the size with naga's layout of the composed shaders.
//!
//! ```
//! use glam::{Mat4, UVec3};
//! use volfog::uniforms::Froxels;
//!
//! let proj = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 1000.0);
//! let froxels = Froxels::new(proj, UVec3::new(160, 90, 128), 0.5, 128.0, 4.0).unwrap();
//! let bytes = froxels.to_bytes();
//! assert_eq!(bytes.len(), 160);
//! assert!(Froxels::new(proj, UVec3::new(160, 90, 128), 2.0, 1.0, 4.0).is_err());
//! ```

use encase::ShaderType;
use glam::{Mat4, UVec3};

/// An invalid uniform value: the field, the value and the valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} = {value} is invalid: expected {expected}")]
pub struct InvalidValue {
    /// The field, e.g. `Froxels.near`.
    pub field: &'static str,
    /// The rejected value, printed.
    pub value: String,
    /// The valid range, in words.
    pub expected: &'static str,
}

pub(crate) fn check(
    ok: bool,
    field: &'static str,
    value: impl std::fmt::Debug,
    expected: &'static str,
) -> Result<(), InvalidValue> {
    if ok {
        Ok(())
    } else {
        Err(InvalidValue {
            field,
            value: format!("{value:?}"),
            expected,
        })
    }
}

/// Largest volume size per axis that volfog accepts (wgpu's default 3D texture limit).
pub const MAX_FROXELS_PER_AXIS: u32 = 2048;
/// Largest slice curve: exp(curve) must stay far from f32 overflow.
pub const MAX_SLICE_CURVE: f32 = 30.0;

/// Placement of a camera-aligned froxel volume (WGSL `volfog::types::Froxels`).
/// `Default` is a placeholder for layout probes, not a valid placement: build one
/// with [`Froxels::new`].
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
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

impl Froxels {
    /// Checks the values and builds the uniform; `view_from_clip` is the inverse
    /// of `clip_from_view`.
    pub fn new(
        clip_from_view: Mat4,
        size: UVec3,
        near: f32,
        far: f32,
        curve: f32,
    ) -> Result<Self, InvalidValue> {
        check(
            clip_from_view.is_finite() && clip_from_view.determinant().abs() > 0.0,
            "Froxels.clip_from_view",
            clip_from_view,
            "a finite, invertible perspective projection",
        )?;
        check(
            size.cmpge(UVec3::ONE).all() && size.cmple(UVec3::splat(MAX_FROXELS_PER_AXIS)).all(),
            "Froxels.size",
            size,
            "1..=2048 froxels per axis",
        )?;
        check(
            near.is_finite() && near > 0.0,
            "Froxels.near",
            near,
            "a finite depth > 0 m",
        )?;
        check(
            far.is_finite() && far > near,
            "Froxels.far",
            far,
            "a finite depth > near",
        )?;
        check(
            (0.0..=MAX_SLICE_CURVE).contains(&curve),
            "Froxels.curve",
            curve,
            "0..=30 (0 linear, ln(far / near) exponential)",
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
        to_uniform_bytes(self)
    }
}

/// Serialises any uniform struct with encase's uniform-buffer layout.
pub fn to_uniform_bytes<T: ShaderType + encase::internal::WriteInto>(value: &T) -> Vec<u8> {
    let mut buffer = encase::UniformBuffer::new(Vec::new());
    buffer
        .write(value)
        .expect("writing into a growable Vec cannot fail");
    buffer.into_inner()
}
