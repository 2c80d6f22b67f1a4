//! `volfog gpu-cost`: every pipeline the runtime creates for the default
//! configuration, the bench's and the demo's, compiled by Mesa's RADV (ACO) on its
//! null device for bonaire (GCN2), navi21 (RDNA2) and gfx1100 (RDNA3), with its
//! registers, spills, scratch, LDS, occupancy, instruction count and ACO's cycle
//! estimates; then the passes of one frame of the bench scene on three GPU models
//! (`volfog_cost::model`): the Xbox One at Wronski's grid (160x90x64) beside
//! Assassin's Creed IV's figures, the RX 6800 XT and the RX 7900 XTX at the default
//! grid, with the bench's per-pixel raymarch and the floors (a plain write and copy
//! of the volume, a blit) on the same models, and the same frames in stereo
//! (`StereoFog`, two 1920x1080 eyes) against one mono view. No GPU is needed: RADV compiles for a
//! chip that is not there, one worker process per chip (`volfog radv-worker`).
//! With `--bevy`, Bevy's own `VolumetricFog` beside volfog in `fog_bench`'s scene on the
//! same models, from the report of the Bevy plugin's `fog_gpu_cost` example.

mod bevy;
mod inputs;
mod medium;
mod stereo;
mod table;
mod transient;

use std::path::PathBuf;
use std::process::ExitCode;

use serde::Serialize;
use volfog::options::ShadowFilter;
use volfog::pipeline::FogConfig;
use volfog_cost::frame::{AC4_MS, AC4_TOTAL_MS, FramePass, frame_passes, runtime_variants};
use volfog_cost::measure::{Measured, PassModel, Shader, measure, model_pass};
use volfog_cost::worker::Worker;
use volfog_cost::workload::Workload;
use volfog_cost::{Chip, CostError, GpuModel, MODELS, ShaderStats};

pub use bevy::{BevyPeer, BevyRow};
pub use inputs::{SCREEN, STEREO_DEFAULT, STEREO_IPD, WRONSKI_GRID, configs};
pub use medium::MediumShadowModel;
pub use stereo::StereoModel;
pub use table::table;
pub use transient::{TRANSIENT_LIGHT_COUNTS, TransientModel};

/// Arguments of `volfog gpu-cost`.
#[derive(Debug, Clone, clap::Args)]
pub struct GpuCostArgs {
    /// Chips to compile for, by `RADV_FORCE_FAMILY` name (bonaire, navi21, gfx1100)
    /// [default: all three].
    #[arg(long, value_delimiter = ',')]
    pub chips: Vec<String>,
    /// Where to write the JSON report.
    #[arg(long, default_value = "gpu-cost.json")]
    pub out: PathBuf,
    /// Print the JSON report to stdout; the tables go to stderr.
    #[arg(long)]
    pub json: bool,
    /// Add Bevy's own `VolumetricFog` beside volfog in `fog_bench`'s scene on the same
    /// models, from this `fog_gpu_cost.json` (written by `cargo run -p volfog-bevy
    /// --example fog_gpu_cost` in `bevy/`, by default to `out/bevy/fog_gpu_cost.json`).
    #[arg(long, value_name = "FOG_GPU_COST_JSON")]
    pub bevy: Option<PathBuf>,
}

/// Errors of `volfog gpu-cost`.
#[derive(Debug, thiserror::Error)]
pub enum GpuCostError {
    /// Compiling or modelling failed.
    #[error(transparent)]
    Cost(#[from] CostError),
    /// A chip name is not one RADV's null device stands for here.
    #[error("--chips: {0:?} is not bonaire, navi21 or gfx1100")]
    UnknownChip(String),
    /// The scene's camera or grid is out of range.
    #[error(transparent)]
    Invalid(#[from] volfog::limits::InvalidValue),
    /// A shader beside the passes failed to compose.
    #[error("composing a shader: {0}")]
    Shader(String),
    /// The worker's own program could not be found.
    #[error("the path of this program (to start its workers): {0}")]
    CurrentExe(std::io::Error),
    /// The Bevy comparison's report could not be read.
    #[error("reading Bevy's fog report {path}: {message}")]
    Bevy {
        /// The report's path.
        path: PathBuf,
        /// What was wrong.
        message: String,
    },
    /// Writing the report failed.
    #[error("writing {path}: {source}")]
    Io {
        /// The report path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

/// One pipeline and its statistics per chip.
#[derive(Debug, Clone, Serialize)]
pub struct PipelineRow {
    /// `variant.entry`.
    pub label: String,
    /// The configurations that create it, and when.
    pub used_by: Vec<String>,
    /// Its statistics, in chip order.
    pub stats: Vec<ShaderStats>,
}

/// A model's verdict on one of AC4's figures.
#[derive(Debug, Clone, Serialize)]
pub struct Ac4Row {
    /// AC4's pass.
    pub name: &'static str,
    /// AC4's time on the Xbox One (ms).
    pub target_ms: f64,
    /// The model's time of volfog's passes that do that work (ms); `None` where
    /// volfog runs no such pass in this configuration.
    pub model_ms: Option<f64>,
}

/// One frame of the bench scene on a GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct FrameModel {
    /// The GPU model.
    pub gpu: GpuModel,
    /// The grid.
    pub grid: [u32; 3],
    /// What the scene asks of the passes.
    pub workload: Workload,
    /// The froxel pipeline's passes.
    pub passes: Vec<PassModel>,
    /// Their total (ms).
    pub total_ms: f64,
    /// The bench's per-pixel raymarch on the same model.
    pub raymarch: PassModel,
    /// The floors (write, copy, blit) on the same model.
    pub floors: Vec<PassModel>,
    /// AC4's figures beside the model's (the Xbox One model only).
    pub ac4: Vec<Ac4Row>,
}

/// The same frame with another shadow filter: what the shadows cost on a GPU model.
#[derive(Debug, Clone, Serialize)]
pub struct FilterModel {
    /// The GPU model's name.
    pub gpu: &'static str,
    /// The filter, as `FogConfig::shadow_filter` names it.
    pub filter: String,
    /// The passes that depend on the filter (the ESM passes and inject).
    pub passes: Vec<PassModel>,
    /// The whole froxel pipeline with this filter (ms).
    pub total_ms: f64,
}

/// The report of `volfog gpu-cost`.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The chips, in order, with the device that compiled for each.
    pub chips: Vec<(Chip, String)>,
    /// Every pipeline of the listed configurations.
    pub pipelines: Vec<PipelineRow>,
    /// The frame on each GPU model whose chip was compiled for.
    pub frames: Vec<FrameModel>,
    /// The same frames with each shadow filter ([`SHADOW_FILTERS`]).
    pub filters: Vec<FilterModel>,
    /// The frames' scan with transient lights ([`TRANSIENT_LIGHT_COUNTS`]).
    pub transient: Vec<TransientModel>,
    /// The frames in stereo (`StereoFog`) against one mono view.
    pub stereo: Vec<StereoModel>,
    /// The frames with the medium's shadows (`MediumShadowConfig::default()`).
    pub medium_shadows: Vec<MediumShadowModel>,
    /// Bevy's own fog beside volfog in `fog_bench`'s scene (`--bevy`).
    pub bevy: Option<BevyPeer>,
}

/// The shadow filters the report sets side by side: the compare filter with one (the
/// default), two and four taps, and the ESM.
pub const SHADOW_FILTERS: [ShadowFilter; 4] = [
    ShadowFilter::Compare { taps: 1 },
    ShadowFilter::Compare { taps: 2 },
    ShadowFilter::Compare { taps: 4 },
    ShadowFilter::Esm,
];

/// Runs `volfog gpu-cost` from the command line.
pub fn main(args: GpuCostArgs) -> ExitCode {
    let worker = match std::env::current_exe() {
        Ok(exe) => Worker::new(exe, &["radv-worker"]),
        Err(e) => {
            eprintln!("error: {}", GpuCostError::CurrentExe(e));
            return ExitCode::FAILURE;
        }
    };
    match run(&args, &worker).and_then(|report| write(&args, &report)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `volfog radv-worker` (hidden): compiles the pipelines of a request on stdin on
/// the RADV null device of this process and answers on stdout.
pub fn worker_main() -> ExitCode {
    match volfog_cost::worker::serve(std::io::stdin().lock(), std::io::stdout().lock()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn write(args: &GpuCostArgs, report: &Report) -> Result<(), GpuCostError> {
    let json = serde_json::to_string_pretty(report).expect("the report serializes") + "\n";
    if args.json {
        eprint!("{}", table(report));
        print!("{json}");
    } else {
        print!("{}", table(report));
    }
    std::fs::write(&args.out, &json).map_err(|source| GpuCostError::Io {
        path: args.out.clone(),
        source,
    })?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// The chips of `--chips`.
pub fn chips(names: &[String]) -> Result<Vec<Chip>, GpuCostError> {
    if names.is_empty() {
        return Ok(Chip::ALL.to_vec());
    }
    let mut chips = Vec::new();
    for n in names {
        let chip =
            Chip::from_family(n.trim()).ok_or_else(|| GpuCostError::UnknownChip(n.clone()))?;
        if !chips.contains(&chip) {
            chips.push(chip);
        }
    }
    chips.sort();
    Ok(chips)
}

/// Every pipeline the runtime creates for `configs` (`VolumetricFog`'s, or
/// `StereoFog`'s for a stereo configuration, [`inputs::is_stereo`]): its shader and who
/// uses it.
pub fn pipelines(
    configs: &[(String, FogConfig)],
) -> Result<Vec<(Shader, Vec<String>)>, GpuCostError> {
    let mut out: Vec<(Shader, Vec<String>)> = Vec::new();
    for (name, config) in configs {
        let variants = if inputs::is_stereo(name) {
            // Stereo fog's pipelines and its multiview apply.
            let mut v = volfog_cost::stereo::stereo_variants(config);
            v.extend(volfog_cost::stereo_multiview::multiview_apply_variants(
                config,
            ));
            v
        } else {
            runtime_variants(config)
        };
        for v in variants {
            let module = volfog::shaders::compose(v.pass, &v.defines).map_err(CostError::from)?;
            for ep in &module.entry_points {
                if ep.stage == naga::ShaderStage::Vertex {
                    continue;
                }
                let label = format!("{}.{}", v.name(), ep.name);
                let user = format!("{name} ({})", v.when);
                match out.iter_mut().find(|(s, _)| s.label == label) {
                    Some((_, users)) => users.push(user),
                    None => out.push((
                        Shader {
                            label,
                            module: module.clone(),
                            entry: ep.name.clone(),
                            render: volfog_cost::pipeline::render_state(v.pass),
                        },
                        vec![user],
                    )),
                }
            }
        }
    }
    Ok(out)
}

/// The models of a frame plan's passes (its raymarch and floors aside).
fn model_passes<'a>(
    p: &FramePlan,
    find: impl Fn(Chip, &str) -> &'a Measured,
) -> Result<Vec<PassModel>, CostError> {
    let sizes = volfog_cost::floor::Sizes::new(&p.config, SCREEN, p.workload.live_fraction);
    p.passes
        .iter()
        .map(|(pass, shader)| {
            model_pass(
                find(p.gpu.chip, &shader.label),
                shader,
                pass,
                &p.gpu,
                &sizes,
            )
        })
        .collect()
}

/// The frame of `config` on `gpu`: its passes, the raymarch and the floors, with the
/// shaders each needs.
struct FramePlan {
    gpu: GpuModel,
    config: FogConfig,
    workload: Workload,
    passes: Vec<(FramePass, Shader)>,
    raymarch: (FramePass, Shader),
    floors: Vec<(FramePass, Shader)>,
}

fn plan(
    gpu: &GpuModel,
    config: FogConfig,
    scene: &crate::bench::scene::Scene,
    depth: &[f32],
) -> Result<FramePlan, GpuCostError> {
    let workload = inputs::workload(scene, depth, &config)?;
    let passes = frame_passes(&config, &workload)
        .into_iter()
        .map(|p| {
            let shader = Shader::of_variant(p.variant.pass, &p.variant.defines, &p.entry)?;
            Ok((p, shader))
        })
        .collect::<Result<_, CostError>>()?;
    Ok(FramePlan {
        gpu: gpu.clone(),
        raymarch: inputs::raymarch(scene, depth, &config)?,
        floors: inputs::floors(&config)?,
        config,
        workload,
        passes,
    })
}

/// Runs the compiles (one worker per chip, started by `worker`) and the model.
pub fn run(args: &GpuCostArgs, worker: &Worker) -> Result<Report, GpuCostError> {
    let chips = chips(&args.chips)?;
    let peer = args.bevy.as_deref().map(bevy::read).transpose()?;
    volfog_cost::worker::check_radv()?;
    let listed = pipelines(&configs())?;
    eprintln!(
        "{} pipelines of {} configurations; the bench scene's frame on {} models",
        listed.len(),
        configs().len(),
        MODELS.iter().filter(|m| chips.contains(&m.chip)).count()
    );
    let scene = crate::bench::scene::Scene::new();
    let depth = scene.depth_buffer(SCREEN.0, SCREEN.1);
    let mut plans = Vec::new();
    let mut filter_plans = Vec::new();
    let mut medium_plans = Vec::new();
    for gpu in MODELS.iter().filter(|m| chips.contains(&m.chip)) {
        // Wronski's grid on his GPU, the default grid on the others.
        let mut config = FogConfig::default();
        if gpu.chip == Chip::Bonaire {
            config.volume_size = WRONSKI_GRID;
        }
        for filter in SHADOW_FILTERS {
            let config = FogConfig {
                shadow_filter: filter,
                ..config.clone()
            };
            filter_plans.push(plan(gpu, config, &scene, &depth)?);
        }
        let medium = FogConfig {
            medium_shadows: Some(volfog::uniforms::MediumShadowConfig::default()),
            ..config.clone()
        };
        medium_plans.push(plan(gpu, medium, &scene, &depth)?);
        plans.push(plan(gpu, config, &scene, &depth)?);
    }
    // Every shader once: the listed pipelines, then what the frames add.
    let mut shaders: Vec<Shader> = listed.iter().map(|(s, _)| s.clone()).collect();
    let transient_plans = transient::plan(&plans)?;
    for p in plans.iter().chain(&filter_plans).chain(&medium_plans) {
        let extra = p
            .passes
            .iter()
            .chain(std::iter::once(&p.raymarch))
            .chain(&p.floors)
            .map(|(_, s)| s);
        for s in extra {
            if !shaders.iter().any(|k| k.label == s.label) {
                shaders.push(s.clone());
            }
        }
    }
    let stereo_plans = stereo::plan(&plans, &scene, &depth)?;
    for s in transient::shaders(&transient_plans).chain(stereo::shaders(&stereo_plans)) {
        if !shaders.iter().any(|k| k.label == s.label) {
            shaders.push(s.clone());
        }
    }
    let start = std::time::Instant::now();
    let measured = measure(worker, &chips, &shaders)?;
    eprintln!(
        "compiled {} shaders and their loops for {} chips in {:.1} s",
        shaders.len(),
        chips.len(),
        start.elapsed().as_secs_f64()
    );
    let find = |chip: Chip, label: &str| -> &Measured {
        measured[&chip]
            .get(label)
            .expect("every shader was measured")
    };
    let pipelines = listed
        .iter()
        .map(|(s, users)| PipelineRow {
            label: s.label.clone(),
            used_by: users.clone(),
            stats: chips
                .iter()
                .map(|&c| find(c, &s.label).stats.clone())
                .collect(),
        })
        .collect();
    let mut frames = Vec::new();
    for p in &plans {
        let sizes = volfog_cost::floor::Sizes::new(&p.config, SCREEN, p.workload.live_fraction);
        let model = |(pass, shader): &(FramePass, Shader)| {
            model_pass(
                find(p.gpu.chip, &shader.label),
                shader,
                pass,
                &p.gpu,
                &sizes,
            )
        };
        let passes: Vec<PassModel> = p.passes.iter().map(model).collect::<Result<_, _>>()?;
        let total_ms = passes.iter().map(|m| m.estimate.ms).sum();
        let ac4 = if p.gpu.chip == Chip::Bonaire {
            let mut rows: Vec<Ac4Row> = AC4_MS
                .iter()
                .map(|&(name, target_ms)| {
                    let of: Vec<f64> = passes
                        .iter()
                        .filter(|m| m.pass.ac4 == Some(name))
                        .map(|m| m.estimate.ms)
                        .collect();
                    Ac4Row {
                        name,
                        target_ms,
                        model_ms: (!of.is_empty()).then(|| of.iter().sum()),
                    }
                })
                .collect();
            rows.push(Ac4Row {
                name: "total",
                target_ms: AC4_TOTAL_MS,
                model_ms: Some(total_ms),
            });
            rows
        } else {
            Vec::new()
        };
        frames.push(FrameModel {
            gpu: p.gpu.clone(),
            grid: p.config.volume_size.to_array(),
            workload: p.workload.clone(),
            passes,
            total_ms,
            raymarch: model(&p.raymarch)?,
            floors: p.floors.iter().map(model).collect::<Result<_, _>>()?,
            ac4,
        });
    }
    let mut filters = Vec::new();
    for p in &filter_plans {
        let passes = model_passes(p, find)?;
        filters.push(FilterModel {
            gpu: p.gpu.name,
            filter: format!("{:?}", p.config.shadow_filter),
            total_ms: passes.iter().map(|m| m.estimate.ms).sum(),
            passes: passes
                .into_iter()
                .filter(|m| {
                    let v = &m.pass.variant.pass;
                    *v == "inject" || v.starts_with("esm_")
                })
                .collect(),
        });
    }
    let transient = transient::models(&transient_plans, &plans, find)?;
    let culled: Vec<f64> = frames.iter().map(|f| f.total_ms).collect();
    let stereo = stereo::models(&stereo_plans, &plans, &culled, find)?;
    let medium_shadows = medium::models(&medium_plans, &frames, find)?;
    Ok(Report {
        chips: measured
            .iter()
            .map(|(chip, m)| (*chip, format!("{}, {}", m.device, chip.generation())))
            .collect(),
        pipelines,
        frames,
        filters,
        transient,
        stereo,
        medium_shadows,
        bevy: peer,
    })
}
