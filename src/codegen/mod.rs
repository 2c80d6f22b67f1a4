//! Shader codegen: compose a pass with naga_oil, validate it with naga, compact it,
//! and translate every entry point to WGSL, SPIR-V, GLSL, HLSL and MSL with explicit
//! binding maps and a reflection record for the binding manifest.
//!
//! `build.rs` includes this module by path to prebuild every variant; the library uses
//! it to compose custom define sets at run time (`volfog export --define ...`).

pub mod compose;
pub mod names;
pub mod reflect;
pub mod translate;

use std::fmt;

/// A shader stage of an entry point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// Compute shader (`.comp`).
    Compute,
    /// Vertex shader (`.vert`).
    Vertex,
    /// Fragment shader (`.frag`).
    Fragment,
}

impl Stage {
    /// The short stage name used in exported file names: `comp`, `vert` or `frag`.
    pub fn short(self) -> &'static str {
        match self {
            Stage::Compute => "comp",
            Stage::Vertex => "vert",
            Stage::Fragment => "frag",
        }
    }

    pub(crate) fn from_naga(stage: naga::ShaderStage) -> Option<Self> {
        match stage {
            naga::ShaderStage::Compute => Some(Stage::Compute),
            naga::ShaderStage::Vertex => Some(Stage::Vertex),
            naga::ShaderStage::Fragment => Some(Stage::Fragment),
            _ => None,
        }
    }

    pub(crate) fn to_naga(self) -> naga::ShaderStage {
        match self {
            Stage::Compute => naga::ShaderStage::Compute,
            Stage::Vertex => naga::ShaderStage::Vertex,
            Stage::Fragment => naga::ShaderStage::Fragment,
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.short())
    }
}

/// An export target language.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    /// Flattened WGSL (no naga_oil directives left).
    Wgsl,
    /// SPIR-V 1.3 binary for Vulkan 1.1.
    Spirv,
    /// GLSL 450 core, one file per entry point.
    Glsl,
    /// HLSL for shader model 6.0.
    Hlsl,
    /// Metal Shading Language 2.1.
    Msl,
}

impl Target {
    /// Every target, in export order.
    pub const ALL: [Target; 5] = [
        Target::Wgsl,
        Target::Spirv,
        Target::Glsl,
        Target::Hlsl,
        Target::Msl,
    ];

    /// The target's name on the command line and as export folder.
    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::Spirv => "spirv",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
            Target::Msl => "msl",
        }
    }

    /// File extension of exported files.
    pub fn extension(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::Spirv => "spv",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
            Target::Msl => "metal",
        }
    }

    /// Parses a target name (`wgsl`, `spirv`, `glsl`, `hlsl`, `msl`).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything that can go wrong while generating shaders.
#[derive(Debug, thiserror::Error)]
pub enum CodegenError {
    /// naga_oil failed to parse or compose a module; the text carries the file, line,
    /// column and source line.
    #[error("{0}")]
    Compose(String),
    /// A module's `#define_import_path` does not match its file.
    #[error(
        "{file}: `#define_import_path {found}` does not match the file; expected `{expected}`"
    )]
    ImportPath {
        /// The module file.
        file: String,
        /// The import path in the file.
        found: String,
        /// The import path its location requires.
        expected: String,
    },
    /// The composed module failed naga validation.
    #[error("{0}")]
    Validation(String),
    /// Two exported items would get the same readable name.
    #[error("name collision in variant {variant}: {detail}")]
    NameCollision {
        /// The variant being translated.
        variant: String,
        /// Which items collide.
        detail: String,
    },
    /// A backend failed to translate the module.
    #[error("{target} translation of {variant} entry point {entry} failed: {message}")]
    Backend {
        /// The target language.
        target: Target,
        /// The variant.
        variant: String,
        /// The entry point.
        entry: String,
        /// The backend's message.
        message: String,
    },
    /// A define is not known to the pass, or its value is out of range.
    #[error("{0}")]
    Define(String),
}

/// Output of one entry point of one variant in every target.
#[derive(Debug, Clone)]
pub struct EntryOutput {
    /// Entry point name, as in the WGSL source.
    pub entry: String,
    /// Its stage.
    pub stage: Stage,
    /// Flattened WGSL.
    pub wgsl: String,
    /// SPIR-V words.
    pub spirv: Vec<u32>,
    /// GLSL 450.
    pub glsl: String,
    /// HLSL (SM 6.0).
    pub hlsl: String,
    /// MSL 2.1.
    pub msl: String,
    /// Bindings, structs and workgroup size, for the manifest.
    pub reflection: reflect::EntryReflection,
}

impl EntryOutput {
    /// The exported file name of this entry point for a target:
    /// `<variant>.<entry>.<stage>.<ext>`.
    pub fn file_name(&self, variant: &str, target: Target) -> String {
        format!(
            "{variant}.{}.{}.{}",
            self.entry,
            self.stage.short(),
            target.extension()
        )
    }

    /// The bytes of the exported file for a target.
    pub fn bytes(&self, target: Target) -> Vec<u8> {
        match target {
            Target::Wgsl => self.wgsl.clone().into_bytes(),
            Target::Spirv => self.spirv.iter().flat_map(|w| w.to_le_bytes()).collect(),
            Target::Glsl => self.glsl.clone().into_bytes(),
            Target::Hlsl => self.hlsl.clone().into_bytes(),
            Target::Msl => self.msl.clone().into_bytes(),
        }
    }
}

/// Output of one variant: a pass composed under one define set.
#[derive(Debug, Clone)]
pub struct VariantOutput {
    /// Variant name, `pass@default` or `pass@A+B`.
    pub name: String,
    /// The pass.
    pub pass: String,
    /// Defines, sorted, as `NAME` or `NAME=VALUE`.
    pub defines: Vec<String>,
    /// One output per entry point.
    pub entries: Vec<EntryOutput>,
}

/// Composes, validates and translates one pass under a define set.
pub fn generate(
    composer: &mut naga_oil::compose::Composer,
    pass: &crate::manifest::PassSource,
    defines: &compose::Defines,
) -> Result<VariantOutput, CodegenError> {
    let name = defines.variant_name(pass.name);
    let module = compose::compose_pass(composer, pass, defines)?;
    let entries = translate::translate(&name, module)?;
    Ok(VariantOutput {
        name,
        pass: pass.name.to_string(),
        defines: defines.as_strings(),
        entries,
    })
}
