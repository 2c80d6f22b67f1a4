//! The lights of the froxel medium: `DirectionalLight` (the sun), `FogLight` (point
//! and spot lights) and `FogLighting` (sun, ambient SH and light count).

use encase::ShaderType;
use glam::{Vec3, Vec4};

use super::{check_channels, check_finite, check_unit};
use crate::limits::{self, InvalidValue, check};

/// The main directional light (WGSL `volfog::types::DirectionalLight`).
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DirectionalLight {
    /// Unit direction from the scene towards the light.
    pub direction: Vec3,
    /// Contribution to the fog, >= 0.
    pub fog_intensity: f32,
    /// Illuminance colour (linear rgb).
    pub color: Vec3,
    /// Two-colour phase: tint looking towards the light.
    pub toward_tint: Vec3,
    /// Two-colour phase: tint looking away from the light.
    pub away_tint: Vec3,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        Self {
            direction: Vec3::new(0.3, 0.6, 0.2).normalize(),
            fog_intensity: 1.0,
            color: Vec3::new(3.0, 2.8, 2.5),
            toward_tint: Vec3::new(1.6, 1.3, 1.0),
            away_tint: Vec3::new(0.5, 0.6, 0.8),
        }
    }
}

impl DirectionalLight {
    /// Checks the values.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check_unit("DirectionalLight.direction", self.direction)?;
        check(
            self.fog_intensity.is_finite() && self.fog_intensity >= 0.0,
            "DirectionalLight.fog_intensity",
            self.fog_intensity,
            "a finite value >= 0",
        )?;
        for (field, v) in [
            ("DirectionalLight.color", self.color),
            ("DirectionalLight.toward_tint", self.toward_tint),
            ("DirectionalLight.away_tint", self.away_tint),
        ] {
            check_channels(field, v, &limits::LIGHT_COLOR)?;
        }
        Ok(())
    }
}

/// A point or spot light affecting the fog (WGSL `volfog::types::FogLight`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogLight {
    /// World position (m).
    pub position: Vec3,
    /// Range (m), > 0.
    pub range: f32,
    /// Intensity colour (illuminance at 1 m).
    pub color: Vec3,
    /// Contribution to the fog, >= 0.
    pub fog_intensity: f32,
    /// Spot axis (unit); ignored for point lights.
    pub direction: Vec3,
    /// Source radius (m), > 0.
    pub radius: f32,
    /// Cosine of the outer half-angle; <= -1 for a point light.
    pub cos_outer: f32,
    /// Cosine of the inner half-angle.
    pub cos_inner: f32,
    /// Index of the light's [`LightProjection`](super::LightProjection) (its shadow and
    /// cookie), or [`LOCAL_SHADOW_NONE`](super::LOCAL_SHADOW_NONE). Set by the runtime
    /// from [`FrameInputs::shadowed_lights`](crate::pipeline::FrameInputs::shadowed_lights);
    /// a shader only reads it under `VOLFOG_INJECT_LOCAL_SHADOWS`, and ignores an index
    /// past the projection buffer.
    pub projection: u32,
}

impl FogLight {
    /// A point light.
    pub fn point(position: Vec3, color: Vec3, range: f32) -> Self {
        Self {
            position,
            range,
            color,
            fog_intensity: 1.0,
            direction: Vec3::NEG_Y,
            radius: 0.05,
            cos_outer: -2.0,
            cos_inner: -2.0,
            projection: super::LOCAL_SHADOW_NONE,
        }
    }

    /// A spot light with full intensity inside `inner` and none outside `outer`
    /// (half-angles in radians).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        color: Vec3,
        range: f32,
        inner: f32,
        outer: f32,
    ) -> Self {
        Self {
            direction: direction.normalize_or(Vec3::NEG_Y),
            cos_outer: outer.cos(),
            cos_inner: inner.min(outer).cos(),
            ..Self::point(position, color, range)
        }
    }

    /// Checks the values.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check_finite("FogLight.position", self.position, "a finite position")?;
        check(
            self.range.is_finite() && self.range > 0.0,
            "FogLight.range",
            self.range,
            "a finite range > 0 m",
        )?;
        check(
            self.color.is_finite() && self.color.cmpge(Vec3::ZERO).all(),
            "FogLight.color",
            self.color,
            "finite channels >= 0",
        )?;
        check(
            self.fog_intensity.is_finite() && self.fog_intensity >= 0.0,
            "FogLight.fog_intensity",
            self.fog_intensity,
            "a finite value >= 0",
        )?;
        check(
            self.radius.is_finite() && self.radius > 0.0,
            "FogLight.radius",
            self.radius,
            "a finite radius > 0 m",
        )?;
        if self.cos_outer > -1.0 {
            check_unit("FogLight.direction", self.direction)?;
            check(
                self.cos_outer <= 1.0 && self.cos_inner >= self.cos_outer && self.cos_inner <= 1.0,
                "FogLight.cos_inner",
                (self.cos_outer, self.cos_inner),
                "cos_outer <= cos_inner <= 1",
            )?;
        }
        Ok(())
    }
}

/// Lighting of the medium (WGSL `volfog::types::FogLighting`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogLighting {
    /// The directional light.
    pub sun: DirectionalLight,
    /// L1 SH of the ambient radiance, red.
    pub ambient_r: Vec4,
    /// L1 SH of the ambient radiance, green.
    pub ambient_g: Vec4,
    /// L1 SH of the ambient radiance, blue.
    pub ambient_b: Vec4,
    /// Number of lights in the light buffer.
    pub light_count: u32,
    /// 1: light reaching a froxel is attenuated by the medium's height profile on its
    /// way (the sun from the medium's top, point and spot lights along the segment);
    /// 0: not. Set by the runtime from
    /// [`FogConfig::light_transmittance`](crate::pipeline::FogConfig::light_transmittance).
    pub transmittance: u32,
}
