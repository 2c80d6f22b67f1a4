//! `SkyAtmosphere`: the single-scattering atmosphere of `volfog::sky`.

use encase::ShaderType;
use glam::Vec3;

use super::{check_channels, check_unit};
use crate::limits::{self, InvalidValue, check};

/// A single-scattering atmosphere (WGSL `volfog::types::SkyAtmosphere`, used by
/// `volfog::sky` and the `sky_solve`, `sky_horizon` and `sky_draw` passes): Rayleigh and
/// Mie scattering with exponential height profiles over a spherical planet, the
/// camera on the ground, +Y up (Nishita et al. 1993; Wenzel 2007, eq. 1). `Default` is
/// a placeholder for layout probes; build one with [`SkyAtmosphere::earth`].
///
/// ```
/// use glam::Vec3;
/// use volfog::uniforms::SkyAtmosphere;
///
/// let noon = SkyAtmosphere::earth(Vec3::new(0.0, 0.9, -0.436).normalize()).unwrap();
/// assert_eq!(noon.planet_radius, 6.36e6);
/// assert!(SkyAtmosphere::earth(Vec3::ZERO).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SkyAtmosphere {
    /// Unit direction towards the sun (world space).
    pub sun_direction: Vec3,
    /// Planet radius (m), [1e3, 1e8].
    pub planet_radius: f32,
    /// Rayleigh scattering at the ground per channel (1/m), [0, 1e-2].
    pub rayleigh: Vec3,
    /// Radius of the top of the atmosphere (m), above `planet_radius`, at most twice it.
    pub atmosphere_radius: f32,
    /// Solar irradiance (linear rgb), [0, 1e9].
    pub sun_intensity: Vec3,
    /// Camera altitude above the ground (m), [0, atmosphere - planet).
    pub camera_height: f32,
    /// Rayleigh scale height (m), [1, 1e6].
    pub rayleigh_height: f32,
    /// Mie scattering at the ground (1/m), [0, 1e-2].
    pub mie: f32,
    /// Mie scale height (m), [1, 1e6].
    pub mie_height: f32,
    /// Mie extinction over Mie scattering, [1, 10].
    pub mie_extinction_ratio: f32,
    /// Cornette–Shanks mean cosine of Mie scattering, [0, 0.999].
    pub mie_g: f32,
    /// Quadrature points along the view ray, [1, 256].
    pub view_samples: u32,
    /// Quadrature points along each sun ray, [1, 256].
    pub light_samples: u32,
    /// First texture row a `sky_solve` dispatch fills.
    pub first_row: u32,
}

impl SkyAtmosphere {
    /// The Earth's clear atmosphere for a sun in `sun_direction` (normalised; unit
    /// length within 1e-3): planet 6360 km, atmosphere 60 km thick, Rayleigh
    /// (5.8, 13.5, 33.1) × 1e-6 / m with an 8 km scale height, Mie 21e-6 / m with a
    /// 1.2 km scale height, extinction 1.11 times scattering and g = 0.76, solar
    /// irradiance 20 in each channel, the camera 2 m above the ground, 64 view and 16
    /// sun samples.
    pub fn earth(sun_direction: Vec3) -> Result<Self, InvalidValue> {
        Self {
            sun_direction,
            planet_radius: 6.36e6,
            rayleigh: Vec3::new(5.802e-6, 13.558e-6, 33.1e-6),
            atmosphere_radius: 6.42e6,
            sun_intensity: Vec3::splat(20.0),
            camera_height: 2.0,
            rayleigh_height: 8000.0,
            mie: 21e-6,
            mie_height: 1200.0,
            mie_extinction_ratio: 1.11,
            mie_g: 0.76,
            view_samples: 128,
            light_samples: 32,
            first_row: 0,
        }
        .validated()
    }

    /// Checks every member against its range; the sun direction is normalised.
    pub fn validated(self) -> Result<Self, InvalidValue> {
        check_unit("SkyAtmosphere.sun_direction", self.sun_direction)?;
        limits::SKY_PLANET_RADIUS.check("SkyAtmosphere.planet_radius", self.planet_radius)?;
        check(
            self.atmosphere_radius > self.planet_radius
                && self.atmosphere_radius <= 2.0 * self.planet_radius,
            "SkyAtmosphere.atmosphere_radius",
            self.atmosphere_radius,
            "above planet_radius, at most twice it",
        )?;
        check_channels(
            "SkyAtmosphere.rayleigh",
            self.rayleigh,
            &limits::SKY_SCATTERING,
        )?;
        check_channels(
            "SkyAtmosphere.sun_intensity",
            self.sun_intensity,
            &limits::FOG_RADIANCE,
        )?;
        check(
            self.camera_height >= 0.0
                && self.camera_height < self.atmosphere_radius - self.planet_radius,
            "SkyAtmosphere.camera_height",
            self.camera_height,
            "0 <= height < atmosphere_radius - planet_radius (m)",
        )?;
        limits::SKY_SCALE_HEIGHT.check("SkyAtmosphere.rayleigh_height", self.rayleigh_height)?;
        limits::SKY_SCATTERING.check("SkyAtmosphere.mie", self.mie)?;
        limits::SKY_SCALE_HEIGHT.check("SkyAtmosphere.mie_height", self.mie_height)?;
        limits::SKY_MIE_EXTINCTION_RATIO.check(
            "SkyAtmosphere.mie_extinction_ratio",
            self.mie_extinction_ratio,
        )?;
        limits::SKY_MIE_G.check("SkyAtmosphere.mie_g", self.mie_g)?;
        limits::SKY_SAMPLES.check("SkyAtmosphere.view_samples", self.view_samples)?;
        limits::SKY_SAMPLES.check("SkyAtmosphere.light_samples", self.light_samples)?;
        Ok(Self {
            sun_direction: self.sun_direction.normalize(),
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
