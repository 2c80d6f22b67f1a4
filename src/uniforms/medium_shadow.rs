//! `MediumShadow`: the placement of the medium-shadow volume (WGSL
//! `volfog::types::MediumShadow`, read by `volfog::medium_shadow` and the
//! `medium_shadow` pass), and [`MediumShadowConfig`], what an application chooses of it.

use encase::ShaderType;
use glam::{Mat4, UVec3, Vec3, Vec4};

use super::check_unit;
use crate::limits::{self, InvalidValue, check};

/// How the medium shadows itself (`FogConfig::medium_shadows`): the size of the
/// sun-aligned volume that tabulates the optical depth of the medium beyond its height
/// profile, the view distance it covers and how far it reaches towards the sun.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MediumShadowConfig {
    /// Texels across the sunlight (x, y) and along it (z), each
    /// [`limits::MEDIUM_SHADOW_AXIS`] (2..=512).
    pub size: UVec3,
    /// View depth (m) up to which the camera's frustum is covered, > 0 (at most the
    /// froxels' far plane is used).
    pub distance: f32,
    /// How far (m) the volume reaches beyond the covered frustum towards the sun, >= 0:
    /// medium farther up the sunlight casts no shadow.
    pub reach: f32,
    /// Midpoint samples of the march towards point, spot and directional lights,
    /// [`limits::MEDIUM_SHADOW_MARCH`] (1..=64).
    pub march_steps: u32,
}

impl Default for MediumShadowConfig {
    /// 64 x 64 x 64 texels over the first 64 m of the view, reaching 32 m further
    /// towards the sun, 8 samples towards local lights.
    fn default() -> Self {
        Self {
            size: UVec3::splat(64),
            distance: 64.0,
            reach: 32.0,
            march_steps: 8,
        }
    }
}

impl MediumShadowConfig {
    /// Checks every field (the error names it).
    pub fn validate(&self) -> Result<(), InvalidValue> {
        for (field, v) in [
            ("MediumShadowConfig.size.x", self.size.x),
            ("MediumShadowConfig.size.y", self.size.y),
            ("MediumShadowConfig.size.z", self.size.z),
        ] {
            limits::MEDIUM_SHADOW_AXIS.check(field, v)?;
        }
        check(
            self.distance.is_finite() && self.distance > 0.0 && self.distance <= 1e6,
            "MediumShadowConfig.distance",
            self.distance,
            "(0, 1e6] m",
        )?;
        check(
            self.reach.is_finite() && (0.0..=1e6).contains(&self.reach),
            "MediumShadowConfig.reach",
            self.reach,
            "[0, 1e6] m",
        )?;
        limits::MEDIUM_SHADOW_MARCH.check("MediumShadowConfig.march_steps", self.march_steps)
    }

    /// Bytes of the volume (rgba16float).
    pub fn memory_bytes(&self) -> u64 {
        self.size.as_u64vec3().element_product() * 8
    }
}

/// Placement of the medium-shadow volume (WGSL `volfog::types::MediumShadow`, 160
/// bytes): a box aligned with the sun, its texel coordinate w running along the
/// sunlight from the face towards the sun.
///
/// ```
/// use volfog::glam::{Mat4, UVec3, Vec3};
/// use volfog::uniforms::{MediumShadow, MediumShadowConfig};
///
/// let proj = volfog::glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.5, 100.0);
/// let config = MediumShadowConfig::default();
/// let sun = Vec3::new(0.3, 0.8, -0.2).normalize();
/// let m = MediumShadow::fit(&config, Mat4::IDENTITY, proj.inverse(), 100.0, sun).unwrap();
/// // The camera is inside the volume; the sun side is w = 0.
/// let uvw = m.coord(Vec3::ZERO);
/// assert!(uvw.cmpge(Vec3::ZERO).all() && uvw.cmple(Vec3::ONE).all());
/// assert!(m.coord(sun * 10.0).z < uvw.z);
/// assert!(MediumShadow::fit(&config, Mat4::IDENTITY, proj.inverse(), 100.0, Vec3::ZERO).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MediumShadow {
    /// World -> volume coordinate uvw in [0, 1]^3 (affine).
    pub volume_from_world: Mat4,
    /// Volume coordinate -> world.
    pub world_from_volume: Mat4,
    /// Texels per axis.
    pub size: UVec3,
    /// Length (m) of one texel along the sunlight.
    pub step: f32,
    /// Midpoint samples of the march towards a point, spot or directional light.
    pub march_steps: u32,
    /// Length (m) marched towards a directional light.
    pub march_length: f32,
}

impl MediumShadow {
    /// The volume for a camera (`world_from_view`, `view_from_clip` of a perspective
    /// projection, `far` the froxels' far plane in m) and the sun (`towards_sun`, unit):
    /// it holds the ball around the view frustum up to `min(config.distance, far)`, and
    /// reaches `config.reach` further towards the sun. Its texel size across the
    /// sunlight depends only on that ball's radius and its origin is snapped to whole
    /// texels, so the volume's texels stay put in the world while the camera turns or
    /// moves less than a texel (no shimmer of the tabulated shadows).
    pub fn fit(
        config: &MediumShadowConfig,
        world_from_view: Mat4,
        view_from_clip: Mat4,
        far: f32,
        towards_sun: Vec3,
    ) -> Result<Self, InvalidValue> {
        config.validate()?;
        check_unit("FogLighting.sun.direction", towards_sun)?;
        check(
            far.is_finite() && far > 0.0,
            "Froxels.far",
            far,
            "a positive depth (m)",
        )?;
        let depth = config.distance.min(far);
        // The frustum's corners at the camera and at `depth`: each corner ray scaled to
        // view depth `depth` (the projection's near plane is left out: the ball around
        // the apex and the far corners holds the whole frustum up to `depth`).
        let mut corners = vec![world_from_view.transform_point3(Vec3::ZERO)];
        for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let p = view_from_clip * Vec4::new(x, y, 1.0, 1.0);
            let v = p.truncate() / p.w;
            check(
                v.is_finite() && v.z < 0.0,
                "MediumShadow.view_from_clip",
                v,
                "a perspective projection looking down -z",
            )?;
            corners.push(world_from_view.transform_point3(v * (depth / -v.z)));
        }
        let center = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
        let radius = corners
            .iter()
            .map(|c| c.distance(center))
            .fold(0.0f32, f32::max)
            .max(1e-3);
        // Light space: x, y across the sunlight, z along it (away from the sun).
        let z_axis = -towards_sun;
        let (x_axis, y_axis) = z_axis.any_orthonormal_pair();
        let light_from_world = Mat4::from_cols(
            x_axis.extend(0.0),
            y_axis.extend(0.0),
            z_axis.extend(0.0),
            Vec4::W,
        )
        .transpose();
        let c = light_from_world.transform_point3(center);
        // One texel of each axis is spare, so the box still holds the ball after its
        // lowest corner is snapped down to a whole texel.
        let base = Vec3::new(2.0 * radius, 2.0 * radius, 2.0 * radius + config.reach);
        let texel = base / (config.size.as_vec3() - 1.0);
        let extent = texel * config.size.as_vec3();
        let low = Vec3::new(c.x - radius, c.y - radius, c.z - radius - config.reach);
        let low = (low / texel).floor() * texel;
        let volume_from_light = Mat4::from_scale(1.0 / extent) * Mat4::from_translation(-low);
        let volume_from_world = volume_from_light * light_from_world;
        Ok(Self {
            volume_from_world,
            world_from_volume: volume_from_world.inverse(),
            size: config.size,
            step: texel.z,
            march_steps: config.march_steps,
            march_length: extent.length(),
        })
    }

    /// The volume coordinate uvw of a world position (m).
    pub fn coord(&self, world: Vec3) -> Vec3 {
        self.volume_from_world.transform_point3(world)
    }
}
