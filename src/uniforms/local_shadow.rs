//! `LightProjection` (a point or spot light's shadow and cookie) and
//! `LocalShadowSource` (one map of the local-light ESM atlas to fill), and the shadow
//! cameras they are built from (`volfog::local_shadow`).

use encase::ShaderType;
use glam::{Mat4, Vec3, Vec4};

use super::FogLight;
use crate::limits::{self, InvalidValue, check};

/// No projection ([`FogLight::projection`]), no shadow ([`LightProjection::layer`]) or
/// no cookie ([`LightProjection::cookie`]) (WGSL `LOCAL_SHADOW_NONE`).
pub const LOCAL_SHADOW_NONE: u32 = u32::MAX;
/// [`LightProjection::kind`] of a spot light (WGSL `LOCAL_SHADOW_SPOT`).
pub const LOCAL_SHADOW_SPOT: u32 = 0;
/// [`LightProjection::kind`] of a point light (WGSL `LOCAL_SHADOW_POINT`).
pub const LOCAL_SHADOW_POINT: u32 = 1;

/// The projection of a point or spot light (WGSL `volfog::types::LightProjection`):
/// its exponential shadow map in the local-light ESM atlas and a spot light's cookie.
/// [`VolumetricFog::prepare`](crate::pipeline::VolumetricFog::prepare) builds these from
/// the frame's [`ShadowedLight`](crate::pipeline::ShadowedLight)s.
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LightProjection {
    /// World -> light space: a spot light's shadow camera clip space (projection times
    /// view), a point light's cube-map space (rigid, the light at the origin).
    pub light_from_world: Mat4,
    /// Distance (m) linear depths are divided by, > 0.
    pub depth_range: f32,
    /// ESM exponent for linear depths in [0, 1].
    pub exponent: f32,
    /// Receivers are tested this far (m) nearer the light, >= 0.
    pub bias: f32,
    /// [`LOCAL_SHADOW_SPOT`] or [`LOCAL_SHADOW_POINT`].
    pub kind: u32,
    /// First atlas layer (the ESM filter) or first layer of the light's own depth map
    /// in the spot or point shadow maps (the compare filter), or [`LOCAL_SHADOW_NONE`]
    /// (unshadowed).
    pub layer: u32,
    /// Cookie array layer (spot lights), or [`LOCAL_SHADOW_NONE`].
    pub cookie: u32,
    /// View depth of a depth value d of the light's shadow maps: `-(x d + y) / (z d +
    /// w)` ([`LightCamera::depth_terms`]); the compare filter maps receivers into the
    /// maps' depth with it.
    pub depth_terms: Vec4,
}

/// One map of the local-light ESM atlas to fill from a shadow depth map (WGSL
/// `volfog::types::LocalShadowSource`, the `local_shadow_downsample` pass).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LocalShadowSource {
    /// View depth of a depth value d: `-(x d + y) / (z d + w)`.
    pub depth_terms: Vec4,
    /// Distance (m) the linear depth is divided by, > 0.
    pub depth_range: f32,
    /// ESM exponent.
    pub exponent: f32,
    /// Layer of the source depth array.
    pub source_layer: u32,
    /// Atlas layer to write.
    pub atlas_layer: u32,
    /// 0: the spot lights' shadow maps; 1: the point lights' cube maps.
    pub source: u32,
}

/// The cube map faces' axes in volfog's order (+X, -X, +Y, -Y, +Z, -Z): for each face
/// its right, up and forward directions, as the Vulkan / WebGPU cube face table lays
/// the faces out (texel row 0 at the top, the face seen from the cube's centre).
pub const CUBE_FACE_AXES: [[Vec3; 3]; 6] = [
    [Vec3::NEG_Z, Vec3::Y, Vec3::X],
    [Vec3::Z, Vec3::Y, Vec3::NEG_X],
    [Vec3::X, Vec3::NEG_Z, Vec3::Y],
    [Vec3::X, Vec3::Z, Vec3::NEG_Y],
    [Vec3::X, Vec3::Y, Vec3::Z],
    [Vec3::NEG_X, Vec3::Y, Vec3::NEG_Z],
];

/// The shadow camera of a point or spot light: what its depth map was rendered with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightCamera {
    /// A spot light's perspective shadow camera.
    Spot {
        /// World -> view (rigid, the camera looks along its -Z or +Z).
        view_from_world: Mat4,
        /// The perspective projection (standard, reversed or infinite depth).
        clip_from_view: Mat4,
    },
    /// A point light's cube shadow map.
    Point {
        /// World -> cube-map space (rigid, the light at the origin, the axes those the
        /// faces were rendered along; [`LightCamera::cube_face_view`] gives each face's
        /// view in this space).
        cube_from_world: Mat4,
        /// The projection of every face (90 degrees, square; standard, reversed or
        /// infinite depth).
        clip_from_view: Mat4,
    },
}

impl LightCamera {
    /// The shadow camera volfog would use for a spot light: at the light, looking
    /// along its axis, square, wide enough for the outer cone, standard depth from
    /// `near` to the light's range (right-handed).
    pub fn spot(light: &FogLight, near: f32) -> Result<Self, InvalidValue> {
        light.validate()?;
        check(
            light.cos_outer > -1.0 && light.cos_outer < 1.0,
            "FogLight.cos_outer",
            light.cos_outer,
            "a spot light's cone, -1 < cos_outer < 1 (a point light has a cube camera)",
        )?;
        check_near(near, light.range)?;
        let up = if light.direction.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view_from_world =
            glam::camera::rh::view::look_to_mat4(light.position, light.direction, up);
        // Half-angle of the outer cone, widened a little so the cone's edge is inside.
        let fov = (2.0 * light.cos_outer.clamp(-1.0, 1.0).acos() * 1.05).min(3.0);
        let clip_from_view =
            glam::camera::rh::proj::directx::perspective(fov, 1.0, near, light.range);
        Ok(Self::Spot {
            view_from_world,
            clip_from_view,
        })
    }

    /// The cube camera volfog would use for a point light: its faces along the world
    /// axes ([`CUBE_FACE_AXES`]), 90 degrees, standard depth from `near` to the light's
    /// range.
    pub fn point(light: &FogLight, near: f32) -> Result<Self, InvalidValue> {
        light.validate()?;
        check_near(near, light.range)?;
        Ok(Self::Point {
            cube_from_world: Mat4::from_translation(-light.position),
            clip_from_view: glam::camera::rh::proj::directx::perspective(
                std::f32::consts::FRAC_PI_2,
                1.0,
                near,
                light.range,
            ),
        })
    }

    /// The view (cube space -> face view) of cube face `face` (0..6, +X, -X, +Y, -Y,
    /// +Z, -Z): render face `face` of a point light's shadow map with
    /// `clip_from_view * cube_face_view(face) * cube_from_world`. The faces are
    /// mirror images of a right-handed view (a cube map is left-handed), so draw them
    /// with the opposite front face or without culling.
    pub fn cube_face_view(face: u32) -> Mat4 {
        let [right, up, forward] = CUBE_FACE_AXES[face as usize % 6];
        Mat4::from_cols(
            Vec4::new(right.x, up.x, -forward.x, 0.0),
            Vec4::new(right.y, up.y, -forward.y, 0.0),
            Vec4::new(right.z, up.z, -forward.z, 0.0),
            Vec4::W,
        )
    }

    /// World -> light space ([`LightProjection::light_from_world`]).
    pub fn light_from_world(&self) -> Mat4 {
        match *self {
            Self::Spot {
                view_from_world,
                clip_from_view,
            } => clip_from_view * view_from_world,
            Self::Point {
                cube_from_world, ..
            } => cube_from_world,
        }
    }

    /// [`LOCAL_SHADOW_SPOT`] or [`LOCAL_SHADOW_POINT`].
    pub fn kind(&self) -> u32 {
        match self {
            Self::Spot { .. } => LOCAL_SHADOW_SPOT,
            Self::Point { .. } => LOCAL_SHADOW_POINT,
        }
    }

    /// The projection of the depth maps.
    pub fn clip_from_view(&self) -> Mat4 {
        match *self {
            Self::Spot { clip_from_view, .. } | Self::Point { clip_from_view, .. } => {
                clip_from_view
            }
        }
    }

    /// The depth terms of the projection (see [`LocalShadowSource::depth_terms`]);
    /// checks that the matrices are finite, the view rigid and the projection a
    /// perspective one.
    pub fn depth_terms(&self) -> Result<Vec4, InvalidValue> {
        let (field, view) = match *self {
            Self::Spot {
                view_from_world, ..
            } => ("LightCamera::Spot.view_from_world", view_from_world),
            Self::Point {
                cube_from_world, ..
            } => ("LightCamera::Point.cube_from_world", cube_from_world),
        };
        check(
            view.is_finite()
                && (view.determinant().abs() - 1.0).abs() < 1e-3
                && view.row(3).abs_diff_eq(Vec4::W, 1e-6),
            field,
            view,
            "a finite rigid transform (rotation, reflection and translation)",
        )?;
        let projection = match self {
            Self::Spot { .. } => "LightCamera::Spot.clip_from_view",
            Self::Point { .. } => "LightCamera::Point.clip_from_view",
        };
        super::frustum::depth_terms(projection, self.clip_from_view())
    }
}

fn check_near(near: f32, range: f32) -> Result<(), InvalidValue> {
    check(
        near.is_finite() && near > 0.0 && near < range,
        "LightCamera near",
        near,
        "0 < near < the light's range (m)",
    )
}

impl LightProjection {
    /// A light's projection: the camera its shadow map was rendered with, its atlas
    /// layer (or its map's first layer, for the compare filter) and cookie layer ([`LOCAL_SHADOW_NONE`] for none), the ESM exponent and
    /// the bias (m); the depth range is the light's range.
    pub fn new(
        light: &FogLight,
        camera: &LightCamera,
        layer: u32,
        cookie: u32,
        exponent: f32,
        bias: f32,
    ) -> Result<Self, InvalidValue> {
        let depth_terms = camera.depth_terms()?;
        limits::LOCAL_SHADOW_BIAS.check("ShadowedLight.bias", bias)?;
        Ok(Self {
            light_from_world: camera.light_from_world(),
            depth_range: light.range,
            exponent,
            bias,
            kind: camera.kind(),
            layer,
            cookie,
            depth_terms,
        })
    }
}

impl Default for LightProjection {
    fn default() -> Self {
        Self {
            light_from_world: Mat4::IDENTITY,
            depth_range: 1.0,
            exponent: 1.0,
            bias: 0.0,
            kind: LOCAL_SHADOW_SPOT,
            layer: LOCAL_SHADOW_NONE,
            cookie: LOCAL_SHADOW_NONE,
            // Standard depth from 1 m to 2 m.
            depth_terms: Vec4::new(0.0, -2.0, -1.0, 2.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_face_views_are_rigid_mirrors_looking_along_their_axes() {
        for face in 0..6 {
            let view = LightCamera::cube_face_view(face);
            assert!((view.determinant() + 1.0).abs() < 1e-6, "face {face}");
            let forward = CUBE_FACE_AXES[face as usize][2];
            // The face looks down its view -Z.
            assert!((view.transform_vector3(forward) - Vec3::NEG_Z).length() < 1e-6);
        }
    }

    #[test]
    fn cameras_check_their_inputs() {
        let spot = FogLight::spot(Vec3::ZERO, Vec3::X, Vec3::ONE, 10.0, 0.3, 0.5);
        let point = FogLight::point(Vec3::ZERO, Vec3::ONE, 10.0);
        assert!(LightCamera::spot(&spot, 0.1).is_ok());
        assert_eq!(
            LightCamera::spot(&point, 0.1).unwrap_err().field,
            "FogLight.cos_outer"
        );
        assert_eq!(
            LightCamera::point(&point, 20.0).unwrap_err().field,
            "LightCamera near"
        );
        let camera = LightCamera::Spot {
            view_from_world: Mat4::from_scale(Vec3::splat(2.0)),
            clip_from_view: Mat4::IDENTITY,
        };
        assert_eq!(
            camera.depth_terms().unwrap_err().field,
            "LightCamera::Spot.view_from_world"
        );
        let camera = LightCamera::Point {
            cube_from_world: Mat4::IDENTITY,
            clip_from_view: glam::camera::rh::proj::directx::orthographic(
                -1.0, 1.0, -1.0, 1.0, 0.1, 10.0,
            ),
        };
        assert_eq!(
            camera.depth_terms().unwrap_err().field,
            "LightCamera::Point.clip_from_view"
        );
    }
}
