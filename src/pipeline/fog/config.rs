//! [`FogConfig`]: what a [`VolumetricFog`](super::VolumetricFog) is built for.

use glam::UVec3;

use crate::limits::{self, InvalidValue};
use crate::options::{EsmOptions, Filtering, InjectOptions, ScanStep, ShadowFilter};
use crate::shaders::CustomModule;
use crate::uniforms::{MediumShadowConfig, ShadowCascades};

/// Configuration of a [`VolumetricFog`](super::VolumetricFog). Every range is in
/// [`crate::limits`].
#[derive(Debug, Clone, PartialEq)]
pub struct FogConfig {
    /// Froxels across the screen (x, y) and depth slices (z).
    pub volume_size: UVec3,
    /// View depth (m) where the volume starts, > 0.
    pub near: f32,
    /// View depth (m) where the volume ends, > near.
    pub far: f32,
    /// Slice distribution curve (0 linear, ln(far / near) exponential).
    pub slice_curve: f32,
    /// How the shadows of the sun and of shadowed point and spot lights are tested in
    /// the fog: depth compares against the full-resolution maps at points spread over
    /// each froxel, accumulated by the temporal blend (the default, one tap per froxel
    /// per frame), or exponential shadow maps ([`ShadowFilter`]). The `esm_*` fields
    /// and [`LocalShadowConfig::exponent`] apply to the ESM filter only.
    pub shadow_filter: ShadowFilter,
    /// ESM size per cascade in texels; the shadow map is 4x as large (with the ESM
    /// filter; the compare filter reads a shadow map of any size).
    pub esm_resolution: u32,
    /// Shadow cascades.
    pub cascades: u32,
    /// ESM exponent for depths in [0, 1]: <= 88 unless `esm_log_space`.
    pub esm_exponent: f32,
    /// Filter the ESM in log space (`VOLFOG_ESM_LOG_SPACE`).
    pub esm_log_space: bool,
    /// Box blur radius (taps = 2 radius + 1).
    pub esm_blur_radius: u32,
    /// The shadow map holds reversed depth (1 nearest the light), as reverse-Z
    /// renderers draw it; see [`EsmOptions::reversed_z`].
    pub shadow_reversed_z: bool,
    /// Capacity of the point/spot light buffer.
    pub max_lights: u32,
    /// Capacity of the transient light buffer
    /// ([`FrameInputs::transient_lights`](super::FrameInputs::transient_lights)), see
    /// [`limits::TRANSIENT_LIGHTS`]; 0 builds no transient scan (the default is 8).
    pub max_transient_lights: u32,
    /// Capacity of the area light buffer
    /// ([`FrameInputs::area_lights`](super::FrameInputs::area_lights)), see
    /// [`limits::AREA_LIGHTS`]; 0 (the default) builds the inject variant without area
    /// lights, any other value the one with them (`VOLFOG_INJECT_AREA_LIGHTS`).
    pub max_area_lights: u32,
    /// Capacity of the particle buffer
    /// ([`FrameInputs::particles`](super::FrameInputs::particles)), see
    /// [`limits::PARTICLES`]; 0 (the default) builds the inject variant without
    /// particles (no cost), any other value the one with them
    /// (`VOLFOG_INJECT_PARTICLES`).
    pub max_particles: u32,
    /// Capacity of the local volume buffer.
    pub max_local_volumes: u32,
    /// Jitter froxel samples each frame (Halton 2, 3, 5).
    pub jitter: bool,
    /// Blend with the reprojected previous frame (allocates two history volumes).
    pub temporal: bool,
    /// Weight of the history, [0, 1).
    pub history_weight: f32,
    /// With `temporal`, blend with the history inside the inject pass
    /// (`VOLFOG_INJECT_TEMPORAL`, on by default): inject writes the stabilised volume
    /// directly, so no scattering volume is written and read back and the temporal
    /// pass does not run. Off runs the separate temporal pass; the two agree within
    /// rgba16float rounding (the fused blend takes the froxel's value before it is
    /// rounded). Ignored without `temporal`.
    pub fuse_temporal: bool,
    /// Scan step.
    pub scan_step: ScanStep,
    /// AC4 two-colour sun phase instead of Henyey-Greenstein.
    pub two_color_phase: bool,
    /// Noise fbm octaves.
    pub noise_octaves: u32,
    /// Multiply the density by a 3D texture (see
    /// [`VolumetricFog::set_density_texture`](super::VolumetricFog::set_density_texture)).
    pub density_texture: bool,
    /// Pass the sun's light in the fog through a cloud layer's shadow
    /// (`VOLFOG_INJECT_CLOUD_SHADOW`): the layer comes with each frame
    /// ([`FrameInputs::clouds`](super::FrameInputs::clouds)), its density map from
    /// [`VolumetricFog::set_cloud_map`](super::VolumetricFog::set_cloud_map) (without
    /// one the map is empty and nothing is shadowed).
    pub cloud_shadow: bool,
    /// Skip the froxels behind the farthest opaque surface of their screen tile in
    /// inject, temporal and scan (`VOLFOG_FROXEL_CULL`), once a scene depth is set
    /// ([`VolumetricFog::set_scene_depth`](super::VolumetricFog::set_scene_depth));
    /// without one every froxel is live.
    pub depth_cull: bool,
    /// Amortise injection over two frames: inject one colour of a 3D checkerboard per
    /// frame and let temporal reprojection fill the other (needs `temporal`). Halves
    /// the injection; lighting changes then take about twice as many frames to settle.
    /// The jitter then advances every two frames
    /// ([`froxel_jitter_amortised`](crate::cpu::froxel::froxel_jitter_amortised)), so
    /// the froxels of each colour still visit all 16 sample points.
    pub amortize: bool,
    /// Read the density noise from a tileable texture baked once on the GPU
    /// (`VOLFOG_INJECT_NOISE_TEXTURE`, see `volfog::noise`; on by default, as Wronski's
    /// fog samples a noise texture) instead of evaluating Perlin noise per froxel: a
    /// trilinear look-up in place of the noise's hashing and gradients (about 320
    /// instructions of inject on a GPU compiler), within 0.143 of the procedural noise
    /// (RMS 0.034 on its [-1, 1] range), tiling every 16 lattice units.
    pub noise_texture: bool,
    /// Filtering of the integrated volume where fog is applied (the fog group's layout).
    pub apply_filtering: Filtering,
    /// Record GPU timestamps per pass (needs `Features::TIMESTAMP_QUERY`).
    pub timestamps: bool,
    /// Shadows and cookies of point and spot lights (`VOLFOG_INJECT_LOCAL_SHADOWS`):
    /// the budget and the atlas; `None` compiles inject without them.
    pub local_shadows: Option<LocalShadowConfig>,
    /// Attenuate the light reaching each froxel by the medium on its way (on by
    /// default): the sun's by the height profile between the froxel and the medium's
    /// top ([`FogMedium::top_height`](crate::uniforms::FogMedium::top_height)) in
    /// Wenzel's closed form, a point or spot light's by the profile along the segment
    /// to the light; the analytic tail's sun lobe likewise. The noise, the density
    /// texture, the custom density and local volumes are on these paths only with
    /// [`FogConfig::medium_shadows`]. Off: light reaches every froxel as in clear air.
    pub light_transmittance: bool,
    /// Shadows the medium casts on itself (`VOLFOG_INJECT_MEDIUM_SHADOW`, see
    /// `volfog::medium_shadow`): with [`FogConfig::light_transmittance`] the light of
    /// the sun and of point, spot and directional lights is also dimmed by the noise,
    /// the density texture, the custom density, the local volumes and the particles on
    /// its way, read from a sun-aligned volume of the medium's excess extinction that
    /// the `medium_shadow` pass fills each frame (a dense column casts a shaft of
    /// shadow into thinner fog). Without `light_transmittance` nothing dims the light
    /// and this is ignored (no pass runs). Area lights, the analytic tail and the epipolar shafts keep
    /// the height profile alone. `None` (the default): the height profile alone.
    pub medium_shadows: Option<MediumShadowConfig>,
    /// Your own density: a WGSL module (naga_oil `#import`s, or WESL `import ...;`
    /// statements) that defines `fn volfog_custom_density(world: vec3<f32>, time: f32,
    /// params: FogCustomParams) -> FogSample` ([`crate::shaders::CUSTOM_DENSITY`]). The
    /// inject pass is composed with it (`VOLFOG_INJECT_CUSTOM_DENSITY`) and adds its
    /// sample at each froxel's position to the medium before the local volumes blend;
    /// `params` is [`FrameInputs::custom_params`](super::FrameInputs::custom_params)
    /// (inject's binding 31). [`VolumetricFog::new`](super::VolumetricFog::new) returns
    /// the module's composition or validation errors with its file, line and column and
    /// the required signature. `None` (the default): no custom density.
    pub custom_density: Option<CustomModule>,
}

/// The budget of shadowed point and spot lights and their ESM atlas (see
/// [`VolumetricFog::set_spot_shadow_maps`](super::VolumetricFog::set_spot_shadow_maps)).
/// A frame's [`ShadowedLight`](super::ShadowedLight)s take atlas maps in the order
/// given until the budget of their kind is spent; those after it light the fog
/// unshadowed (their cookies still apply).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalShadowConfig {
    /// Shadowed spot lights per frame (one atlas layer each), see
    /// [`limits::SPOT_SHADOWS`].
    pub spot_shadows: u32,
    /// Shadowed point lights per frame (six atlas layers each), see
    /// [`limits::POINT_SHADOWS`].
    pub point_shadows: u32,
    /// Texels per side of each atlas map, see [`limits::LOCAL_SHADOW_RESOLUTION`]; the
    /// lights' depth maps are a whole multiple of it (1 to 16 times).
    pub resolution: u32,
    /// ESM exponent for linear depths in [0, 1] (the light's range maps to 1): behind
    /// an occluder the fog's light falls below 5 % within `3 range / exponent` metres.
    /// At most 88 unless `FogConfig::esm_log_space`. The compare filter has no atlas
    /// and ignores `resolution` and `exponent`.
    pub exponent: f32,
}

impl Default for LocalShadowConfig {
    fn default() -> Self {
        Self {
            spot_shadows: 4,
            point_shadows: 2,
            resolution: 256,
            exponent: 80.0,
        }
    }
}

impl LocalShadowConfig {
    /// Layers of the atlas: one per spot light, six per point light.
    pub fn layers(&self) -> u32 {
        self.spot_shadows + 6 * self.point_shadows
    }
}

impl Default for FogConfig {
    fn default() -> Self {
        let inject = InjectOptions::default();
        let esm = EsmOptions::default();
        Self {
            volume_size: UVec3::new(160, 90, 128),
            near: 0.5,
            far: 128.0,
            slice_curve: 4.0,
            shadow_filter: ShadowFilter::default(),
            esm_resolution: 256,
            cascades: 4,
            esm_exponent: 40.0,
            esm_log_space: esm.log_space,
            esm_blur_radius: esm.blur_radius,
            shadow_reversed_z: esm.reversed_z,
            max_lights: limits::MAX_LIGHTS,
            max_transient_lights: 8,
            max_area_lights: 0,
            max_particles: 0,
            max_local_volumes: 16,
            jitter: inject.jitter,
            temporal: true,
            history_weight: 0.9,
            fuse_temporal: true,
            scan_step: ScanStep::EnergyConserving,
            two_color_phase: inject.two_color_phase,
            noise_octaves: inject.noise_octaves,
            density_texture: inject.density_texture,
            cloud_shadow: inject.cloud_shadow,
            depth_cull: true,
            amortize: false,
            noise_texture: inject.noise_texture,
            apply_filtering: Filtering::Sampler,
            timestamps: false,
            local_shadows: Some(LocalShadowConfig::default()),
            light_transmittance: true,
            medium_shadows: None,
            custom_density: None,
        }
    }
}

impl FogConfig {
    /// Checks every field; the error names the field and its valid range.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        crate::uniforms::froxels::check_slices(
            [
                "FogConfig.volume_size",
                "FogConfig.near",
                "FogConfig.far",
                "FogConfig.slice_curve",
            ],
            self.volume_size,
            self.near,
            self.far,
            self.slice_curve,
        )?;
        if let ShadowFilter::Compare { taps } = self.shadow_filter {
            limits::SHADOW_TAPS.check("FogConfig.shadow_filter.taps", taps)?;
        }
        limits::ESM_RESOLUTION.check("FogConfig.esm_resolution", self.esm_resolution)?;
        limits::CASCADES.check("FogConfig.cascades", self.cascades)?;
        ShadowCascades::exponent_range(self.esm_log_space)
            .check("FogConfig.esm_exponent", self.esm_exponent)?;
        limits::ESM_BLUR_RADIUS.check("FogConfig.esm_blur_radius", self.esm_blur_radius)?;
        limits::LIGHTS.check("FogConfig.max_lights", self.max_lights)?;
        limits::TRANSIENT_LIGHTS
            .check("FogConfig.max_transient_lights", self.max_transient_lights)?;
        limits::AREA_LIGHTS.check("FogConfig.max_area_lights", self.max_area_lights)?;
        limits::PARTICLES.check("FogConfig.max_particles", self.max_particles)?;
        limits::LOCAL_VOLUMES.check("FogConfig.max_local_volumes", self.max_local_volumes)?;
        limits::HISTORY_WEIGHT.check("FogConfig.history_weight", self.history_weight)?;
        limits::NOISE_OCTAVES.check("FogConfig.noise_octaves", self.noise_octaves)?;
        if let Some(l) = &self.local_shadows {
            limits::SPOT_SHADOWS.check("LocalShadowConfig.spot_shadows", l.spot_shadows)?;
            limits::POINT_SHADOWS.check("LocalShadowConfig.point_shadows", l.point_shadows)?;
            limits::LOCAL_SHADOW_RESOLUTION.check("LocalShadowConfig.resolution", l.resolution)?;
            ShadowCascades::exponent_range(self.esm_log_space)
                .check("LocalShadowConfig.exponent", l.exponent)?;
        }
        if let Some(m) = &self.medium_shadows {
            m.validate()?;
        }
        limits::check(
            !self.amortize || self.temporal,
            "FogConfig.amortize",
            self.amortize,
            "false unless FogConfig.temporal is true (the skipped froxels come from the history)",
        )
    }

    /// The options of the inject variant.
    pub fn inject_options(&self) -> InjectOptions {
        InjectOptions {
            jitter: self.jitter,
            two_color_phase: self.two_color_phase,
            density_texture: self.density_texture,
            esm_log_space: self.esm_log_space && !self.shadow_filter.compares(),
            shadow_compare: self.shadow_filter.compares(),
            noise_texture: self.noise_texture,
            depth_cull: self.depth_cull,
            checkerboard: self.amortize,
            cloud_shadow: self.cloud_shadow,
            local_shadows: self.local_shadows.is_some(),
            noise_octaves: self.noise_octaves,
            temporal: self.fused_temporal(),
            custom_density: self.custom_density.is_some(),
            area_lights: self.max_area_lights > 0,
            particles: self.max_particles > 0,
            medium_shadow: self.medium_shadows.is_some() && self.light_transmittance,
        }
    }

    /// Whether temporal reprojection runs inside inject (`temporal` and
    /// `fuse_temporal`).
    pub fn fused_temporal(&self) -> bool {
        self.temporal && self.fuse_temporal
    }

    /// The options of the ESM variants.
    pub fn esm_options(&self) -> EsmOptions {
        EsmOptions {
            log_space: self.esm_log_space,
            blur_radius: self.esm_blur_radius,
            reversed_z: self.shadow_reversed_z,
        }
    }

    /// The shadow map [`VolumetricFog::set_shadow_map`](super::VolumetricFog::set_shadow_map)
    /// expects with the ESM filter: texels per side (4x the ESM) and layers (one per
    /// cascade). The compare filter takes any square size with as many layers.
    pub fn shadow_map_size(&self) -> (u32, u32) {
        (self.esm_resolution * 4, self.cascades)
    }
}
