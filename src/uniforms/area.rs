//! `AreaLight`: a rectangle or disk emitter lighting the fog (WGSL
//! `volfog::types::AreaLight`, integrated by `volfog::area_lights`).

use encase::ShaderType;
use glam::Vec3;

use super::{check_channels, check_finite, check_unit};
use crate::limits::{self, InvalidValue, check};

/// [`AreaLight::shape`]: a rectangle of `2 half_x` by `2 half_y` (WGSL
/// `volfog::area_lights::AREA_LIGHT_RECT`).
pub const AREA_LIGHT_RECT: u32 = 0;
/// [`AreaLight::shape`]: a disk, or an ellipse of semi-axes `half_x` and `half_y`
/// (WGSL `volfog::area_lights::AREA_LIGHT_DISK`).
pub const AREA_LIGHT_DISK: u32 = 1;

/// A one-sided Lambertian emitter lighting the fog: a rectangle or a disk in the plane
/// of `axis_x` and `axis_y`, emitting `radiance` towards `axis_x x axis_y` (WGSL
/// `volfog::types::AreaLight`, 80-byte storage stride). Its in-scattering is
/// integrated over its area (see [`crate::cpu::area`]).
///
/// ```
/// use volfog::glam::Vec3;
/// use volfog::uniforms::AreaLight;
///
/// // A 2 m x 1 m panel 3 m up, facing down, of radiance 5 W / (m^2 sr).
/// let panel = AreaLight::rect(Vec3::new(0.0, 3.0, 0.0), Vec3::X, Vec3::Z, 1.0, 0.5, Vec3::splat(5.0), 20.0);
/// assert!((panel.normal() - Vec3::NEG_Y).length() < 1e-6);
/// assert!(panel.validate().is_ok());
/// let flat = AreaLight { half_y: 0.0, ..panel };
/// assert_eq!(flat.validate().unwrap_err().field, "AreaLight.half_y");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AreaLight {
    /// Centre of the emitter (m).
    pub center: Vec3,
    /// [`AREA_LIGHT_RECT`] or [`AREA_LIGHT_DISK`].
    pub shape: u32,
    /// Unit axis in the emitter's plane: the rectangle's width, the disk's first
    /// semi-axis.
    pub axis_x: Vec3,
    /// Half the rectangle's width along `axis_x`, or the disk's radius along it (m), > 0.
    pub half_x: f32,
    /// Unit axis in the emitter's plane, orthogonal to `axis_x`.
    pub axis_y: Vec3,
    /// Half the rectangle's height along `axis_y`, or the disk's radius along it (m), > 0.
    pub half_y: f32,
    /// Emitted radiance, W / (m^2 sr) per channel, >= 0.
    pub radiance: Vec3,
    /// Contribution to the fog, >= 0.
    pub fog_intensity: f32,
    /// Range (m) from the centre, > 0: the light fades out smoothly towards it as a
    /// point light's does, and blocks of froxels beyond it skip the light (0 marks an
    /// unused slot of the buffer).
    pub range: f32,
}

impl AreaLight {
    /// A rectangle of `2 half_x` by `2 half_y` centred at `center`, emitting towards
    /// `axis_x x axis_y`.
    pub fn rect(
        center: Vec3,
        axis_x: Vec3,
        axis_y: Vec3,
        half_x: f32,
        half_y: f32,
        radiance: Vec3,
        range: f32,
    ) -> Self {
        Self {
            center,
            shape: AREA_LIGHT_RECT,
            axis_x,
            half_x,
            axis_y,
            half_y,
            radiance,
            fog_intensity: 1.0,
            range,
        }
    }

    /// A disk of `radius` centred at `center`, emitting towards its unit `normal`.
    pub fn disk(center: Vec3, normal: Vec3, radius: f32, radiance: Vec3, range: f32) -> Self {
        let (axis_x, axis_y) = normal.normalize().any_orthonormal_pair();
        Self {
            shape: AREA_LIGHT_DISK,
            ..Self::rect(center, axis_x, axis_y, radius, radius, radiance, range)
        }
    }

    /// The side the emitter lights: `axis_x x axis_y`.
    pub fn normal(&self) -> Vec3 {
        self.axis_x.cross(self.axis_y)
    }

    /// The emitter's area (m^2).
    pub fn area(&self) -> f32 {
        if self.shape == AREA_LIGHT_DISK {
            std::f32::consts::PI * self.half_x * self.half_y
        } else {
            4.0 * self.half_x * self.half_y
        }
    }

    /// Checks every field; the error names the first one out of its range (a NaN or
    /// non-unit axis, axes that are not orthogonal, a zero extent: a zero-area emitter).
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check_finite("AreaLight.center", self.center, "a finite position")?;
        check(
            self.shape == AREA_LIGHT_RECT || self.shape == AREA_LIGHT_DISK,
            "AreaLight.shape",
            self.shape,
            "AREA_LIGHT_RECT (0) or AREA_LIGHT_DISK (1)",
        )?;
        check_unit("AreaLight.axis_x", self.axis_x)?;
        check_unit("AreaLight.axis_y", self.axis_y)?;
        check(
            self.axis_x.dot(self.axis_y).abs() < 1e-3,
            "AreaLight.axis_y",
            self.axis_y,
            "a unit vector orthogonal to axis_x",
        )?;
        for (field, v) in [
            ("AreaLight.half_x", self.half_x),
            ("AreaLight.half_y", self.half_y),
        ] {
            check(
                v.is_finite() && v > 0.0,
                field,
                v,
                "a finite extent > 0 (the emitter has no area otherwise)",
            )?;
        }
        check_channels("AreaLight.radiance", self.radiance, &limits::LIGHT_COLOR)?;
        check(
            self.fog_intensity.is_finite() && self.fog_intensity >= 0.0,
            "AreaLight.fog_intensity",
            self.fog_intensity,
            "a finite value >= 0",
        )?;
        check(
            self.range.is_finite() && self.range > 0.0,
            "AreaLight.range",
            self.range,
            "a finite range > 0 (m)",
        )
    }
}
