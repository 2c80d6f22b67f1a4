//! The report's sections on shadows: the shadowed point and spot lights through the
//! ESM atlas, the two shadow filters side by side (the sun's cascades and the lamps),
//! and the ESM the raymarch reads.

use super::*;

/// Four spot and two point lights over the bench scene, shadowed through the local-light
/// ESM atlas (fogs of the baseline configuration with `ShadowFilter::Esm`) against the
/// same lights unshadowed and against them lit by an inject compiled without local
/// shadows, in the same run.
#[derive(Debug, Clone, Serialize)]
pub struct LocalShadowCost {
    /// Median inject with the lights shadowed / median inject with them unshadowed.
    pub inject_shadowed_vs_unshadowed: Ratio,
    /// Median (inject + atlas pass) with the lights shadowed / median inject with them
    /// unshadowed.
    pub total_shadowed_vs_unshadowed: Ratio,
    /// Median inject with the lights shadowed / median inject of the same lights with
    /// `FogConfig::local_shadows` `None` (compiled without local shadows).
    pub inject_shadowed_vs_compiled_out: Ratio,
    /// Median (inject + atlas pass) with the lights shadowed / median inject with
    /// `local_shadows` `None`.
    pub total_shadowed_vs_compiled_out: Ratio,
    /// Median (inject + atlas pass) with the lights shadowed and their maps unchanged
    /// (`ShadowedLight::map_unchanged`: the atlas keeps its layers and fills none) /
    /// median inject with them unshadowed.
    pub total_kept_vs_unshadowed: Ratio,
    /// Median inject of the lights unshadowed / with `local_shadows` `None`: what
    /// compiling the local shadows in costs lights without a shadow.
    pub unshadowed_vs_compiled_out: f64,
    /// Median atlas pass (downsample and blur of the frame's layers), ms.
    pub atlas_ms: f64,
    /// Bytes the atlas adds to `VolumetricFog::memory_bytes()` (the atlas and the
    /// blur's scratch array).
    pub atlas_bytes: u64,
    /// The same in MiB.
    pub atlas_mib: f64,
    /// Atlas texels per side (`LocalShadowConfig::resolution`).
    pub atlas_resolution: u32,
    /// Atlas layers the frame filled (one per spot light, six per point light).
    pub atlas_layers: u32,
    /// Atlas layers the frame with unchanged maps kept (and filled: `kept_filled`).
    pub kept_layers: u32,
    /// Atlas layers the frame with unchanged maps filled.
    pub kept_filled: u32,
    /// Texels per side of the lights' depth maps.
    pub depth_map_resolution: u32,
    /// Bytes of the lights' depth maps (Depth32Float; the caller's textures).
    pub depth_map_bytes: u64,
    /// Spot lights shadowed.
    pub spot_shadows: u32,
    /// Point lights shadowed.
    pub point_shadows: u32,
    /// Lights beyond the budget, lit unshadowed.
    pub over_budget: u32,
    /// The six lights' in-scattering with their shadows / without (inject alone, the
    /// sun, ambient light and emission off; rgb summed over every froxel): below 1 as
    /// far as the shadows darken the fog in view (the ESM filter).
    pub light_through_shadows: f64,
}

/// The two filters of `FogConfig::shadow_filter` side by side in the same run, the
/// fogs of the baseline configuration otherwise: the sun's cascades (the baseline,
/// which takes the default compare filter at one tap, and the same fog at two taps,
/// against a fog with `ShadowFilter::Esm` whose ESM passes run each frame), and the six
/// shadowed lamps of [`LocalShadowCost`] (the compare filter's shadowed inject against
/// the ESM filter's inject and atlas pass).
#[derive(Debug, Clone, Serialize)]
pub struct ShadowFilterCost {
    /// Inject with the compare filter, one tap / (ESM downsample + ESM blur + inject)
    /// with the ESM filter, per frame.
    pub sun_compare_vs_esm: Ratio,
    /// The same with the compare filter at two taps.
    pub sun_compare_2_vs_esm: Ratio,
    /// Median inject, compare filter (one tap) / median inject, ESM filter: the
    /// look-ups alone, without the ESM passes.
    pub sun_inject_compare_vs_esm: f64,
    /// Median inject, compare filter, two taps / one tap.
    pub sun_compare_2_vs_compare: f64,
    /// Median ESM downsample + median ESM blur (ms): the passes the compare filter
    /// does not run.
    pub sun_esm_passes_ms: f64,
    /// Median inject, compare filter, the six lamps shadowed / median inject, the same
    /// filter, the lamps unshadowed.
    pub lamps_compare_vs_unshadowed: Ratio,
    /// Median inject, compare filter, the lamps shadowed / median (inject + atlas
    /// pass), ESM filter, the lamps shadowed with every map filtered.
    pub lamps_compare_vs_esm: Ratio,
    /// The same against the ESM filter's frame with the maps unchanged (the atlas
    /// kept, not filled).
    pub lamps_compare_vs_esm_kept: f64,
    /// Median inject with the lamps unshadowed, compare filter / ESM filter: the two
    /// filters' sun look-ups in the lamps' frame.
    pub lamps_unshadowed_compare_vs_esm: f64,
    /// Bytes the compare filter's shadowed lamps add to `VolumetricFog::memory_bytes()`
    /// (with their maps set minus without): it has no atlas.
    pub lamps_compare_bytes: u64,
    /// The six lamps' in-scattering with / without their shadows under the compare
    /// filter (one frame's taps; [`LocalShadowCost::light_through_shadows`] is the ESM
    /// filter's).
    pub lamps_compare_light_through_shadows: f64,
}

/// The filtered ESM the per-pixel raymarch reads for the sun's shadow (that of the
/// ESM filter's fog, filtered from the bench's shadow map and cascades each frame),
/// read back after the run.
#[derive(Debug, Clone, Serialize)]
pub struct RaymarchEsm {
    /// Texels per side and layers (one per cascade).
    pub size: [u32; 3],
    /// The smallest occluder depth its texels hold (the filtered occluder term
    /// decoded: `ln(mean(exp(c d))) / c`, in [0, 1]).
    pub occluder_depth_min: f64,
    /// The largest.
    pub occluder_depth_max: f64,
    /// Texels that are not finite.
    pub nan_texels: usize,
}

impl RaymarchEsm {
    /// The ESM `texture` of a fog with `config`'s ESM settings and the ESM filter, read
    /// back.
    pub(super) fn read(
        gpu: &Gpu,
        texture: &wgpu::Texture,
        config: &FogConfig,
    ) -> Result<Self, BenchError> {
        let raw = gpu.read_texture_raw(texture, 4)?;
        let texels: &[f32] = bytemuck::cast_slice(&raw);
        let exponent = f64::from(config.esm_exponent);
        let depth = |v: f32| {
            let v = f64::from(v);
            if config.esm_log_space {
                v / exponent
            } else {
                v.ln() / exponent
            }
        };
        let finite: Vec<f64> = texels
            .iter()
            .filter(|v| v.is_finite())
            .map(|&v| depth(v))
            .collect();
        let s = texture.size();
        Ok(Self {
            size: [s.width, s.height, s.depth_or_array_layers],
            occluder_depth_min: finite.iter().copied().fold(f64::INFINITY, f64::min),
            occluder_depth_max: finite.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            nan_texels: texels.len() - finite.len(),
        })
    }
}

/// The atlas rows of the report from the medians of the run.
pub(super) fn local_shadow_cost(
    median: &dyn Fn(&str) -> f64,
    local: &LocalLightSetup,
) -> LocalShadowCost {
    LocalShadowCost {
        inject_shadowed_vs_unshadowed: Ratio::at_most(
            "median inject, 4 spot + 2 point lights shadowed / the same lights unshadowed",
            median("local_inject_shadowed") / median("local_inject_unshadowed"),
            TARGET_LOCAL_SHADOWS,
        ),
        total_shadowed_vs_unshadowed: Ratio::at_most(
            "median (inject + local shadow atlas), shadowed / median inject, unshadowed",
            median("local_shadowed_total") / median("local_inject_unshadowed"),
            TARGET_LOCAL_SHADOWS,
        ),
        inject_shadowed_vs_compiled_out: Ratio::at_most(
            "median inject, the lights shadowed / the same lights, local_shadows None",
            median("local_inject_shadowed") / median("local_inject_compiled_out"),
            TARGET_LOCAL_SHADOWS,
        ),
        total_shadowed_vs_compiled_out: Ratio::at_most(
            "median (inject + local shadow atlas), shadowed / median inject, local_shadows None",
            median("local_shadowed_total") / median("local_inject_compiled_out"),
            TARGET_LOCAL_SHADOWS,
        ),
        total_kept_vs_unshadowed: Ratio::at_most(
            "median (inject + local shadow atlas), shadowed, maps unchanged / median inject, unshadowed",
            median("local_kept_total") / median("local_inject_unshadowed"),
            TARGET_LOCAL_SHADOWS,
        ),
        unshadowed_vs_compiled_out: median("local_inject_unshadowed")
            / median("local_inject_compiled_out"),
        atlas_ms: median("local_shadow_atlas"),
        atlas_bytes: local.atlas_bytes,
        atlas_mib: to_mib(local.atlas_bytes),
        atlas_resolution: local.atlas_size,
        atlas_layers: local.stats.layers,
        kept_layers: local.kept_stats.kept,
        kept_filled: local.kept_stats.layers,
        depth_map_resolution: local.map_size,
        depth_map_bytes: local.map_bytes,
        spot_shadows: local.stats.spot_shadows,
        point_shadows: local.stats.point_shadows,
        over_budget: local.stats.unshadowed,
        light_through_shadows: local.light_through_shadows,
    }
}

/// The two filters' rows from the medians of the run and its per-frame ratios.
pub(super) fn shadow_filter_cost(
    median: &dyn Fn(&str) -> f64,
    per_frame: &dyn Fn(&str, &'static str) -> PairedRatio,
    local: &LocalLightSetup,
) -> ShadowFilterCost {
    let esm_total = median("local_shadowed_total");
    ShadowFilterCost {
        sun_compare_vs_esm: Ratio::paired_at_most(
            per_frame(
                "compare_vs_esm",
                "inject, compare filter (1 tap) / (ESM downsample + ESM blur + inject), ESM filter, per frame",
            ),
            TARGET_SHADOW_FILTER,
        ),
        sun_compare_2_vs_esm: Ratio::paired_at_most(
            per_frame(
                "compare_2_vs_esm",
                "inject, compare filter (2 taps) / (ESM downsample + ESM blur + inject), ESM filter, per frame",
            ),
            TARGET_SHADOW_FILTER,
        ),
        sun_inject_compare_vs_esm: median("inject") / median("inject_esm"),
        sun_compare_2_vs_compare: median("inject_compare_2") / median("inject"),
        sun_esm_passes_ms: median("esm_downsample") + median("esm_blur"),
        lamps_compare_vs_unshadowed: Ratio::at_most(
            "median inject, 4 spot + 2 point lights shadowed / unshadowed, compare filter",
            median("local_compare_shadowed") / median("local_compare_unshadowed"),
            TARGET_LOCAL_SHADOWS,
        ),
        lamps_compare_vs_esm: Ratio::at_most(
            "median inject, the lights shadowed, compare filter / median (inject + local shadow atlas), ESM filter",
            median("local_compare_shadowed") / esm_total,
            TARGET_SHADOW_FILTER,
        ),
        lamps_compare_vs_esm_kept: median("local_compare_shadowed") / median("local_kept_total"),
        lamps_unshadowed_compare_vs_esm: median("local_compare_unshadowed")
            / median("local_inject_unshadowed"),
        lamps_compare_bytes: local.compare_bytes,
        lamps_compare_light_through_shadows: local.compare_light_through_shadows,
    }
}
