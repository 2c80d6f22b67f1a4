//! Export of shaders for engines that do not use Rust: every selected variant's
//! entry points in the chosen targets, as `DIR/<target>/<variant>.<entry>.<stage>.<ext>`,
//! plus `DIR/manifest.json` with defines, workgroup sizes, bindings (with their
//! slots in every target) and uniform struct layouts.
//!
//! Everything is written into a staging folder beside `DIR` first and moved into
//! place only when complete, so a failed export leaves `DIR` as it was.
//!
//! ```no_run
//! use volfog_codegen::export::{export, ExportRequest};
//! use volfog_codegen::Target;
//!
//! let summary = export(&ExportRequest {
//!     out: "fog-shaders".into(),
//!     targets: vec![Target::Hlsl, Target::Spirv],
//!     variants: vec![],
//!     defines: vec![],
//! })
//! .unwrap();
//! println!("{} files", summary.files);
//! ```

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::compose::{Defines, valid_defines};
use crate::manifest::{self, PASSES};
use crate::reflect::{Binding, HlslSamplerIndexBuffer, StructLayout};
use crate::translate::{VariantOutput, compose_variant, generate_variant};
use crate::{CodegenError, Stage, Target};

/// What to export.
#[derive(Debug, Clone)]
pub struct ExportRequest {
    /// Destination folder (created if missing).
    pub out: PathBuf,
    /// Targets to write.
    pub targets: Vec<Target>,
    /// Prebuilt variant names or pass names; empty selects every prebuilt variant
    /// (or, with defines, every pass that accepts them).
    pub variants: Vec<String>,
    /// Custom defines (`NAME` or `NAME=VALUE`), composed at run time.
    pub defines: Vec<String>,
}

/// Export failures. Each leaves the destination untouched.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A `--variant` that is neither a prebuilt variant nor a pass.
    #[error("unknown variant {name}; valid variants: {valid}; passes: {passes}")]
    UnknownVariant {
        /// The requested name.
        name: String,
        /// Every prebuilt variant.
        valid: String,
        /// Every pass.
        passes: String,
    },
    /// A define no selected pass accepts, or a bad value.
    #[error(transparent)]
    Define(#[from] CodegenError),
    /// No targets were requested.
    #[error("no target selected; valid targets: wgsl, spirv, glsl, hlsl, msl, all")]
    NoTarget,
    /// Writing failed.
    #[error("writing {path}: {source}")]
    Io {
        /// The path being written.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// What an export wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExportSummary {
    /// Variants exported.
    pub variants: usize,
    /// Entry points exported.
    pub entry_points: usize,
    /// Shader files written (excluding the manifest).
    pub files: usize,
}

#[derive(Serialize)]
struct Manifest<'a> {
    generator: String,
    conventions: Conventions,
    targets: Vec<TargetInfo>,
    variants: Vec<VariantEntry<'a>>,
}

#[derive(Serialize)]
struct Conventions {
    clip_space: &'static str,
    uniforms: &'static str,
    glsl: &'static str,
    hlsl_samplers: &'static str,
    msl: &'static str,
}

#[derive(Serialize)]
struct TargetInfo {
    target: &'static str,
    folder: &'static str,
    extension: &'static str,
    version: &'static str,
    validated_by: &'static str,
}

#[derive(Serialize)]
struct VariantEntry<'a> {
    name: &'a str,
    pass: &'a str,
    defines: &'a [String],
    usage: &'static str,
    entry_points: Vec<EntryEntry<'a>>,
}

#[derive(Serialize)]
struct EntryEntry<'a> {
    name: &'a str,
    stage: Stage,
    #[serde(skip_serializing_if = "Option::is_none")]
    workgroup_size: Option<[u32; 3]>,
    files: std::collections::BTreeMap<&'static str, String>,
    bindings: &'a [Binding],
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    hlsl_sampler_index_buffers: &'a [HlslSamplerIndexBuffer],
    structs: &'a [StructLayout],
}

fn target_info(target: Target) -> TargetInfo {
    let (version, validated_by) = match target {
        Target::Wgsl => (
            "WGSL (WebGPU)",
            "naga validation (all flags); runs on wgpu in the tests",
        ),
        Target::Spirv => (
            "SPIR-V 1.3, Vulkan 1.1",
            "naga validation; spirv-val --target-env vulkan1.1 in the tests",
        ),
        Target::Glsl => (
            "GLSL 450 core",
            "naga validation; glslangValidator in the tests",
        ),
        Target::Hlsl => (
            "HLSL shader model 6.0",
            "naga validation only: no HLSL compiler runs on Linux here; reviewed as snapshots",
        ),
        Target::Msl => (
            "Metal Shading Language 2.1",
            "naga validation only: no Metal compiler runs on Linux here; reviewed as snapshots",
        ),
    };
    TargetInfo {
        target: target.name(),
        folder: target.name(),
        extension: target.extension(),
        version,
        validated_by,
    }
}

const CONVENTIONS: Conventions = Conventions {
    clip_space: "WebGPU: NDC x, y in [-1, 1] with y up, depth in [0, 1]; framebuffer and texture \
                 coordinates start at the top-left. Froxel volumes map screen uv (v down) to x, y.",
    uniforms: "Uniform buffers use the WGSL uniform layout (std140-compatible); struct member \
               offsets and sizes are listed per entry point.",
    glsl: "GL-style bindings: layout(binding = N) numbered per namespace (uniform blocks, texture \
           units, image units, shader storage blocks). A sampler is merged into the combined \
           sampler of the texture it samples and has no binding of its own. Vertex outputs are \
           adjusted to OpenGL clip space (y flipped, depth remapped to [-1, 1]) so images keep \
           WebGPU's memory layout.",
    hlsl_samplers: "Samplers are read from naga's sampler heaps: SamplerState \
                    nagaSamplerHeap[2048] at s0 space0 and SamplerComparisonState \
                    nagaComparisonSamplerHeap[2048] at s0 space1. Each group with samplers has \
                    a StructuredBuffer<uint> of heap indices (hlsl_sampler_index_buffers); a \
                    sampler's hlsl.sampler_index is its element in that buffer. Engines without \
                    a sampler heap use the variants with BINDINGS_NO_SAMPLER (manual filtering).",
    msl: "Argument indices are assigned per entry point: [[buffer(i)]], [[texture(i)]] and \
          [[sampler(i)]] count up separately over all groups in (group, binding) order; the \
          buffer after the last bound buffer receives runtime array sizes when a storage buffer \
          has a runtime-sized array.",
};

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ExportError + '_ {
    move |source| ExportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Resolves the request into variant outputs, composed and translated.
pub fn select(request: &ExportRequest) -> Result<Vec<VariantOutput>, ExportError> {
    let mut passes: Vec<&str> = Vec::new();
    let mut chosen: Vec<manifest::Variant> = Vec::new();
    for name in &request.variants {
        if let Some(v) = manifest::variant(name) {
            passes.push(v.pass.name);
            chosen.push(v);
        } else if let Some(p) = manifest::pass(name) {
            chosen.extend(
                manifest::variants()
                    .into_iter()
                    .filter(|v| v.pass.name == p.name),
            );
            passes.push(p.name);
        } else {
            return Err(ExportError::UnknownVariant {
                name: name.clone(),
                valid: manifest::variants()
                    .iter()
                    .map(|v| v.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                passes: PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", "),
            });
        }
    }
    passes.dedup();
    if request.defines.is_empty() {
        if request.variants.is_empty() {
            chosen = manifest::variants();
        }
        return chosen
            .iter()
            .map(|v| generate_variant(v).map_err(ExportError::from))
            .collect();
    }
    if passes.is_empty() {
        // Every pass that accepts the whole define set.
        passes = PASSES
            .iter()
            .filter(|p| Defines::parse(p, &request.defines).is_ok())
            .map(|p| p.name)
            .collect();
        if passes.is_empty() {
            let detail = PASSES
                .iter()
                .map(|p| format!("{}: {}", p.name, valid_defines(p).join(", ")))
                .collect::<Vec<_>>()
                .join("; ");
            return Err(ExportError::Define(CodegenError::Define(format!(
                "no pass accepts the defines {}; valid defines per pass: {detail}",
                request.defines.join(", ")
            ))));
        }
    }
    passes
        .iter()
        .map(|p| compose_variant(p, &request.defines).map_err(ExportError::from))
        .collect()
}

/// Builds the manifest JSON for variant outputs and targets.
pub fn manifest_json(variants: &[VariantOutput], targets: &[Target]) -> String {
    serde_json::to_string_pretty(&manifest_value(variants, targets)).expect("manifest serialises")
}

/// The manifest as a JSON value: `generator`, `conventions`, `targets` and `variants`.
pub fn manifest_value(variants: &[VariantOutput], targets: &[Target]) -> serde_json::Value {
    let manifest = Manifest {
        generator: format!("volfog {}", env!("CARGO_PKG_VERSION")),
        conventions: CONVENTIONS,
        targets: targets.iter().map(|t| target_info(*t)).collect(),
        variants: variants
            .iter()
            .map(|v| VariantEntry {
                name: &v.name,
                pass: &v.pass,
                defines: &v.defines,
                usage: manifest::pass(&v.pass).map(|p| p.usage).unwrap_or(""),
                entry_points: v
                    .entries
                    .iter()
                    .map(|e| EntryEntry {
                        name: &e.entry,
                        stage: e.stage,
                        workgroup_size: e.reflection.workgroup_size,
                        files: targets
                            .iter()
                            .map(|t| {
                                (
                                    t.name(),
                                    format!("{}/{}", t.name(), e.file_name(&v.name, *t)),
                                )
                            })
                            .collect(),
                        bindings: &e.reflection.bindings,
                        hlsl_sampler_index_buffers: &e.reflection.hlsl_sampler_index_buffers,
                        structs: &e.reflection.structs,
                    })
                    .collect(),
            })
            .collect(),
    };
    serde_json::to_value(&manifest).expect("manifest serialises")
}

/// Exports the request; the destination changes only when everything was written.
pub fn export(request: &ExportRequest) -> Result<ExportSummary, ExportError> {
    if request.targets.is_empty() {
        return Err(ExportError::NoTarget);
    }
    let mut targets = request.targets.clone();
    targets.sort();
    targets.dedup();
    let variants = select(request)?;

    let out = &request.out;
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    let leaf = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "export".to_string());
    let staging = parent.join(format!(".{leaf}.volfog-staging-{}", std::process::id()));
    let result = write_staging(&staging, &variants, &targets)
        .and_then(|summary| commit(&staging, out, &targets).map(|_| summary));
    if staging.exists() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    result
}

fn write_staging(
    staging: &Path,
    variants: &[VariantOutput],
    targets: &[Target],
) -> Result<ExportSummary, ExportError> {
    if staging.exists() {
        std::fs::remove_dir_all(staging).map_err(io(staging))?;
    }
    let mut files = 0;
    let mut entry_points = 0;
    for target in targets {
        let dir = staging.join(target.name());
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    }
    for v in variants {
        for e in &v.entries {
            entry_points += 1;
            for target in targets {
                let path = staging
                    .join(target.name())
                    .join(e.file_name(&v.name, *target));
                std::fs::write(&path, e.bytes(*target)).map_err(io(&path))?;
                files += 1;
            }
        }
    }
    let path = staging.join("manifest.json");
    std::fs::write(&path, manifest_json(variants, targets)).map_err(io(&path))?;
    Ok(ExportSummary {
        variants: variants.len(),
        entry_points,
        files,
    })
}

/// Moves the staged target folders and manifest into `out`, replacing an earlier
/// export: target folders that this export does not write are removed, so the folder
/// always matches its manifest. Other files in `out` are left alone.
fn commit(staging: &Path, out: &Path, targets: &[Target]) -> Result<(), ExportError> {
    std::fs::create_dir_all(out).map_err(io(out))?;
    for target in Target::ALL {
        let dir = out.join(target.name());
        if !targets.contains(&target) && dir.is_dir() {
            std::fs::remove_dir_all(&dir).map_err(io(&dir))?;
        }
    }
    let mut names: Vec<&str> = targets.iter().map(|t| t.name()).collect();
    names.push("manifest.json");
    for name in names {
        let from = staging.join(name);
        let to = out.join(name);
        if to.exists() {
            let old = out.join(format!(".{name}.volfog-old-{}", std::process::id()));
            std::fs::rename(&to, &old).map_err(io(&to))?;
            std::fs::rename(&from, &to).map_err(io(&to))?;
            let removed = if old.is_dir() {
                std::fs::remove_dir_all(&old)
            } else {
                std::fs::remove_file(&old)
            };
            removed.map_err(io(&old))?;
        } else {
            std::fs::rename(&from, &to).map_err(io(&to))?;
        }
    }
    Ok(())
}
