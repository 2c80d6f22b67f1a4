//! `volfog bench`: the time of every pass of the froxel pipeline, measured side by
//! side in the same run with the floors and the alternative it is compared with:
//!
//! 1. the scan against a plain copy of the same volume (160x90x128 rgba16float, the
//!    scan's access pattern): the bandwidth floor;
//! 2. the fullscreen apply at 1920x1080 against a fullscreen blit of the same size;
//! 3. the froxel pipeline (inject + temporal + scan + 1080p apply) against a per-pixel
//!    raymarch of the same scene with 64 samples per pixel (`raymarch.wgsl`);
//! 4. the froxel pipeline (without apply) behind a 1280x720 camera against a 3840x2160
//!    camera: the volume does not depend on the screen.
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

pub mod raymarch;
mod scene;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use serde::Serialize;
use volfog::pipeline::apply::ApplyPipeline;
use volfog::pipeline::{FogConfig, FogError, FogPass, PassTimings, TimestampPairs, VolumetricFog};
use volfog_testkit::{Gpu, GpuError};

use raymarch::{RAYMARCH_STEPS, Raymarch, RaymarchOptions, ShaderError};
use scene::Scene;

/// Warm-up frames of a default run. On lavapipe (Mesa 22.3, 2 CPU cores) a frame of
/// every workload but the raymarch takes 5 to 10 s of wall time and a 1080p raymarch
/// about a minute, so the default run (2 + 7 frames, 1 + 2 of them with the raymarch)
/// takes about 4 minutes and `--quick` about 2.
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

/// Target: scan / copy.
const TARGET_SCAN: f64 = 1.25;
/// Target: apply / blit.
const TARGET_APPLY: f64 = 1.5;
/// Target: raymarch / froxel pipeline (speed-up).
const TARGET_SPEEDUP: f64 = 20.0;
/// Target: froxel cost at 4K / 720p.
const TARGET_SCREEN: f64 = 1.05;
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
    fn new(label: &str, samples: &[f64]) -> Self {
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

/// A ratio of medians and its target.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    /// What is divided by what.
    pub definition: &'static str,
    /// The ratio.
    pub value: f64,
    /// The target, e.g. "<= 1.25".
    pub target: String,
    /// Whether the target is met.
    pub met: bool,
}

impl Ratio {
    fn at_most(definition: &'static str, value: f64, limit: f64) -> Self {
        Self {
            definition,
            value,
            target: format!("<= {limit}"),
            met: value <= limit,
        }
    }

    fn at_least(definition: &'static str, value: f64, limit: f64) -> Self {
        Self {
            definition,
            value,
            target: format!(">= {limit}"),
            met: value >= limit,
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
    /// Wall-clock time of the whole run, seconds.
    pub wall_seconds: f64,
}

/// Timestamp queries of the bench's own passes (begin/end pair per pass).
struct Timer {
    pairs: TimestampPairs,
}

impl Timer {
    fn new(gpu: &Gpu, pairs: u32) -> Self {
        Self {
            pairs: TimestampPairs::new(&gpu.device, "bench timestamps", pairs),
        }
    }

    fn compute(&self, pass: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        Some(self.pairs.compute(pass))
    }

    fn render(&self, pass: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        Some(self.pairs.render(pass, true, true))
    }

    /// Records one pass with `record` (which uses the timestamp writes of `slot`),
    /// submits it alone and returns its time by both clocks.
    fn run(
        &self,
        gpu: &Gpu,
        slot: u32,
        record: impl FnOnce(&mut wgpu::CommandEncoder),
    ) -> Result<Sample, BenchError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        record(&mut encoder);
        self.pairs.resolve(&mut encoder);
        let cpu = submit_and_wait(gpu, encoder.finish())?;
        let gpu_ms = self
            .pairs
            .read_ms(&gpu.device, &gpu.queue)
            .map_err(|e| BenchError::Readback(e.to_string()))?[slot as usize];
        Ok(Sample { gpu: gpu_ms, cpu })
    }
}

fn texture_2d(
    gpu: &Gpu,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn depth_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    })
}

/// One screen the froxel pipeline is applied to: its `VolumetricFog`, apply pass,
/// depth group and colour target.
struct Screen {
    fog: VolumetricFog,
    apply: ApplyPipeline,
    depth: wgpu::TextureView,
    depth_group: wgpu::BindGroup,
    color: wgpu::TextureView,
}

impl Screen {
    fn new(
        gpu: &Gpu,
        scene: &Scene,
        config: &FogConfig,
        shadow_map: &wgpu::Texture,
        size: (u32, u32),
    ) -> Result<Self, BenchError> {
        let mut fog = VolumetricFog::new(&gpu.device, config)?;
        fog.set_shadow_map(&gpu.device, shadow_map)?;
        let apply = fog.create_apply(&gpu.device, COLOR_FORMAT)?;
        let depth = volfog_testkit::selfcheck::depth_texture(
            gpu,
            size.0,
            size.1,
            &scene.depth_buffer(size.0, size.1),
        )?;
        let depth = depth_view(&depth);
        let depth_group = apply.depth_bind_group(&gpu.device, &depth);
        let color = texture_2d(
            gpu,
            "bench colour",
            size,
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Ok(Self {
            fog,
            apply,
            depth,
            depth_group,
            color: color.create_view(&Default::default()),
        })
    }

    /// Runs one frame, each pass (and the apply) submitted alone; returns its pass
    /// timings by both clocks.
    fn frame(&mut self, gpu: &Gpu) -> Result<(PassTimings, PassTimings), BenchError> {
        let mut gpu_ms = [0.0; 6];
        let mut wall_ms = [0.0; 6];
        let passes = FogPass::ALL.map(Some).into_iter().chain([None]);
        for (i, pass) in passes.enumerate() {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            match pass {
                Some(pass) => self.fog.encode_pass(&mut encoder, pass)?,
                None => self.fog.record_apply(
                    &mut encoder,
                    &self.apply,
                    &self.color,
                    &self.depth_group,
                )?,
            }
            self.fog.resolve_timestamps(&mut encoder);
            wall_ms[i] = submit_and_wait(gpu, encoder.finish())?;
            let t = self
                .fog
                .read_timings(&gpu.device, &gpu.queue)
                .ok_or_else(|| BenchError::Readback("VolumetricFog::read_timings".to_string()))?;
            gpu_ms[i] = [
                t.esm_downsample,
                t.esm_blur,
                t.inject,
                t.temporal,
                t.scan,
                t.apply,
            ][i];
        }
        let timings = |ms: [f64; 6]| PassTimings {
            esm_downsample: ms[0],
            esm_blur: ms[1],
            inject: ms[2],
            temporal: ms[3],
            scan: ms[4],
            apply: ms[5],
        };
        Ok((timings(gpu_ms), timings(wall_ms)))
    }
}

/// The plain volume copy (bandwidth floor of the scan).
struct CopyPass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    size: [u32; 3],
}

impl CopyPass {
    fn new(gpu: &Gpu, source: &wgpu::Texture) -> Result<Self, BenchError> {
        let module = raymarch::shader_module(
            &gpu.device,
            include_str!("copy.wgsl"),
            "cli/src/bench/copy.wgsl",
            &[],
        )?;
        let pipeline = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("bench copy_volume"),
                layout: None,
                module: &module,
                entry_point: Some("copy_volume"),
                compilation_options: Default::default(),
                cache: None,
            });
        let s = source.size();
        let destination = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("bench copy destination"),
            size: s,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: source.format(),
            usage: wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench copy_volume"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(
                        &source.create_view(&Default::default()),
                    ),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(
                        &destination.create_view(&Default::default()),
                    ),
                },
            ],
        });
        Ok(Self {
            pipeline,
            group,
            size: [s.width, s.height, s.depth_or_array_layers],
        })
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, timer: &Timer, slot: u32) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("bench copy_volume"),
            timestamp_writes: timer.compute(slot),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.size[0].div_ceil(8), self.size[1].div_ceil(8), 1);
    }
}

/// The plain fullscreen blit (floor of the apply pass).
struct BlitPass {
    pipeline: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
    target: wgpu::TextureView,
}

impl BlitPass {
    fn new(gpu: &Gpu, size: (u32, u32), format: wgpu::TextureFormat) -> Result<Self, BenchError> {
        let module = raymarch::shader_module(
            &gpu.device,
            include_str!("blit.wgsl"),
            "cli/src/bench/blit.wgsl",
            &[],
        )?;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("bench blit"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                }],
            });
        let pipeline = raymarch::fullscreen_pipeline(
            &gpu.device,
            "bench blit",
            &module,
            ("blit_vs", "blit_fs"),
            &layout,
            wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            },
        );
        let source = texture_2d(
            gpu,
            "bench blit source",
            size,
            format,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let target = texture_2d(
            gpu,
            "bench blit target",
            size,
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bench blit"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &source.create_view(&Default::default()),
                ),
            }],
        });
        Ok(Self {
            pipeline,
            group,
            target: target.create_view(&Default::default()),
        })
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, timer: &Timer, slot: u32) {
        let mut pass =
            raymarch::fullscreen_pass(encoder, "bench blit", &self.target, timer.render(slot));
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// Series measured each frame, in table order: (key, label).
const SERIES: &[(&str, &str)] = &[
    ("esm_downsample", "esm downsample (4 cascades)"),
    ("esm_blur", "esm blur (x + y)"),
    ("inject", "inject 160x90x128"),
    ("temporal", "temporal 160x90x128"),
    ("scan", "scan 160x90x128"),
    ("copy", "copy 160x90x128 (floor)"),
    ("apply_1080p", "apply 1920x1080"),
    ("blit_1080p", "blit 1920x1080 (floor)"),
    ("froxel_1080p", "froxel pipeline 1080p *"),
    ("raymarch_1080p", "raymarch 1080p, 64 steps"),
    ("froxel_720p", "froxel 720p camera **"),
    ("froxel_4k", "froxel 4K camera **"),
    ("apply_720p", "apply 1280x720"),
    ("apply_4k", "apply 3840x2160"),
];

fn froxel_cost(t: &PassTimings) -> f64 {
    t.inject + t.temporal + t.scan
}

/// Frame counts of a run.
#[derive(Debug, Clone, Copy)]
struct Plan {
    warmup: u32,
    frames: u32,
    raymarch_frames: u32,
}

impl Plan {
    fn new(args: &BenchArgs) -> Result<Self, BenchError> {
        let pick = |given: Option<u32>, quick: u32, default: u32| {
            given.unwrap_or(if args.quick { quick } else { default })
        };
        let frames = pick(args.frames, QUICK_FRAMES, DEFAULT_FRAMES);
        if frames == 0 {
            return Err(BenchError::NoFrames);
        }
        Ok(Self {
            warmup: pick(args.warmup, QUICK_WARMUP, DEFAULT_WARMUP),
            frames,
            raymarch_frames: pick(
                args.raymarch_frames,
                QUICK_RAYMARCH_FRAMES,
                DEFAULT_RAYMARCH_FRAMES,
            )
            .clamp(1, frames),
        })
    }

    /// Whether frame `f` is measured, and whether it runs the raymarch (the last
    /// warm-up frame and the first `raymarch_frames` measured ones).
    fn frame(&self, f: u32) -> (bool, bool) {
        let measured = f >= self.warmup;
        let raymarch = if measured {
            f - self.warmup < self.raymarch_frames
        } else {
            f + 1 == self.warmup
        };
        (measured, raymarch)
    }
}

/// Every workload of a frame, built once.
struct Workloads {
    config: FogConfig,
    scene: Scene,
    cascades: volfog::uniforms::ShadowCascades,
    main: Screen,
    small: Screen,
    large: Screen,
    copy: CopyPass,
    blit: BlitPass,
    reference: Raymarch,
    reference_group: wgpu::BindGroup,
    reference_target: wgpu::TextureView,
    timer: Timer,
}

impl Workloads {
    fn new(gpu: &Gpu) -> Result<Self, BenchError> {
        let config = FogConfig {
            timestamps: true,
            ..FogConfig::default()
        };
        let scene = Scene::new();
        eprintln!("preparing the scene (shadow cascades, depth buffers, pipelines)...");
        let (cascades, layers) = scene.cascades(&config);
        let shadow_size = config.esm_resolution * 4;
        let layer_refs: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
        let shadow_map = volfog_testkit::selfcheck::depth_array_texture(
            gpu,
            shadow_size,
            shadow_size,
            &layer_refs,
        )?;
        let main = Screen::new(gpu, &scene, &config, &shadow_map, SCREEN)?;
        let small = Screen::new(gpu, &scene, &config, &shadow_map, SMALL_SCREEN)?;
        let large = Screen::new(gpu, &scene, &config, &shadow_map, LARGE_SCREEN)?;
        let copy = CopyPass::new(gpu, main.fog.scattering_texture())?;
        let blit = BlitPass::new(gpu, SCREEN, COLOR_FORMAT)?;
        let reference = Raymarch::new(
            &gpu.device,
            &RaymarchOptions {
                steps: RAYMARCH_STEPS,
                noise_octaves: config.noise_octaves,
                color_format: COLOR_FORMAT,
                max_lights: config.max_lights,
                max_local_volumes: config.max_local_volumes,
            },
        )?;
        let reference_target = texture_2d(
            gpu,
            "bench raymarch target",
            SCREEN,
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&Default::default());
        let esm_view = main
            .fog
            .esm_texture()
            .create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
        let reference_group = reference.bind_group(&gpu.device, &esm_view, &main.depth);
        Ok(Self {
            config,
            scene,
            cascades,
            main,
            small,
            large,
            copy,
            blit,
            reference,
            reference_group,
            reference_target,
            timer: Timer::new(gpu, 3),
        })
    }

    /// Runs frame `f` and returns its samples by series key.
    fn frame(
        &mut self,
        gpu: &Gpu,
        f: u32,
        with_raymarch: bool,
    ) -> Result<Vec<(&'static str, Sample)>, BenchError> {
        let inputs = self.scene.inputs(f as f32 / 60.0, self.cascades);
        for s in [&mut self.main, &mut self.small, &mut self.large] {
            s.fog.prepare(&gpu.queue, &inputs)?;
        }
        let (tg, tc) = self.main.frame(gpu)?;
        let timer = &self.timer;
        let copy_t = timer.run(gpu, 0, |e| self.copy.encode(e, timer, 0))?;
        let blit_t = timer.run(gpu, 1, |e| self.blit.encode(e, timer, 1))?;
        let index = self.main.fog.frame_index().expect("prepared above");
        let uniforms = inputs.uniforms(&self.config, index)?;
        self.reference.upload(
            &gpu.queue,
            &uniforms,
            &self.scene.lights,
            &self.scene.local_volumes,
        );
        let raymarch_t = if with_raymarch {
            Some(timer.run(gpu, 2, |e| {
                self.reference.draw(
                    e,
                    &self.reference_target,
                    &self.reference_group,
                    timer.render(2),
                )
            })?)
        } else {
            None
        };
        // Alternate the order of the two cameras so that drift cancels.
        let (ts, tl) = if f.is_multiple_of(2) {
            let ts = self.small.frame(gpu)?;
            (ts, self.large.frame(gpu)?)
        } else {
            let tl = self.large.frame(gpu)?;
            (self.small.frame(gpu)?, tl)
        };
        let both = |pick: &dyn Fn(&PassTimings) -> f64, t: &(PassTimings, PassTimings)| Sample {
            gpu: pick(&t.0),
            cpu: pick(&t.1),
        };
        let main = (tg, tc);
        let mut samples = vec![
            ("esm_downsample", both(&|p| p.esm_downsample, &main)),
            ("esm_blur", both(&|p| p.esm_blur, &main)),
            ("inject", both(&|p| p.inject, &main)),
            ("temporal", both(&|p| p.temporal, &main)),
            ("scan", both(&|p| p.scan, &main)),
            ("copy", copy_t),
            ("apply_1080p", both(&|p| p.apply, &main)),
            ("blit_1080p", blit_t),
            ("froxel_1080p", both(&|p| froxel_cost(p) + p.apply, &main)),
            ("froxel_720p", both(&froxel_cost, &ts)),
            ("froxel_4k", both(&froxel_cost, &tl)),
            ("apply_720p", both(&|p| p.apply, &ts)),
            ("apply_4k", both(&|p| p.apply, &tl)),
        ];
        samples.extend(raymarch_t.map(|r| ("raymarch_1080p", r)));
        Ok(samples)
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
    println!("volfog bench on {}", gpu.describe());
    println!("clock: {}", clock.describe());

    // Memory at the default configuration (no timestamps), before anything else.
    let memory_bytes = VolumetricFog::new(&gpu.device, &FogConfig::default())?.memory_bytes();
    let mut work = Workloads::new(&gpu)?;
    let size = work.config.volume_size;
    println!(
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
    );
    let mut samples: std::collections::BTreeMap<&str, Vec<Sample>> =
        SERIES.iter().map(|(k, _)| (*k, Vec::new())).collect();
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
            for (key, value) in frame {
                samples.get_mut(key).expect("listed in SERIES").push(value);
            }
        }
    }
    let report = summarize(
        &gpu,
        clock,
        &plan,
        &work.config,
        &samples,
        memory_bytes,
        start,
    );
    print!("{}", table(&report));
    let json = serde_json::to_string_pretty(&report).expect("the report serializes");
    std::fs::write(&args.out, json + "\n").map_err(|source| BenchError::Io {
        path: args.out.clone(),
        source,
    })?;
    println!("wrote {}", args.out.display());
    Ok(())
}

/// The report of a run: statistics per series, ratios and memory.
fn summarize(
    gpu: &Gpu,
    clock: Clock,
    plan: &Plan,
    config: &FogConfig,
    samples: &std::collections::BTreeMap<&str, Vec<Sample>>,
    memory_bytes: u64,
    start: Instant,
) -> Report {
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
    let ratios = Ratios {
        scan_vs_copy: Ratio::at_most(
            "median scan / median copy",
            median("scan") / median("copy"),
            TARGET_SCAN,
        ),
        apply_vs_blit: Ratio::at_most(
            "median apply / median blit (1920x1080)",
            median("apply_1080p") / median("blit_1080p"),
            TARGET_APPLY,
        ),
        raymarch_vs_froxel: Ratio::at_least(
            "median raymarch / median (inject + temporal + scan + apply), 1080p",
            median("raymarch_1080p") / median("froxel_1080p"),
            TARGET_SPEEDUP,
        ),
        froxel_4k_vs_720p: Ratio::at_most(
            "median (inject + temporal + scan) behind a 3840x2160 / a 1280x720 camera",
            median("froxel_4k") / median("froxel_720p"),
            TARGET_SCREEN,
        ),
    };
    let mib = memory_bytes as f64 / (1024.0 * 1024.0);
    Report {
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
        memory: Memory {
            bytes: memory_bytes,
            mib,
            limit_mib: TARGET_MEMORY_MIB,
            met: mib <= TARGET_MEMORY_MIB,
        },
        wall_seconds: start.elapsed().as_secs_f64(),
    }
}

fn status(met: bool) -> &'static str {
    if met { "met" } else { "MISSED" }
}

/// The report as a text table.
pub fn table(report: &Report) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(out, "\nadapter: {}", report.adapter_details);
    let _ = writeln!(out, "clock: {}", report.clock.describe());
    let _ = writeln!(
        out,
        "{:<30} {:>10} {:>10} {:>10}",
        "pass", "median ms", "min ms", "max ms"
    );
    for (key, _) in SERIES {
        let s = &report.passes[*key];
        let _ = writeln!(
            out,
            "{:<30} {:>10.3} {:>10.3} {:>10.3}",
            s.label, s.median_ms, s.min_ms, s.max_ms
        );
    }
    let _ = writeln!(
        out,
        "  * inject + temporal + scan + apply (ESM passes excluded: the raymarch uses the same ESM)"
    );
    let _ = writeln!(out, "  ** inject + temporal + scan, apply excluded");
    let _ = writeln!(
        out,
        "\n{:<36} {:>10} {:>10}  status",
        "ratio (of medians)", "value", "target"
    );
    let r = &report.ratios;
    for (name, ratio) in [
        ("scan / copy", &r.scan_vs_copy),
        ("apply / blit", &r.apply_vs_blit),
        (
            "raymarch / froxel pipeline (speed-up)",
            &r.raymarch_vs_froxel,
        ),
        ("froxel cost 4K / 720p camera", &r.froxel_4k_vs_720p),
    ] {
        let _ = writeln!(
            out,
            "{:<36} {:>9.3}x {:>10}  {}",
            name,
            ratio.value,
            ratio.target,
            status(ratio.met)
        );
    }
    let m = &report.memory;
    let _ = writeln!(
        out,
        "{:<36} {:>6.2} MiB {:>6} MiB  {} ({} bytes)",
        "VolumetricFog::memory_bytes (default)",
        m.mib,
        format!("<= {}", m.limit_mib),
        status(m.met),
        m.bytes
    );
    let _ = writeln!(
        out,
        "{} warm-up + {} measured frames ({} with the raymarch), wall time {:.1} s",
        report.settings.warmup,
        report.settings.frames,
        report.settings.raymarch_frames,
        report.wall_seconds
    );
    out
}
