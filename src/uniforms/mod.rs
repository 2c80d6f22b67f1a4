//! Rust twins of the WGSL uniform and storage structs (encase `ShaderType` with glam
//! members), each with the checks that keep its values in the range the shaders
//! handle without NaN or overflow.
//!
//! Each struct has the same members, in the same order, as its WGSL twin in
//! `shaders/volfog/types.wgsl`; the tests compare every member offset and the size
//! with naga's layout of the composed shaders.
//!
//! With the `serde` feature (on by default) each struct serializes with its WGSL
//! member names: vectors as arrays, matrices as 16 numbers in column order, nested
//! structs as objects. Those names are the `structs` members of the export manifest,
//! so a host in another language can lay the bytes out from the manifest's offsets.
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

mod area;
mod bytes;
mod clouds;
mod custom;
mod epipolar;
mod fog_volume;
mod frame;
pub(crate) mod froxels;
pub(crate) mod frustum;
mod height_fog;
mod hull;
mod lighting;
mod local_shadow;
mod medium;
mod medium_shadow;
mod particles;
mod shadow;
mod sky;
mod water;

pub use area::{AREA_LIGHT_DISK, AREA_LIGHT_RECT, AreaLight};
pub use bytes::{to_storage_bytes, to_uniform_bytes};
pub use clouds::CloudLayer;
pub use custom::{FogCustomParams, FogSample};
pub use epipolar::{EPIPOLE_LIMIT, EpipolarFrame, EpipolarPhase, EpipolarSampling, EpipolarView};
pub use fog_volume::FogVolume;
pub use frame::{FogFrame, FogView, HistoryState};
pub use froxels::Froxels;
pub use frustum::FrustumRays;
pub use height_fog::HeightFog;
pub use hull::FogHull;
pub use lighting::{
    DirectionalLight, FOG_LIGHT_DIRECTIONAL, FOG_LIGHT_SPOT_SQUARED, FogLight, FogLighting,
    TransientLighting,
};
pub use local_shadow::{
    CUBE_FACE_AXES, LOCAL_SHADOW_NONE, LOCAL_SHADOW_POINT, LOCAL_SHADOW_SPOT, LightCamera,
    LightProjection, LocalShadowSource,
};
pub use medium::{BlendMode, FogMedium, LocalVolume, VolumeShape};
pub use medium_shadow::{MediumShadow, MediumShadowConfig};
pub use particles::FogParticle;
pub use shadow::{ShadowCascades, ShadowTaps};
pub use sky::SkyAtmosphere;
pub use water::Water;

use glam::Vec3;

use crate::limits::{InvalidValue, Range, check};

/// A unit vector within 1e-3.
pub(crate) fn check_unit(field: &'static str, v: Vec3) -> Result<(), InvalidValue> {
    check(
        v.is_finite() && (v.length() - 1.0).abs() < 1e-3,
        field,
        v,
        "a unit vector",
    )
}

/// A finite vector.
pub(crate) fn check_finite(
    field: &'static str,
    v: Vec3,
    what: &'static str,
) -> Result<(), InvalidValue> {
    check(v.is_finite(), field, v, what)
}

/// Every channel of `v` in `range`.
pub(crate) fn check_channels(
    field: &'static str,
    v: Vec3,
    range: &Range<f32>,
) -> Result<(), InvalidValue> {
    check(
        v.to_array().iter().all(|c| range.contains(*c)),
        field,
        v,
        format!("each channel in {}", range.describe()),
    )
}

/// A finite matrix with a determinant of magnitude above `min_determinant`.
pub(crate) fn check_invertible(
    field: &'static str,
    m: glam::Mat4,
    min_determinant: f32,
    what: &'static str,
) -> Result<(), InvalidValue> {
    check(
        m.is_finite() && m.determinant().abs() > min_determinant,
        field,
        m,
        what,
    )
}
