//! The components a Bevy app puts on its entities: [`FroxelFog`] on a camera and
//! [`FroxelFogVolume`] on local fog volumes.

use bevy::prelude::*;
pub use volfog::uniforms::BlendMode;

/// Froxel volumetric fog for a 3D camera: add it next to `Camera3d`. The fog is
/// computed in a volume of froxels (screen tiles x depth slices) from the camera's
/// near fog plane to `far`, lit by the first shadow-casting `DirectionalLight` (through
/// its shadow cascades) and the other `DirectionalLight`s (unshadowed), the
/// `PointLight`s and `SpotLight`s (the first 64 found, those with `shadow_maps_enabled`
/// first; up to `point_shadows` and `spot_shadows` of them through Bevy's own shadow
/// maps; spot cones fall off as on Bevy's surfaces) and the global ambient light, and
/// applied to the opaque scene before the transparent pass and tonemapping. Beyond
/// `far` an analytic height-fog tail continues it. `lights` chooses between every light
/// and those with Bevy's `VolumetricLight`.
///
/// Values out of range switch the fog off for this camera with one warning naming
/// the field and its range.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct FroxelFog {
    /// Screen pixels per froxel side: the grid is `ceil(viewport / tile_size)`
    /// froxels across, and follows the viewport when it is resized. 1..=256; by
    /// default 12, which gives Wronski 2014's 160 x 90 froxels at 1920 x 1080 (8 gives
    /// 2.25 times the froxels and costs about 1.7 times the GPU time: see the
    /// benchmark guide).
    pub tile_size: u32,
    /// Depth slices, 8..=256 (with `tile_size`, see `volfog::limits`).
    pub slices: u32,
    /// View depth (m) where the volume starts, > 0.
    pub near: f32,
    /// View depth (m) where the volume ends; the analytic tail continues beyond it.
    pub far: f32,
    /// Slice distribution: 0 linear in depth, larger values put more slices near the
    /// camera (ln(far / near) is exponential).
    pub slice_curve: f32,
    /// The medium.
    pub medium: FogMediumSettings,
    /// Blend each frame with the reprojected previous one (steadier, jittered
    /// sampling).
    pub temporal: bool,
    /// Weight of the history with `temporal`, [0, 1).
    pub history_weight: f32,
    /// With `temporal`, inject one froxel of every pair of slices per frame in a 3D
    /// checkerboard and take the other from the reprojected history
    /// (`volfog::pipeline::FogConfig::amortize`): about half the injection's cost; a
    /// change of lighting settles in about twice as many frames. Ignored without
    /// `temporal`.
    pub amortize: bool,
    /// Read the density noise from a baked 64³ tileable texture instead of computing it
    /// per froxel (`volfog::pipeline::FogConfig::noise_texture`; the same Perlin noise
    /// with a shorter period, within 0.143 of it, RMS 0.034, on a [-1, 1] range). Off
    /// by default: its noise pattern changes the image (measured in the `fog_scene`
    /// scene: 5 % mean, 17 % at the 95th percentile of pixels), where `amortize` keeps
    /// it (1.1 % and 3.1 %).
    pub noise_texture: bool,
    /// Continue the fog analytically beyond `far` (the medium's height fog, lit by
    /// the sun without shadows).
    pub tail: bool,
    /// Attenuate the lights by the medium on their way to each point of the fog: the
    /// sun through the height profile up to `medium.top_height`, point and spot
    /// lights along the segment to the light
    /// (`volfog::pipeline::FogConfig::light_transmittance`). Off, the fog is lit as if
    /// the air between it and the lights were clear.
    pub light_transmittance: bool,
    /// Scale of the sun's light in the fog (the surfaces see all of it), >= 0.
    pub sun_scattering: f32,
    /// Scale of the point and spot lights' light in the fog, >= 0.
    pub light_scattering: f32,
    /// Scale of the global ambient light in the fog, >= 0.
    pub ambient_scattering: f32,
    /// Which lights light the fog: every light (the default), or as Bevy's own
    /// volumetric fog only those with a `VolumetricLight` component.
    pub lights: FogLightSelection,
    /// The ambient radiance lighting the fog (linear rgb, before the camera's
    /// exposure), or `None` for the `GlobalAmbientLight`'s `color * brightness`.
    pub ambient_radiance: Option<LinearRgba>,
    /// Exponent of the sun's exponential shadow map in the fog, filtered in log space
    /// (`volfog::limits::ESM_EXPONENT_LOG_SPACE`, (0, 1e4]): larger is sharper, with
    /// less light leaking behind occluders, at depths relative to each cascade's
    /// depth range.
    pub esm_exponent: f32,
    /// Shadowed `SpotLight`s the fog takes per frame (`volfog::limits::SPOT_SHADOWS`,
    /// 0..=16): spot lights with `shadow_maps_enabled` are shadowed in the fog through
    /// Bevy's own shadow maps, the nearest to the camera first (by the distance to the
    /// light's range sphere); the others light the fog unshadowed.
    pub spot_shadows: u32,
    /// Shadowed `PointLight`s the fog takes per frame (`volfog::limits::POINT_SHADOWS`,
    /// 0..=8), chosen as `spot_shadows`: each takes six atlas layers.
    pub point_shadows: u32,
    /// Exponent of the point and spot lights' exponential shadow maps in the fog, on
    /// depths relative to each light's range ((0, 1e4], log-space ESM): behind an
    /// occluder the fog gets under 5 % of the light once it is `3 range /
    /// light_shadow_exponent` m behind it (plus the light's `shadow_depth_bias`).
    pub light_shadow_exponent: f32,
    /// Room for [`FroxelFogParticles`](crate::FroxelFogParticles) in this camera's fog
    /// (`volfog::pipeline::FogConfig::max_particles`, 0..=65,536): 0 (the default)
    /// takes none, at no cost; more particles in the scene than this switch the fog
    /// off with one warning naming `FrameInputs.particles`.
    pub max_particles: u32,
}

impl Default for FroxelFog {
    fn default() -> Self {
        let local = volfog::pipeline::LocalShadowConfig::default();
        Self {
            tile_size: 12,
            slices: 128,
            near: 0.5,
            far: 128.0,
            slice_curve: 4.0,
            medium: FogMediumSettings::default(),
            temporal: true,
            history_weight: 0.9,
            amortize: true,
            noise_texture: false,
            tail: true,
            light_transmittance: true,
            sun_scattering: 1.0,
            light_scattering: 1.0,
            ambient_scattering: 1.0,
            lights: FogLightSelection::All,
            ambient_radiance: None,
            esm_exponent: 300.0,
            spot_shadows: local.spot_shadows,
            point_shadows: local.point_shadows,
            light_shadow_exponent: local.exponent,
            max_particles: 0,
        }
    }
}

/// Which of the scene's lights light a [`FroxelFog`] ([`FroxelFog::lights`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FogLightSelection {
    /// Every `DirectionalLight`, `PointLight` and `SpotLight`.
    #[default]
    All,
    /// Only the lights with a `VolumetricLight` component, as Bevy's `VolumetricFog`
    /// (the fog's light shafts come from chosen lights; the others light surfaces
    /// only).
    Volumetric,
}

/// The participating medium of a [`FroxelFog`]: exponential height fog with animated
/// noise (`volfog::uniforms::FogMedium`).
#[derive(Clone, Debug, PartialEq)]
pub struct FogMediumSettings {
    /// Extinction at `base_height` (1/m), >= 0.
    pub density: f32,
    /// Scattering albedo (linear rgb, each in [0, 1]).
    pub albedo: LinearRgba,
    /// Height falloff (1/m): the density falls as exp(-falloff * (y - base_height)).
    pub height_falloff: f32,
    /// World height (m) of `density`.
    pub base_height: f32,
    /// Henyey-Greenstein mean cosine, (-1, 1): > 0 scatters forward (bright towards
    /// the sun).
    pub phase_g: f32,
    /// Strength of the density noise, [0, 1].
    pub noise_strength: f32,
    /// Frequency of the density noise (1/m).
    pub noise_scale: f32,
    /// Wind moving the noise (m/s, world space).
    pub wind: Vec3,
    /// World height (m) where the medium ends: no fog above it, and the sun's light
    /// enters the fog there. `volfog::limits::NO_TOP` (the default) for none; a
    /// uniform medium (`height_falloff` 0) needs a top, or with `light_transmittance`
    /// no sunlight reaches it. `|top_height| <= 1e9`.
    pub top_height: f32,
    /// Radiance the medium emits per metre of path where its extinction is `density`
    /// (linear rgb, before the camera's exposure; it follows the density's profile):
    /// glowing fog, or with a black albedo the fog colour of a distance fog (the fog
    /// then tends to `emission / density`).
    pub emission: LinearRgba,
}

impl Default for FogMediumSettings {
    fn default() -> Self {
        let m = volfog::uniforms::FogMedium::default();
        Self {
            density: m.density,
            albedo: LinearRgba::rgb(m.albedo.x, m.albedo.y, m.albedo.z),
            height_falloff: m.height_falloff,
            base_height: m.base_height,
            phase_g: m.phase_g,
            noise_strength: m.noise_strength,
            noise_scale: m.noise_scale,
            wind: Vec3::from_array(m.wind.to_array()),
            top_height: m.top_height,
            emission: LinearRgba::BLACK,
        }
    }
}

/// The shape of a [`FroxelFogVolume`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FogVolumeShape {
    /// The unit cube (-0.5..0.5 on each axis) under the entity's transform, as Bevy's
    /// own `FogVolume`.
    #[default]
    Box,
    /// The sphere of diameter 1 under the entity's transform: scale it for an
    /// ellipsoid.
    Ellipsoid,
}

/// A local fog volume: density added, removed, scaled, capped, raised or set (its
/// `blend`) inside a box or an ellipsoid placed by the entity's transform. Every
/// [`FroxelFog`] camera sees it. The volumes blend into the medium in increasing
/// `order`, volumes of the same order by entity.
#[derive(Component, Clone, Debug, PartialEq)]
#[require(Transform)]
pub struct FroxelFogVolume {
    /// Box or ellipsoid.
    pub shape: FogVolumeShape,
    /// The volume's extinction inside (1/m), combined with the fog's by `blend`: added
    /// (negative clears fog, see `volfog::limits::LOCAL_VOLUME_DENSITY`), or >= 0 for
    /// the other modes (subtracted, the cap, the floor, the value, or under
    /// `BlendMode::Multiply` the factor).
    pub density: f32,
    /// Width of the soft edge as a fraction of the shape's half extent, (0, 1].
    pub edge: f32,
    /// How the volume combines with the fog before it (`volfog::uniforms::BlendMode`:
    /// add by default, subtract to clear fog indoors, multiply, min, max, overwrite).
    pub blend: BlendMode,
    /// Where the volume comes in the blend: lower orders first (default 0).
    pub order: i32,
}

/// The density texture of the [`FroxelFogVolume`] on the same entity: the red channel
/// of a 3D image scales the volume's density in the volume's own space, as Bevy's
/// `FogVolume.density_texture` does: the unit shape spans the texture once, sampled at
/// `local + 0.5 + offset` (`local` in -0.5..0.5, linear filtering, repeat addressing),
/// so move `offset` to scroll the pattern. The image must be 3D with a filterable float
/// format (e.g. `R8Unorm`, `R16Float`). A fog reads one density texture: the first
/// volume's (by entity); a volume with another image is drawn uniform, with one
/// warning naming `FroxelFogVolumeTexture.image`.
#[derive(Component, Clone, Debug, PartialEq)]
#[require(FroxelFogVolume)]
pub struct FroxelFogVolumeTexture {
    /// The 3D density texture.
    pub image: Handle<Image>,
    /// Added to the texture coordinate (texture units).
    pub offset: Vec3,
}

impl Default for FroxelFogVolume {
    fn default() -> Self {
        Self {
            shape: FogVolumeShape::Box,
            density: 0.1,
            edge: 0.3,
            blend: BlendMode::Add,
            order: 0,
        }
    }
}
