//! `FogParticle`: a sphere of smoke, dust or glowing gas added to the fog (WGSL
//! `volfog::types::FogParticle`, evaluated by `volfog::particles`).

use encase::ShaderType;
use glam::Vec3;

use super::{check_channels, check_finite};
use crate::limits::{self, InvalidValue, Range, check};

/// A particle in the fog: a sphere of `radius` around `position` whose extinction and
/// emission fall off from the centre by the profile
/// `(1 - falloff) + falloff (1 - r^2 / R^2)^2` (0 beyond the radius), added to the
/// medium after the local volumes (WGSL `volfog::types::FogParticle`, 48-byte storage
/// stride; see [`crate::cpu::particles`] for the profile and its closed-form optical
/// depth).
///
/// ```
/// use volfog::glam::Vec3;
/// use volfog::uniforms::FogParticle;
///
/// // A puff of grey smoke 1.5 m across, 2 m up.
/// let puff = FogParticle::smoke(Vec3::new(0.0, 2.0, 0.0), 0.75, 0.8, Vec3::splat(0.5));
/// assert!(puff.validate().is_ok());
/// let flat = FogParticle { radius: 0.0, ..puff };
/// assert_eq!(flat.validate().unwrap_err().field, "FogParticle.radius");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogParticle {
    /// Centre (m, world space), finite.
    pub position: Vec3,
    /// Radius R (m), see [`limits::PARTICLE_RADIUS`]: nothing beyond it.
    pub radius: f32,
    /// Single-scattering albedo per channel, [0, 1].
    pub albedo: Vec3,
    /// Extinction at the centre (1/m), see [`limits::PARTICLE_EXTINCTION`].
    pub extinction: f32,
    /// Radiance emitted per metre of path at the centre (linear rgb, W / (sr m^3)),
    /// see [`limits::EMISSION`]; it follows the extinction's profile.
    pub emission: Vec3,
    /// Falloff in [0, 1]: 0 a uniform sphere, 1 a smooth one whose density and slope
    /// vanish at the radius.
    pub falloff: f32,
}

impl FogParticle {
    /// A smooth (falloff 1) particle that scatters without emitting.
    pub fn smoke(position: Vec3, radius: f32, extinction: f32, albedo: Vec3) -> Self {
        Self {
            position,
            radius,
            albedo,
            extinction,
            emission: Vec3::ZERO,
            falloff: 1.0,
        }
    }

    /// Checks every field; the error names the first one out of its range (a NaN or
    /// infinite position, a radius <= 0, a negative extinction ...).
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check_finite(
            "FogParticle.position",
            self.position,
            "a finite position (m)",
        )?;
        limits::PARTICLE_RADIUS.check("FogParticle.radius", self.radius)?;
        check_channels("FogParticle.albedo", self.albedo, &Range::new(0.0, 1.0, ""))?;
        limits::PARTICLE_EXTINCTION.check("FogParticle.extinction", self.extinction)?;
        check_channels("FogParticle.emission", self.emission, &limits::EMISSION)?;
        check(
            (0.0..=1.0).contains(&self.falloff),
            "FogParticle.falloff",
            self.falloff,
            "a falloff in [0, 1]",
        )
    }
}
