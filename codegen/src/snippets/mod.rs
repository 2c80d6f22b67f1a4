//! Engine include snippets: the in-shader modules (`apply`, `height_fog`,
//! `fog_volume`, `lightning`, `soft_particles`, `fog_lit`, `phase`, ...) as files an
//! engine includes in its own shaders, in HLSL (`.hlsli`), GLSL 450 (`.glsl`), GLSL ES
//! 3.00 for WebGL2 (`.es.glsl`), MSL (`.h`) and flattened WGSL, generated from the one
//! WGSL source.
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

mod backends;
mod chunks;
mod render;

use naga::back::wgsl;
use naga_oil::compose::NagaModuleDescriptor;
use serde::Serialize;

use crate::compose::{validate, with_shared_composer};
use crate::manifest::MODULES;
use crate::reflect::{StructLayout, struct_layouts};
use crate::{CodegenError, Target, names};

use backends::{write_glsl, write_glsl_es, write_hlsl, write_msl};
use chunks::chunks;
use render::{render, union};

/// The modules exported as snippets.
pub const SNIPPET_MODULES: [&str; 12] = [
    "apply",
    "stereo_apply",
    "height_fog",
    "fog_volume",
    "lightning",
    "soft_particles",
    "fog_lit",
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
/// The fragment entry point GLSL ES 3.00 needs (it has no compute stage); its name
/// holds [`ENTRY`], so it is removed the same way.
const FRAGMENT_ENTRY: &str = "volfog_snippet_entry_fragment";

/// A snippet's language.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SnippetLanguage {
    /// HLSL include (`.hlsli`).
    Hlsl,
    /// GLSL include (`.glsl`), for `#version 450` shaders.
    Glsl,
    /// GLSL ES include (`.es.glsl`), for `#version 300 es` shaders (WebGL2); in the
    /// GLSL target's folder next to the GLSL 450 one.
    GlslEs,
    /// Metal header (`.h`).
    Msl,
    /// Flattened WGSL (`.wgsl`).
    Wgsl,
}

impl SnippetLanguage {
    /// Every language.
    pub const ALL: [SnippetLanguage; 5] =
        [Self::Hlsl, Self::Glsl, Self::GlslEs, Self::Msl, Self::Wgsl];

    /// The export target whose folder holds this language's snippets.
    pub fn target(self) -> Target {
        match self {
            Self::Hlsl => Target::Hlsl,
            Self::Glsl | Self::GlslEs => Target::Glsl,
            Self::Msl => Target::Msl,
            Self::Wgsl => Target::Wgsl,
        }
    }

    /// The languages whose snippets a target's folder holds (SPIR-V has none, GLSL
    /// two).
    pub fn of_target(target: Target) -> impl Iterator<Item = Self> {
        Self::ALL.into_iter().filter(move |l| l.target() == target)
    }

    /// The language's name in the manifest (`glsl_es` for GLSL ES, otherwise the
    /// target's).
    pub fn name(self) -> &'static str {
        match self {
            Self::GlslEs => "glsl_es",
            other => other.target().name(),
        }
    }

    /// File extension.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Hlsl => "hlsli",
            Self::Glsl => "glsl",
            Self::GlslEs => "es.glsl",
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
    texts: [String; 5],
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
    let text = format!(
        "{body}\n@compute @workgroup_size(1) fn {ENTRY}() {{}}\n\
         @fragment fn {FRAGMENT_ENTRY}() -> @location(0) vec4<f32> {{ return vec4<f32>(0.0); }}\n"
    );
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
        write_glsl_es(&module, &info).map_err(backend)?,
        write_msl(&module, &info).map_err(backend)?,
        wgsl::write_string(&module, &info, wgsl::WriterFlags::empty())
            .map_err(|e| backend(e.to_string()))?,
    ];
    let mut texts: [String; 5] = Default::default();
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

#[cfg(test)]
mod tests {
    use super::*;

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
