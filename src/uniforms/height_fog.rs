//! `HeightFog`: the closed-form global height fog of `volfog::height_fog`, also the
//! analytic tail beyond a froxel volume's far plane.

use encase::ShaderType;
use glam::{Mat4, Vec3};

use super::{FogMedium, check_channels, check_unit};
use crate::limits::{self, InvalidValue};

/// Closed-form global height fog (WGSL `volfog::types::HeightFog`, used by
/// `volfog::height_fog`): extinction `density * exp(-falloff * (dot(p, up) - base_height))`
/// lit by `color` plus an optional sun lobe. `Default` is a placeholder for layout
/// probes; build one with [`HeightFog::new`] (and [`HeightFog::with_sun`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HeightFog {
    /// In-scattered radiance (linear rgb), [0, 1e9].
    pub color: Vec3,
    /// Extinction on the reference plane (1/m), [0, 1e3].
    pub density: f32,
    /// Unit axis the density falls along.
    pub up: Vec3,
    /// Falloff along `up` (1/m), [-1e3, 1e3].
    pub falloff: f32,
    /// Unit direction from the scene towards the sun.
    pub sun_direction: Vec3,
    /// Height (m along `up`) of the reference plane, |h| <= 1e9.
    pub base_height: f32,
    /// Sun light scattered by the fog (linear rgb, radiance * sr), [0, 1e9].
    pub sun_color: Vec3,
    /// HG mean cosine of the sun lobe, [-0.999, 0.999].
    pub sun_g: f32,
    /// Height (m along `up`) where the fog ends: no medium above it, and the sun's
    /// light enters the fog there. [`limits::NO_TOP`] (the default) for fog without a
    /// top; |h| <= 1e9.
    pub top_height: f32,
    /// 1: the sun lobe is attenuated by the fog between each point and the sun (the
    /// closed form of `volfog::height_fog::height_fog_lit_integral`); 0 (the default of
    /// [`HeightFog::new`]): the sun reaches every point unattenuated. `VolumetricFog`
    /// sets its tail's from [`FogConfig::light_transmittance`](crate::pipeline::FogConfig::light_transmittance).
    pub sun_transmittance: u32,
}

impl HeightFog {
    /// Height fog without a sun lobe. `up` is normalised (it must have unit length
    /// within 1e-3).
    pub fn new(
        color: Vec3,
        density: f32,
        up: Vec3,
        falloff: f32,
        base_height: f32,
    ) -> Result<Self, InvalidValue> {
        check_channels("HeightFog.color", color, &limits::FOG_RADIANCE)?;
        limits::FOG_DENSITY.check("HeightFog.density", density)?;
        check_unit("HeightFog.up", up)?;
        limits::FOG_FALLOFF.check("HeightFog.falloff", falloff)?;
        limits::FOG_POSITION.check("HeightFog.base_height", base_height)?;
        let up = up.normalize();
        Ok(Self {
            color,
            density,
            up,
            falloff,
            sun_direction: up,
            base_height,
            sun_color: Vec3::ZERO,
            sun_g: 0.0,
            top_height: limits::NO_TOP,
            sun_transmittance: 0,
        })
    }

    /// Checks every value as [`HeightFog::new`] and [`HeightFog::with_sun`] do.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        Self::new(
            self.color,
            self.density,
            self.up,
            self.falloff,
            self.base_height,
        )?
        .with_sun(self.sun_direction, self.sun_color, self.sun_g)?
        .with_top(self.top_height)?;
        limits::Range::new(0, 1, "(0 off, 1 on)")
            .check("HeightFog.sun_transmittance", self.sun_transmittance)
    }

    /// No fog: density 0 (the apply tail is then empty).
    pub fn none() -> Self {
        Self {
            color: Vec3::ZERO,
            density: 0.0,
            up: Vec3::Y,
            falloff: 0.0,
            sun_direction: Vec3::Y,
            base_height: 0.0,
            sun_color: Vec3::ZERO,
            sun_g: 0.0,
            top_height: limits::NO_TOP,
            sun_transmittance: 0,
        }
    }

    /// The same fog expressed in the view space of `view_from_world` (a rigid
    /// transform), as the apply tail expects: the up axis and sun direction rotated,
    /// the base height measured from the camera.
    pub fn to_view_space(&self, view_from_world: Mat4) -> Self {
        let camera = view_from_world.inverse().w_axis.truncate();
        Self {
            up: view_from_world
                .transform_vector3(self.up)
                .normalize_or(Vec3::Y),
            sun_direction: view_from_world
                .transform_vector3(self.sun_direction)
                .normalize_or(Vec3::Y),
            base_height: self.base_height - camera.dot(self.up),
            // No top stays no top; a top is clamped to the range a HeightFog holds.
            top_height: if self.top_height >= limits::NO_TOP {
                limits::NO_TOP
            } else {
                (self.top_height - camera.dot(self.up)).clamp(-limits::NO_TOP, limits::NO_TOP)
            },
            ..*self
        }
    }

    /// The height fog matching a froxel medium's height profile (noise and local
    /// volumes aside), lit by a constant radiance `color` (the in-scattered light per
    /// unit extinction, `albedo * L_in`): use it as the apply tail so the fog continues
    /// beyond the volume's far plane with the same density. The medium's emission, whose
    /// shape is that of its extinction, adds `emission / density` to the colour.
    pub fn from_medium(medium: &FogMedium, color: Vec3) -> Self {
        let glow = if medium.density > 0.0 {
            medium.emission / medium.density
        } else {
            Vec3::ZERO
        };
        Self {
            color: (color + glow).min(Vec3::splat(limits::MAX_FOG_RADIANCE)),
            density: medium.density,
            up: medium.up,
            falloff: medium.height_falloff,
            base_height: medium.base_height,
            top_height: medium.top_height,
            ..Self::none()
        }
    }

    /// Ends the fog at `top_height` (m along `up`): no medium above it, and the sun's
    /// light enters the fog there. `|top_height| <= 1e9`.
    pub fn with_top(self, top_height: f32) -> Result<Self, InvalidValue> {
        limits::FOG_POSITION.check("HeightFog.top_height", top_height)?;
        Ok(Self { top_height, ..self })
    }

    /// Attenuates (`true`) or not the sun lobe by the fog between each point and the
    /// sun (see [`HeightFog::sun_transmittance`]).
    pub fn with_sun_transmittance(self, on: bool) -> Self {
        Self {
            sun_transmittance: u32::from(on),
            ..self
        }
    }

    /// Adds a Henyey-Greenstein sun lobe: `sun_color * HG(dot(view_dir, direction), g)`
    /// is added to the in-scattered radiance. `direction` points towards the sun.
    pub fn with_sun(self, direction: Vec3, sun_color: Vec3, g: f32) -> Result<Self, InvalidValue> {
        check_unit("HeightFog.sun_direction", direction)?;
        check_channels("HeightFog.sun_color", sun_color, &limits::FOG_RADIANCE)?;
        limits::FOG_SUN_G.check("HeightFog.sun_g", g)?;
        Ok(Self {
            sun_direction: direction.normalize(),
            sun_color,
            sun_g: g,
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
