//! Engine include snippets: the in-shader modules (`apply`, `height_fog`,
//! `fog_volume`, `lightning`, `soft_particles`, `phase`) as files an engine includes
//! in its own shaders, in HLSL (`.hlsli`), GLSL (`.glsl`), MSL (`.h`) and flattened
//! WGSL, generated from the one WGSL source.
//!
//! Every global name starts with `volfog_` (functions, structs, constants; the module's
//! dependencies come along under their own `volfog_` names); nothing is bound: the
//! caller passes its textures, samplers and values. In HLSL, GLSL and MSL every
//! definition is guarded (`#ifndef VOLFOG_HAVE_<name>`), so several snippets can be
//! included in one shader; WGSL has no preprocessor, so `volfog_all.wgsl` holds every
//! snippet's definitions once.
//!
//! ```
//! use volfog_codegen::snippets::{SnippetLanguage, snippet};
//!
//! let phase = snippet("phase").unwrap();
//! assert!(phase.functions.contains(&"volfog_phase_hg".to_string()));
//! assert!(phase.text(SnippetLanguage::Hlsl).contains("float volfog_phase_hg("));
//! assert!(!phase.text(SnippetLanguage::Glsl).contains("#version"));
//! ```

use std::collections::HashSet;

use naga::back::{glsl, hlsl, msl, wgsl};
use naga_oil::compose::NagaModuleDescriptor;
use serde::Serialize;

use crate::compose::{validate, with_shared_composer};
use crate::manifest::MODULES;
use crate::reflect::{StructLayout, struct_layouts};
use crate::{CodegenError, Target, names};

/// The modules exported as snippets.
pub const SNIPPET_MODULES: [&str; 10] = [
    "apply",
    "height_fog",
    "fog_volume",
    "lightning",
    "soft_particles",
    "water",
    "sky",
    "clouds",
    "frustum",
    "phase",
];

/// The name of the snippet that holds every other one (once each definition).
pub const ALL_SNIPPETS: &str = "all";

/// The entry point a snippet module gets for the backends that need one; removed again.
const ENTRY: &str = "volfog_snippet_entry";

/// A snippet's language.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SnippetLanguage {
    /// HLSL include (`.hlsli`).
    Hlsl,
    /// GLSL include (`.glsl`), for `#version 450` shaders.
    Glsl,
    /// Metal header (`.h`).
    Msl,
    /// Flattened WGSL (`.wgsl`).
    Wgsl,
}

impl SnippetLanguage {
    /// Every language.
    pub const ALL: [SnippetLanguage; 4] = [Self::Hlsl, Self::Glsl, Self::Msl, Self::Wgsl];

    /// The export target whose folder holds this language's snippets.
    pub fn target(self) -> Target {
        match self {
            Self::Hlsl => Target::Hlsl,
            Self::Glsl => Target::Glsl,
            Self::Msl => Target::Msl,
            Self::Wgsl => Target::Wgsl,
        }
    }

    /// The language of a target, if it has snippets (SPIR-V has none).
    pub fn of_target(target: Target) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.target() == target)
    }

    /// File extension.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Hlsl => "hlsli",
            Self::Glsl => "glsl",
            Self::Msl => "h",
            Self::Wgsl => "wgsl",
        }
    }

    fn guarded(self) -> bool {
        self != Self::Wgsl
    }
}

/// One snippet in every language.
#[derive(Debug, Clone)]
pub struct Snippet {
    /// The module, e.g. `apply` (`all` for the union of every snippet).
    pub name: String,
    /// The module's own functions, `volfog_`-prefixed.
    pub functions: Vec<String>,
    /// The structs its functions take, `volfog_`-prefixed, with their WGSL layouts.
    pub structs: Vec<StructLayout>,
    /// Text per language, in [`SnippetLanguage::ALL`] order.
    texts: [String; 4],
}

impl Snippet {
    /// The snippet's text in a language.
    pub fn text(&self, language: SnippetLanguage) -> &str {
        &self.texts[SnippetLanguage::ALL
            .iter()
            .position(|l| *l == language)
            .unwrap()]
    }

    /// Its file name in a language, `volfog_<name>.<ext>`.
    pub fn file_name(&self, language: SnippetLanguage) -> String {
        format!("volfog_{}.{}", self.name, language.extension())
    }
}

/// The snippet of one module of [`SNIPPET_MODULES`], or [`ALL_SNIPPETS`].
pub fn snippet(name: &str) -> Result<Snippet, CodegenError> {
    if name == ALL_SNIPPETS {
        let parts = SNIPPET_MODULES
            .iter()
            .map(|m| snippet(m))
            .collect::<Result<Vec<_>, _>>()?;
        return Ok(union(&parts));
    }
    if !SNIPPET_MODULES.contains(&name) {
        return Err(CodegenError::Define(format!(
            "unknown snippet {name}; snippets: {}, {ALL_SNIPPETS}",
            SNIPPET_MODULES.join(", ")
        )));
    }
    let source = MODULES
        .iter()
        .find(|m| m.import_path == format!("volfog::{name}"))
        .expect("every snippet module is in the manifest");
    let body: String = source
        .source
        .lines()
        .filter(|l| !l.trim_start().starts_with("#define_import_path"))
        .map(|l| format!("{l}\n"))
        .collect();
    let text = format!("{body}\n@compute @workgroup_size(1) fn {ENTRY}() {{}}\n");
    let mut module = with_shared_composer(|composer| {
        composer
            .make_naga_module(NagaModuleDescriptor {
                source: &text,
                file_path: source.file,
                ..Default::default()
            })
            .map_err(|e| CodegenError::Compose(e.emit_to_string(composer)))
    })?;
    // The module's own functions are the ones naga_oil left undecorated.
    let own: Vec<String> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .filter(|n| names::undecorate(n).is_none())
        .collect();
    names::make_readable(&mut module, &format!("snippet {name}"))?;
    prefix_names(&mut module);
    let info = validate(&module, &format!("snippet {name}"))?;
    let structs: Vec<StructLayout> = struct_layouts(&module)
        .into_iter()
        .filter(|s| s.name.starts_with("volfog_"))
        .collect();
    let functions: Vec<String> = own.iter().map(|n| format!("volfog_{n}")).collect();
    let backend = |e: String| CodegenError::Backend {
        target: Target::Wgsl,
        variant: format!("snippet {name}"),
        entry: ENTRY.to_string(),
        message: e,
    };
    let raw = [
        write_hlsl(&module, &info).map_err(backend)?,
        write_glsl(&module, &info).map_err(backend)?,
        write_msl(&module, &info).map_err(backend)?,
        wgsl::write_string(&module, &info, wgsl::WriterFlags::empty())
            .map_err(|e| backend(e.to_string()))?,
    ];
    let mut texts: [String; 4] = Default::default();
    for (i, language) in SnippetLanguage::ALL.into_iter().enumerate() {
        let chunks = chunks(&raw[i], name);
        texts[i] = render(name, language, &functions, &structs, &chunks);
    }
    Ok(Snippet {
        name: name.to_string(),
        functions,
        structs,
        texts,
    })
}

/// Every snippet of [`SNIPPET_MODULES`] and [`ALL_SNIPPETS`].
pub fn all() -> Result<Vec<Snippet>, CodegenError> {
    let mut parts = SNIPPET_MODULES
        .iter()
        .map(|m| snippet(m))
        .collect::<Result<Vec<_>, _>>()?;
    parts.push(union(&parts));
    Ok(parts)
}

/// Prefixes every function (but the entry point), named type and constant with
/// `volfog_`.
fn prefix_names(module: &mut naga::Module) {
    let prefix = |n: &mut Option<String>| {
        if let Some(name) = n
            && !name.starts_with("volfog_")
        {
            *name = format!("volfog_{name}");
        }
    };
    for (_, f) in module.functions.iter_mut() {
        prefix(&mut f.name);
    }
    for (_, c) in module.constants.iter_mut() {
        prefix(&mut c.name);
    }
    let handles: Vec<_> = module.types.iter().map(|(h, _)| h).collect();
    for h in handles {
        let t = &module.types[h];
        if t.name.is_some() && matches!(t.inner, naga::TypeInner::Struct { .. }) {
            let mut name = t.name.clone();
            prefix(&mut name);
            let inner = t.inner.clone();
            module.types.replace(h, naga::Type { name, inner });
        }
    }
}

fn write_hlsl(module: &naga::Module, info: &naga::valid::ModuleInfo) -> Result<String, String> {
    let options = hlsl::Options::default();
    let pipeline = hlsl::PipelineOptions {
        entry_point: Some((naga::ShaderStage::Compute, ENTRY.to_string())),
    };
    let mut text = String::new();
    hlsl::Writer::new(&mut text, &options, &pipeline)
        .write(module, info, None)
        .map_err(|e| e.to_string())?;
    Ok(text)
}

fn write_glsl(module: &naga::Module, info: &naga::valid::ModuleInfo) -> Result<String, String> {
    let options = glsl::Options {
        version: glsl::Version::Desktop(450),
        ..Default::default()
    };
    let pipeline = glsl::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: ENTRY.to_string(),
        multiview: None,
    };
    let mut text = String::new();
    glsl::Writer::new(
        &mut text,
        module,
        info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .map_err(|e| e.to_string())?
    .write()
    .map_err(|e| e.to_string())?;
    Ok(text)
}

fn write_msl(module: &naga::Module, info: &naga::valid::ModuleInfo) -> Result<String, String> {
    let pipeline = msl::PipelineOptions {
        entry_point: Some((naga::ShaderStage::Compute, ENTRY.to_string())),
        ..Default::default()
    };
    msl::write_string(module, info, &msl::Options::default(), &pipeline)
        .map(|(text, _)| text)
        .map_err(|e| e.to_string())
}

/// A top-level definition of generated text: its name (`None` for preprocessor lines
/// and `using` declarations) and its lines.
#[derive(Debug, Clone, PartialEq)]
struct Chunk {
    name: Option<String>,
    text: String,
}

/// Splits generated text into top-level definitions, drops the snippet entry point and
/// what only it needs (GLSL's `#version`, extensions and workgroup layout, naga's
/// comments), and gives naga's anonymous types (`type_N`) names of this module.
fn chunks(text: &str, module: &str) -> Vec<Chunk> {
    let text = rename_anonymous_types(text, module);
    // naga's `// language:` note and GLSL's compute-stage extension belong to the
    // removed entry point's file, not to an include.
    let kept: String = text
        .lines()
        .filter(|l| !(l.starts_with("//") || l.starts_with("#extension")))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut out = split_top_level(&kept);
    out.retain(|c| {
        let text = c.text.trim_start();
        !(c.text.contains(ENTRY)
            || text.starts_with("void main(")
            || text.starts_with("#version")
            || text.starts_with("layout(local_size"))
    });
    for c in &mut out {
        let trimmed = c.text.trim_end().to_string();
        c.text = trimmed + "\n";
    }
    out
}

/// Splits text into top-level definitions: one starts at each line that begins in the
/// first column with something other than a closing bracket; attribute lines (HLSL
/// `[numthreads(..)]`, WGSL `@...`) belong to the definition after them.
fn split_top_level(text: &str) -> Vec<Chunk> {
    let mut out: Vec<Chunk> = Vec::new();
    let mut pending_attribute = String::new();
    for line in text.lines() {
        let top = line
            .chars()
            .next()
            .is_some_and(|c| !c.is_whitespace() && c != '{' && c != '}' && c != ')');
        if line.starts_with('[') || line.starts_with('@') {
            pending_attribute.push_str(line);
            pending_attribute.push('\n');
            continue;
        }
        if top {
            out.push(Chunk {
                name: chunk_name(line),
                text: std::mem::take(&mut pending_attribute),
            });
        }
        if let Some(last) = out.last_mut() {
            last.text.push_str(line);
            last.text.push('\n');
        }
    }
    out
}

/// Gives the names naga invents module-independent meaning: anonymous types
/// (`type_N`) become `volfog_<module>_type_N`, helpers (`naga_*`, `Naga*`) `volfog_*`;
/// and gives back the WGSL name of a global that ends in a digit, to which naga's namer
/// appends `_` (`volfog_phase_hg_sh_l1_` -> `volfog_phase_hg_sh_l1`): the namer's own
/// collision suffixes are `_N`, so the shorter name stays unique.
fn rename_anonymous_types(text: &str, module: &str) -> String {
    rename_identifiers(text, |ident| {
        let anonymous = ident
            .strip_prefix("type_")
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
        if anonymous {
            Some(format!("volfog_{module}_{ident}"))
        } else if ident.starts_with("naga_") || ident.starts_with("Naga") {
            Some(format!("volfog_{ident}"))
        } else if ident.starts_with("volfog_")
            && ident
                .strip_suffix('_')
                .is_some_and(|stem| stem.ends_with(|c: char| c.is_ascii_digit()))
        {
            Some(ident[..ident.len() - 1].to_string())
        } else {
            None
        }
    })
}

/// Replaces every identifier `rename` returns a new name for.
fn rename_identifiers(text: &str, rename: impl Fn(&str) -> Option<String>) -> String {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(ident) {
        out.push_str(&rest[..start]);
        let len = rest[start..]
            .find(|c: char| !ident(c))
            .unwrap_or(rest.len() - start);
        let word = &rest[start..start + len];
        match rename(word).filter(|_| !word.starts_with(|c: char| c.is_ascii_digit())) {
            Some(new) => out.push_str(&new),
            None => out.push_str(word),
        }
        rest = &rest[start + len..];
    }
    out.push_str(rest);
    out
}

/// The name a top-level line defines.
fn chunk_name(line: &str) -> Option<String> {
    let line = line.trim();
    if line.starts_with('#') || line.starts_with("using ") {
        return None;
    }
    let ident = |s: &str| {
        let s = s.trim();
        let start = s
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |p| p + 1);
        (!s[start..].is_empty()).then(|| s[start..].to_string())
    };
    if let Some(rest) = line.strip_prefix("struct ") {
        return ident(rest.split([' ', '{']).next()?);
    }
    if let Some((decl, _)) = line.split_once(" = ") {
        // WGSL declares `const NAME: TYPE = ...`; the C family `TYPE NAME = ...`.
        return ident(decl.split_once(": ").map_or(decl, |(name, _)| name));
    }
    if let Some((head, _)) = line.split_once('(') {
        return ident(head);
    }
    ident(line.trim_end_matches(';'))
}

fn render(
    name: &str,
    language: SnippetLanguage,
    functions: &[String],
    structs: &[StructLayout],
    chunks: &[Chunk],
) -> String {
    let mut out = String::new();
    let comment = match language {
        SnippetLanguage::Wgsl
        | SnippetLanguage::Hlsl
        | SnippetLanguage::Glsl
        | SnippetLanguage::Msl => "//",
    };
    let source = if name == ALL_SNIPPETS {
        format!("the volfog modules {}", SNIPPET_MODULES.join(", "))
    } else {
        format!("volfog::{name} (shaders/volfog/{name}.wgsl)")
    };
    let mut header = vec![
        format!(
            "volfog_{name}.{}: {source} as a {} include, generated by volfog {}; do not edit.",
            language.extension(),
            match language {
                SnippetLanguage::Hlsl => "HLSL (shader model 6.0)",
                SnippetLanguage::Glsl => "GLSL 450",
                SnippetLanguage::Msl => "Metal Shading Language 2.1",
                SnippetLanguage::Wgsl => "flattened WGSL",
            },
            env!("CARGO_PKG_VERSION")
        ),
        format!("Functions: {}.", functions.join(", ")),
    ];
    if !structs.is_empty() {
        header.push(format!(
            "Structs (WGSL uniform layout; see volfog_layout.h): {}.",
            structs
                .iter()
                .map(|s| format!("{} ({} bytes)", s.name, s.size))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    header.push(
        "Every global name starts with volfog_; nothing is bound: pass your textures, \
         samplers and values as arguments."
            .to_string(),
    );
    header.push(if language.guarded() {
        "Each definition is guarded (VOLFOG_HAVE_<name>): several volfog snippets can be \
         included in one shader."
            .to_string()
    } else {
        "WGSL has no preprocessor: use one volfog WGSL snippet per shader, or \
         volfog_all.wgsl for all of them."
            .to_string()
    });
    for line in header {
        for wrapped in wrap(&line, 86) {
            out.push_str(&format!("{comment} {wrapped}\n"));
        }
    }
    out.push('\n');
    for c in chunks {
        match (&c.name, language.guarded()) {
            (Some(n), true) => {
                out.push_str(&format!(
                    "#ifndef VOLFOG_HAVE_{n}\n#define VOLFOG_HAVE_{n}\n"
                ));
                out.push_str(&c.text);
                out.push_str("#endif\n\n");
            }
            _ => {
                out.push_str(&c.text);
                out.push('\n');
            }
        }
    }
    out.trim_end().to_string() + "\n"
}

fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut().unwrap();
        if !last.is_empty() && last.len() + 1 + word.len() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// One snippet holding every part's definitions once.
fn union(parts: &[Snippet]) -> Snippet {
    let mut functions = Vec::new();
    let mut structs: Vec<StructLayout> = Vec::new();
    for p in parts {
        functions.extend(p.functions.iter().cloned());
        for s in &p.structs {
            if !structs.iter().any(|t| t.name == s.name) {
                structs.push(s.clone());
            }
        }
    }
    let mut texts: [String; 4] = Default::default();
    for (i, language) in SnippetLanguage::ALL.into_iter().enumerate() {
        let mut seen = HashSet::new();
        let mut merged = Vec::new();
        for p in parts {
            let body = p.texts[i]
                .split_once("\n\n")
                .map_or(p.texts[i].as_str(), |(_, body)| body);
            for c in split_rendered(body, language) {
                let fresh = c.name.as_ref().is_none_or(|n| seen.insert(n.clone()));
                let repeated_line =
                    c.name.is_none() && merged.iter().any(|m: &Chunk| m.text == c.text);
                if fresh && !repeated_line {
                    merged.push(c);
                }
            }
        }
        texts[i] = render(ALL_SNIPPETS, language, &functions, &structs, &merged);
    }
    Snippet {
        name: ALL_SNIPPETS.to_string(),
        functions,
        structs,
        texts,
    }
}

/// The chunks of a rendered snippet body (guards removed).
fn split_rendered(body: &str, language: SnippetLanguage) -> Vec<Chunk> {
    if !language.guarded() {
        return split_top_level(body)
            .into_iter()
            .map(|c| Chunk {
                text: c.text.trim_end().to_string() + "\n",
                ..c
            })
            .collect();
    }
    let mut out = Vec::new();
    let mut lines = body.lines().peekable();
    while let Some(line) = lines.next() {
        if let Some(name) = line.strip_prefix("#ifndef VOLFOG_HAVE_") {
            lines.next();
            let mut text = String::new();
            for l in lines.by_ref() {
                if l == "#endif" {
                    break;
                }
                text.push_str(l);
                text.push('\n');
            }
            out.push(Chunk {
                name: Some(name.to_string()),
                text,
            });
        } else if !line.trim().is_empty() {
            out.push(Chunk {
                name: None,
                text: format!("{line}\n"),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_level_names() {
        assert_eq!(
            chunk_name("struct volfog_Froxels {").as_deref(),
            Some("volfog_Froxels")
        );
        assert_eq!(
            chunk_name("float volfog_phase_hg(float cos_theta, float g)").as_deref(),
            Some("volfog_phase_hg")
        );
        assert_eq!(
            chunk_name("static const float volfog_PI = 3.1415927;").as_deref(),
            Some("volfog_PI")
        );
        assert_eq!(
            chunk_name("const volfog_PI: f32 = 3.1415927f;").as_deref(),
            Some("volfog_PI")
        );
        assert_eq!(
            chunk_name("fn volfog_phase_hg(cos_theta: f32, g: f32) -> f32 {").as_deref(),
            Some("volfog_phase_hg")
        );
        assert_eq!(
            chunk_name("constant metal::float4 volfog_FOG_NONE = metal::float4(0.0);").as_deref(),
            Some("volfog_FOG_NONE")
        );
        assert_eq!(chunk_name("#include <metal_stdlib>"), None);
        assert_eq!(chunk_name("using metal::uint;"), None);
    }

    #[test]
    fn invented_names_are_prefixed() {
        assert_eq!(
            rename_anonymous_types(
                "struct type_5 { float inner[3]; }; type_50 x; my_type_5; naga_f2i32(v); NagaDimensions3D(t); 1.0e5",
                "phase"
            ),
            "struct volfog_phase_type_5 { float inner[3]; }; volfog_phase_type_50 x; my_type_5; \
             volfog_naga_f2i32(v); volfog_NagaDimensions3D(t); 1.0e5"
        );
        assert_eq!(
            rename_anonymous_types("volfog_sh_l1_(d); volfog_SH_Y0_; g0_; volfog_x_", "phase"),
            "volfog_sh_l1(d); volfog_SH_Y0; g0_; volfog_x_"
        );
    }

    #[test]
    fn every_wgsl_snippet_parses_and_validates_whole() {
        for s in all().unwrap() {
            let text = s.text(SnippetLanguage::Wgsl);
            let module = naga::front::wgsl::parse_str(text)
                .unwrap_or_else(|e| panic!("{}: {}", s.name, e.emit_to_string(text)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {e:?}", s.name));
            for f in &s.functions {
                assert!(
                    module
                        .functions
                        .iter()
                        .any(|(_, g)| g.name.as_ref() == Some(f)),
                    "{}: {f}",
                    s.name
                );
            }
        }
    }

    #[test]
    fn every_snippet_is_prefixed_and_guarded() {
        for s in all().unwrap() {
            for language in SnippetLanguage::ALL {
                let text = s.text(language);
                assert!(!text.contains(ENTRY), "{} {language:?}", s.name);
                assert!(!text.contains("naga_oil"), "{} {language:?}", s.name);
                for line in text.lines() {
                    if let Some(name) = line.strip_prefix("#ifndef VOLFOG_HAVE_") {
                        assert!(
                            name.starts_with("volfog_"),
                            "{} {language:?}: {name}",
                            s.name
                        );
                    }
                }
                for f in &s.functions {
                    assert!(text.contains(f.as_str()), "{} {language:?}: {f}", s.name);
                    assert!(
                        !text.contains(&format!("{f}_(")),
                        "{} {language:?}: {f}_",
                        s.name
                    );
                }
                if language.guarded() {
                    for f in &s.functions {
                        assert!(
                            text.contains(&format!("#ifndef VOLFOG_HAVE_{f}\n")),
                            "{} {language:?}: {f} unguarded",
                            s.name
                        );
                    }
                }
            }
        }
    }
}
