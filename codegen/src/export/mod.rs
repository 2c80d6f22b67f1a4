//! Export of shaders for engines that do not use Rust: every selected variant's
//! entry points in the chosen targets, as `DIR/<target>/<variant>.<entry>.<stage>.<ext>`;
//! on request the include snippets, as `DIR/<target>/include/volfog_<module>.<ext>`;
//! `DIR/volfog_layout.h`, the C/C++ structs of every uniform and storage buffer; and
//! `DIR/manifest.json` with defines, workgroup sizes, draw state, bindings (with their
//! slots in every target), struct layouts and the snippets.
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
//!     hlsl_samplers: Default::default(),
//!     snippets: Some(vec![]),
//!     custom_density: None,
//! })
//! .unwrap();
//! println!("{} files", summary.files);
//! ```

use std::path::{Path, PathBuf};

mod manifest_json;

use crate::compose::{Defines, valid_defines};
use crate::snippets::{self, Snippet, SnippetLanguage};

pub use manifest_json::{manifest_json, manifest_value};

use crate::custom::CustomModule;
use crate::manifest::{self, PASSES};
use crate::reflect::HlslSamplers;
use crate::translate::{VariantOutput, compose_variant_with, generate_variant};
use crate::{CodegenError, Target};

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
    /// How HLSL binds samplers.
    pub hlsl_samplers: HlslSamplers,
    /// Include snippets to write: `None` for none, an empty list for every one, or
    /// module names (see [`snippets::SNIPPET_MODULES`]; `all` is the union).
    pub snippets: Option<Vec<String>>,
    /// The user's custom density module ([`manifest::CUSTOM_DENSITY`]): the inject
    /// variants composed under `VOLFOG_INJECT_CUSTOM_DENSITY` (which `defines` must
    /// name) import its `volfog_custom_density`.
    pub custom_density: Option<CustomModule>,
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
    /// A snippet name that is not a snippet module.
    #[error("unknown snippet {name}; valid snippets: {valid}")]
    UnknownSnippet {
        /// The requested name.
        name: String,
        /// Every snippet.
        valid: String,
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
    /// Snippet files written.
    pub snippet_files: usize,
}

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
    if request.custom_density.is_some()
        && !request
            .defines
            .iter()
            .any(|d| d.trim() == manifest::CUSTOM_DENSITY.define)
    {
        return Err(ExportError::Define(CodegenError::Define(format!(
            "a custom density module is composed under {}: add the define",
            manifest::CUSTOM_DENSITY.define
        ))));
    }
    if request.defines.is_empty() {
        if request.variants.is_empty() {
            chosen = manifest::variants();
        }
        add_vertex_passes(&mut chosen);
        return chosen
            .iter()
            .map(|v| generate_variant(v, request.hlsl_samplers).map_err(ExportError::from))
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
    let modules: Vec<_> = request
        .custom_density
        .iter()
        .map(|m| (&manifest::CUSTOM_DENSITY, m))
        .collect();
    let mut outputs: Vec<VariantOutput> = passes
        .iter()
        .map(|p| {
            compose_variant_with(p, &request.defines, request.hlsl_samplers, &modules)
                .map_err(ExportError::from)
        })
        .collect::<Result<_, _>>()?;
    let mut vertex = Vec::new();
    add_vertex_passes_of(&mut vertex, passes.iter().copied(), |name| {
        outputs.iter().any(|o| o.name == name)
    });
    for v in &vertex {
        outputs.push(generate_variant(v, request.hlsl_samplers)?);
    }
    Ok(outputs)
}

/// Adds the default variant of every pass whose vertex shader a chosen pass draws with.
fn add_vertex_passes(chosen: &mut Vec<manifest::Variant>) {
    let passes: Vec<&str> = chosen.iter().map(|v| v.pass.name).collect();
    let names: Vec<String> = chosen.iter().map(|v| v.name.clone()).collect();
    let mut extra = Vec::new();
    add_vertex_passes_of(&mut extra, passes.into_iter(), |name| {
        names.iter().any(|n| n == name)
    });
    chosen.extend(extra);
}

fn add_vertex_passes_of<'a>(
    out: &mut Vec<manifest::Variant>,
    passes: impl Iterator<Item = &'a str>,
    present: impl Fn(&str) -> bool,
) {
    for pass in passes {
        let vertex = manifest::pass(pass)
            .and_then(|p| p.render)
            .and_then(|r| r.vertex);
        if let Some((vertex_pass, _)) = vertex {
            let name = manifest::variant_name(vertex_pass, &[]);
            if !present(&name) && !out.iter().any(|v| v.name == name) {
                out.extend(manifest::variant(&name));
            }
        }
    }
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
    let snippets = select_snippets(request)?;

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
    let contents = Contents {
        variants: &variants,
        snippets: &snippets,
        targets: &targets,
        hlsl_samplers: request.hlsl_samplers,
    };
    let result = write_staging(&staging, &contents)
        .and_then(|summary| commit(&staging, out, &targets).map(|_| summary));
    if staging.exists() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    result
}

/// Everything an export writes.
struct Contents<'a> {
    variants: &'a [VariantOutput],
    snippets: &'a [Snippet],
    targets: &'a [Target],
    hlsl_samplers: HlslSamplers,
}

/// The snippets a request names (every one for an empty list).
fn select_snippets(request: &ExportRequest) -> Result<Vec<Snippet>, ExportError> {
    let Some(names) = &request.snippets else {
        return Ok(Vec::new());
    };
    if names.is_empty() {
        return Ok(snippets::all()?);
    }
    names
        .iter()
        .map(|n| {
            if n != snippets::ALL_SNIPPETS && !snippets::SNIPPET_MODULES.contains(&n.as_str()) {
                return Err(ExportError::UnknownSnippet {
                    name: n.clone(),
                    valid: format!(
                        "{}, {}",
                        snippets::SNIPPET_MODULES.join(", "),
                        snippets::ALL_SNIPPETS
                    ),
                });
            }
            Ok(snippets::snippet(n)?)
        })
        .collect()
}

/// The layouts `volfog_layout.h` declares: every struct of the variants and snippets.
pub fn header_structs(
    variants: &[VariantOutput],
    snippets: &[Snippet],
) -> Result<Vec<crate::reflect::StructLayout>, CodegenError> {
    let mut lists: Vec<&[crate::reflect::StructLayout]> = Vec::new();
    for v in variants {
        for e in &v.entries {
            lists.push(&e.reflection.structs);
        }
    }
    for s in snippets {
        lists.push(&s.structs);
    }
    crate::c_header::merge(&lists)
}

fn write_staging(staging: &Path, c: &Contents<'_>) -> Result<ExportSummary, ExportError> {
    if staging.exists() {
        std::fs::remove_dir_all(staging).map_err(io(staging))?;
    }
    let mut files = 0;
    let mut entry_points = 0;
    for target in c.targets {
        let dir = staging.join(target.name());
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    }
    for v in c.variants {
        for e in &v.entries {
            entry_points += 1;
            for target in c.targets {
                let path = staging
                    .join(target.name())
                    .join(e.file_name(&v.name, *target));
                std::fs::write(&path, e.bytes(*target)).map_err(io(&path))?;
                files += 1;
            }
        }
    }
    let mut snippet_files = 0;
    for language in c
        .targets
        .iter()
        .flat_map(|t| SnippetLanguage::of_target(*t))
        .filter(|_| !c.snippets.is_empty())
    {
        let dir = staging.join(language.target().name()).join("include");
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        for s in c.snippets {
            let path = dir.join(s.file_name(language));
            std::fs::write(&path, s.text(language)).map_err(io(&path))?;
            snippet_files += 1;
        }
    }
    let header = crate::c_header::c_header(&header_structs(c.variants, c.snippets)?)?;
    let path = staging.join("volfog_layout.h");
    std::fs::write(&path, header).map_err(io(&path))?;
    let path = staging.join("manifest.json");
    std::fs::write(
        &path,
        manifest_json(c.variants, c.snippets, c.targets, c.hlsl_samplers),
    )
    .map_err(io(&path))?;
    Ok(ExportSummary {
        variants: c.variants.len(),
        entry_points,
        files,
        snippet_files,
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
    names.push("volfog_layout.h");
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
