//! The bench report: statistics per series, the ratios against their targets, memory
//! and the settings of the run (printed by [`super::table`]).

use super::*;

/// Statistics of one measured series, in milliseconds.
#[derive(Debug, Clone, Serialize)]
pub struct Stats {
    /// What was measured.
    pub label: String,
    /// Median.
    pub median_ms: f64,
    /// Smallest sample.
    pub min_ms: f64,
    /// Largest sample.
    pub max_ms: f64,
    /// 10th percentile (linear interpolation between ranks).
    pub p10_ms: f64,
    /// 90th percentile.
    pub p90_ms: f64,
    /// Every sample, in frame order.
    pub samples_ms: Vec<f64>,
    /// Median by the other clock (GPU timestamps when the table uses wall time, and
    /// the reverse), for comparison.
    pub other_clock_median_ms: f64,
}

impl Stats {
    pub(super) fn new(label: &str, samples: &[f64]) -> Self {
        let mut sorted = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        let at = |p: f64| {
            if sorted.is_empty() {
                return f64::NAN;
            }
            let rank = p * (sorted.len() - 1) as f64;
            let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
            sorted[lo] + (sorted[hi] - sorted[lo]) * (rank - lo as f64)
        };
        Self {
            label: label.to_string(),
            median_ms: at(0.5),
            min_ms: at(0.0),
            max_ms: at(1.0),
            p10_ms: at(0.1),
            p90_ms: at(0.9),
            samples_ms: samples.to_vec(),
            other_clock_median_ms: f64::NAN,
        }
    }
}

/// A ratio and its target: of medians, or the median of per-frame ratios.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    /// What is divided by what.
    pub definition: &'static str,
    /// The ratio.
    pub value: f64,
    /// Where the ratio is taken frame by frame: each frame's ratio, whose median is
    /// `value`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<PairedRatio>,
    /// The target, e.g. "<= 1.25".
    pub target: String,
    /// Whether the target is met.
    pub met: bool,
}

impl Ratio {
    pub(super) fn at_most(definition: &'static str, value: f64, limit: f64) -> Self {
        Self {
            definition,
            value,
            frames: None,
            target: format!("<= {limit}"),
            met: value <= limit,
        }
    }

    pub(super) fn at_least(definition: &'static str, value: f64, limit: f64) -> Self {
        Self {
            definition,
            value,
            frames: None,
            target: format!(">= {limit}"),
            met: value >= limit,
        }
    }

    /// The median of the per-frame ratios `frames`, at most `limit`.
    pub(super) fn paired_at_most(frames: PairedRatio, limit: f64) -> Self {
        Self {
            frames: Some(frames.clone()),
            ..Self::at_most(frames.definition, frames.median, limit)
        }
    }

    /// The median of the per-frame ratios `frames`, at least `limit`.
    pub(super) fn paired_at_least(frames: PairedRatio, limit: f64) -> Self {
        Self {
            frames: Some(frames.clone()),
            ..Self::at_least(frames.definition, frames.median, limit)
        }
    }
}

/// The four ratios.
#[derive(Debug, Clone, Serialize)]
pub struct Ratios {
    /// Scan / copy of the same volume.
    pub scan_vs_copy: Ratio,
    /// Apply / blit at 1080p.
    pub apply_vs_blit: Ratio,
    /// Raymarch / froxel pipeline at 1080p (how many times faster the froxels are).
    pub raymarch_vs_froxel: Ratio,
    /// Froxel pipeline behind a 4K camera / behind a 720p camera.
    pub froxel_4k_vs_720p: Ratio,
    /// Inject (baseline) / a plain write of the same volume.
    pub inject_vs_write: Ratio,
    /// Inject with culling, checkerboard and noise texture, the temporal blend fused
    /// into it / a plain write.
    pub inject_fast_vs_write: Ratio,
    /// Raymarch / the fast froxel pipeline at 1080p.
    pub raymarch_vs_froxel_fast: Ratio,
}

/// A ratio measured frame by frame (the two sides run back to back in each frame, in
/// alternating order), so one noisy frame does not decide it.
#[derive(Debug, Clone, Serialize)]
pub struct PairedRatio {
    /// What is divided by what, per frame.
    pub definition: &'static str,
    /// The ratio of each paired sample (of each measured frame, or of each pair of
    /// cameras for the 4K / 720p ratio), in the order they ran.
    pub samples: Vec<f64>,
    /// Their median.
    pub median: f64,
    /// The smallest.
    pub min: f64,
    /// The largest.
    pub max: f64,
}

impl PairedRatio {
    fn new(definition: &'static str, numerator: &[f64], denominator: &[f64]) -> Self {
        let samples: Vec<f64> = numerator
            .iter()
            .zip(denominator)
            .map(|(a, b)| a / b)
            .collect();
        Self::of(definition, samples)
    }

    /// The ratios `samples`, one per frame.
    fn of(definition: &'static str, samples: Vec<f64>) -> Self {
        let stats = Stats::new(definition, &samples);
        Self {
            definition,
            samples,
            median: stats.median_ms,
            min: stats.min_ms,
            max: stats.max_ms,
        }
    }
}

/// The cheap path with the temporal blend fused into inject against the same path
/// with the temporal pass apart, in the same run.
#[derive(Debug, Clone, Serialize)]
pub struct FusedTemporal {
    /// Median fused inject, ms.
    pub fused_inject_ms: f64,
    /// Median inject + median temporal with the pass apart, ms.
    pub separate_inject_temporal_ms: f64,
    /// The first over the second.
    pub fused_vs_separate: f64,
    /// Median (cull + inject + scan + apply), fused / the same with the temporal pass
    /// apart.
    pub froxel_fast_fused_vs_separate: f64,
}

/// The sky and cloud passes against a fullscreen blit at 1080p (no targets: their
/// cost relative to the floor of a fullscreen pass).
#[derive(Debug, Clone, Serialize)]
pub struct AtmosphereCost {
    /// Median sky solve (the whole 128 x 64 texture) / median 1080p blit.
    pub sky_solve_vs_blit: f64,
    /// Median cloud shadow pass / median blit, 1920x1080.
    pub cloud_shadow_vs_blit: f64,
    /// Median distance clouds pass / median blit, 1920x1080.
    pub distance_clouds_vs_blit: f64,
}

/// The apply pass's stages against a blit at 1080p (`apply_parts.wgsl`): where its
/// time goes on the adapter. Each part loads the depth and blends like apply.
#[derive(Debug, Clone, Serialize)]
pub struct ApplyBreakdown {
    /// The depth texel alone / blit.
    pub depth_vs_blit: f64,
    /// With the pixel's view position / blit.
    pub unproject_vs_blit: f64,
    /// With the fog coordinate and the volume look-up, no tail / blit.
    pub lookup_vs_blit: f64,
    /// The whole apply with the tail behind a branch no pixel takes / blit.
    pub tail_untaken_vs_blit: f64,
    /// The whole apply as the fog draws it / blit: the bench scene has no far-plane
    /// tail, so the variant without it (`VOLFOG_APPLY_NO_TAIL`); with a tail the apply
    /// costs about `tail_untaken_vs_blit` plus the tail of the pixels beyond far.
    pub apply_vs_blit: f64,
    /// Share of the 1080p pixels beyond the far plane (the tail's).
    pub beyond_far_fraction: f64,
}

/// Epipolar sun shafts at 1080p: the two ratios of the issue and the image error.
#[derive(Debug, Clone, Serialize)]
pub struct ShaftCost {
    /// Median march of the same samples over every section / median tree march.
    pub march_steps_vs_tree: Ratio,
    /// Median per-pixel brute force / median whole epipolar path (tree build included).
    pub reference_vs_epipolar: Ratio,
    /// The tree path's image against the reference.
    pub image: ShaftImage,
    /// Steps of the per-pixel reference march.
    pub reference_steps: u32,
}

/// The lit fraction of the epipolar image against the per-pixel reference.
#[derive(Debug, Clone, Serialize)]
pub struct ShaftImage {
    /// Mean absolute error of the lit fraction F (in [0, 1]) over every pixel, against
    /// the timed reference.
    pub lit_fraction_mean_abs_error: f64,
    /// Its 99th percentile.
    pub lit_fraction_p99_abs_error: f64,
    /// The same against the fine reference.
    pub fine_mean_abs_error: f64,
    /// Its 99th percentile.
    pub fine_p99_abs_error: f64,
    /// Mean absolute difference of the timed reference from the fine one.
    pub reference_vs_fine_mean_abs_error: f64,
    /// Steps per pixel of the fine reference.
    pub fine_reference_steps: u32,
    /// Pixels the resolve and the upscale corrected with a march.
    pub corrected_pixels: u32,
    /// Pixels that are not finite (NaN or Inf).
    pub nan_pixels: usize,
    /// `EpipolarShafts::memory_bytes()` at the bench's sampling.
    pub memory_bytes: u64,
}

/// Depth culling in the bench scene.
#[derive(Debug, Clone, Serialize)]
pub struct Culling {
    /// Fraction of the froxels the culling fog processed (1 = nothing culled).
    pub live_fraction: f64,
    /// Baseline inject / inject with depth culling alone.
    pub inject_saving: f64,
}

/// GPU memory of `VolumetricFog` at the default configuration.
#[derive(Debug, Clone, Serialize)]
pub struct Memory {
    /// `VolumetricFog::memory_bytes()`.
    pub bytes: u64,
    /// The same in MiB.
    pub mib: f64,
    /// The limit (MiB).
    pub limit_mib: f64,
    /// Whether it stays within the limit.
    pub met: bool,
}

/// What was run.
#[derive(Debug, Clone, Serialize)]
pub struct Settings {
    /// Froxels (x, y, slices).
    pub volume: [u32; 3],
    /// Volume texel format.
    pub volume_format: &'static str,
    /// Screen of apply, blit and raymarch.
    pub screen: [u32; 2],
    /// The two cameras of the screen-independence comparison.
    pub compared_screens: [[u32; 2]; 2],
    /// Samples per pixel of the raymarch.
    pub raymarch_steps: u32,
    /// Warm-up frames.
    pub warmup: u32,
    /// Measured frames.
    pub frames: u32,
    /// Measured frames that include the raymarch.
    pub raymarch_frames: u32,
}

/// The JSON report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Adapter name.
    pub adapter: String,
    /// Adapter, driver and backend.
    pub adapter_details: String,
    /// The clock of every figure.
    pub clock: Clock,
    /// What was run.
    pub settings: Settings,
    /// Every series, by key.
    pub passes: std::collections::BTreeMap<String, Stats>,
    /// The ratios and their targets.
    pub ratios: Ratios,
    /// Memory of the default configuration.
    pub memory: Memory,
    /// Depth culling in the bench scene.
    pub culling: Culling,
    /// The sky and the clouds against a blit.
    pub atmosphere: AtmosphereCost,
    /// The apply pass's stages against a blit.
    pub apply_breakdown: ApplyBreakdown,
    /// Epipolar sun shafts.
    pub shafts: ShaftCost,
    /// Shadowed point and spot lights (the ESM filter).
    pub local_shadows: LocalShadowCost,
    /// The two shadow filters side by side: the sun and the shadowed lamps.
    pub shadow_filters: ShadowFilterCost,
    /// The ESM the raymarch reads for the sun's shadow.
    pub raymarch_esm: RaymarchEsm,
    /// The temporal blend fused into inject against the temporal pass apart.
    pub fused_temporal: FusedTemporal,
    /// Median inject with `FogConfig::light_transmittance` (the default) / without:
    /// what attenuating the sun and the scene's lights through the medium costs.
    pub transmittance_inject_vs_without: f64,
    /// Each main pass against its memory floor at two bandwidths.
    pub cost: super::cost::CostModel,
    /// The scan with short-lived lights.
    pub transient_lights: TransientCost,
    /// Area lights against point lights in inject.
    pub area_lights: AreaLightCost,
    /// Stereo fog against one and two mono fogs.
    pub stereo: StereoCost,
    /// Inject with 0, 1,000 and 10,000 particles.
    pub particles: ParticleCost,
    /// The medium's shadows: their pass and inject against the baseline's inject.
    pub medium_shadows: MediumShadowCost,
    /// Wall-clock time of the whole run, seconds.
    pub wall_seconds: f64,
}

/// What a run measured besides the series.
pub(super) struct Extra {
    /// `VolumetricFog::memory_bytes()` at the default configuration.
    pub(super) memory_bytes: u64,
    /// The share of froxels the culling fog processed.
    pub(super) live_fraction: f64,
    /// The share of the 1080p pixels beyond the far plane.
    pub(super) beyond_far: f64,
    /// The epipolar image against its references.
    pub(super) shaft_image: ShaftImage,
    /// The shadowed local lights' setup and what their frame got.
    pub(super) local_lights: LocalLightSetup,
    /// The ESM the raymarch read.
    pub(super) raymarch_esm: RaymarchEsm,
    /// The ratios of [`PAIRED`], one per measured frame that ran both sides.
    pub(super) paired: std::collections::BTreeMap<&'static str, Vec<f64>>,
    /// Stereo fog's figures.
    pub(super) stereo: StereoCost,
}

/// The report of a run: statistics per series, ratios and memory.
pub(super) fn summarize(
    gpu: &Gpu,
    clock: Clock,
    plan: &Plan,
    config: &FogConfig,
    samples: &std::collections::BTreeMap<&str, Vec<Sample>>,
    extra: Extra,
    start: Instant,
) -> Result<Report, BenchError> {
    let Extra {
        memory_bytes,
        live_fraction,
        beyond_far,
        shaft_image,
        local_lights: local,
        raymarch_esm,
        paired,
        stereo,
    } = extra;
    let series = |k: &str, c: Clock| -> Vec<f64> {
        samples[k]
            .iter()
            .map(|s| match c {
                Clock::GpuTimestamps => s.gpu,
                Clock::CpuWallPerSubmission => s.cpu,
            })
            .collect()
    };
    let other = match clock {
        Clock::GpuTimestamps => Clock::CpuWallPerSubmission,
        Clock::CpuWallPerSubmission => Clock::GpuTimestamps,
    };
    let passes: std::collections::BTreeMap<String, Stats> = SERIES
        .iter()
        .map(|(k, label)| {
            let mut stats = Stats::new(label, &series(k, clock));
            stats.other_clock_median_ms = Stats::new(label, &series(k, other)).median_ms;
            (k.to_string(), stats)
        })
        .collect();
    let median = |k: &str| passes[k].median_ms;
    let screens = PairedRatio::new(
        "(inject + temporal + scan) behind a 3840x2160 / a 1280x720 camera, per pair of cameras (three pairs per frame)",
        &series("froxel_4k", clock),
        &series("froxel_720p", clock),
    );
    let per_frame =
        |key: &str, definition: &'static str| PairedRatio::of(definition, paired[key].clone());
    let ratios = Ratios {
        scan_vs_copy: Ratio::paired_at_most(
            per_frame("scan_vs_copy", "scan / copy, per frame"),
            TARGET_SCAN,
        ),
        apply_vs_blit: Ratio::paired_at_most(
            per_frame("apply_vs_blit", "apply / blit (1920x1080), per frame"),
            TARGET_APPLY,
        ),
        raymarch_vs_froxel: Ratio::paired_at_least(
            per_frame(
                "raymarch_vs_froxel",
                "raymarch / (inject + temporal + scan + apply), 1080p, per frame with the raymarch",
            ),
            TARGET_SPEEDUP,
        ),
        froxel_4k_vs_720p: Ratio::paired_at_most(screens, TARGET_SCREEN),
        inject_vs_write: Ratio::paired_at_most(
            per_frame(
                "inject_vs_write",
                "inject (baseline) / plain write of the volume, per frame",
            ),
            TARGET_INJECT,
        ),
        inject_fast_vs_write: Ratio::paired_at_most(
            per_frame(
                "inject_fast_vs_write",
                "inject (culled, checkerboard, noise texture, temporal fused) / plain write, per frame",
            ),
            TARGET_INJECT,
        ),
        raymarch_vs_froxel_fast: Ratio::paired_at_least(
            per_frame(
                "raymarch_vs_froxel_fast",
                "raymarch / fast (cull + fused inject + scan + apply), 1080p, per frame with the raymarch",
            ),
            TARGET_FAST_SPEEDUP,
        ),
    };
    let culling = Culling {
        live_fraction,
        inject_saving: median("inject") / median("inject_cull"),
    };
    let atmosphere = AtmosphereCost {
        sky_solve_vs_blit: median("sky_solve") / median("blit_1080p"),
        cloud_shadow_vs_blit: median("cloud_shadow_1080p") / median("blit_1080p"),
        distance_clouds_vs_blit: median("distance_clouds_1080p") / median("blit_1080p"),
    };
    let blit = median("blit_1080p");
    let apply_breakdown = ApplyBreakdown {
        depth_vs_blit: median("apply_part_depth") / blit,
        unproject_vs_blit: median("apply_part_unproject") / blit,
        lookup_vs_blit: median("apply_part_lookup") / blit,
        tail_untaken_vs_blit: median("apply_part_untaken") / blit,
        apply_vs_blit: median("apply_1080p") / blit,
        beyond_far_fraction: beyond_far,
    };
    let shafts = ShaftCost {
        march_steps_vs_tree: Ratio::at_least(
            "median march over every section / median min/max tree march (same samples)",
            median("epipolar_march_steps") / median("epipolar_march_tree"),
            TARGET_TREE_MARCH,
        ),
        reference_vs_epipolar: Ratio::at_least(
            "median per-pixel brute force / median epipolar path (trees included), 1080p",
            median("epipolar_reference_1080p") / median("epipolar_1080p"),
            TARGET_EPIPOLAR,
        ),
        image: shaft_image,
        reference_steps: volfog::uniforms::EpipolarSampling::new(1, 1, 64).reference_steps,
    };
    let local_shadows = local_shadow_cost(&median, &local);
    let shadow_filters = shadow_filter_cost(&median, &per_frame, &local);
    let transmittance_inject_vs_without = median("inject") / median("inject_no_transmittance");
    let separate = median("inject_fast_separate") + median("temporal_fast");
    let fused_temporal = FusedTemporal {
        fused_inject_ms: median("inject_fast"),
        separate_inject_temporal_ms: separate,
        fused_vs_separate: median("inject_fast") / separate,
        froxel_fast_fused_vs_separate: median("froxel_fast_1080p")
            / median("froxel_fast_separate_1080p"),
    };
    let cost = super::cost::model(config, &super::cost::sizes(config, live_fraction), &median)?;
    let transient_lights = transient_cost(&median, &per_frame);
    let area_lights = area_light_cost(&median);
    let particles = particle_cost(&median);
    let medium_shadows = medium_shadow_cost(&median);
    let mib = to_mib(memory_bytes);
    Ok(Report {
        adapter: gpu.info.name.clone(),
        adapter_details: gpu.describe(),
        clock,
        settings: Settings {
            volume: config.volume_size.to_array(),
            volume_format: "rgba16float",
            screen: [SCREEN.0, SCREEN.1],
            compared_screens: [
                [SMALL_SCREEN.0, SMALL_SCREEN.1],
                [LARGE_SCREEN.0, LARGE_SCREEN.1],
            ],
            raymarch_steps: RAYMARCH_STEPS,
            warmup: plan.warmup,
            frames: plan.frames,
            raymarch_frames: plan.raymarch_frames,
        },
        passes,
        ratios,
        culling,
        atmosphere,
        apply_breakdown,
        shafts,
        local_shadows,
        shadow_filters,
        raymarch_esm,
        fused_temporal,
        transmittance_inject_vs_without,
        memory: Memory {
            bytes: memory_bytes,
            mib,
            limit_mib: TARGET_MEMORY_MIB,
            met: mib <= TARGET_MEMORY_MIB,
        },
        cost,
        transient_lights,
        area_lights,
        stereo,
        particles,
        medium_shadows,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

pub(super) fn to_mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

pub(super) fn status(met: bool) -> &'static str {
    if met { "met" } else { "MISSED" }
}
