//! The shader library: prebuilt variants in every target, the raw module sources for
//! composing into an engine's own shaders, and custom compositions.
//!
//! Every pass is prebuilt by `build.rs` for each combination of its define axes
//! (validated by naga with every flag). Names follow `pass@default` or
//! `pass@A+B`, the defines without their `VOLFOG_` prefix, sorted.
//!
//! ```
//! use volfog::shaders::{self, Target};
//!
//! let scan = shaders::variant("scan@default").expect("prebuilt");
//! let entry = &scan.entries[0];
//! assert_eq!(entry.entry, "scan");
//! assert!(entry.text(Target::Hlsl).unwrap().contains("RWTexture3D"));
//! ```

use naga_oil::compose::Composer;

pub use crate::codegen::reflect::EntryReflection;
pub use crate::codegen::{CodegenError, EntryOutput, Stage, Target, VariantOutput};
pub use crate::manifest::{Axis, ModuleSource, PassSource, ValueDefine, MODULES, PASSES};

use crate::codegen::{self, compose::Defines};

/// A variant built into the library at compile time.
#[derive(Debug)]
pub struct PrebuiltVariant {
    /// Variant name, `pass@default` or `pass@A+B`.
    pub name: &'static str,
    /// The pass it was built from.
    pub pass: &'static str,
    /// Its defines, sorted.
    pub defines: &'static [&'static str],
    /// Its entry points.
    pub entries: &'static [PrebuiltEntry],
}

/// One entry point of a prebuilt variant, in every target.
#[derive(Debug)]
pub struct PrebuiltEntry {
    /// Entry point name.
    pub entry: &'static str,
    /// Stage.
    pub stage: Stage,
    /// Flattened WGSL.
    pub wgsl: &'static str,
    /// SPIR-V, little-endian bytes.
    pub spirv: &'static [u8],
    /// GLSL 450.
    pub glsl: &'static str,
    /// HLSL SM 6.0.
    pub hlsl: &'static str,
    /// MSL 2.1.
    pub msl: &'static str,
    /// Reflection (JSON of [`EntryReflection`]).
    pub reflection: &'static str,
}

impl PrebuiltEntry {
    /// Text of a text target; `None` for SPIR-V (use [`PrebuiltEntry::spirv_words`]).
    pub fn text(&self, target: Target) -> Option<&'static str> {
        match target {
            Target::Wgsl => Some(self.wgsl),
            Target::Spirv => None,
            Target::Glsl => Some(self.glsl),
            Target::Hlsl => Some(self.hlsl),
            Target::Msl => Some(self.msl),
        }
    }

    /// SPIR-V as words.
    pub fn spirv_words(&self) -> Vec<u32> {
        self.spirv
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    /// Parsed reflection.
    pub fn reflection(&self) -> EntryReflection {
        serde_json::from_str(self.reflection).expect("reflection written by build.rs parses")
    }

    /// An owned copy, as produced by a custom composition.
    pub fn to_output(&self) -> EntryOutput {
        EntryOutput {
            entry: self.entry.to_string(),
            stage: self.stage,
            wgsl: self.wgsl.to_string(),
            spirv: self.spirv_words(),
            glsl: self.glsl.to_string(),
            hlsl: self.hlsl.to_string(),
            msl: self.msl.to_string(),
            reflection: self.reflection(),
        }
    }
}

impl PrebuiltVariant {
    /// The entry point with this name.
    pub fn entry(&self, name: &str) -> Option<&'static PrebuiltEntry> {
        self.entries.iter().find(|e| e.entry == name)
    }

    /// An owned copy, as produced by a custom composition.
    pub fn to_output(&self) -> VariantOutput {
        VariantOutput {
            name: self.name.to_string(),
            pass: self.pass.to_string(),
            defines: self.defines.iter().map(|d| d.to_string()).collect(),
            entries: self.entries.iter().map(PrebuiltEntry::to_output).collect(),
        }
    }
}

static VARIANTS: &[PrebuiltVariant] = include!(concat!(env!("OUT_DIR"), "/shader_index.rs"));

/// Every prebuilt variant, grouped by pass in manifest order.
pub fn variants() -> &'static [PrebuiltVariant] {
    VARIANTS
}

/// A prebuilt variant by name.
pub fn variant(name: &str) -> Option<&'static PrebuiltVariant> {
    VARIANTS.iter().find(|v| v.name == name)
}

/// A pass by name.
pub fn pass(name: &str) -> Option<&'static PassSource> {
    crate::manifest::pass(name)
}

/// Adds every volfog module (`volfog::types`, `volfog::phase`, ...) to an engine's
/// naga_oil composer, so its shaders can `#import volfog::apply::...`.
///
/// ```
/// use naga_oil::compose::{Composer, NagaModuleDescriptor};
///
/// let mut composer = Composer::default();
/// volfog::shaders::add_to_composer(&mut composer).unwrap();
/// let module = composer
///     .make_naga_module(NagaModuleDescriptor {
///         source: "#import volfog::phase::phase_hg\n\
///                  @compute @workgroup_size(1) fn main() { let p = phase_hg(0.5, 0.7); }",
///         file_path: "example.wgsl",
///         ..Default::default()
///     })
///     .unwrap();
/// assert_eq!(module.entry_points.len(), 1);
/// ```
pub fn add_to_composer(composer: &mut Composer) -> Result<(), CodegenError> {
    codegen::compose::add_all_modules(composer)
}

/// Composes a pass under a custom define set (`NAME` or `NAME=VALUE` items) and
/// translates it to every target. Unknown defines, values out of range and
/// exclusive defines set together are errors that list what is valid.
pub fn compose_variant(pass_name: &str, defines: &[String]) -> Result<VariantOutput, CodegenError> {
    let pass = pass(pass_name).ok_or_else(|| {
        CodegenError::Define(format!(
            "unknown pass {pass_name}; passes: {}",
            PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let defines = Defines::parse(pass, defines)?;
    let mut composer = codegen::compose::composer()?;
    codegen::generate(&mut composer, pass, &defines)
}
