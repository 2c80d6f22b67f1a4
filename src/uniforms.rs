//! Rust twins of the WGSL uniform structs (encase `ShaderType` with glam members).
//!
//! Each struct here has the same members, in the same order, as its WGSL twin in
//! `shaders/volfog/types.wgsl`; `tests/layout.rs` compares every member offset and
//! the size with naga's layout of the composed shaders.
//!
//! ```
//! use glam::{Mat4, UVec3};
//! use volfog::uniforms::Froxels;
//!
//! let proj = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 1000.0);
//! let froxels = Froxels::new(proj, UVec3::new(160, 90, 128), 0.5, 128.0, 4.0).unwrap();
//! let bytes = froxels.to_bytes();
//! assert_eq!(bytes.len(), 160);
//! assert!(Froxels::new(proj, UVec3::new(160, 90, 128), 2.0, 1.0, 4.0).is_err());
//! ```

use encase::ShaderType;
use glam::{Mat4, UVec3, Vec3, Vec4};

/// An invalid uniform value: the field, the value and the valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} = {value} is invalid: expected {expected}")]
pub struct InvalidValue {
    /// The field, e.g. `Froxels.near`.
    pub field: &'static str,
    /// The rejected value, printed.
    pub value: String,
    /// The valid range, in words.
    pub expected: &'static str,
}

pub(crate) fn check(
    ok: bool,
    field: &'static str,
    value: impl std::fmt::Debug,
    expected: &'static str,
) -> Result<(), InvalidValue> {
    if ok {
        Ok(())
    } else {
        Err(InvalidValue {
            field,
            value: format!("{value:?}"),
            expected,
        })
    }
}

/// Largest volume size per axis that volfog accepts (wgpu's default 3D texture limit).
pub const MAX_FROXELS_PER_AXIS: u32 = 2048;
/// Largest slice curve: exp(curve) must stay far from f32 overflow.
pub const MAX_SLICE_CURVE: f32 = 30.0;

/// Placement of a camera-aligned froxel volume (WGSL `volfog::types::Froxels`).
/// `Default` is a placeholder for layout probes, not a valid placement: build one
/// with [`Froxels::new`].
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct Froxels {
    /// Projection (view -> clip).
    pub clip_from_view: Mat4,
    /// Its inverse (clip -> view).
    pub view_from_clip: Mat4,
    /// Volume size in froxels.
    pub size: UVec3,
    /// View depth of the first slice's front, metres.
    pub near: f32,
    /// View depth of the last slice's back, metres.
    pub far: f32,
    /// Slice distribution curve (0 = linear, ln(far / near) = exponential).
    pub curve: f32,
}

impl Froxels {
    /// Checks the values and builds the uniform; `view_from_clip` is the inverse
    /// of `clip_from_view`.
    pub fn new(
        clip_from_view: Mat4,
        size: UVec3,
        near: f32,
        far: f32,
        curve: f32,
    ) -> Result<Self, InvalidValue> {
        check(
            clip_from_view.is_finite() && clip_from_view.determinant().abs() > 0.0,
            "Froxels.clip_from_view",
            clip_from_view,
            "a finite, invertible perspective projection",
        )?;
        check(
            size.cmpge(UVec3::ONE).all() && size.cmple(UVec3::splat(MAX_FROXELS_PER_AXIS)).all(),
            "Froxels.size",
            size,
            "1..=2048 froxels per axis",
        )?;
        check(
            near.is_finite() && near > 0.0,
            "Froxels.near",
            near,
            "a finite depth > 0 m",
        )?;
        check(
            far.is_finite() && far > near,
            "Froxels.far",
            far,
            "a finite depth > near",
        )?;
        check(
            (0.0..=MAX_SLICE_CURVE).contains(&curve),
            "Froxels.curve",
            curve,
            "0..=30 (0 linear, ln(far / near) exponential)",
        )?;
        Ok(Self {
            clip_from_view,
            view_from_clip: clip_from_view.inverse(),
            size,
            near,
            far,
            curve,
        })
    }

    /// The uniform buffer bytes (std140-compatible uniform layout).
    pub fn to_bytes(&self) -> Vec<u8> {
        to_uniform_bytes(self)
    }
}

/// Serialises any uniform struct with encase's uniform-buffer layout.
pub fn to_uniform_bytes<T: ShaderType + encase::internal::WriteInto>(value: &T) -> Vec<u8> {
    let mut buffer = encase::UniformBuffer::new(Vec::new());
    buffer
        .write(value)
        .expect("writing into a growable Vec cannot fail");
    buffer.into_inner()
}

/// Serialises a runtime-sized array with encase's storage-buffer layout (at least one
/// element is written so the buffer is never empty).
pub fn to_storage_bytes<T>(values: &[T]) -> Vec<u8>
where
    T: ShaderType + encase::internal::WriteInto + encase::ShaderSize + Default + Clone,
{
    let items: Vec<T> = if values.is_empty() {
        vec![T::default()]
    } else {
        values.to_vec()
    };
    let mut buffer = encase::StorageBuffer::new(Vec::new());
    buffer
        .write(&items)
        .expect("writing into a growable Vec cannot fail");
    buffer.into_inner()
}

fn finite3(v: Vec3) -> bool {
    v.is_finite()
}

fn unit3(v: Vec3) -> bool {
    v.is_finite() && (v.length() - 1.0).abs() < 1e-3
}

/// Per-frame camera and temporal state (WGSL `volfog::types::FogFrame`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct FogFrame {
    /// View -> world transform of the current camera.
    pub world_from_view: Mat4,
    /// World -> clip of the previous frame.
    pub prev_clip_from_world: Mat4,
    /// Camera position in world space.
    pub camera_position: Vec3,
    /// Seconds since start.
    pub time: f32,
    /// Sample offset inside each froxel (froxel units, [-0.5, 0.5]^3).
    pub jitter: Vec3,
    /// History weight in [0, 1).
    pub history_weight: f32,
    /// 1 when the history holds a previous frame.
    pub history_valid: u32,
}

/// The participating medium (WGSL `volfog::types::FogMedium`).
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
pub struct FogMedium {
    /// Single-scattering albedo per channel, [0, 1].
    pub albedo: Vec3,
    /// Extinction at `base_height` (1/m), >= 0.
    pub density: f32,
    /// Unit up axis of the height gradient.
    pub up: Vec3,
    /// Height falloff (1/m), >= 0.
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
    /// Number of local volumes in use.
    pub local_volume_count: u32,
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
        }
    }
}

impl FogMedium {
    /// Checks every value that could produce NaN, Inf or nonsense on the GPU.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check(
            self.albedo.is_finite()
                && self.albedo.cmpge(Vec3::ZERO).all()
                && self.albedo.cmple(Vec3::ONE).all(),
            "FogMedium.albedo",
            self.albedo,
            "each channel in [0, 1]",
        )?;
        check(
            self.density.is_finite() && self.density >= 0.0 && self.density <= 1.0e3,
            "FogMedium.density",
            self.density,
            "0..=1000 1/m",
        )?;
        check(unit3(self.up), "FogMedium.up", self.up, "a unit vector")?;
        check(
            self.height_falloff.is_finite() && (0.0..=100.0).contains(&self.height_falloff),
            "FogMedium.height_falloff",
            self.height_falloff,
            "0..=100 1/m",
        )?;
        check(
            finite3(self.wind),
            "FogMedium.wind",
            self.wind,
            "a finite velocity",
        )?;
        check(
            self.base_height.is_finite(),
            "FogMedium.base_height",
            self.base_height,
            "a finite height",
        )?;
        check(
            finite3(self.texture_scale) && finite3(self.texture_offset),
            "FogMedium.texture_scale/texture_offset",
            (self.texture_scale, self.texture_offset),
            "finite values",
        )?;
        check(
            (0.0..=1.0).contains(&self.noise_strength),
            "FogMedium.noise_strength",
            self.noise_strength,
            "0..=1",
        )?;
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
        Ok(())
    }
}

/// Shape of a [`LocalVolume`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum VolumeShape {
    /// The box [-1, 1]^3 in local space.
    Box = 0,
    /// The unit sphere in local space.
    Ellipsoid = 1,
}

/// A local fog volume (WGSL `volfog::types::LocalVolume`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct LocalVolume {
    /// World -> unit shape space.
    pub local_from_world: Mat4,
    /// Extinction added inside (1/m); negative clears fog.
    pub density: f32,
    /// Edge falloff width, fraction of the unit extent, (0, 1].
    pub edge: f32,
    /// 0 box, 1 ellipsoid.
    pub shape: u32,
}

impl LocalVolume {
    /// A volume covering `world_from_local` applied to the unit shape.
    pub fn new(
        world_from_local: Mat4,
        shape: VolumeShape,
        density: f32,
        edge: f32,
    ) -> Result<Self, InvalidValue> {
        check(
            world_from_local.is_finite() && world_from_local.determinant().abs() > 1e-12,
            "LocalVolume.world_from_local",
            world_from_local,
            "a finite, invertible transform",
        )?;
        check(
            density.is_finite() && density.abs() <= 1.0e3,
            "LocalVolume.density",
            density,
            "-1000..=1000 1/m",
        )?;
        check(
            edge > 0.0 && edge <= 1.0,
            "LocalVolume.edge",
            edge,
            "0 < edge <= 1",
        )?;
        Ok(Self {
            local_from_world: world_from_local.inverse(),
            density,
            edge,
            shape: shape as u32,
        })
    }
}

/// The main directional light (WGSL `volfog::types::DirectionalLight`).
#[derive(Debug, Clone, Copy, PartialEq, ShaderType)]
pub struct DirectionalLight {
    /// Unit direction from the scene towards the light.
    pub direction: Vec3,
    /// Contribution to the fog, >= 0.
    pub fog_intensity: f32,
    /// Illuminance colour (linear rgb).
    pub color: Vec3,
    /// Two-colour phase: tint looking towards the light.
    pub toward_tint: Vec3,
    /// Two-colour phase: tint looking away from the light.
    pub away_tint: Vec3,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        Self {
            direction: Vec3::new(0.3, 0.6, 0.2).normalize(),
            fog_intensity: 1.0,
            color: Vec3::new(3.0, 2.8, 2.5),
            toward_tint: Vec3::new(1.6, 1.3, 1.0),
            away_tint: Vec3::new(0.5, 0.6, 0.8),
        }
    }
}

impl DirectionalLight {
    /// Checks the values.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check(
            unit3(self.direction),
            "DirectionalLight.direction",
            self.direction,
            "a unit vector",
        )?;
        check(
            self.fog_intensity.is_finite() && self.fog_intensity >= 0.0,
            "DirectionalLight.fog_intensity",
            self.fog_intensity,
            "a finite value >= 0",
        )?;
        for (field, v) in [
            ("DirectionalLight.color", self.color),
            ("DirectionalLight.toward_tint", self.toward_tint),
            ("DirectionalLight.away_tint", self.away_tint),
        ] {
            check(
                v.is_finite() && v.cmpge(Vec3::ZERO).all() && v.max_element() <= 1.0e4,
                field,
                v,
                "each channel in 0..=10000",
            )?;
        }
        Ok(())
    }
}

/// A point or spot light affecting the fog (WGSL `volfog::types::FogLight`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct FogLight {
    /// World position (m).
    pub position: Vec3,
    /// Range (m), > 0.
    pub range: f32,
    /// Intensity colour (illuminance at 1 m).
    pub color: Vec3,
    /// Contribution to the fog, >= 0.
    pub fog_intensity: f32,
    /// Spot axis (unit); ignored for point lights.
    pub direction: Vec3,
    /// Source radius (m), > 0.
    pub radius: f32,
    /// Cosine of the outer half-angle; <= -1 for a point light.
    pub cos_outer: f32,
    /// Cosine of the inner half-angle.
    pub cos_inner: f32,
}

impl FogLight {
    /// A point light.
    pub fn point(position: Vec3, color: Vec3, range: f32) -> Self {
        Self {
            position,
            range,
            color,
            fog_intensity: 1.0,
            direction: Vec3::NEG_Y,
            radius: 0.05,
            cos_outer: -2.0,
            cos_inner: -2.0,
        }
    }

    /// A spot light with full intensity inside `inner` and none outside `outer`
    /// (half-angles in radians).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        color: Vec3,
        range: f32,
        inner: f32,
        outer: f32,
    ) -> Self {
        Self {
            direction: direction.normalize_or(Vec3::NEG_Y),
            cos_outer: outer.cos(),
            cos_inner: inner.min(outer).cos(),
            ..Self::point(position, color, range)
        }
    }

    /// Checks the values.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        check(
            finite3(self.position),
            "FogLight.position",
            self.position,
            "a finite position",
        )?;
        check(
            self.range.is_finite() && self.range > 0.0,
            "FogLight.range",
            self.range,
            "a finite range > 0 m",
        )?;
        check(
            self.color.is_finite() && self.color.cmpge(Vec3::ZERO).all(),
            "FogLight.color",
            self.color,
            "finite channels >= 0",
        )?;
        check(
            self.fog_intensity.is_finite() && self.fog_intensity >= 0.0,
            "FogLight.fog_intensity",
            self.fog_intensity,
            "a finite value >= 0",
        )?;
        check(
            self.radius.is_finite() && self.radius > 0.0,
            "FogLight.radius",
            self.radius,
            "a finite radius > 0 m",
        )?;
        if self.cos_outer > -1.0 {
            check(
                unit3(self.direction),
                "FogLight.direction",
                self.direction,
                "a unit vector",
            )?;
            check(
                self.cos_outer <= 1.0 && self.cos_inner >= self.cos_outer && self.cos_inner <= 1.0,
                "FogLight.cos_inner",
                (self.cos_outer, self.cos_inner),
                "cos_outer <= cos_inner <= 1",
            )?;
        }
        Ok(())
    }
}

/// Lighting of the medium (WGSL `volfog::types::FogLighting`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct FogLighting {
    /// The directional light.
    pub sun: DirectionalLight,
    /// L1 SH of the ambient radiance, red.
    pub ambient_r: Vec4,
    /// L1 SH of the ambient radiance, green.
    pub ambient_g: Vec4,
    /// L1 SH of the ambient radiance, blue.
    pub ambient_b: Vec4,
    /// Number of lights in the light buffer.
    pub light_count: u32,
}

/// L1 SH coefficients (Y00, Y1-1, Y10, Y11) of ambient radiance per channel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AmbientSh {
    /// Red, green and blue coefficients.
    pub rgb: [Vec4; 3],
}

impl AmbientSh {
    /// Constant ambient radiance from every direction.
    pub fn constant(radiance: Vec3) -> Self {
        let k = (4.0 * std::f32::consts::PI).sqrt();
        Self {
            rgb: [0, 1, 2].map(|c| Vec4::new(radiance[c] * k, 0.0, 0.0, 0.0)),
        }
    }

    /// Radiance `sky` from above (along `up`) blending linearly to `ground` from below:
    /// L(w) = mix(ground, sky, 0.5 + 0.5 dot(w, up)), which is exactly L1.
    pub fn sky_ground(sky: Vec3, ground: Vec3, up: Vec3) -> Self {
        let k0 = (4.0 * std::f32::consts::PI).sqrt();
        let k1 = crate::cpu::phase::SH_Y1 * 4.0 * std::f32::consts::PI / 3.0;
        let mean = (sky + ground) * 0.5;
        let slope = (sky - ground) * 0.5;
        Self {
            rgb: [0, 1, 2].map(|c| {
                Vec4::new(
                    mean[c] * k0,
                    k1 * slope[c] * up.y,
                    k1 * slope[c] * up.z,
                    k1 * slope[c] * up.x,
                )
            }),
        }
    }

    /// Converts SH of irradiance (cosine-convolved, as many engines store) to SH of
    /// radiance: band 0 divided by pi, band 1 by 2 pi / 3.
    pub fn from_irradiance(irradiance: [Vec4; 3]) -> Self {
        let a0 = std::f32::consts::PI;
        let a1 = 2.0 * std::f32::consts::PI / 3.0;
        Self {
            rgb: irradiance.map(|e| Vec4::new(e.x / a0, e.y / a1, e.z / a1, e.w / a1)),
        }
    }
}

/// Maximum number of shadow cascades.
pub const MAX_CASCADES: usize = 4;
/// Largest ESM exponent without log-space filtering: exp(88) < f32::MAX.
pub const MAX_LINEAR_ESM_EXPONENT: f32 = 88.0;

/// Cascaded shadow maps of the directional light (WGSL `volfog::types::ShadowCascades`).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct ShadowCascades {
    /// World -> light clip space per cascade.
    pub light_from_world: [Mat4; 4],
    /// Far view depth of each cascade (m).
    pub splits: Vec4,
    /// Cascades in use, 0..=4.
    pub count: u32,
    /// ESM exponent.
    pub exponent: f32,
}

impl ShadowCascades {
    /// Checks the values; `log_space` tells whether the ESM is filtered in log space
    /// (VOLFOG_ESM_LOG_SPACE), which lifts the exponent limit of 88.
    pub fn validate(&self, log_space: bool) -> Result<(), InvalidValue> {
        check(
            self.count as usize <= MAX_CASCADES,
            "ShadowCascades.count",
            self.count,
            "0..=4",
        )?;
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
        if log_space {
            check(
                self.exponent.is_finite() && self.exponent > 0.0 && self.exponent <= 1.0e4,
                "ShadowCascades.exponent",
                self.exponent,
                "0 < c <= 10000 (log-space ESM)",
            )?;
        } else {
            check(
                self.exponent.is_finite() && self.exponent > 0.0 && self.exponent <= MAX_LINEAR_ESM_EXPONENT,
                "ShadowCascades.exponent",
                self.exponent,
                "0 < c <= 88 (exp(c) must stay finite in f32; use log-space ESM filtering for more)",
            )?;
        }
        Ok(())
    }
}
