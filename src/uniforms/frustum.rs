//! `FrustumRays`: rays through the screen's corners for world positions from depth
//! (`volfog::frustum`).

use encase::ShaderType;
use glam::{Mat4, Vec3, Vec4};

use crate::limits::{InvalidValue, check};

/// Rays through the screen's corners (WGSL `volfog::types::FrustumRays`, used by
/// `volfog::frustum` and the `clouds` and `sky_draw` passes): the world-space vectors
/// from the camera to the points at view depth 1 through the corners uv (0, 0), (1, 0),
/// (0, 1), (1, 1), the camera position and the depth terms of the inverse projection.
///
/// ```
/// use glam::{Mat4, Vec3};
/// use volfog::uniforms::FrustumRays;
///
/// let proj = glam::camera::rh::proj::directx::perspective(1.0, 2.0, 0.1, 100.0);
/// let rays = FrustumRays::new(Mat4::from_translation(Vec3::Y), proj).unwrap();
/// assert_eq!(rays.camera.truncate(), Vec3::Y);
/// // The corner rays reach view depth 1 (the camera looks along -Z).
/// assert!((rays.corners[0].z + 1.0).abs() < 1e-6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FrustumRays {
    /// World vectors to view depth 1 through the corners (xyz; w 0).
    pub corners: [Vec4; 4],
    /// Camera position (xyz); w the view depth of the far plane (at most 1e30):
    /// depth-buffer values at or beyond it are the sky.
    pub camera: Vec4,
    /// View depth from a depth value d: `-(x d + y) / (z d + w)`.
    pub depth_terms: Vec4,
}

/// The depth terms of a perspective projection (standard, reversed or infinite depth,
/// right- or left-handed): the view depth of a depth value d is
/// `-(x d + y) / (z d + w)`, positive in front of the camera (the depth rows of the
/// inverse projection, signed by the side the camera looks to). `field` names the
/// projection in the error.
pub(crate) fn depth_terms(field: &'static str, clip_from_view: Mat4) -> Result<Vec4, InvalidValue> {
    check(
        clip_from_view.is_finite(),
        field,
        clip_from_view,
        "a finite matrix",
    )?;
    let view_from_clip = clip_from_view.inverse();
    let (z, w) = (view_from_clip.row(2), view_from_clip.row(3));
    check(
        view_from_clip.is_finite()
            && z.x.abs() + z.y.abs() + w.x.abs() + w.y.abs()
                <= 1e-6 * (z.abs().max_element() + w.abs().max_element())
            && w.z != 0.0,
        field,
        clip_from_view,
        "an invertible perspective projection whose depth does not depend on x and y",
    )?;
    // Forward is -Z (right-handed) or +Z (left-handed): the sign of the view z of a
    // point inside the clip volume.
    let probe = view_from_clip * Vec4::new(0.0, 0.0, 0.5, 1.0);
    let forward = -(probe.z / probe.w).signum();
    Ok(Vec4::new(z.z * forward, z.w * forward, w.z, w.w))
}

impl FrustumRays {
    /// The rays of a camera with `world_from_view` (rigid) and the perspective
    /// `clip_from_view` (standard, reversed or infinite depth, right- or left-handed).
    pub fn new(world_from_view: Mat4, clip_from_view: Mat4) -> Result<Self, InvalidValue> {
        check(
            world_from_view.is_finite() && clip_from_view.is_finite(),
            "FrustumRays",
            (world_from_view, clip_from_view),
            "finite matrices",
        )?;
        let view_from_clip = clip_from_view.inverse();
        let depth_terms = depth_terms("FrustumRays.clip_from_view", clip_from_view)?;
        let corner = |u: f32, v: f32| {
            let p = view_from_clip * Vec4::new(2.0 * u - 1.0, 1.0 - 2.0 * v, 0.5, 1.0);
            let p = p.truncate() / p.w;
            world_from_view.transform_vector3(p / p.z.abs()).extend(0.0)
        };
        let view_depth = |d: f32| {
            let den = depth_terms.z * d + depth_terms.w;
            if den.abs() < 1e-30 {
                1e30
            } else {
                (-(depth_terms.x * d + depth_terms.y) / den).clamp(0.0, 1e30)
            }
        };
        // The far plane sits at depth 1 (standard) or 0 (reversed): the deeper of the two.
        let far = view_depth(0.0).max(view_depth(1.0));
        Ok(Self {
            corners: [
                corner(0.0, 0.0),
                corner(1.0, 0.0),
                corner(0.0, 1.0),
                corner(1.0, 1.0),
            ],
            camera: world_from_view.w_axis.truncate().extend(far),
            depth_terms,
        })
    }

    /// Checks a `FrustumRays` built by hand: finite corners, camera and depth terms,
    /// and a far plane beyond the camera.
    pub fn validated(self) -> Result<Self, InvalidValue> {
        let finite = self.corners.iter().all(|c| c.is_finite())
            && self.camera.is_finite()
            && self.depth_terms.is_finite();
        check(
            finite,
            "FrustumRays",
            self,
            "finite corners, camera and depth terms",
        )?;
        check(
            self.camera.w > 0.0,
            "FrustumRays.camera.w",
            self.camera.w,
            "the far plane's view depth, above 0",
        )?;
        Ok(self)
    }

    /// The camera position.
    pub fn camera_position(&self) -> Vec3 {
        self.camera.truncate()
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
