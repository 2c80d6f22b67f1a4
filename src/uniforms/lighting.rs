//! The lights of the froxel medium: `DirectionalLight` (the sun), `FogLight` (point,
//! spot and further directional lights) and `FogLighting` (sun, ambient SH and light
//! count).

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

/// [`FogLight::flags`]: a directional light at infinity (WGSL
/// `volfog::lights::FOG_LIGHT_DIRECTIONAL`). Its `direction` is the way its light
/// travels, its `color` its illuminance; it lights every point without falloff, and
/// its position, range, radius and cone are ignored.
pub const FOG_LIGHT_DIRECTIONAL: u32 = 1;

/// [`FogLight::flags`]: the spot cone falls off as `saturate(t)^2`,
/// `t = (cos_angle - cos_outer) / max(cos_inner - cos_outer, 1e-4)` (Filament's
/// punctual light, which Bevy's surfaces use) instead of the smoothstep (WGSL
/// `volfog::lights::FOG_LIGHT_SPOT_SQUARED`).
pub const FOG_LIGHT_SPOT_SQUARED: u32 = 2;

/// A point, spot or directional light affecting the fog (WGSL
/// `volfog::types::FogLight`).
///
/// ```
/// use volfog::glam::Vec3;
/// use volfog::uniforms::{FOG_LIGHT_DIRECTIONAL, FogLight};
///
/// // A second, unshadowed sun: light from the west, travelling east and down.
/// let moon = FogLight::directional(Vec3::new(-1.0, 1.0, 0.0).normalize(), Vec3::splat(0.2));
/// assert_eq!(moon.flags, FOG_LIGHT_DIRECTIONAL);
/// assert!((moon.direction - Vec3::new(1.0, -1.0, 0.0).normalize()).length() < 1e-6);
/// assert!(moon.validate().is_ok());
/// ```
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
    /// [`FOG_LIGHT_DIRECTIONAL`] and [`FOG_LIGHT_SPOT_SQUARED`] bits; 0 for a point or
    /// spot light with the smoothstep cone.
    pub flags: u32,
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
            flags: 0,
        }
    }

    /// A directional light at infinity: `toward` is the unit direction from the scene
    /// towards the light (as [`DirectionalLight::direction`]), `color` its illuminance.
    /// Unlike the sun it has no shadow.
    pub fn directional(toward: Vec3, color: Vec3) -> Self {
        Self {
            direction: -toward.normalize_or(Vec3::Y),
            flags: FOG_LIGHT_DIRECTIONAL,
            ..Self::point(Vec3::ZERO, color, 1.0)
        }
    }

    /// Whether this is a directional light ([`FOG_LIGHT_DIRECTIONAL`]).
    pub fn is_directional(&self) -> bool {
        self.flags & FOG_LIGHT_DIRECTIONAL != 0
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
        check(
            self.flags & !(FOG_LIGHT_DIRECTIONAL | FOG_LIGHT_SPOT_SQUARED) == 0,
            "FogLight.flags",
            self.flags,
            "FOG_LIGHT_DIRECTIONAL | FOG_LIGHT_SPOT_SQUARED bits only",
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
        if self.is_directional() {
            return check_unit("FogLight.direction", self.direction);
        }
        check_finite("FogLight.position", self.position, "a finite position")?;
        check(
            self.range.is_finite() && self.range > 0.0,
            "FogLight.range",
            self.range,
            "a finite range > 0 m",
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

/// The short-lived lights of a frame as the scan's `VOLFOG_SCAN_TRANSIENT_LIGHTS` variant
/// reads them (WGSL `volfog::types::TransientLighting`): the camera and its view rays
/// (as [`ShadowTaps`](super::ShadowTaps) holds them), the number of lights in the
/// transient light buffer and the transmittance switch.
/// [`VolumetricFog`](crate::pipeline::VolumetricFog) builds it each frame from
/// [`FrameInputs::transient_lights`](crate::pipeline::FrameInputs::transient_lights).
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TransientLighting {
    /// Camera position in world space (m).
    pub camera_position: Vec3,
    /// Number of lights in the transient light buffer.
    pub count: u32,
    /// The world-space view ray per metre of view depth at `ndc` (0, 0); a froxel's
    /// centre at `ndc` lies at the camera plus `(ray_origin + ray_x ndc.x + ray_y
    /// ndc.y)` times its view depth ([`crate::cpu::shadow::shadow_tap_rays`]).
    pub ray_origin: Vec3,
    /// 1: each transient light is attenuated by the medium's height profile on its way
    /// to the froxel (as [`FogLighting::transmittance`]); 0: not.
    pub transmittance: u32,
    /// The ray's change per unit of `ndc.x`.
    pub ray_x: Vec3,
    /// The ray's change per unit of `ndc.y`.
    pub ray_y: Vec3,
}

impl Default for TransientLighting {
    /// No lights, a camera at the origin looking down -Z with a 90 degree square
    /// frustum, no transmittance.
    fn default() -> Self {
        Self {
            camera_position: Vec3::ZERO,
            count: 0,
            ray_origin: Vec3::NEG_Z,
            transmittance: 0,
            ray_x: Vec3::X,
            ray_y: Vec3::Y,
        }
    }
}
