//! `FogHull`: camera, depth range and medium of the fog hull passes (Boyd 2001).

use encase::ShaderType;

use crate::limits::{self, InvalidValue, check};

/// A fog hull: camera, depth range and medium (WGSL `volfog::types::FogHull`), the
/// uniform of the `hull_thickness` and `hull_composite` passes. `Default` is a
/// placeholder for layout probes: build one with [`FogHull::new`].
///
/// ```
/// use glam::{Mat4, Vec3};
/// use volfog::cpu::hull::depth_range;
/// use volfog::uniforms::FogHull;
///
/// let proj = glam::camera::rh::proj::directx::perspective(1.0, 4.0 / 3.0, 0.1, 100.0);
/// let eye = Vec3::new(0.0, 1.0, 5.0);
/// let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y);
/// let hull = FogHull::new(proj, view, Vec3::splat(0.8), 0.5).unwrap();
/// assert!((hull.camera_position - eye).length() < 1e-5);
/// assert_eq!(hull.to_bytes().len(), 176);
/// // For an rgba16float target: the depth range of the hull's bounding box.
/// let (reference, quantum) = depth_range(eye, Vec3::splat(-1.0), Vec3::ONE, 4);
/// let hull = hull.with_depth_range(reference, quantum).unwrap();
/// assert_eq!(hull.reference, 4.0);
/// assert!(hull.with_depth_range(-1.0, 0.0).is_err());
/// assert!(hull.with_depth_range(1.0, 0.3).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FogHull {
    /// World -> clip (projection * view).
    pub clip_from_world: glam::Mat4,
    /// Inverse of the projection (clip -> view).
    pub view_from_clip: glam::Mat4,
    /// Camera position in world space (m).
    pub camera_position: glam::Vec3,
    /// Reference distance (m): a lower bound of the distance of every hull point.
    pub reference: f32,
    /// In-scattered colour (linear rgb).
    pub color: glam::Vec3,
    /// Extinction inside the hull (1/m).
    pub density: f32,
    /// Step of the split of each term for rgba16float targets (m, a power of two),
    /// 0 for none.
    pub quantum: f32,
}

impl FogHull {
    /// Checks the values and builds the uniform with reference and quantum 0 (exact
    /// with an rgba32float target; see [`FogHull::with_depth_range`] for
    /// rgba16float). `view_from_world` must be rigid (rotation and translation).
    pub fn new(
        clip_from_view: glam::Mat4,
        view_from_world: glam::Mat4,
        color: glam::Vec3,
        density: f32,
    ) -> Result<Self, InvalidValue> {
        check(
            clip_from_view.is_finite() && clip_from_view.determinant().abs() > 0.0,
            "FogHull.view_from_clip",
            clip_from_view,
            "the inverse of a finite, invertible perspective projection",
        )?;
        let rotation = glam::Mat3::from_mat4(view_from_world);
        let rigid = view_from_world.is_finite()
            && (rotation * rotation.transpose()).abs_diff_eq(glam::Mat3::IDENTITY, 1e-4)
            && (rotation.determinant() - 1.0).abs() < 1e-4
            && view_from_world.row(3).abs_diff_eq(glam::Vec4::W, 0.0);
        check(
            rigid,
            "FogHull.clip_from_world",
            view_from_world,
            "projection * a rigid view_from_world (rotation and translation only)",
        )?;
        check(
            color.is_finite() && color.cmpge(glam::Vec3::ZERO).all(),
            "FogHull.color",
            color,
            "finite linear rgb >= 0",
        )?;
        limits::HULL_DENSITY.check("FogHull.density", density)?;
        Ok(Self {
            clip_from_world: clip_from_view * view_from_world,
            view_from_clip: clip_from_view.inverse(),
            camera_position: view_from_world.inverse().w_axis.truncate(),
            reference: 0.0,
            color,
            density,
            quantum: 0.0,
        })
    }

    /// The same hull with another depth range, as `volfog::cpu::hull::depth_range`
    /// computes it from the hull's bounding box: `reference` (m, `0..=1e9`) a lower
    /// bound of the distance from the camera of every point of the hull (0 is always
    /// valid), `quantum` (m) 0 or a power of two in `2^-20..=2^20`.
    pub fn with_depth_range(self, reference: f32, quantum: f32) -> Result<Self, InvalidValue> {
        check(
            limits::HULL_REFERENCE.contains(reference),
            "FogHull.reference",
            reference,
            format!(
                "{}, at most the distance of the nearest hull point",
                limits::HULL_REFERENCE.describe()
            ),
        )?;
        let power_of_two = quantum.is_finite()
            && (2f32.powi(-20)..=2f32.powi(20)).contains(&quantum)
            && quantum.log2().fract() == 0.0;
        check(
            quantum == 0.0 || power_of_two,
            "FogHull.quantum",
            quantum,
            "0 or a power of two in 2^-20..=2^20 m",
        )?;
        Ok(Self {
            reference,
            quantum,
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        super::to_uniform_bytes(self)
    }
}
