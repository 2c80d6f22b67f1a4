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
        if self.count == 0 {
            return Ok(());
        }
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

/// Largest radiance (linear, per channel) accepted for fog colours.
pub const MAX_FOG_RADIANCE: f32 = 1.0e9;
/// Largest entry of the linear part of a fog volume's world -> local matrix (volumes
/// smaller than about a micrometre are rejected).
pub const MAX_FOG_VOLUME_LOCAL_SCALE: f32 = 1.0e6;

fn radiance3(v: Vec3) -> bool {
    v.is_finite() && v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::splat(MAX_FOG_RADIANCE)).all()
}

/// Closed-form global height fog (WGSL `volfog::types::HeightFog`, used by
/// `volfog::height_fog`): extinction `density * exp(-falloff * (dot(p, up) - base_height))`
/// lit by `color` plus an optional sun lobe. `Default` is a placeholder for layout
/// probes; build one with [`HeightFog::new`] (and [`HeightFog::with_sun`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
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
        use crate::cpu::height_fog::{FOG_DENSITY_LIMIT, FOG_FALLOFF_LIMIT, FOG_POSITION_LIMIT};
        check(
            radiance3(color),
            "HeightFog.color",
            color,
            "each channel in [0, 1e9]",
        )?;
        check(
            (0.0..=FOG_DENSITY_LIMIT).contains(&density),
            "HeightFog.density",
            density,
            "0..=1000 1/m",
        )?;
        check(unit3(up), "HeightFog.up", up, "a unit vector")?;
        check(
            (-FOG_FALLOFF_LIMIT..=FOG_FALLOFF_LIMIT).contains(&falloff),
            "HeightFog.falloff",
            falloff,
            "-1000..=1000 1/m",
        )?;
        check(
            (-FOG_POSITION_LIMIT..=FOG_POSITION_LIMIT).contains(&base_height),
            "HeightFog.base_height",
            base_height,
            "a height within +-1e9 m",
        )?;
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
        .with_sun(self.sun_direction, self.sun_color, self.sun_g)
        .map(|_| ())
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
            ..*self
        }
    }

    /// The height fog matching a froxel medium's height profile (noise and local
    /// volumes aside), lit by a constant radiance: use it as the apply tail so the
    /// fog continues beyond the volume's far plane with the same density.
    pub fn from_medium(medium: &FogMedium, color: Vec3) -> Self {
        Self {
            color,
            density: medium.density,
            up: medium.up,
            falloff: medium.height_falloff,
            base_height: medium.base_height,
            ..Self::none()
        }
    }

    /// Adds a Henyey-Greenstein sun lobe: `sun_color * HG(dot(view_dir, direction), g)`
    /// is added to the in-scattered radiance. `direction` points towards the sun.
    pub fn with_sun(self, direction: Vec3, sun_color: Vec3, g: f32) -> Result<Self, InvalidValue> {
        check(
            unit3(direction),
            "HeightFog.sun_direction",
            direction,
            "a unit vector",
        )?;
        check(
            radiance3(sun_color),
            "HeightFog.sun_color",
            sun_color,
            "each channel in [0, 1e9]",
        )?;
        check(
            (-0.999..=0.999).contains(&g),
            "HeightFog.sun_g",
            g,
            "-0.999..=0.999",
        )?;
        Ok(Self {
            sun_direction: direction.normalize(),
            sun_color,
            sun_g: g,
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        to_uniform_bytes(self)
    }
}

/// An analytic fog volume (WGSL `volfog::types::FogVolume`, used by
/// `volfog::fog_volume`): a box or ellipsoid ray traced per pixel, filled with
/// `density * exp(-falloff * (dot(p - center, gradient) - offset))`. `Default` is a
/// placeholder for layout probes; build one with [`FogVolume::new`].
#[derive(Debug, Clone, Copy, PartialEq, Default, ShaderType)]
pub struct FogVolume {
    /// World -> local transform (affine); the shape is the unit box or sphere there.
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
    /// 0 box, 1 ellipsoid ([`VolumeShape`]).
    pub shape: u32,
}

impl FogVolume {
    /// A volume of uniform fog covering `world_from_local` applied to the unit shape
    /// (an affine transform: the box `[-1, 1]^3` or the unit sphere become a box or an
    /// ellipsoid of any size, orientation and position).
    pub fn new(
        world_from_local: Mat4,
        shape: VolumeShape,
        color: Vec3,
        density: f32,
    ) -> Result<Self, InvalidValue> {
        use crate::cpu::height_fog::{FOG_DENSITY_LIMIT, FOG_POSITION_LIMIT};
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
                    .all(|m| m.abs() <= MAX_FOG_VOLUME_LOCAL_SCALE),
            "FogVolume.world_from_local",
            world_from_local,
            "an inverse whose linear part has entries within +-1e6 (volumes larger than \
             about 1e-6 m)",
        )?;
        let center = world_from_local.w_axis.truncate();
        check(
            center.abs().max_element() <= FOG_POSITION_LIMIT,
            "FogVolume.center",
            center,
            "a position within +-1e9 m",
        )?;
        check(
            radiance3(color),
            "FogVolume.color",
            color,
            "each channel in [0, 1e9]",
        )?;
        check(
            (0.0..=FOG_DENSITY_LIMIT).contains(&density),
            "FogVolume.density",
            density,
            "0..=1000 1/m",
        )?;
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

    /// Makes the density fall exponentially along the unit world direction `gradient`
    /// with `falloff` (1/m); it equals `density` on the plane `offset` metres from the
    /// centre along `gradient`.
    pub fn with_gradient(
        self,
        gradient: Vec3,
        falloff: f32,
        offset: f32,
    ) -> Result<Self, InvalidValue> {
        use crate::cpu::height_fog::{FOG_FALLOFF_LIMIT, FOG_POSITION_LIMIT};
        check(
            unit3(gradient),
            "FogVolume.gradient",
            gradient,
            "a unit vector",
        )?;
        check(
            (-FOG_FALLOFF_LIMIT..=FOG_FALLOFF_LIMIT).contains(&falloff),
            "FogVolume.falloff",
            falloff,
            "-1000..=1000 1/m",
        )?;
        check(
            (-FOG_POSITION_LIMIT..=FOG_POSITION_LIMIT).contains(&offset),
            "FogVolume.offset",
            offset,
            "an offset within +-1e9 m",
        )?;
        Ok(Self {
            gradient: gradient.normalize(),
            falloff,
            offset,
            ..self
        })
    }

    /// The uniform buffer bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        to_uniform_bytes(self)
    }
}

/// Largest extinction a fog hull accepts (1/m).
pub const HULL_DENSITY_LIMIT: f32 = 1e3;
/// Largest reference distance a fog hull accepts (m).
pub const HULL_REFERENCE_LIMIT: f32 = 1e9;

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
        check(
            (0.0..=HULL_DENSITY_LIMIT).contains(&density),
            "FogHull.density",
            density,
            "0..=1000 per metre",
        )?;
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
            (0.0..=HULL_REFERENCE_LIMIT).contains(&reference),
            "FogHull.reference",
            reference,
            "0..=1e9 m, at most the distance of the nearest hull point",
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
        to_uniform_bytes(self)
    }
}
