//! The `volfog` command line: export shaders, run the GPU self-check, render the demo,
//! run the benchmark, cost the passes on a GPU compiler.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use volfog_cli::{bench, demo, gpu_cost, truth};
use volfog_codegen::Target;
use volfog_codegen::export::{ExportError, ExportRequest, export};
use volfog_codegen::reflect::HlslSamplers;

#[derive(Parser)]
#[command(
    name = "volfog",
    version,
    about = "Volumetric fog shaders: export, self-check, demo, benchmark, GPU cost"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum TargetArg {
    Wgsl,
    Spirv,
    Glsl,
    Hlsl,
    Msl,
    All,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum HlslSamplersArg {
    Classic,
    Heap,
}

#[derive(Subcommand)]
enum Command {
    /// Write shaders for the chosen targets and DIR/manifest.json.
    Export {
        /// Target language(s); repeat or separate with commas.
        #[arg(long, short, value_enum, value_delimiter = ',', required = true)]
        target: Vec<TargetArg>,
        /// Destination folder.
        #[arg(long, short)]
        out: PathBuf,
        /// Compose with custom defines, `NAME` or `NAME=VALUE` (repeatable).
        #[arg(long, short = 'D')]
        define: Vec<String>,
        /// Export only these variants or passes (repeatable).
        #[arg(long)]
        variant: Vec<String>,
        /// How HLSL binds samplers: `classic` registers (s0, s1, ... per space) or
        /// naga's sampler `heap` (wgpu's Direct3D 12 layout).
        #[arg(long, value_enum, default_value_t = HlslSamplersArg::Classic)]
        hlsl_samplers: HlslSamplersArg,
        /// Also write the include snippets into `DIR/<target>/include`: every one, or
        /// those named (apply, height_fog, fog_volume, lightning, soft_particles,
        /// phase, all).
        #[arg(long, num_args = 0.., value_delimiter = ',')]
        snippets: Option<Vec<String>>,
        /// Your density function: a WGSL module (naga_oil or WESL imports) defining
        /// `fn volfog_custom_density(world: vec3<f32>, time: f32, params:
        /// FogCustomParams) -> FogSample`; the inject pass is exported under
        /// VOLFOG_INJECT_CUSTOM_DENSITY with it (and the other defines).
        #[arg(long, value_name = "FILE")]
        custom_density: Option<PathBuf>,
    },
    /// Render the demo scene headless with the fog pipeline: PNG + per-pass GPU times.
    Demo(demo::DemoArgs),
    /// Time every pass with GPU timestamps against its floor and a per-pixel raymarch.
    Bench(bench::BenchArgs),
    /// Compile every pipeline with AMD's compiler (Mesa's RADV/ACO on its null device,
    /// no GPU needed) for GCN2, RDNA2 and RDNA3: registers, spills, occupancy and cycles
    /// per pass, and a per-pass time model on an Xbox One, an RX 6800 XT and an RX 7900
    /// XTX.
    GpuCost(gpu_cost::GpuCostArgs),
    /// The worker `gpu-cost` starts per chip (reads its request on stdin).
    #[command(hide = true)]
    RadvWorker,
    /// Compare the froxel pipeline with Mitsuba 3 in every reference scene (needs
    /// `cargo xtask tools`).
    Truth(truth::TruthArgs),
    /// Run every pass on the GPU against closed forms and the CPU mirror.
    Selfcheck,
    /// List the variants of every pass and their defines.
    List,
}

fn targets(args: &[TargetArg]) -> Vec<Target> {
    if args.contains(&TargetArg::All) {
        return Target::ALL.to_vec();
    }
    args.iter()
        .map(|t| match t {
            TargetArg::Wgsl => Target::Wgsl,
            TargetArg::Spirv => Target::Spirv,
            TargetArg::Glsl => Target::Glsl,
            TargetArg::Hlsl => Target::Hlsl,
            TargetArg::Msl => Target::Msl,
            TargetArg::All => unreachable!("handled above"),
        })
        .collect()
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Export {
            target,
            out,
            define,
            variant,
            hlsl_samplers,
            snippets,
            custom_density,
        } => {
            let (mut variants, mut defines) = (variant, define);
            let custom_density = match custom_density {
                Some(path) => match std::fs::read_to_string(&path) {
                    Ok(source) => {
                        let hook = volfog_codegen::manifest::CUSTOM_DENSITY;
                        if !defines.iter().any(|d| d == hook.define) {
                            defines.push(hook.define.to_string());
                        }
                        if variants.is_empty() {
                            variants.push("inject".to_string());
                        }
                        Some(volfog_codegen::custom::CustomModule::new(
                            path.display().to_string(),
                            source,
                        ))
                    }
                    Err(e) => {
                        eprintln!("error: --custom-density {}: {e}", path.display());
                        return ExitCode::FAILURE;
                    }
                },
                None => None,
            };
            let request = ExportRequest {
                out: out.clone(),
                targets: targets(&target),
                variants,
                defines,
                hlsl_samplers: match hlsl_samplers {
                    HlslSamplersArg::Classic => HlslSamplers::Classic,
                    HlslSamplersArg::Heap => HlslSamplers::Heap,
                },
                snippets,
                custom_density,
            };
            match export(&request) {
                Ok(s) => {
                    println!(
                        "exported {} variants, {} entry points, {} files and {} snippet files \
                         to {} (+ volfog_layout.h, manifest.json)",
                        s.variants,
                        s.entry_points,
                        s.files,
                        s.snippet_files,
                        out.display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e @ ExportError::Io { .. }) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::Demo(args) => match demo::run(&args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Bench(args) => bench::main(args),
        Command::GpuCost(args) => gpu_cost::main(args),
        Command::RadvWorker => gpu_cost::worker_main(),
        Command::Truth(args) => truth::main(&args),
        Command::Selfcheck => {
            let gpu = match volfog_testkit::Gpu::new() {
                Ok(g) => g,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            match volfog_testkit::selfcheck::run(&gpu) {
                Ok(report) => {
                    print!("{report}");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
        Command::List => {
            for v in volfog_codegen::manifest::variants() {
                println!("{:40} {}", v.name, v.defines.join(" "));
            }
            ExitCode::SUCCESS
        }
    }
}
