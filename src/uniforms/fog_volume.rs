//! `FogVolume`: an analytic box, ellipsoid, plane, cylinder or cone of fog
//! (`volfog::fog_volume`).

use encase::ShaderType;
use glam::{Mat4, Vec3};

use super::{VolumeShape, check_channels, check_unit};
use crate::limits::{self, InvalidValue, check};

/// An analytic fog volume (WGSL `volfog::types::FogVolume`, used by
/// `volfog::fog_volume`): a box, ellipsoid, cylinder, cone or plane volume ray traced
/// per pixel, filled with
/// `density * exp(-falloff * (dot(p - center, gradient) - offset))`. `Default` is a
/// placeholder for layout probes; build one with [`FogVolume::new`].
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogVolume {
    /// World -> local transform (affine); the shape is the unit [`VolumeShape`] there.
    pub local_from_world: Mat4,
    /// In-scattered radiance (linear rgb), [0, 1e9].
    pub color: Vec3,
    /// Extinction on the gradient's reference plane (1/m), [0, 1e3].
    pub density: f32,
    /// Unit world direction the density falls along.
    pub gradient: Vec3,
    /// Falloff along `gradient` (1/m), [-1e3, 1e3]; 0 is uniform.
    pub falloff: f32,
    /// World position of the local origin (m).
    pub center: Vec3,
    /// Offset (m) of the reference plane from `center` along `gradient`.
    pub offset: f32,
    /// 0 box, 1 ellipsoid, 3 cylinder, 4 cone ([`VolumeShape`]), 2 plane
    /// ([`FogVolume::plane`]).
    pub shape: u32,
}

impl FogVolume {
    /// A volume of uniform fog covering `world_from_local` applied to the unit shape
    /// (an affine transform: the unit box, sphere, cylinder or cone become one of any
    /// size, orientation and position).
    pub fn new(
        world_from_local: Mat4,
        shape: VolumeShape,
        color: Vec3,
        density: f32,
    ) -> Result<Self, InvalidValue> {
        let affine = world_from_local.row(3) == glam::Vec4::W;
        check(
            world_from_local.is_finite() && affine && world_from_local.determinant() != 0.0,
            "FogVolume.world_from_local",
            world_from_local,
            "a finite, invertible affine transform (last row 0, 0, 0, 1)",
        )?;
        let local_from_world = Mat4::from(glam::Affine3A::from_mat4(world_from_local).inverse());
        check(
            local_from_world.is_finite()
                && glam::Mat3::from_mat4(local_from_world)
                    .to_cols_array()
                    .iter()
                    .all(|m| m.abs() <= limits::MAX_FOG_VOLUME_LOCAL_SCALE),
            "FogVolume.world_from_local",
            world_from_local,
            "an inverse whose linear part has entries within +-1e6 (volumes larger than \
             about 1e-6 m)",
        )?;
        let center = world_from_local.w_axis.truncate();
        check(
            center.abs().max_element() <= limits::FOG_POSITION_LIMIT,
            "FogVolume.center",
            center,
            "a position within +-1e9 m",
        )?;
        check_channels("FogVolume.color", color, &limits::FOG_RADIANCE)?;
        limits::FOG_DENSITY.check("FogVolume.density", density)?;
        Ok(Self {
            local_from_world,
            color,
            density,
            gradient: Vec3::Y,
            falloff: 0.0,
            center,
            offset: 0.0,
            shape: shape as u32,
        })
    }

    /// A plane volume: fog below the plane through `point` with unit `normal` (pointing
    /// out of the fog), unbounded along the plane and downwards (Wenzel 2007's fog
    /// volume type for rivers and water areas). The camera may be above or below it.
    ///
    /// ```
    /// use glam::Vec3;
    /// use volfog::cpu::fog_volume::fog_volume;
    /// use volfog::uniforms::FogVolume;
    ///
    /// let river = FogVolume::plane(Vec3::ZERO, Vec3::Y, Vec3::new(0.1, 0.3, 0.3), 0.5).unwrap();
    /// // From 1 m above the surface straight down to the bed 2 m below it: 2 m of fog.
    /// let fog = fog_volume(&river, Vec3::Y, Vec3::new(0.0, -2.0, 0.0));
    /// assert!((fog.w - (-1.0f32).exp()).abs() < 1e-6);
    /// ```
    pub fn plane(
        point: Vec3,
        normal: Vec3,
        color: Vec3,
        density: f32,
    ) -> Result<Self, InvalidValue> {
        check_unit("FogVolume.normal", normal)?;
        check(
            point.is_finite() && point.abs().max_element() <= limits::FOG_POSITION_LIMIT,
            "FogVolume.center",
            point,
            "a position within +-1e9 m",
        )?;
        let normal = normal.normalize();
        // Local +Y is the normal; the other two axes complete a right-handed frame.
        let rotation = glam::Quat::from_rotation_arc(Vec3::Y, normal);
        let world_from_local = Mat4::from_rotation_translation(rotation, point);
        Self::new(world_from_local, VolumeShape::Plane, color, density)
    }

    /// Makes the density fall exponentially along the unit world direction `gradient`
    /// with `falloff` (1/m); it equals `density` on the plane `offset` metres from the
    /// centre along `gradient`.
    pub fn with_gradient(
        self,
        gradient: Vec3,
        falloff: f32,
        offset: f32,
    ) -> Result<Self, InvalidValue> {
        check_unit("FogVolume.gradient", gradient)?;
        limits::FOG_FALLOFF.check("FogVolume.falloff", falloff)?;
        limits::FOG_POSITION.check("FogVolume.offset", offset)?;
        Ok(Self {
            gradient: gradient.normalize(),
            falloff,
            offset,
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
