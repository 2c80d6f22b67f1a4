//! `FogMedium` (the froxel volume's participating medium) and `LocalVolume` (a box,
//! ellipsoid, cylinder or cone that adds, clears, scales, caps, raises, replaces or
//! lights fog, by its [`BlendMode`]).

use encase::ShaderType;
use glam::{Mat4, Vec3};

use super::{check_finite, check_invertible, check_unit};
use crate::limits::{self, InvalidValue, Range, check};

/// The participating medium (WGSL `volfog::types::FogMedium`).
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogMedium {
    /// Single-scattering albedo per channel, [0, 1].
    pub albedo: Vec3,
    /// Extinction at `base_height` (1/m), see [`limits::MEDIUM_DENSITY`].
    pub density: f32,
    /// Unit up axis of the height gradient.
    pub up: Vec3,
    /// Height falloff (1/m), see [`limits::MEDIUM_FALLOFF`].
    pub height_falloff: f32,
    /// Wind velocity (m/s).
    pub wind: Vec3,
    /// Height (m) where the extinction equals `density`.
    pub base_height: f32,
    /// World -> density texture coordinate scale (1/m).
    pub texture_scale: Vec3,
    /// Noise amplitude in [0, 1].
    pub noise_strength: f32,
    /// Density texture coordinate offset.
    pub texture_offset: Vec3,
    /// Noise frequency (1/m), > 0.
    pub noise_scale: f32,
    /// Henyey-Greenstein mean cosine, (-1, 1).
    pub phase_g: f32,
    /// Number of local volumes in use (set by the runtime).
    pub local_volume_count: u32,
    /// Radiance emitted per metre of path where the extinction equals `density`
    /// (linear rgb, W / (sr m^3)); it follows the extinction's shape (height profile,
    /// noise, density texture). See [`limits::EMISSION`].
    pub emission: Vec3,
    /// Height (m along `up`) where the medium ends: its extinction and emission are 0
    /// above it, and the sun's light enters the medium there (with
    /// [`FogConfig::light_transmittance`](crate::pipeline::FogConfig::light_transmittance)).
    /// [`limits::NO_TOP`] (the default) for a medium without a top; a uniform medium
    /// (`height_falloff` 0) without a top lets no sunlight through. `|h| <= 1e9`.
    #[cfg_attr(feature = "serde", serde(default = "no_top"))]
    pub top_height: f32,
    /// 1 (the default): the density texture
    /// ([`VolumetricFog::set_density_texture`](crate::pipeline::VolumetricFog::set_density_texture),
    /// with `FogConfig::density_texture`) scales the medium in world space at
    /// `world * texture_scale + texture_offset`; 0: it does not, and only shapes the
    /// local volumes made with [`LocalVolume::with_density_texture`].
    #[cfg_attr(feature = "serde", serde(default = "textured"))]
    pub textured: u32,
    /// Number of particles in use (set by the runtime from
    /// [`FrameInputs::particles`](crate::pipeline::FrameInputs::particles)).
    #[cfg_attr(feature = "serde", serde(default))]
    pub particle_count: u32,
}

#[cfg(feature = "serde")]
fn no_top() -> f32 {
    limits::NO_TOP
}

#[cfg(feature = "serde")]
fn textured() -> u32 {
    1
}

impl Default for FogMedium {
    fn default() -> Self {
        Self {
            albedo: Vec3::splat(0.9),
            density: 0.02,
            up: Vec3::Y,
            height_falloff: 0.05,
            wind: Vec3::new(1.0, 0.0, 0.5),
            base_height: 0.0,
            texture_scale: Vec3::splat(0.05),
            noise_strength: 0.5,
            texture_offset: Vec3::ZERO,
            noise_scale: 0.15,
            phase_g: 0.4,
            local_volume_count: 0,
            emission: Vec3::ZERO,
            top_height: limits::NO_TOP,
            textured: 1,
            particle_count: 0,
        }
    }
}

impl FogMedium {
    /// Checks every value that could produce NaN, Inf or nonsense on the GPU.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        super::check_channels("FogMedium.albedo", self.albedo, &Range::new(0.0, 1.0, ""))?;
        limits::MEDIUM_DENSITY.check("FogMedium.density", self.density)?;
        check_unit("FogMedium.up", self.up)?;
        limits::MEDIUM_FALLOFF.check("FogMedium.height_falloff", self.height_falloff)?;
        check_finite("FogMedium.wind", self.wind, "a finite velocity")?;
        check(
            self.base_height.is_finite(),
            "FogMedium.base_height",
            self.base_height,
            "a finite height",
        )?;
        check_finite(
            "FogMedium.texture_scale",
            self.texture_scale,
            "finite values",
        )?;
        check_finite(
            "FogMedium.texture_offset",
            self.texture_offset,
            "finite values",
        )?;
        Range::new(0.0, 1.0, "").check("FogMedium.noise_strength", self.noise_strength)?;
        check(
            self.noise_scale.is_finite() && self.noise_scale > 0.0,
            "FogMedium.noise_scale",
            self.noise_scale,
            "a finite frequency > 0 (1/m)",
        )?;
        check(
            self.phase_g > -1.0 && self.phase_g < 1.0,
            "FogMedium.phase_g",
            self.phase_g,
            "-1 < g < 1",
        )?;
        super::check_channels("FogMedium.emission", self.emission, &limits::EMISSION)?;
        limits::FOG_POSITION.check("FogMedium.top_height", self.top_height)?;
        check(
            self.textured <= 1,
            "FogMedium.textured",
            self.textured,
            "0 or 1",
        )
    }
}

/// Shape of a [`LocalVolume`] or an analytic [`FogVolume`](super::FogVolume), in its
/// local (unit shape) space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum VolumeShape {
    /// The box [-1, 1]^3.
    Box = 0,
    /// The unit sphere.
    Ellipsoid = 1,
    /// The half-space y <= 0 (fog volumes only: [`FogVolume::plane`](super::FogVolume::plane)).
    Plane = 2,
    /// The cylinder of radius 1 around the y axis, |y| <= 1.
    Cylinder = 3,
    /// The cone with its apex at y = 1 and a base of radius 1 at y = -1.
    Cone = 4,
}

/// How a [`LocalVolume`] combines with the medium before it: the global medium, then
/// the volumes before it in the buffer (`FrameInputs::local_volumes`), in that order
/// (WGSL `volfog::density::local_volume_blend`). With `m` the medium's (emission,
/// extinction) and `v` the volume's (`emission`, `density`), channel by channel, faded
/// in by the volume's edge weight `w` as `m + w (blend(m, v) - m)`:
///
/// | mode | blend(m, v) | extinction | emission |
/// | --- | --- | --- | --- |
/// | `Add` | `m + v` | plus `density` (negative clears; the sum is clamped at 0 at the end) | plus `emission` |
/// | `Subtract` | `max(m - v, 0)` | minus `density`, clamped at 0 at once | minus `emission`, clamped at 0 |
/// | `Multiply` | `m * density` | times `density` | times `density` (`emission` must be 0) |
/// | `Min` | `min(m, v)` | at most `density` | at most `emission` |
/// | `Max` | `max(m, v)` | at least `density` | at least `emission` |
/// | `Overwrite` | `v` | `density` | `emission` |
///
/// The scattering follows the extinction (`FogMedium::albedo` times it). Every mode
/// leaves the medium unchanged where `w` is 0, so volumes stay culled per froxel
/// block. Only `Add` takes a negative `density`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(u32)]
pub enum BlendMode {
    /// Adds the volume's fog (the default).
    #[default]
    Add = 0,
    /// Removes the volume's density and emission from the medium, clamped at zero:
    /// clears fog indoors (Godot's negative density); volumes after it add fog again.
    Subtract = 1,
    /// Scales the medium's extinction and emission by `density` (a factor >= 0).
    Multiply = 2,
    /// Caps the medium's extinction at `density` and its emission at `emission`.
    Min = 3,
    /// Raises the medium's extinction to at least `density`, its emission to at least
    /// `emission`.
    Max = 4,
    /// Replaces the medium by the volume's density and emission.
    Overwrite = 5,
}

impl BlendMode {
    /// Every mode, by code.
    pub const ALL: [BlendMode; 6] = [
        BlendMode::Add,
        BlendMode::Subtract,
        BlendMode::Multiply,
        BlendMode::Min,
        BlendMode::Max,
        BlendMode::Overwrite,
    ];

    /// The mode of a `LocalVolume::blend` code.
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.get(code as usize).copied()
    }
}

/// A local fog volume (WGSL `volfog::types::LocalVolume`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LocalVolume {
    /// World -> unit shape space.
    pub local_from_world: Mat4,
    /// Radiance emitted per metre of path inside (linear rgb, W / (sr m^3)), faded with
    /// the edge like the density. See [`limits::EMISSION`].
    pub emission: Vec3,
    /// The volume's extinction inside (1/m), combined with the medium's by `blend`:
    /// added (negative clears fog, see [`limits::LOCAL_VOLUME_DENSITY`]), or, for the
    /// other modes, >= 0 (see [`limits::LOCAL_VOLUME_BLEND_DENSITY`]): subtracted, the
    /// cap, the floor, the value, or under [`BlendMode::Multiply`] the factor.
    pub density: f32,
    /// Edge falloff width, fraction of the unit extent, (0, 1].
    pub edge: f32,
    /// A [`VolumeShape`] code: 0 box, 1 ellipsoid, 3 cylinder, 4 cone.
    pub shape: u32,
    /// A [`BlendMode`] code: 0 add (the default), 1 subtract, 2 multiply, 3 min, 4 max,
    /// 5 overwrite.
    #[cfg_attr(feature = "serde", serde(default))]
    pub blend: u32,
    /// Added to the density texture's coordinate in this volume, whose unit shape spans
    /// [0, 1] of the texture; move it to scroll the pattern. Finite.
    pub texture_offset: Vec3,
    /// 1: the density texture (`VolumetricFog::set_density_texture`, with
    /// `FogConfig::density_texture`) scales the volume's density and emission, sampled
    /// in the volume's own space (see [`LocalVolume::with_density_texture`]); 0: it
    /// does not.
    pub textured: u32,
}

impl LocalVolume {
    /// A volume covering `world_from_local` applied to the unit shape.
    pub fn new(
        world_from_local: Mat4,
        shape: VolumeShape,
        density: f32,
        edge: f32,
    ) -> Result<Self, InvalidValue> {
        check_invertible(
            "LocalVolume.world_from_local",
            world_from_local,
            1e-12,
            "a finite, invertible transform",
        )?;
        let volume = Self {
            local_from_world: world_from_local.inverse(),
            emission: Vec3::ZERO,
            density,
            edge,
            shape: shape as u32,
            blend: BlendMode::Add as u32,
            texture_offset: Vec3::ZERO,
            textured: 0,
        };
        volume.validate()?;
        Ok(volume)
    }

    /// The volume scaled by the density texture's red channel in its own space, at
    /// `local * 0.5 + 0.5 + offset` (`local` in the unit shape's [-1, 1]^3, repeat
    /// addressing: Bevy's `FogVolume` convention, where the unit cube spans the whole
    /// texture). The fog needs `FogConfig::density_texture`; without it the volume is
    /// not textured. The texture also scales the global medium, in world space.
    pub fn with_density_texture(self, offset: Vec3) -> Result<Self, InvalidValue> {
        let volume = Self {
            texture_offset: offset,
            textured: 1,
            ..self
        };
        volume.validate()?;
        Ok(volume)
    }

    /// The volume glowing with `emission` (radiance per metre, linear rgb; under
    /// [`BlendMode::Min`], `Max` and `Overwrite` the emission's cap, floor or value,
    /// under `Subtract` what it removes).
    pub fn with_emission(self, emission: Vec3) -> Result<Self, InvalidValue> {
        let volume = Self { emission, ..self };
        volume.validate()?;
        Ok(volume)
    }

    /// The volume combined with the medium by `blend` (see [`BlendMode`]); its density
    /// and emission must suit the mode.
    ///
    /// ```
    /// use glam::{Mat4, Vec3};
    /// use volfog::uniforms::{BlendMode, LocalVolume, VolumeShape};
    ///
    /// // A house that clears the fog inside it.
    /// let house = Mat4::from_scale_rotation_translation(
    ///     Vec3::new(4.0, 3.0, 5.0),
    ///     glam::Quat::IDENTITY,
    ///     Vec3::new(0.0, 3.0, -20.0),
    /// );
    /// let clear = LocalVolume::new(house, VolumeShape::Box, 10.0, 0.05)?
    ///     .with_blend(BlendMode::Subtract)?;
    /// assert_eq!(clear.blend, 1);
    /// // Only an additive volume takes a negative density.
    /// let err = LocalVolume::new(house, VolumeShape::Box, -1.0, 0.05)?
    ///     .with_blend(BlendMode::Min)
    ///     .unwrap_err();
    /// assert_eq!(err.field, "LocalVolume.density");
    /// # Ok::<(), volfog::limits::InvalidValue>(())
    /// ```
    pub fn with_blend(self, blend: BlendMode) -> Result<Self, InvalidValue> {
        let volume = Self {
            blend: blend as u32,
            ..self
        };
        volume.validate()?;
        Ok(volume)
    }

    /// Checks every member, as [`LocalVolume::new`] does (for volumes built member by
    /// member).
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check_invertible(
            "LocalVolume.local_from_world",
            self.local_from_world,
            0.0,
            "a finite, invertible transform",
        )?;
        let blend = BlendMode::from_code(self.blend);
        check(
            blend.is_some(),
            "LocalVolume.blend",
            self.blend,
            "0 (add), 1 (subtract), 2 (multiply), 3 (min), 4 (max) or 5 (overwrite)",
        )?;
        if blend == Some(BlendMode::Add) {
            limits::LOCAL_VOLUME_DENSITY.check("LocalVolume.density", self.density)?;
        } else {
            limits::LOCAL_VOLUME_BLEND_DENSITY.check("LocalVolume.density", self.density)?;
        }
        limits::LOCAL_VOLUME_EDGE.check("LocalVolume.edge", self.edge)?;
        super::check_channels("LocalVolume.emission", self.emission, &limits::EMISSION)?;
        check(
            blend != Some(BlendMode::Multiply) || self.emission == Vec3::ZERO,
            "LocalVolume.emission",
            self.emission,
            "0 for BlendMode::Multiply (the factor scales the medium's own emission)",
        )?;
        check_finite(
            "LocalVolume.texture_offset",
            self.texture_offset,
            "finite values",
        )?;
        check(
            self.textured <= 1,
            "LocalVolume.textured",
            self.textured,
            "0 or 1",
        )?;
        check(
            [
                VolumeShape::Box,
                VolumeShape::Ellipsoid,
                VolumeShape::Cylinder,
                VolumeShape::Cone,
            ]
            .iter()
            .any(|shape| *shape as u32 == self.shape),
            "LocalVolume.shape",
            self.shape,
            "0 (box), 1 (ellipsoid), 3 (cylinder) or 4 (cone)",
        )
    }
}
