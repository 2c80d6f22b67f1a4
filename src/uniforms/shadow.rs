//! `ShadowCascades`: the sun's cascaded shadow maps as the ESM passes and the
//! injection read them; `ShadowTaps`: where the compare filter tests the lights'
//! visibility within a froxel.

use encase::ShaderType;
use glam::{Mat4, Vec3, Vec4};

use crate::limits::{self, InvalidValue, Range, check};

/// Cascaded shadow maps of the directional light (WGSL `volfog::types::ShadowCascades`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShadowCascades {
    /// World -> light clip space per cascade.
    pub light_from_world: [Mat4; limits::MAX_CASCADES],
    /// Far view depth of each cascade (m).
    pub splits: Vec4,
    /// Cascades in use, 0..=4.
    pub count: u32,
    /// ESM exponent, see [`limits::ESM_EXPONENT`].
    pub exponent: f32,
}

impl ShadowCascades {
    /// The exponent range for linear or log-space (`VOLFOG_ESM_LOG_SPACE`) filtering.
    pub fn exponent_range(log_space: bool) -> Range<f32> {
        if log_space {
            limits::ESM_EXPONENT_LOG_SPACE
        } else {
            limits::ESM_EXPONENT
        }
    }

    /// Checks the values; `log_space` tells whether the ESM is filtered in log space
    /// (`VOLFOG_ESM_LOG_SPACE`), which lifts the exponent limit of 88.
    pub fn validate(&self, log_space: bool) -> Result<(), InvalidValue> {
        Range::new(0, limits::MAX_CASCADES as u32, "cascades")
            .check("ShadowCascades.count", self.count)?;
        let n = self.count as usize;
        check(
            self.light_from_world[..n]
                .iter()
                .all(|m| m.is_finite() && m.determinant().abs() > 0.0),
            "ShadowCascades.light_from_world",
            &self.light_from_world[..n],
            "finite, invertible matrices",
        )?;
        let splits = self.splits.to_array();
        check(
            splits[..n].iter().all(|s| s.is_finite() && *s > 0.0)
                && splits[..n].windows(2).all(|w| w[0] < w[1]),
            "ShadowCascades.splits",
            self.splits,
            "increasing finite depths > 0 m",
        )?;
        if self.count == 0 {
            return Ok(());
        }
        Self::exponent_range(log_space).check("ShadowCascades.exponent", self.exponent)
    }
}

/// Where the fog's compare filter tests the lights' visibility within a froxel this
/// frame (WGSL `volfog::types::ShadowTaps`, `VOLFOG_INJECT_SHADOW_COMPARE`):
/// [`VolumetricFog`](crate::pipeline::VolumetricFog) builds it each frame with
/// [`crate::cpu::shadow::shadow_taps`].
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShadowTaps {
    /// Offsets from the froxel's centre in froxel units, xyz in [-0.5, 0.5) (w unused);
    /// tap 0 is the froxel's own sample (`FogFrame::jitter`).
    pub offsets: [Vec4; limits::MAX_SHADOW_TAPS as usize],
    /// The world-space view ray per metre of view depth at the screen's centre
    /// (`ndc` 0, 0): a tap at `ndc` lies at the camera plus `(ray_origin + ray_x ndc.x
    /// + ray_y ndc.y)` times its view depth.
    pub ray_origin: Vec3,
    /// Taps of a froxel, 1..=16: the configuration's taps ([`limits::SHADOW_TAPS`])
    /// with temporal reprojection, `fresh` without it.
    pub count: u32,
    /// The ray's change per unit of `ndc.x`.
    pub ray_x: Vec3,
    /// Taps of a froxel whose history the fused temporal blend does not find (the
    /// first frame, disocclusions), `count..=16`.
    pub fresh: u32,
    /// The ray's change per unit of `ndc.y`.
    pub ray_y: Vec3,
    /// 1: the sun's shadow map holds reversed depth.
    pub sun_reversed_z: u32,
    /// The camera's depth terms (view depth of a scene-depth value d:
    /// `-(x d + y) / (z d + w)`).
    pub camera_depth_terms: Vec4,
    /// 1: a scene depth is bound (depth culling), and each froxel's taps are moved into
    /// the part of it in front of the surface that depth holds
    /// (`cpu::shadow::shadow_tap_visible_depth`); 0: the taps stay where they are.
    pub use_scene_depth: u32,
}

impl Default for ShadowTaps {
    /// One tap at the froxel's centre, standard depth.
    fn default() -> Self {
        Self {
            offsets: [Vec4::ZERO; limits::MAX_SHADOW_TAPS as usize],
            ray_origin: Vec3::NEG_Z,
            count: 1,
            ray_x: Vec3::X,
            fresh: 1,
            ray_y: Vec3::Y,
            sun_reversed_z: 0,
            // Standard depth from 1 m to 2 m.
            camera_depth_terms: Vec4::new(0.0, -2.0, -1.0, 2.0),
            use_scene_depth: 0,
        }
    }
}

impl ShadowTaps {
    /// Checks the values: 1 <= count <= fresh <= 16, offsets within the froxel, finite
    /// rays.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check(
            self.ray_origin.is_finite() && self.ray_x.is_finite() && self.ray_y.is_finite(),
            "ShadowTaps.ray_origin",
            (self.ray_origin, self.ray_x, self.ray_y),
            "finite rays",
        )?;
        Range::new(1, limits::MAX_SHADOW_TAPS, "taps").check("ShadowTaps.count", self.count)?;
        Range::new(self.count, limits::MAX_SHADOW_TAPS, "taps")
            .check("ShadowTaps.fresh", self.fresh)?;
        check(
            self.offsets[..self.fresh as usize].iter().all(|o| {
                o.truncate().cmpge(Vec3::splat(-0.5)).all()
                    && o.truncate().cmplt(Vec3::splat(0.5)).all()
            }),
            "ShadowTaps.offsets",
            &self.offsets[..self.fresh as usize],
            "offsets in [-0.5, 0.5) froxels",
        )
    }
}
