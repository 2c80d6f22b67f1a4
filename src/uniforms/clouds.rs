//! `CloudLayer`: a cloud layer from a wind-scrolled 2D density map (`volfog::clouds`).

use encase::ShaderType;
use glam::{Vec2, Vec3};

use super::{check_channels, check_unit};
use crate::limits::{self, InvalidValue, check};

/// A cloud layer (WGSL `volfog::types::CloudLayer`, used by `volfog::clouds`, the
/// `clouds` pass and the inject pass's `VOLFOG_INJECT_CLOUD_SHADOW`): a horizontal slab
/// from `base_height` to `base_height + thickness` whose extinction is `extinction`
/// times a 2D map's red channel, scrolled by `wind`. `Default` is a placeholder for
/// layout probes; build one with [`CloudLayer::new`].
///
/// ```
/// use glam::{Vec2, Vec3};
/// use volfog::uniforms::CloudLayer;
///
/// let layer = CloudLayer::new(1500.0, 400.0, 0.01, 8000.0).unwrap()
///     .with_sun(Vec3::new(0.3, 0.8, -0.5).normalize(), Vec3::splat(6.0), Vec3::new(0.3, 0.4, 0.6), 0.6)
///     .unwrap()
///     .with_wind(Vec2::new(12.0, 3.0), 10.0)
///     .unwrap();
/// assert_eq!(layer.wind, Vec2::new(12.0, 3.0));
/// assert!(CloudLayer::new(1500.0, 0.0, 0.01, 8000.0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CloudLayer {
    /// Unit direction towards the sun.
    pub sun_direction: Vec3,
    /// Height of the layer's base (m along +Y).
    pub base_height: f32,
    /// Sun radiance scattered by the clouds (linear rgb, radiance · sr), [0, 1e9].
    pub sun_color: Vec3,
    /// Thickness (m), (0, 1e5].
    pub thickness: f32,
    /// Sky light on the clouds (linear rgb), [0, 1e9].
    pub sky_color: Vec3,
    /// Extinction at map density 1 (1/m), [0, 10].
    pub extinction: f32,
    /// How far the map moves per second (m/s, world x and z).
    pub wind: Vec2,
    /// Metres of world per repeat of the map, (0, 1e7].
    pub map_size: f32,
    /// Time (s).
    pub time: f32,
    /// Samples along the view ray (distance clouds), [1, 64].
    pub view_samples: u32,
    /// Samples towards the sun (distance clouds), [1, 64].
    pub sun_samples: u32,
    /// HG mean cosine of the sun's scattering, [-0.999, 0.999].
    pub g: f32,
    /// Rim light strength, [0, 1e3].
    pub rim: f32,
}

impl CloudLayer {
    /// A layer without light (add it with [`CloudLayer::with_sun`]), no wind, 16 view
    /// and 4 sun samples, g = 0.6, rim 1.
    pub fn new(
        base_height: f32,
        thickness: f32,
        extinction: f32,
        map_size: f32,
    ) -> Result<Self, InvalidValue> {
        Self {
            sun_direction: Vec3::Y,
            base_height,
            sun_color: Vec3::ZERO,
            thickness,
            sky_color: Vec3::ZERO,
            extinction,
            wind: Vec2::ZERO,
            map_size,
            time: 0.0,
            view_samples: 16,
            sun_samples: 4,
            g: 0.6,
            rim: 1.0,
        }
        .validated()
    }

    /// Lights the layer: the sun's direction, its scattered radiance, the sky's, and
    /// the HG mean cosine of the sun lobe.
    pub fn with_sun(
        self,
        direction: Vec3,
        sun_color: Vec3,
        sky_color: Vec3,
        g: f32,
    ) -> Result<Self, InvalidValue> {
        Self {
            sun_direction: direction,
            sun_color,
            sky_color,
            g,
            ..self
        }
        .validated()
    }

    /// Scrolls the map by `wind` (m/s) at `time` (s).
    pub fn with_wind(self, wind: Vec2, time: f32) -> Result<Self, InvalidValue> {
        Self { wind, time, ..self }.validated()
    }

    /// Checks every member against its range; the sun direction is normalised.
    pub fn validated(self) -> Result<Self, InvalidValue> {
        check_unit("CloudLayer.sun_direction", self.sun_direction)?;
        limits::FOG_POSITION.check("CloudLayer.base_height", self.base_height)?;
        check_channels(
            "CloudLayer.sun_color",
            self.sun_color,
            &limits::FOG_RADIANCE,
        )?;
        limits::CLOUD_THICKNESS.check("CloudLayer.thickness", self.thickness)?;
        check_channels(
            "CloudLayer.sky_color",
            self.sky_color,
            &limits::FOG_RADIANCE,
        )?;
        limits::CLOUD_EXTINCTION.check("CloudLayer.extinction", self.extinction)?;
        check(
            self.wind.is_finite() && self.wind.abs().max_element() <= 1e4,
            "CloudLayer.wind",
            self.wind,
            "a finite wind within +-1e4 m/s",
        )?;
        limits::CLOUD_MAP_SIZE.check("CloudLayer.map_size", self.map_size)?;
        check(
            self.time.is_finite() && self.time.abs() <= 1e7,
            "CloudLayer.time",
            self.time,
            "a finite time within +-1e7 s",
        )?;
        limits::CLOUD_SAMPLES.check("CloudLayer.view_samples", self.view_samples)?;
        limits::CLOUD_SAMPLES.check("CloudLayer.sun_samples", self.sun_samples)?;
        limits::FOG_SUN_G.check("CloudLayer.g", self.g)?;
        limits::CLOUD_RIM.check("CloudLayer.rim", self.rim)?;
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
