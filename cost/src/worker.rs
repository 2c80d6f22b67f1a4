//! Compiling on RADV's null device, one child process per chip.
//!
//! RADV reads `RADV_FORCE_FAMILY` (which chip its null device stands for) and the
//! loader reads `VK_ICD_FILENAMES` when a Vulkan instance is created; setting them in
//! a running, threaded process is unsound, and one process would see one chip. So the
//! parent ([`Worker::compile`]) starts a worker process per chip with that
//! environment, writes the pipelines to its stdin as JSON, and reads their statistics
//! from its stdout; the worker ([`serve`]) is any program that calls [`serve`] on its
//! stdin and stdout (`volfog radv-worker`, a hidden subcommand of the CLI).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use serde::{Deserialize, Serialize};
use vkcheck::{
    Blend, BlendComponent, DescriptorBinding, DescriptorKind, Executable, GraphicsDesc,
    ShaderEntry, Stages, StatsDevice, VertexAttribute, VertexBuffer, vk,
};

use crate::pipeline::*;
use crate::{Chip, CostError};

/// RADV's ICD file as Debian's `mesa-vulkan-drivers` installs it.
pub const RADV_ICD: &str = "/usr/share/vulkan/icd.d/radeon_icd.x86_64.json";

/// What the parent sends a worker.
#[derive(Debug, Serialize, Deserialize)]
struct Request {
    chip: Chip,
    jobs: Vec<Job>,
}

/// What a worker answers.
#[derive(Debug, Serialize, Deserialize)]
struct Response {
    device: String,
    results: Vec<Compiled>,
}

/// One executable (a compiled shader stage) of a pipeline, as the driver describes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExecutableStats {
    /// The driver's name for it (`Compute Shader`, `Fragment Shader`, ...).
    pub name: String,
    /// `compute`, `vertex`, `fragment` or the stage flags' debug form.
    pub stage: String,
    /// Its subgroup (wave) size.
    pub subgroup_size: u32,
    /// Every statistic, by name, as a number.
    pub statistics: Vec<(String, f64)>,
    /// Loops in ACO's IR (blocks of kind `loop-header`), when the job asked.
    pub aco_loops: Option<u32>,
}

impl ExecutableStats {
    /// The statistic named `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.statistics
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
    }
}

/// One job's outcome: its executables, or the driver's error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Compiled {
    /// The job's label.
    pub label: String,
    /// The executables, or why the pipeline did not compile.
    pub outcome: Result<Vec<ExecutableStats>, String>,
}

/// What a worker compiled for one chip.
#[derive(Debug, Clone)]
pub struct ChipResults {
    /// The chip.
    pub chip: Chip,
    /// The device that compiled and its driver (e.g. `Null hardware (RADV BONAIRE),
    /// radv Mesa 22.3.6`).
    pub device: String,
    /// One per job, in order.
    pub results: Vec<Compiled>,
}

fn stage_name(flags: vk::ShaderStageFlags) -> String {
    match flags {
        vk::ShaderStageFlags::COMPUTE => "compute".to_string(),
        vk::ShaderStageFlags::VERTEX => "vertex".to_string(),
        vk::ShaderStageFlags::FRAGMENT => "fragment".to_string(),
        other => format!("{other:?}"),
    }
}

fn executable_stats(e: &Executable, count_loops: bool) -> ExecutableStats {
    ExecutableStats {
        name: e.name.clone(),
        stage: stage_name(e.stages),
        subgroup_size: e.subgroup_size,
        statistics: e
            .statistics
            .iter()
            .map(|s| (s.name.clone(), s.value.as_f64()))
            .collect(),
        aco_loops: count_loops.then(|| {
            e.representation("ACO IR")
                .map_or(0, |ir| ir.matches("loop-header").count() as u32)
        }),
    }
}

fn descriptor_kind(ty: DescriptorType) -> DescriptorKind {
    match ty {
        DescriptorType::UniformBuffer => DescriptorKind::UniformBuffer,
        DescriptorType::StorageBuffer => DescriptorKind::StorageBuffer,
        DescriptorType::SampledImage => DescriptorKind::SampledImage,
        DescriptorType::StorageImage => DescriptorKind::StorageImage,
        DescriptorType::Sampler => DescriptorKind::Sampler,
    }
}

/// Descriptor sets (index = set) of the bindings, visible to `stages`.
fn sets(bindings: &[BindingDesc], stages: Stages) -> Vec<Vec<DescriptorBinding>> {
    let count = bindings
        .iter()
        .map(|b| b.set as usize + 1)
        .max()
        .unwrap_or(0);
    let mut sets = vec![Vec::new(); count];
    for b in bindings {
        sets[b.set as usize].push(DescriptorBinding::new(
            b.binding,
            descriptor_kind(b.ty),
            stages,
        ));
    }
    sets
}

/// A WebGPU texture or vertex format as Vulkan's.
fn format(name: &str) -> Result<vk::Format, String> {
    Ok(match name {
        "rgba16float" => vk::Format::R16G16B16A16_SFLOAT,
        "rgba32float" => vk::Format::R32G32B32A32_SFLOAT,
        "rgba8unorm" => vk::Format::R8G8B8A8_UNORM,
        "rgba8unorm-srgb" => vk::Format::R8G8B8A8_SRGB,
        "bgra8unorm" => vk::Format::B8G8R8A8_UNORM,
        "bgra8unorm-srgb" => vk::Format::B8G8R8A8_SRGB,
        "rgb10a2unorm" => vk::Format::A2B10G10R10_UNORM_PACK32,
        "r32float" => vk::Format::R32_SFLOAT,
        "float32" => vk::Format::R32_SFLOAT,
        "float32x2" => vk::Format::R32G32_SFLOAT,
        "float32x3" => vk::Format::R32G32B32_SFLOAT,
        "float32x4" => vk::Format::R32G32B32A32_SFLOAT,
        other => return Err(format!("format {other:?} is not known to the worker")),
    })
}

fn factor(name: &str) -> Result<vk::BlendFactor, String> {
    Ok(match name {
        "one" => vk::BlendFactor::ONE,
        "zero" => vk::BlendFactor::ZERO,
        "src-alpha" => vk::BlendFactor::SRC_ALPHA,
        "one-minus-src-alpha" => vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
        "dst-alpha" => vk::BlendFactor::DST_ALPHA,
        "src" => vk::BlendFactor::SRC_COLOR,
        other => return Err(format!("blend factor {other:?} is not known to the worker")),
    })
}

fn component((src, dst): &(String, String)) -> Result<BlendComponent, String> {
    Ok(BlendComponent {
        src_factor: factor(src)?,
        dst_factor: factor(dst)?,
        op: vk::BlendOp::ADD,
    })
}

/// Compiles one job on `device`.
fn compile(device: &StatsDevice, job: &Job) -> Result<Vec<ExecutableStats>, String> {
    let executables = match &job.pipeline {
        PipelineDesc::Compute { stage, bindings } => device
            .compute(
                &stage.spirv,
                &stage.entry,
                &sets(bindings, Stages::COMPUTE),
                job.count_loops,
            )
            .map_err(|e| e.to_string())?,
        PipelineDesc::Graphics {
            vertex,
            fragment,
            bindings,
            vertex_buffers,
            color_format,
            blend,
        } => {
            let buffers = vertex_buffers
                .iter()
                .map(|b| {
                    Ok(VertexBuffer {
                        stride: b.stride,
                        per_instance: b.per_instance,
                        attributes: b
                            .attributes
                            .iter()
                            .map(|a| {
                                Ok(VertexAttribute {
                                    location: a.location,
                                    format: format(&a.format)?,
                                    offset: a.offset,
                                })
                            })
                            .collect::<Result<_, String>>()?,
                    })
                })
                .collect::<Result<Vec<_>, String>>()?;
            let blend = match blend {
                Some(b) => Some(Blend {
                    color: component(&b.color)?,
                    alpha: component(&b.alpha)?,
                }),
                None => None,
            };
            let sets = sets(bindings, Stages::VERTEX_FRAGMENT);
            device
                .graphics(
                    &GraphicsDesc {
                        vertex: ShaderEntry {
                            spirv: &vertex.spirv,
                            entry: &vertex.entry,
                        },
                        fragment: ShaderEntry {
                            spirv: &fragment.spirv,
                            entry: &fragment.entry,
                        },
                        sets: &sets,
                        vertex_buffers: &buffers,
                        color_format: format(color_format)?,
                        blend,
                    },
                    job.count_loops,
                )
                .map_err(|e| e.to_string())?
        }
    };
    Ok(executables
        .iter()
        .map(|e| executable_stats(e, job.count_loops))
        .collect())
}

/// The worker's side: reads a request from `input`, compiles every job on the RADV
/// null device this process was started for, writes the answer to `output`.
///
/// Errors when `RADV_FORCE_FAMILY` is not the request's chip (the parent sets it) or
/// when no such device opens.
pub fn serve(input: impl Read, output: impl Write) -> Result<(), CostError> {
    let request: Request =
        serde_json::from_reader(input).map_err(|e| CostError::Protocol(e.to_string()))?;
    let family = std::env::var("RADV_FORCE_FAMILY").unwrap_or_default();
    if Chip::from_family(&family) != Some(request.chip) {
        return Err(CostError::Invalid {
            field: "RADV_FORCE_FAMILY",
            message: format!(
                "is {family:?}, the request is for {}: start the worker through Worker::compile",
                request.chip
            ),
        });
    }
    let device = StatsDevice::new(Some(&request.chip.device_name_fragment()))?;
    let results = request
        .jobs
        .iter()
        .map(|job| Compiled {
            label: job.label.clone(),
            outcome: compile(&device, job),
        })
        .collect();
    let response = Response {
        device: format!("{}, {}", device.device_name(), device.driver()),
        results,
    };
    serde_json::to_writer(output, &response).map_err(|e| CostError::Protocol(e.to_string()))
}

/// The parent's side: how to start a worker.
#[derive(Debug, Clone)]
pub struct Worker {
    program: PathBuf,
    args: Vec<String>,
}

/// Fails with the install command when RADV's ICD file is missing.
pub fn check_radv() -> Result<(), CostError> {
    if Path::new(RADV_ICD).exists() {
        Ok(())
    } else {
        Err(CostError::RadvMissing {
            icd: RADV_ICD.to_string(),
        })
    }
}

/// The last `lines` lines of `text`.
fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

impl Worker {
    /// A worker started as `program args...`.
    pub fn new(program: impl Into<PathBuf>, args: &[&str]) -> Self {
        Self {
            program: program.into(),
            args: args.iter().map(|a| a.to_string()).collect(),
        }
    }

    /// Compiles `jobs` for `chip` in a worker process.
    pub fn compile(&self, chip: Chip, jobs: &[Job]) -> Result<ChipResults, CostError> {
        check_radv()?;
        let fail = |message: String| CostError::Worker {
            chip,
            program: self.program.display().to_string(),
            message,
        };
        let mut child = Command::new(&self.program)
            .args(&self.args)
            .env("RADV_FORCE_FAMILY", chip.family())
            .env("VK_ICD_FILENAMES", RADV_ICD)
            .env("VK_DRIVER_FILES", RADV_ICD)
            .env("MESA_SHADER_CACHE_DISABLE", "true")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| fail(format!("could not start it: {e}")))?;
        let request = serde_json::to_vec(&Request {
            chip,
            jobs: jobs.to_vec(),
        })
        .map_err(|e| CostError::Protocol(e.to_string()))?;
        let mut stdin = child.stdin.take().expect("stdin is piped");
        let mut stderr = child.stderr.take().expect("stderr is piped");
        let writer = std::thread::spawn(move || stdin.write_all(&request));
        let errors = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = stderr.read_to_string(&mut text);
            text
        });
        let mut answer = Vec::new();
        let read = child
            .stdout
            .take()
            .expect("stdout is piped")
            .read_to_end(&mut answer);
        let status = child.wait().map_err(|e| fail(e.to_string()))?;
        let stderr_text = errors.join().unwrap_or_default();
        let written = writer.join();
        if !status.success() {
            return Err(fail(format!(
                "exited with {status}: {}",
                tail(&stderr_text, 20)
            )));
        }
        read.map_err(|e| fail(format!("reading its answer: {e}")))?;
        match written {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(fail(format!("writing the request: {e}"))),
            Err(_) => return Err(fail("the request's writer panicked".to_string())),
        }
        let response: Response = serde_json::from_slice(&answer).map_err(|e| {
            fail(format!(
                "its answer is not JSON ({e}); stderr: {}",
                tail(&stderr_text, 20)
            ))
        })?;
        if response.results.len() != jobs.len() {
            return Err(fail(format!(
                "answered {} results for {} jobs",
                response.results.len(),
                jobs.len()
            )));
        }
        Ok(ChipResults {
            chip,
            device: response.device,
            results: response.results,
        })
    }

    /// Compiles `jobs` for every chip of `chips`, one worker per chip, side by side.
    pub fn compile_chips(
        &self,
        chips: &[Chip],
        jobs: &[Job],
    ) -> Result<Vec<ChipResults>, CostError> {
        check_radv()?;
        std::thread::scope(|scope| {
            let handles: Vec<_> = chips
                .iter()
                .map(|&chip| scope.spawn(move || self.compile(chip, jobs)))
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join().unwrap_or_else(|_| {
                        Err(CostError::Protocol("a worker thread panicked".into()))
                    })
                })
                .collect()
        })
    }
}
