//! `Water`: underwater fog below a water plane (`volfog::water`).

use encase::ShaderType;
use glam::Vec3;

use super::{check_channels, check_unit};
use crate::limits::{self, InvalidValue};

/// Water below a plane (WGSL `volfog::types::Water`, used by `volfog::water`): uniform
/// extinction along the view ray; light falling in straight down with radiance
/// `light` just below the surface and fading as `exp(-attenuation * depth)`.
/// `attenuation` 0 is the uniform river model, above 0 the ocean model. `Default` is a
/// placeholder for layout probes; build one with [`Water::river`] or [`Water::ocean`].
///
/// ```
/// use glam::Vec3;
/// use volfog::uniforms::Water;
///
/// let sea = Water::ocean(0.0, Vec3::ONE, 0.2, Vec3::new(0.3, 0.08, 0.03)).unwrap();
/// assert_eq!(sea.normal, Vec3::Y);
/// assert!(Water::ocean(0.0, Vec3::ONE, -0.2, Vec3::ZERO).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Water {
    /// Unit normal of the surface, pointing out of the water.
    pub normal: Vec3,
    /// The surface is the plane `dot(p, normal) = height` (m), |height| <= 1e9.
    pub height: f32,
    /// Radiance just below the surface of the light falling in (linear rgb), [0, 1e9].
    pub light: Vec3,
    /// Extinction along the view ray (1/m), [0, 1e3].
    pub extinction: f32,
    /// Single-scattering albedo per channel, [0, 1].
    pub albedo: Vec3,
    /// HG mean cosine of the scattering of the light falling in, [-0.999, 0.999].
    pub g: f32,
    /// Attenuation of the light with depth per channel (1/m), [0, 1e3].
    pub attenuation: Vec3,
    /// View depth (m) over which the surface fades in at the shore, [0, 1e9].
    pub shore_fade: f32,
}

impl Water {
    /// The uniform river model: a horizontal (+Y up) surface at `height`, light
    /// `light` at every depth, isotropic scattering with albedo 1, a 1 m shore fade.
    pub fn river(height: f32, light: Vec3, extinction: f32) -> Result<Self, InvalidValue> {
        Self {
            normal: Vec3::Y,
            height,
            light,
            extinction,
            albedo: Vec3::ONE,
            g: 0.0,
            attenuation: Vec3::ZERO,
            shore_fade: 1.0,
        }
        .validated()
    }

    /// The ocean model: as [`Water::river`] with the light attenuated with depth by
    /// `attenuation` (1/m per channel).
    pub fn ocean(
        height: f32,
        light: Vec3,
        extinction: f32,
        attenuation: Vec3,
    ) -> Result<Self, InvalidValue> {
        Self {
            attenuation,
            ..Self::river(height, light, extinction)?
        }
        .validated()
    }

    /// Checks every member against its range (the normal must have unit length within
    /// 1e-3 and is normalised).
    pub fn validated(self) -> Result<Self, InvalidValue> {
        check_unit("Water.normal", self.normal)?;
        limits::FOG_POSITION.check("Water.height", self.height)?;
        check_channels("Water.light", self.light, &limits::FOG_RADIANCE)?;
        limits::FOG_DENSITY.check("Water.extinction", self.extinction)?;
        check_channels("Water.albedo", self.albedo, &limits::WATER_ALBEDO)?;
        limits::FOG_SUN_G.check("Water.g", self.g)?;
        check_channels("Water.attenuation", self.attenuation, &limits::FOG_DENSITY)?;
        limits::WATER_SHORE_FADE.check("Water.shore_fade", self.shore_fade)?;
        Ok(Self {
            normal: self.normal.normalize(),
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
