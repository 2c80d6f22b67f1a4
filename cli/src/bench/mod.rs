//! `volfog bench`: the time of every pass of the froxel pipeline, measured side by
//! side in the same run with the floors and the alternative it is compared with:
//!
//! 1. the scan against a plain copy of the same volume (160x90x128 rgba16float, the
//!    scan's access pattern): the bandwidth floor;
//! 2. the fullscreen apply at 1920x1080 against a fullscreen blit of the same size;
//! 3. the froxel pipeline (inject + temporal + scan + 1080p apply) against a per-pixel
//!    raymarch of the same scene with 64 samples per pixel (`raymarch.wgsl`, which reads
//!    the sun's shadow from the filtered ESM of the ESM fog of 8.);
//! 4. the froxel pipeline (without apply) behind a 1280x720 camera against a 3840x2160
//!    camera, three pairs per frame in alternating order: the volume does not depend on
//!    the screen;
//! 5. the cheap path at 1080p: depth culling by the scene's depth buffer, checkerboard
//!    amortisation and the noise texture, each alone and all three, per pass, with the
//!    inject against a plain write of the volume (its floor) and the whole pipeline
//!    against the raymarch; and the share of froxels culling keeps;
//! 6. epipolar sun shafts at 1080p: the min/max tree march against the march of the
//!    same samples over every section of the shadow map, and the whole epipolar path
//!    (tree build included) against the per-pixel brute-force march, with the error of
//!    its image against that reference;
//! 7. four spot and two point lights over the same scene and medium, unshadowed and
//!    shadowed through the local-light ESM atlas (depth maps ray cast on the CPU from
//!    the scene's geometry) by fogs with the ESM filter: inject with and without the
//!    shadows and compiled without them (`FogConfig::local_shadows` `None`), and the
//!    atlas pass, every map filtered and the maps kept; and the same lights under the
//!    compare filter, unshadowed and shadowed (inject alone: it has no atlas);
//! 8. the two shadow filters (`FogConfig::shadow_filter`) for the sun: the baseline's
//!    inject (the default compare filter, one tap) and the same at two taps against ESM
//!    downsample + ESM blur + inject of the baseline with `ShadowFilter::Esm`, the
//!    order rotating from frame to frame;
//! 9. short-lived lights (`FrameInputs::transient_lights`): the baseline's scan without
//!    transient lights, with one and with eight, the order rotating from frame to frame;
//! 10. area lights (`FrameInputs::area_lights`): the baseline's inject with room for
//!     them, with four point, rectangle or disk lights added, the order rotating;
//! 11. particles (`FrameInputs::particles`): the baseline's inject with room for 10,000,
//!     with none, 1,000 and 10,000, the order rotating;
//! 12. the medium's shadows (`FogConfig::medium_shadows`): the `medium_shadow` pass and
//!     the inject that reads it against the baseline's inject;
//! 13. stereo fog (`StereoFog`, two 1920x1080 eye views 64 mm apart) against one mono
//!     fog and against two, whole frames with and without the applies, after the
//!     frames above (its own warm-up and measured frames).
//!
//! The baseline takes `FogConfig::default`'s shadow filter (the compare filter), so its
//! ESM passes do not run; the ESM rows come from the ESM fog of 8.
//!
//! Every pass is submitted alone and waited for, and timed by GPU timestamp queries
//! (`wgpu::Features::TIMESTAMP_QUERY`, required) and by the wall time from submission
//! to completion; the table uses the timestamps, except on CPU adapters (lavapipe),
//! whose compute-pass timestamps are recorded by the rasterizer threads when a later
//! draw is flushed and so do not bracket the pass; there the wall time is used (both
//! are in the JSON). Each frame runs every workload (the slow raymarch only in the last
//! warm-up frame and the first `--raymarch-frames` measured frames); each series is
//! reported by its median over the measured frames with min, max, p10 and p90, printed
//! as a table and written as JSON. The targets are printed, never asserted.

mod area_lights;
pub mod cost;
mod floors;
mod local_lights;
mod medium_shadows;
mod particles;
mod passes;
pub mod raymarch;
mod report;
pub(crate) mod scene;
mod shadow_cost;
mod stereo;
mod table;
mod transient;
pub(crate) mod workloads;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use serde::Serialize;
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::{FogConfig, FogError, FogPass, PassTimings, TimestampPairs, VolumetricFog};
use volfog_testkit::gpu::texture_2d;
use volfog_testkit::{Gpu, GpuError};

use raymarch::{RAYMARCH_STEPS, Raymarch, RaymarchOptions, ShaderError};
use scene::Scene;

pub use area_lights::AreaLightCost;
use area_lights::*;
use floors::*;
use local_lights::*;
pub use medium_shadows::MediumShadowCost;
use medium_shadows::*;
pub use particles::ParticleCost;
use particles::*;
use passes::*;
pub use report::*;
pub use shadow_cost::*;
pub use stereo::StereoCost;
use stereo::*;
pub use table::table;
pub use transient::TransientCost;
use transient::*;
use workloads::*;

/// Warm-up frames of a default run. On lavapipe (Mesa 22.3, 2 CPU cores) a frame of
/// every workload but the raymarch takes about 5 s of wall time and a 1080p raymarch
/// about 9 s, so the default run (2 + 7 frames, 1 + 2 of them with the raymarch) takes
/// about two minutes and `--quick` about half of that.
pub const DEFAULT_WARMUP: u32 = 2;
/// Measured frames of a default run.
pub const DEFAULT_FRAMES: u32 = 7;
/// Measured frames of a default run that include the raymarch.
pub const DEFAULT_RAYMARCH_FRAMES: u32 = 2;
/// Warm-up frames of `--quick`.
pub const QUICK_WARMUP: u32 = 1;
/// Measured frames of `--quick`.
pub const QUICK_FRAMES: u32 = 2;
/// Measured frames of `--quick` that include the raymarch.
pub const QUICK_RAYMARCH_FRAMES: u32 = 1;

/// The colour format the fog is applied onto.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The main screen (apply, blit and raymarch).
const SCREEN: (u32, u32) = (1920, 1080);
/// The two cameras of the screen-independence comparison.
const SMALL_SCREEN: (u32, u32) = (1280, 720);
const LARGE_SCREEN: (u32, u32) = (3840, 2160);
/// Pairs of the two cameras run in each measured frame: each pair is one sample of the
/// 4K / 720p ratio, so 7 frames give 21 paired samples.
const SCREEN_PAIRS: u32 = 3;

/// Target: scan / copy.
const TARGET_SCAN: f64 = 1.25;
/// Target: apply / blit.
const TARGET_APPLY: f64 = 1.5;
/// Target: raymarch / froxel pipeline (speed-up).
const TARGET_SPEEDUP: f64 = 20.0;
/// Target: inject (culled, checkerboard, noise texture) / plain write of the volume.
const TARGET_INJECT: f64 = 5.0;
/// Target: raymarch / fast froxel pipeline (speed-up).
const TARGET_FAST_SPEEDUP: f64 = 50.0;
/// Target: froxel cost at 4K / 720p.
const TARGET_SCREEN: f64 = 1.05;
/// Target: march of the ray-marching samples over every section / min/max tree march.
const TARGET_TREE_MARCH: f64 = 5.0;
/// Target: per-pixel brute force / the whole epipolar path at 1080p.
const TARGET_EPIPOLAR: f64 = 4.0;
/// Target: inject (and the atlas pass) with four spot and two point lights shadowed /
/// inject with the same lights unshadowed (or compiled without local shadows).
const TARGET_LOCAL_SHADOWS: f64 = 1.5;
/// Target: the compare filter's shadow passes / the ESM filter's, for the sun
/// (inject / ESM downsample + blur + inject) and for the shadowed lamps (inject /
/// inject + atlas): the compare filter at no more than the ESM path's cost.
const TARGET_SHADOW_FILTER: f64 = 1.0;
/// Target: GPU memory of `VolumetricFog` at the default configuration (MiB).
const TARGET_MEMORY_MIB: f64 = 48.0;

/// Arguments of `volfog bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Frames run before measuring [default: 2; 1 with --quick].
    #[arg(long)]
    warmup: Option<u32>,
    /// Measured frames [default: 7; 2 with --quick].
    #[arg(long)]
    frames: Option<u32>,
    /// Measured frames that also run the (slow) per-pixel raymarch, at most --frames
    /// [default: 2; 1 with --quick]. The raymarch also runs in the last warm-up frame.
    #[arg(long)]
    raymarch_frames: Option<u32>,
    /// Where to write the JSON report.
    #[arg(long, default_value = "bench.json")]
    out: PathBuf,
    /// Print the JSON report to stdout; the table and the progress lines go to stderr
    /// (the report is still written to --out).
    #[arg(long)]
    json: bool,
    /// A short run (1 warm-up + 2 measured frames, 1 with the raymarch, unless given).
    #[arg(long)]
    quick: bool,
    /// Which clock the table uses: GPU timestamps, or the CPU wall time from submitting
    /// a pass to its completion (each pass is submitted alone). `auto` picks the wall
    /// time on CPU adapters (lavapipe), whose compute-pass timestamps are recorded by
    /// the rasterizer threads at a later flush and do not bracket the pass, and the
    /// timestamps elsewhere.
    #[arg(long, value_enum, default_value_t = ClockArg::Auto)]
    clock: ClockArg,
    /// Run only the stereo comparison (12.): its table, and its figures as the JSON
    /// report.
    #[arg(long)]
    stereo_only: bool,
}

/// `--clock`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ClockArg {
    /// Wall time on CPU adapters, GPU timestamps elsewhere.
    Auto,
    /// GPU timestamp queries.
    Gpu,
    /// CPU wall time per pass submission.
    Cpu,
}

/// The clock of the reported figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Clock {
    /// `end - begin` of the pass's timestamp queries.
    GpuTimestamps,
    /// Wall time from submitting the pass alone to its completion.
    CpuWallPerSubmission,
}

impl Clock {
    fn describe(self) -> &'static str {
        match self {
            Clock::GpuTimestamps => "GPU timestamp queries (end - begin of each pass)",
            Clock::CpuWallPerSubmission => {
                "CPU wall time from submitting each pass alone to its completion \
                 (a CPU adapter: its compute-pass timestamps do not bracket the pass)"
            }
        }
    }
}

/// One measurement by both clocks (ms).
#[derive(Debug, Clone, Copy, Default)]
struct Sample {
    gpu: f64,
    cpu: f64,
}

impl std::ops::Add for Sample {
    type Output = Sample;
    fn add(self, o: Sample) -> Sample {
        Sample {
            gpu: self.gpu + o.gpu,
            cpu: self.cpu + o.cpu,
        }
    }
}

/// Submits a command buffer alone and waits for it; the wall time (ms).
fn submit_and_wait(gpu: &Gpu, commands: wgpu::CommandBuffer) -> Result<f64, BenchError> {
    let start = Instant::now();
    gpu.queue.submit([commands]);
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| BenchError::Readback(e.to_string()))?;
    Ok(start.elapsed().as_secs_f64() * 1.0e3)
}

/// Errors of the benchmark.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// No adapter or no device.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The froxel pipeline refused the configuration or the device.
    #[error(transparent)]
    Fog(#[from] FogError),
    /// A bench shader failed to compose.
    #[error(transparent)]
    Shader(#[from] ShaderError),
    /// A frame's inputs are out of range.
    #[error(transparent)]
    Invalid(#[from] volfog::limits::InvalidValue),
    /// The sky passes failed to build.
    #[error(transparent)]
    Sky(#[from] volfog::pipeline::sky::SkyError),
    /// A volfog pass failed to compose.
    #[error(transparent)]
    Codegen(#[from] volfog::shaders::CodegenError),
    /// The epipolar shafts refused their inputs.
    #[error(transparent)]
    Epipolar(#[from] volfog::pipeline::epipolar::EpipolarError),
    /// The adapter cannot time passes.
    #[error(
        "the adapter {adapter} does not support timestamp queries \
         (wgpu::Features::TIMESTAMP_QUERY), which volfog bench needs to time every pass"
    )]
    NoTimestamps {
        /// The adapter.
        adapter: String,
    },
    /// Reading the timestamps back failed.
    #[error("reading the GPU timestamps back failed: {0}")]
    Readback(String),
    /// `--frames 0`.
    #[error("--frames must be at least 1")]
    NoFrames,
    /// Writing the report failed.
    #[error("writing {path}: {source}")]
    Io {
        /// The report path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

/// Runs the benchmark from the command line.
pub fn main(args: BenchArgs) -> ExitCode {
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &BenchArgs) -> Result<(), BenchError> {
    let start = Instant::now();
    let plan = Plan::new(args)?;
    let gpu = Gpu::with_features(wgpu::Features::TIMESTAMP_QUERY)?;
    if !gpu
        .device
        .features()
        .contains(wgpu::Features::TIMESTAMP_QUERY)
    {
        return Err(BenchError::NoTimestamps {
            adapter: gpu.describe(),
        });
    }
    let clock = match args.clock {
        ClockArg::Gpu => Clock::GpuTimestamps,
        ClockArg::Cpu => Clock::CpuWallPerSubmission,
        ClockArg::Auto if gpu.info.device_type == wgpu::DeviceType::Cpu => {
            Clock::CpuWallPerSubmission
        }
        ClockArg::Auto => Clock::GpuTimestamps,
    };
    // With --json, stdout carries the report alone.
    let say = |line: String| {
        if args.json {
            eprintln!("{line}");
        } else {
            println!("{line}");
        }
    };
    say(format!("volfog bench on {}", gpu.describe()));
    if args.stereo_only {
        return run_stereo_only(args, &gpu, &plan, &say);
    }
    say(format!("clock: {}", clock.describe()));

    // Memory at the default configuration (no timestamps), before anything else.
    let memory_bytes = VolumetricFog::new(&gpu.device, &FogConfig::default())?.memory_bytes();
    let mut work = Workloads::new(&gpu)?;
    let size = work.config.volume_size;
    say(format!(
        "froxels {}x{}x{} rgba16float; apply, blit and raymarch ({RAYMARCH_STEPS} steps/pixel) at {}x{}; \
         {} warm-up + {} measured frames (setup {:.1} s)",
        size.x,
        size.y,
        size.z,
        SCREEN.0,
        SCREEN.1,
        plan.warmup,
        plan.frames,
        start.elapsed().as_secs_f64()
    ));
    let mut samples: std::collections::BTreeMap<&str, Vec<Sample>> =
        SERIES.iter().map(|(k, _)| (*k, Vec::new())).collect();
    let mut paired: std::collections::BTreeMap<&'static str, Vec<f64>> =
        PAIRED.iter().map(|(k, _, _)| (*k, Vec::new())).collect();
    let pick = |s: Sample| match clock {
        Clock::GpuTimestamps => s.gpu,
        Clock::CpuWallPerSubmission => s.cpu,
    };
    for f in 0..plan.warmup + plan.frames {
        let (measured, with_raymarch) = plan.frame(f);
        let frame = work.frame(&gpu, f, with_raymarch)?;
        let get = |key: &str| frame.iter().find(|(k, _)| *k == key).map(|(_, s)| *s);
        eprintln!(
            "frame {}/{}{}: froxel pipeline 1080p {:.1} ms{} ({:.0} s elapsed)",
            f + 1,
            plan.warmup + plan.frames,
            if measured { "" } else { " (warm-up)" },
            get("froxel_1080p").map_or(f64::NAN, pick),
            get("raymarch_1080p")
                .map(|r| format!(", raymarch {:.1} ms", pick(r)))
                .unwrap_or_default(),
            start.elapsed().as_secs_f64()
        );
        if measured {
            for (key, numerator, denominator) in PAIRED {
                if let (Some(a), Some(b)) = (get(numerator), get(denominator)) {
                    paired
                        .get_mut(key)
                        .expect("listed in PAIRED")
                        .push(pick(a) / pick(b));
                }
            }
            for (key, value) in frame {
                samples.get_mut(key).expect("listed in SERIES").push(value);
            }
        }
    }
    let live = volfog_testkit::scene::live_fraction(&gpu, &work.variants[3].fog)?
        .ok_or_else(|| BenchError::Readback("the live slices of a culling fog".to_string()))?;
    let shaft_image = work.shafts.image_error(&gpu)?;
    let last = work
        .scene
        .inputs((plan.warmup + plan.frames) as f32 / 60.0, work.cascades);
    let [esm_through, compare_through] = work.local_lights.light_through_shadows(&gpu, &last)?;
    work.local_lights.setup.light_through_shadows = esm_through;
    work.local_lights.setup.compare_light_through_shadows = compare_through;
    let raymarch_esm = RaymarchEsm::read(&gpu, work.esm.fog.esm_texture(), &work.config)?;
    let stereo = StereoBench::new(&gpu, &work.config, &work.scene)?.run(
        &gpu,
        &plan,
        &work.scene,
        work.cascades,
    )?;
    let report = summarize(
        &gpu,
        clock,
        &plan,
        &work.config,
        &samples,
        Extra {
            memory_bytes,
            live_fraction: live,
            beyond_far: work.beyond_far,
            shaft_image,
            local_lights: work.local_lights.setup,
            raymarch_esm,
            paired,
            stereo,
        },
        start,
    )?;
    let json = serde_json::to_string_pretty(&report).expect("the report serializes") + "\n";
    if args.json {
        eprint!("{}", table(&report));
        print!("{json}");
    } else {
        print!("{}", table(&report));
    }
    std::fs::write(&args.out, &json).map_err(|source| BenchError::Io {
        path: args.out.clone(),
        source,
    })?;
    say(format!("wrote {}", args.out.display()));
    Ok(())
}

/// `--stereo-only`: the stereo comparison alone over the bench scene.
fn run_stereo_only(
    args: &BenchArgs,
    gpu: &Gpu,
    plan: &Plan,
    say: &dyn Fn(String),
) -> Result<(), BenchError> {
    let config = base_config();
    let scene = Scene::new();
    let (cascades, _) = scene.cascades(&config);
    let cost = StereoBench::new(gpu, &config, &scene)?.run(gpu, plan, &scene, cascades)?;
    let mut out = String::new();
    stereo_table(&mut out, &cost);
    let json = serde_json::to_string_pretty(&cost).expect("the figures serialize") + "\n";
    if args.json {
        eprint!("{out}");
        print!("{json}");
    } else {
        print!("{out}");
    }
    std::fs::write(&args.out, &json).map_err(|source| BenchError::Io {
        path: args.out.clone(),
        source,
    })?;
    say(format!("wrote {}", args.out.display()));
    Ok(())
}
