//! Every limit volfog checks, in one place, and the error that names a value outside
//! one.
//!
//! A limit that bounds a WGSL formula has a twin constant of the same name in the
//! shader module that uses it (`FOG_DENSITY_LIMIT` in `volfog::height_fog`, ...); the
//! tests compare each pair. Limits of define values come from the shader manifest.
//!
//! ```
//! use volfog::limits::{self, InvalidValue};
//!
//! assert!(limits::CASCADES.check("FogConfig.cascades", 4).is_ok());
//! let err: InvalidValue = limits::CASCADES.check("FogConfig.cascades", 5).unwrap_err();
//! assert_eq!(err.to_string(), "FogConfig.cascades = 5 is invalid: expected 1..=4 cascades");
//! ```

use std::borrow::Cow;
use std::fmt;

use volfog_codegen::manifest;

/// A value outside its valid range: the field, the value and the valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} = {value} is invalid: expected {expected}")]
pub struct InvalidValue {
    /// The field, e.g. `Froxels.near`.
    pub field: &'static str,
    /// The rejected value, printed.
    pub value: String,
    /// The valid range, in words.
    pub expected: Cow<'static, str>,
}

/// `Ok` when `ok`, otherwise an [`InvalidValue`] for `field` with `expected` as the
/// valid range.
pub fn check(
    ok: bool,
    field: &'static str,
    value: impl fmt::Debug,
    expected: impl Into<Cow<'static, str>>,
) -> Result<(), InvalidValue> {
    if ok {
        Ok(())
    } else {
        Err(InvalidValue {
            field,
            value: format!("{value:?}"),
            expected: expected.into(),
        })
    }
}

/// A closed range `min..=max` (or `min < x <= max` when the minimum is excluded) with
/// the unit of its values; its error message is written from these values, so the
/// text never disagrees with the check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range<T> {
    /// Smallest valid value (excluded when `exclusive_min`).
    pub min: T,
    /// Largest valid value.
    pub max: T,
    /// `min` itself is invalid.
    pub exclusive_min: bool,
    /// `max` itself is invalid.
    pub exclusive_max: bool,
    /// Unit and meaning, printed after the range (may be empty).
    pub unit: &'static str,
}

impl<T: PartialOrd + Copy + fmt::Display + fmt::Debug> Range<T> {
    /// `min..=max`.
    pub const fn new(min: T, max: T, unit: &'static str) -> Self {
        Self {
            min,
            max,
            exclusive_min: false,
            exclusive_max: false,
            unit,
        }
    }

    /// `min < x <= max`.
    pub const fn above(min: T, max: T, unit: &'static str) -> Self {
        Self {
            exclusive_min: true,
            ..Self::new(min, max, unit)
        }
    }

    /// `min <= x < max`.
    pub const fn below(min: T, max: T, unit: &'static str) -> Self {
        Self {
            exclusive_max: true,
            ..Self::new(min, max, unit)
        }
    }

    /// Whether `value` lies in the range (NaN never does).
    pub fn contains(&self, value: T) -> bool {
        let low = if self.exclusive_min {
            value > self.min
        } else {
            value >= self.min
        };
        let high = if self.exclusive_max {
            value < self.max
        } else {
            value <= self.max
        };
        low && high
    }

    /// The range in words, e.g. `1..=4 cascades` or `0 < x <= 88`.
    pub fn describe(&self) -> String {
        let range = match (self.exclusive_min, self.exclusive_max) {
            (false, false) => format!("{}..={}", self.min, self.max),
            (true, false) => format!("{} < x <= {}", self.min, self.max),
            (false, true) => format!("{} <= x < {}", self.min, self.max),
            (true, true) => format!("{} < x < {}", self.min, self.max),
        };
        if self.unit.is_empty() {
            range
        } else {
            format!("{range} {}", self.unit)
        }
    }

    /// `Ok` when `value` lies in the range, otherwise an error naming `field`.
    pub fn check(&self, field: &'static str, value: T) -> Result<(), InvalidValue> {
        check(self.contains(value), field, value, self.describe())
    }
}

impl Range<u32> {
    const fn from_define(define: &manifest::ValueDefine, unit: &'static str) -> Self {
        Self::new(define.min, define.max, unit)
    }
}

/// Froxels per axis of a volume (wgpu's default 3D texture limit).
pub const VOLUME_AXIS: Range<u32> = Range::new(1, 2048, "froxels per axis");
/// Most froxels in a volume (64 MiB per rgba16float volume).
pub const MAX_FROXELS: u64 = 8 * 1024 * 1024;
/// Slice distribution curve: 0 is linear, ln(far / near) exponential; exp(curve) must
/// stay far from f32 overflow.
pub const SLICE_CURVE: Range<f32> = Range::new(0.0, 30.0, "(0 linear, ln(far / near) exponential)");
/// ESM texels per side and cascade (the shadow map is 4x as large).
pub const ESM_RESOLUTION: Range<u32> = Range::new(4, 2048, "texels");
/// Most shadow cascades (the `ShadowCascades` uniform holds four).
pub const MAX_CASCADES: usize = 4;
/// Shadow cascades a volume is configured for.
pub const CASCADES: Range<u32> = Range::new(1, MAX_CASCADES as u32, "cascades");
/// Largest ESM exponent without log-space filtering: exp(88) < f32::MAX.
pub const MAX_LINEAR_ESM_EXPONENT: f32 = 88.0;
/// ESM exponent for depths in [0, 1] with linear filtering.
pub const ESM_EXPONENT: Range<f32> = Range::above(
    0.0,
    MAX_LINEAR_ESM_EXPONENT,
    "(exp(c) must stay finite in f32; filter in log space for more)",
);
/// ESM exponent with log-space filtering (`VOLFOG_ESM_LOG_SPACE`).
pub const ESM_EXPONENT_LOG_SPACE: Range<f32> = Range::above(0.0, 1.0e4, "(log-space ESM)");
/// Box blur radius of the ESM (taps = 2 radius + 1), `VOLFOG_ESM_BLUR_RADIUS`.
pub const ESM_BLUR_RADIUS: Range<u32> = Range::from_define(&manifest::ESM_BLUR_RADIUS, "texels");
/// Noise fbm octaves, `VOLFOG_INJECT_NOISE_OCTAVES`.
pub const NOISE_OCTAVES: Range<u32> =
    Range::from_define(&manifest::INJECT_NOISE_OCTAVES, "octaves");
/// Point and spot lights one inject workgroup gathers (WGSL `TILE_LIGHTS`).
pub const MAX_LIGHTS: u32 = 64;
/// Capacity of the light buffer.
pub const LIGHTS: Range<u32> = Range::new(0, MAX_LIGHTS, "lights");
/// Transient lights a frame may hold: the scan evaluates each of them at every live
/// froxel (they are not culled per block as inject culls its lights).
pub const MAX_TRANSIENT_LIGHTS: u32 = 16;

/// Most area lights a fog holds (`FogConfig::max_area_lights`): each is integrated
/// over 16 (rectangle) or 32 (disk) cells at every froxel its range reaches.
pub const MAX_AREA_LIGHTS: u32 = 16;

/// `FogConfig::max_area_lights`: 0 (no area-light variant) to [`MAX_AREA_LIGHTS`].
pub const AREA_LIGHTS: Range<u32> = Range::new(0, MAX_AREA_LIGHTS, "area lights");

/// Most particles a fog holds (`FogConfig::max_particles`; 48 bytes each, 3 MiB).
pub const MAX_PARTICLES: u32 = 65_536;
/// `FogConfig::max_particles`: 0 (no particle variant) to [`MAX_PARTICLES`].
pub const PARTICLES: Range<u32> = Range::new(0, MAX_PARTICLES, "particles");
/// `FogParticle::radius` (m).
pub const PARTICLE_RADIUS: Range<f32> = Range::above(0.0, 1.0e4, "m");
/// `FogParticle::extinction` at the particle's centre (1/m).
pub const PARTICLE_EXTINCTION: Range<f32> = Range::new(0.0, 1.0e3, "1/m");
/// Capacity of the transient light buffer (`FogConfig::max_transient_lights`; 0 builds
/// no transient scan).
pub const TRANSIENT_LIGHTS: Range<u32> = Range::new(0, MAX_TRANSIENT_LIGHTS, "transient lights");
/// Capacity of the local volume buffer.
pub const LOCAL_VOLUMES: Range<u32> = Range::new(0, 256, "volumes");
/// Texels per axis of the medium-shadow volume (`MediumShadowConfig::size`).
pub const MEDIUM_SHADOW_AXIS: Range<u32> = Range::new(2, 512, "texels per axis");
/// Midpoint samples of the medium shadow's march towards a local light
/// (`MediumShadowConfig::march_steps`).
pub const MEDIUM_SHADOW_MARCH: Range<u32> = Range::new(1, 64, "samples");
/// Weight of the reprojected history.
pub const HISTORY_WEIGHT: Range<f32> = Range::below(0.0, 1.0, "");

/// Extinction of the froxel medium at its base height (1/m).
pub const MEDIUM_DENSITY: Range<f32> = Range::new(0.0, 1.0e3, "1/m");
/// Height falloff of the froxel medium (1/m).
pub const MEDIUM_FALLOFF: Range<f32> = Range::new(0.0, 100.0, "1/m");
/// Extinction a local volume adds (1/m); negative clears fog.
pub const LOCAL_VOLUME_DENSITY: Range<f32> = Range::new(-1.0e3, 1.0e3, "1/m");
/// The density of a local volume that does not add (`BlendMode` other than `Add`): the
/// extinction it subtracts, caps at, raises to or sets (1/m), or under `Multiply` the
/// factor of the medium.
pub const LOCAL_VOLUME_BLEND_DENSITY: Range<f32> = Range::new(
    0.0,
    1.0e3,
    "1/m (a factor under BlendMode::Multiply) for a volume that does not add",
);
/// Edge falloff width of a local volume, as a fraction of its unit extent.
pub const LOCAL_VOLUME_EDGE: Range<f32> = Range::above(0.0, 1.0, "");
/// Colour channels of the directional light and its tints.
pub const LIGHT_COLOR: Range<f32> = Range::new(0.0, 1.0e4, "per channel");

/// Largest extinction of the analytic fogs (1/m; WGSL `FOG_DENSITY_LIMIT`).
pub const FOG_DENSITY_LIMIT: f32 = 1e3;
/// Largest |falloff| of the analytic fogs (1/m; WGSL `FOG_FALLOFF_LIMIT`).
pub const FOG_FALLOFF_LIMIT: f32 = 1e3;
/// Largest |coordinate| of the analytic fogs (m; WGSL `FOG_POSITION_LIMIT`).
pub const FOG_POSITION_LIMIT: f32 = 1e9;
/// The top height (m) of a medium or height fog that has no top: the analytic fogs
/// clamp heights to [`FOG_POSITION_LIMIT`], so nothing lies above it.
pub const NO_TOP: f32 = FOG_POSITION_LIMIT;
/// Extinction of the analytic fogs.
pub const FOG_DENSITY: Range<f32> = Range::new(0.0, FOG_DENSITY_LIMIT, "1/m");
/// Falloff of the analytic fogs.
pub const FOG_FALLOFF: Range<f32> = Range::new(-FOG_FALLOFF_LIMIT, FOG_FALLOFF_LIMIT, "1/m");
/// Heights and offsets of the analytic fogs.
pub const FOG_POSITION: Range<f32> = Range::new(-FOG_POSITION_LIMIT, FOG_POSITION_LIMIT, "m");
/// Largest radiance (linear, per channel) accepted for fog colours.
pub const MAX_FOG_RADIANCE: f32 = 1.0e9;
/// Fog colours (linear radiance per channel).
pub const FOG_RADIANCE: Range<f32> = Range::new(0.0, MAX_FOG_RADIANCE, "per channel");
/// Henyey-Greenstein mean cosine of the height fog's sun lobe.
pub const FOG_SUN_G: Range<f32> = Range::new(-0.999, 0.999, "");
/// Largest entry of the linear part of a fog volume's world -> local matrix (volumes
/// smaller than about a micrometre are rejected).
pub const MAX_FOG_VOLUME_LOCAL_SCALE: f32 = 1.0e6;
/// Single-scattering albedo of water, per channel.
pub const WATER_ALBEDO: Range<f32> = Range::new(0.0, 1.0, "per channel");
/// Planet radius of a sky atmosphere.
pub const SKY_PLANET_RADIUS: Range<f32> = Range::new(1.0e3, 1.0e8, "m");
/// Scattering coefficients of a sky atmosphere at the ground.
pub const SKY_SCATTERING: Range<f32> = Range::new(0.0, 1.0e-2, "1/m");
/// Scale heights of a sky atmosphere.
pub const SKY_SCALE_HEIGHT: Range<f32> = Range::new(1.0, 1.0e6, "m");
/// Mie extinction over Mie scattering.
pub const SKY_MIE_EXTINCTION_RATIO: Range<f32> = Range::new(1.0, 10.0, "");
/// Mean cosine of Mie scattering (Cornette-Shanks).
pub const SKY_MIE_G: Range<f32> = Range::new(0.0, 0.999, "");
/// Quadrature points of the sky solve.
pub const SKY_SAMPLES: Range<u32> = Range::new(1, 256, "samples");
/// Thickness of a cloud layer.
pub const CLOUD_THICKNESS: Range<f32> = Range::above(0.0, 1.0e5, "m");
/// Extinction of a cloud layer at map density 1.
pub const CLOUD_EXTINCTION: Range<f32> = Range::new(0.0, 10.0, "1/m");
/// World size of one repeat of a cloud map.
pub const CLOUD_MAP_SIZE: Range<f32> = Range::above(0.0, 1.0e7, "m");
/// Samples of the distance clouds' march.
pub const CLOUD_SAMPLES: Range<u32> = Range::new(1, 64, "samples");
/// Rim light strength of a cloud layer.
pub const CLOUD_RIM: Range<f32> = Range::new(0.0, 1.0e3, "");
/// Shore fade distance of a water surface.
pub const WATER_SHORE_FADE: Range<f32> = Range::new(0.0, 1.0e9, "m");
/// Extinction inside a fog hull (1/m).
pub const HULL_DENSITY: Range<f32> = Range::new(0.0, 1.0e3, "1/m");
/// Reference distance of a fog hull (m).
pub const HULL_REFERENCE: Range<f32> = Range::new(0.0, 1.0e9, "m");
/// Radiance a medium or a local volume emits per metre of path, per channel.
pub const EMISSION: Range<f32> = Range::new(0.0, 1.0e6, "per channel (W / (sr m^3))");
/// Texels per side of one map of the local-light ESM atlas.
pub const LOCAL_SHADOW_RESOLUTION: Range<u32> = Range::new(8, 1024, "texels");
/// Shadowed spot lights per frame (one atlas layer each).
pub const MAX_SPOT_SHADOWS: u32 = 16;
/// Capacity of the atlas for shadowed spot lights.
pub const SPOT_SHADOWS: Range<u32> = Range::new(0, MAX_SPOT_SHADOWS, "shadowed spot lights");
/// Shadowed point lights per frame (six atlas layers each).
pub const MAX_POINT_SHADOWS: u32 = 8;
/// Capacity of the atlas for shadowed point lights.
pub const POINT_SHADOWS: Range<u32> = Range::new(0, MAX_POINT_SHADOWS, "shadowed point lights");
/// Shadow-map texels per atlas texel along each axis (the shadow map is this many
/// times the atlas resolution).
pub const LOCAL_SHADOW_FACTOR: Range<u32> = Range::new(1, 16, "shadow-map texels per atlas texel");
/// Shadow taps per froxel per frame of the compare filter
/// ([`ShadowFilter::Compare`](crate::options::ShadowFilter::Compare)).
pub const SHADOW_TAPS: Range<u32> = Range::new(1, MAX_SHADOW_TAPS / 4, "taps");
/// The tap offsets a frame holds ([`ShadowTaps`](crate::uniforms::ShadowTaps)): the most
/// taps a froxel without history takes (4 x [`SHADOW_TAPS`]).
pub const MAX_SHADOW_TAPS: u32 = 16;
/// Depth bias of a local light's shadow (m).
pub const LOCAL_SHADOW_BIAS: Range<f32> = Range::new(0.0, 1.0e3, "m");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_check_and_describe() {
        assert!(ESM_EXPONENT.contains(88.0));
        assert!(!ESM_EXPONENT.contains(0.0));
        assert!(!ESM_EXPONENT.contains(f32::NAN));
        assert_eq!(
            ESM_BLUR_RADIUS.describe(),
            format!(
                "{}..={} texels",
                manifest::ESM_BLUR_RADIUS.min,
                manifest::ESM_BLUR_RADIUS.max
            )
        );
        let err = LOCAL_VOLUME_EDGE
            .check("LocalVolume.edge", 0.0)
            .unwrap_err();
        assert_eq!(err.field, "LocalVolume.edge");
        assert_eq!(err.expected, "0 < x <= 1");
    }
}
