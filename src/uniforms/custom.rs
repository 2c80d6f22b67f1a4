//! `FogSample` (what a custom density function gives at a point) and
//! `FogCustomParams` (the parameters the application hands it each frame).

use encase::ShaderType;
use glam::{Vec3, Vec4};

use crate::limits::{InvalidValue, check};

/// What a custom density function gives at a point (WGSL `volfog::types::FogSample`):
/// a medium of its own, added to the global medium before the local volumes blend. The
/// inject pass clamps it into the ranges below first
/// (`volfog::cpu::density::fog_sample_clamped`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogSample {
    /// Single-scattering albedo per channel, [0, 1].
    pub albedo: Vec3,
    /// Extinction (1/m), [0, 1e3].
    pub extinction: f32,
    /// Radiance emitted per metre of path (linear rgb, W / (sr m^3)), [0, 1e6].
    pub emission: Vec3,
}

/// The parameters of a custom density function (WGSL `volfog::types::FogCustomParams`,
/// inject's binding 31 under `VOLFOG_INJECT_CUSTOM_DENSITY`): eight `vec4` the
/// application sets each frame (`FrameInputs::custom_params`) and the function reads
/// as it pleases (a centre, a radius, a colour, a phase, ...).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogCustomParams {
    /// The values, finite.
    pub values: [Vec4; 8],
}

impl FogCustomParams {
    /// Parameters from up to eight `vec4` (the rest 0).
    pub fn new(values: &[Vec4]) -> Result<Self, InvalidValue> {
        check(
            values.len() <= 8,
            "FogCustomParams.values",
            values.len(),
            "at most 8 vec4",
        )?;
        let mut params = Self::default();
        params.values[..values.len()].copy_from_slice(values);
        params.validate()?;
        Ok(params)
    }

    /// Checks that every value is finite.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check(
            self.values.iter().all(|v| v.is_finite()),
            "FogCustomParams.values",
            self.values,
            "finite values",
        )
    }
}
