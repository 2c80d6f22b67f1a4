//! The options that choose a shader variant, each with the define it sets. The CPU
//! mirror evaluates the same options, and the wgpu runtime composes the variant they
//! select.
//!
//! ```
//! use volfog::options::{InjectOptions, ScanStep};
//!
//! assert_eq!(ScanStep::Wronski.defines(), ["VOLFOG_SCAN_WRONSKI_STEP"]);
//! let inject = InjectOptions { noise_octaves: 3, ..InjectOptions::default() };
//! assert_eq!(
//!     inject.defines(),
//!     ["VOLFOG_INJECT_JITTER", "VOLFOG_INJECT_NOISE_OCTAVES=3", "VOLFOG_INJECT_NOISE_TEXTURE"]
//! );
//! ```

use volfog_codegen::manifest;

/// Which integration step the scan uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ScanStep {
    /// In-scattering of a slice integrated against its own extinction (default).
    #[default]
    EnergyConserving,
    /// Wronski 2014: the slice's in-scattering enters unattenuated
    /// (`VOLFOG_SCAN_WRONSKI_STEP`).
    Wronski,
}

impl ScanStep {
    /// The defines of the scan variant.
    pub fn defines(self) -> Vec<String> {
        match self {
            ScanStep::EnergyConserving => Vec::new(),
            ScanStep::Wronski => vec!["VOLFOG_SCAN_WRONSKI_STEP".to_string()],
        }
    }
}

/// How the integrated volume is filtered where fog is applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Filtering {
    /// A linear, clamp-to-edge sampler (binding 2 of the fog group).
    #[default]
    Sampler,
    /// Eight texel loads filtered in the shader; no sampler binding
    /// (`VOLFOG_BINDINGS_NO_SAMPLER`).
    Manual,
}

impl Filtering {
    /// The defines of the variants that read the fog group.
    pub fn defines(self) -> Vec<String> {
        match self {
            Filtering::Sampler => Vec::new(),
            Filtering::Manual => vec!["VOLFOG_BINDINGS_NO_SAMPLER".to_string()],
        }
    }
}

/// What the fullscreen apply pass reads at group 1, binding 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ApplyInput {
    /// The scene depth buffer (a depth-aspect view, read as unfilterable float).
    #[default]
    Depth,
    /// The resolved MSAA fog layout ([`FOG_LAYOUT_FORMAT`]: r the view depth in m, g the
    /// fog amount `1 - T`) that a multisampled depth pre-pass wrote with
    /// `volfog::apply::fog_layout` and resolved: the fog's colour at the resolved
    /// depth, its amount averaged over the samples (Wenzel 2007, "Scene depth based
    /// rendering and MSAA: Fog"), so silhouettes get no outline.
    ResolvedLayout,
    /// The scene depth buffer at binding 0 and, at binding 1, the shaft texture of
    /// [`EpipolarShafts`](crate::pipeline::epipolar::EpipolarShafts) marched from the
    /// far plane in the tail's medium: beyond the far plane the tail's sun light is
    /// shadowed (the far field, `VOLFOG_APPLY_EPIPOLAR`).
    FarField,
}

/// The format of the MSAA fog layout target: two half floats (view depth in m, fog
/// amount; half floats keep 11 bits, 0.05 % of the depth), resolvable everywhere.
pub const FOG_LAYOUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

impl ApplyInput {
    /// The shader defines of the apply pass variant.
    pub fn defines(self) -> Vec<String> {
        match self {
            ApplyInput::Depth => Vec::new(),
            ApplyInput::ResolvedLayout => vec!["VOLFOG_APPLY_RESOLVED".to_string()],
            ApplyInput::FarField => vec!["VOLFOG_APPLY_EPIPOLAR".to_string()],
        }
    }
}

/// How the fog tests the shadows of the sun and of shadowed point and spot lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowFilter {
    /// Depth compares against the full-resolution shadow maps
    /// (`VOLFOG_INJECT_SHADOW_COMPARE`, the default with one tap): `taps` compares per
    /// froxel per frame (see [`limits::SHADOW_TAPS`](crate::limits::SHADOW_TAPS)), four
    /// times as many where the froxel has no history, at points spread over the froxel
    /// that move from frame to frame; the temporal blend accumulates them into the
    /// visibility averaged over the froxel, so shafts stay as sharp as the grid allows
    /// and light does not leak past an occluder's edge. Each compare is a 2 x 2
    /// percentage-closer filter of the map. No ESM pass runs.
    Compare {
        /// Compares per froxel per frame where the froxel has history, 1..=4.
        taps: u32,
    },
    /// Exponential shadow maps (Wronski 2014): the sun's map downsampled 4x and
    /// blurred, shadowed lights' maps filtered into the local-light atlas, each froxel
    /// reading one filtered value. Smooth without temporal accumulation, but the blur
    /// leaks light around occluders (see the accuracy guide).
    Esm,
}

impl Default for ShadowFilter {
    fn default() -> Self {
        ShadowFilter::Compare { taps: 1 }
    }
}

impl ShadowFilter {
    /// Whether this is the compare filter.
    pub fn compares(self) -> bool {
        matches!(self, ShadowFilter::Compare { .. })
    }
}

/// The define of depth culling (`VOLFOG_FROXEL_CULL`) for the inject, temporal and scan
/// variants: none when `cull` is false.
pub fn cull_defines(cull: bool) -> Vec<String> {
    if cull {
        vec![CULL_DEFINE.to_string()]
    } else {
        Vec::new()
    }
}

/// The define that enables depth culling in inject, temporal and scan.
pub const CULL_DEFINE: &str = "VOLFOG_FROXEL_CULL";

/// Options of the inject pass and its CPU mirror.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InjectOptions {
    /// Jittered sample positions (`VOLFOG_INJECT_JITTER`).
    pub jitter: bool,
    /// AC4 two-colour sun phase (`VOLFOG_INJECT_TWO_COLOR_PHASE`).
    pub two_color_phase: bool,
    /// Density multiplied by a 3D texture (`VOLFOG_INJECT_DENSITY_TEXTURE`).
    pub density_texture: bool,
    /// Log-space ESM (`VOLFOG_ESM_LOG_SPACE`); ignored with `shadow_compare`.
    pub esm_log_space: bool,
    /// The compare filter instead of the ESM (`VOLFOG_INJECT_SHADOW_COMPARE`): the sun's
    /// and shadowed lights' depth maps compared at the taps of `ShadowTaps`.
    pub shadow_compare: bool,
    /// Noise read from the baked tileable texture instead of evaluated
    /// (`VOLFOG_INJECT_NOISE_TEXTURE`, on by default).
    pub noise_texture: bool,
    /// Froxels behind their column's live slices skipped (`VOLFOG_FROXEL_CULL`).
    pub depth_cull: bool,
    /// One froxel of each pair of slices injected per frame
    /// (`VOLFOG_INJECT_CHECKERBOARD`; `FogFrame::checkerboard` must then be 1).
    pub checkerboard: bool,
    /// The sun term passes the cloud layer's shadow (`VOLFOG_INJECT_CLOUD_SHADOW`).
    pub cloud_shadow: bool,
    /// Point and spot lights with a projection pass their shadow in the local-light
    /// ESM atlas and their cookie (`VOLFOG_INJECT_LOCAL_SHADOWS`).
    pub local_shadows: bool,
    /// fbm octaves (`VOLFOG_INJECT_NOISE_OCTAVES`), see
    /// [`limits::NOISE_OCTAVES`](crate::limits::NOISE_OCTAVES).
    pub noise_octaves: u32,
    /// Temporal reprojection fused into injection (`VOLFOG_INJECT_TEMPORAL`): the pass
    /// blends each froxel with its reprojected history and writes the stabilised
    /// volume, so the temporal pass does not run
    /// ([`InjectResources::temporal`](crate::pipeline::inject::InjectResources::temporal)).
    pub temporal: bool,
    /// The user's density function added to the medium
    /// (`VOLFOG_INJECT_CUSTOM_DENSITY`; composed with the user's module, see
    /// `FogConfig::custom_density`).
    pub custom_density: bool,
    /// Rectangle and disk emitters added to the lights (`VOLFOG_INJECT_AREA_LIGHTS`,
    /// binding 33; see `volfog::area_lights`).
    pub area_lights: bool,
    /// Particles added to the medium (`VOLFOG_INJECT_PARTICLES`, binding 34; see
    /// `volfog::particles`).
    pub particles: bool,
    /// The medium's extinction beyond its height profile dims the lights' paths
    /// (`VOLFOG_INJECT_MEDIUM_SHADOW`, bindings 35 to 37; see `volfog::medium_shadow`).
    pub medium_shadow: bool,
}

impl Default for InjectOptions {
    fn default() -> Self {
        Self {
            jitter: true,
            two_color_phase: false,
            density_texture: false,
            esm_log_space: false,
            shadow_compare: false,
            noise_texture: true,
            depth_cull: false,
            checkerboard: false,
            cloud_shadow: false,
            local_shadows: false,
            noise_octaves: manifest::INJECT_NOISE_OCTAVES.default,
            temporal: false,
            custom_density: false,
            area_lights: false,
            particles: false,
            medium_shadow: false,
        }
    }
}

impl InjectOptions {
    /// The defines of the inject variant, sorted.
    pub fn defines(&self) -> Vec<String> {
        let mut d = Vec::new();
        if self.shadow_compare {
            d.push("VOLFOG_INJECT_SHADOW_COMPARE".to_string());
        } else if self.esm_log_space {
            d.push("VOLFOG_ESM_LOG_SPACE".to_string());
        }
        if self.jitter {
            d.push("VOLFOG_INJECT_JITTER".to_string());
        }
        if self.two_color_phase {
            d.push("VOLFOG_INJECT_TWO_COLOR_PHASE".to_string());
        }
        if self.density_texture {
            d.push("VOLFOG_INJECT_DENSITY_TEXTURE".to_string());
        }
        if self.cloud_shadow {
            d.push("VOLFOG_INJECT_CLOUD_SHADOW".to_string());
        }
        if self.local_shadows {
            d.push("VOLFOG_INJECT_LOCAL_SHADOWS".to_string());
        }
        if self.noise_texture {
            d.push("VOLFOG_INJECT_NOISE_TEXTURE".to_string());
        }
        if self.checkerboard {
            d.push("VOLFOG_INJECT_CHECKERBOARD".to_string());
        }
        if self.temporal {
            d.push("VOLFOG_INJECT_TEMPORAL".to_string());
        }
        if self.custom_density {
            d.push(manifest::CUSTOM_DENSITY.define.to_string());
        }
        if self.area_lights {
            d.push("VOLFOG_INJECT_AREA_LIGHTS".to_string());
        }
        if self.particles {
            d.push("VOLFOG_INJECT_PARTICLES".to_string());
        }
        if self.medium_shadow {
            d.push("VOLFOG_INJECT_MEDIUM_SHADOW".to_string());
        }
        d.extend(cull_defines(self.depth_cull));
        if self.noise_octaves != manifest::INJECT_NOISE_OCTAVES.default {
            d.push(format!(
                "{}={}",
                manifest::INJECT_NOISE_OCTAVES.name,
                self.noise_octaves
            ));
        }
        d.sort();
        d
    }
}

/// Options of the ESM passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EsmOptions {
    /// Filter in log space (`VOLFOG_ESM_LOG_SPACE`).
    pub log_space: bool,
    /// Box blur radius (`VOLFOG_ESM_BLUR_RADIUS`), see
    /// [`limits::ESM_BLUR_RADIUS`](crate::limits::ESM_BLUR_RADIUS).
    pub blur_radius: u32,
    /// The shadow map holds reversed depth, 1 at the light's near plane and 0 at its
    /// far plane, as reverse-Z renderers (Bevy among them) draw it
    /// (`VOLFOG_ESM_REVERSED_Z`): the downsample reads `1 - d`. The cascades'
    /// `light_from_world` still map to standard depth (0 at the near plane).
    pub reversed_z: bool,
}

impl Default for EsmOptions {
    fn default() -> Self {
        Self {
            log_space: false,
            blur_radius: manifest::ESM_BLUR_RADIUS.default,
            reversed_z: false,
        }
    }
}

impl EsmOptions {
    /// The defines of the downsample variant.
    pub fn downsample_defines(&self) -> Vec<String> {
        let mut d = self.filter_defines();
        if self.reversed_z {
            d.push("VOLFOG_ESM_REVERSED_Z".to_string());
        }
        d
    }

    fn filter_defines(&self) -> Vec<String> {
        if self.log_space {
            vec!["VOLFOG_ESM_LOG_SPACE".to_string()]
        } else {
            Vec::new()
        }
    }

    /// The defines of the blur variant.
    pub fn blur_defines(&self) -> Vec<String> {
        let mut d = self.filter_defines();
        if self.blur_radius != manifest::ESM_BLUR_RADIUS.default {
            d.push(format!(
                "{}={}",
                manifest::ESM_BLUR_RADIUS.name,
                self.blur_radius
            ));
        }
        d
    }
}
