//! volfog's shader codegen: the WGSL modules and passes of volfog, composed, validated
//! and translated.
//!
//! One variant of the manifest, composed with naga_oil and validated with naga, and
//! (feature `translate`) translated to every target language:
//!
//! ```
//! use volfog_codegen::compose::{self, Defines};
//! use volfog_codegen::manifest;
//!
//! // A prebuilt variant: the scan pass with froxel culling.
//! let variant = manifest::variant("scan@FROXEL_CULL").unwrap();
//! assert_eq!(variant.defines, ["VOLFOG_FROXEL_CULL"]);
//! let defines = Defines::flags(variant.defines.iter().copied());
//! let module = compose::compose_validated(variant.pass, &defines)?;
//! assert_eq!(module.entry_points[0].name, "scan");
//!
//! #[cfg(feature = "translate")]
//! {
//!     use volfog_codegen::reflect::HlslSamplers;
//!     use volfog_codegen::{Target, translate};
//!
//!     let out = translate::generate_variant(&variant, HlslSamplers::Classic)?;
//!     let scan = &out.entries[0];
//!     assert_eq!(scan.file_name(&out.name, Target::Hlsl), "scan@FROXEL_CULL.scan.comp.hlsl");
//!     assert_eq!(scan.reflection.workgroup_size, Some([8, 8, 1]));
//!     assert!(scan.hlsl.contains("RWTexture3D"));
//!     assert!(scan.glsl.starts_with("#version 450"));
//!     assert_eq!(scan.spirv[0], 0x0723_0203); // the SPIR-V magic number
//!     assert!(!scan.wgsl.contains("#import"));
//! }
//! # Ok::<(), volfog_codegen::CodegenError>(())
//! ```
//!
//! What it holds: the manifest of WGSL modules and passes, composition with
//! naga_oil under define sets, validation with naga, reflection of bindings and
//! struct layouts, and (feature `translate`) compaction and translation of every entry
//! point to WGSL, SPIR-V, GLSL, HLSL and MSL plus the export of a folder with its
//! binding manifest; and the same modules as a WESL package ([`wesl`]) for Bevy.
//!
//! The `volfog` library uses it as a build dependency (every variant is composed and
//! validated when the library builds, so a shader error fails `cargo build`) and at run
//! time to compose the variants its wgpu pipeline needs.
//!
//! ```
//! use volfog_codegen::{compose, manifest};
//!
//! let pass = manifest::pass("scan").unwrap();
//! let module = compose::compose_validated(pass, &compose::Defines::default()).unwrap();
//! assert_eq!(module.entry_points[0].name, "scan");
//! ```
#![warn(missing_docs)]

#[cfg(feature = "translate")]
pub mod c_header;
pub mod compose;
pub mod custom;
#[cfg(feature = "translate")]
pub mod export;
pub mod manifest;
pub mod names;
pub mod reflect;
#[cfg(feature = "translate")]
mod rewrite;
#[cfg(feature = "translate")]
pub mod snippets;
#[cfg(feature = "translate")]
pub mod translate;
pub mod wesl;

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

    /// The stage of a naga shader stage (`None` for stages volfog does not use).
    pub fn from_naga(stage: naga::ShaderStage) -> Option<Self> {
        match stage {
            naga::ShaderStage::Compute => Some(Stage::Compute),
            naga::ShaderStage::Vertex => Some(Stage::Vertex),
            naga::ShaderStage::Fragment => Some(Stage::Fragment),
            _ => None,
        }
    }

    /// The naga shader stage.
    pub fn to_naga(self) -> naga::ShaderStage {
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
    #[error("{file}: `#define_import_path {found}` does not match the file; expected `{expected}`")]
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
    /// A hook's define (e.g. `VOLFOG_INJECT_CUSTOM_DENSITY`) was set without the user's
    /// module that defines its function.
    #[error(
        "{define} needs your module defining `{signature}` (VolumetricFog: \
         FogConfig::custom_density; volfog export: --custom-density FILE)"
    )]
    CustomModuleMissing {
        /// The define.
        define: String,
        /// The function's required signature.
        signature: String,
    },
    /// The user's module for a hook does not define its function.
    #[error("{file}: no function `{function}`; define `{signature}`")]
    CustomFunctionMissing {
        /// The user's file.
        file: String,
        /// The function's name.
        function: String,
        /// Its required signature.
        signature: String,
    },
    /// The user's module defines the hook's function with another signature.
    #[error(
        "{file}:{line}:{column}: `{function}` does not have the required signature \
         `{signature}`: {message}"
    )]
    CustomSignature {
        /// The user's file.
        file: String,
        /// 1-based line of the function.
        line: usize,
        /// 1-based column of `fn`.
        column: usize,
        /// The function's name.
        function: String,
        /// Its required signature.
        signature: String,
        /// What naga says of the call the pass makes.
        message: String,
    },
    /// The user's module for a hook does not parse, compose or validate; the message
    /// names its file, line and column.
    #[error("{message}\nin your module {file}, which must define `{signature}`")]
    CustomModule {
        /// The user's file.
        file: String,
        /// naga_oil's message (file:line:column and the offending line).
        message: String,
        /// The hook function's required signature.
        signature: String,
    },
    /// A module uses a naga_oil construct that the WESL translation does not handle.
    #[error("{file}:{line}: cannot translate to WESL: {message}")]
    Wesl {
        /// The module file.
        file: String,
        /// 1-based line of the construct.
        line: usize,
        /// What is wrong.
        message: String,
    },
}
