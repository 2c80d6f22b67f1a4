//! The shader library: the composable WGSL modules for an engine's own shaders, and
//! the variants of the passes as naga modules for a GPU API.
//!
//! Every pass is composed and validated for each combination of its define axes when
//! the library builds; names follow `pass@default` or `pass@A+B` (the defines without
//! their `VOLFOG_` prefix, sorted). Translations to WGSL, SPIR-V, GLSL, HLSL and MSL
//! come from `volfog_codegen::translate` (the codegen crate's feature `translate`).
//!
//! ```
//! let module = volfog::shaders::compose("scan", &[]).unwrap();
//! assert_eq!(module.entry_points[0].name, "scan");
//! assert!(volfog::shaders::compose("scan", &["VOLFOG_NOPE".into()]).is_err());
//! ```

use naga_oil::compose::Composer;

pub use volfog_codegen::custom::CustomModule;
pub use volfog_codegen::manifest::{self, CUSTOM_DENSITY, MODULES, PASSES};
pub use volfog_codegen::{CodegenError, Stage};

use volfog_codegen::compose::{self as codegen_compose, Defines};

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
    codegen_compose::add_all_modules(composer)
}

/// Composes a pass under a define set (`NAME` or `NAME=VALUE` items) into a validated
/// naga module, ready for `wgpu::ShaderSource::Naga`. Unknown passes or defines and
/// values out of range are errors that list what is valid.
pub fn compose(pass_name: &str, defines: &[String]) -> Result<naga::Module, CodegenError> {
    let pass = manifest::pass(pass_name).ok_or_else(|| {
        CodegenError::Define(format!(
            "unknown pass {pass_name}; passes: {}",
            PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let defines = Defines::parse(pass, defines)?;
    codegen_compose::compose_validated(pass, &defines)
}

/// [`compose`] with the user's custom density module (`VOLFOG_INJECT_CUSTOM_DENSITY` of
/// inject; see [`CUSTOM_DENSITY`] for the function it must define). The module is
/// checked first: a composition or validation error names its file, line and column
/// and the required signature; a module without the function is
/// [`CodegenError::CustomFunctionMissing`].
///
/// ```
/// use volfog::shaders::{CUSTOM_DENSITY, CodegenError, CustomModule, compose_with_custom};
///
/// let fog = CustomModule::new(
///     "column.wgsl",
///     "#import volfog::types::{FogSample, FogCustomParams}\n\
///      fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {\n\
///          let r = length(world.xz - params.values[0].xy);\n\
///          return FogSample(vec3<f32>(0.9), 0.2 * exp(-r * r), vec3<f32>(0.0));\n\
///      }\n",
/// );
/// let defines = [CUSTOM_DENSITY.define.to_string()];
/// assert!(compose_with_custom("inject", &defines, Some(&fog)).is_ok());
/// // The define without a module:
/// assert!(matches!(
///     compose_with_custom("inject", &defines, None),
///     Err(CodegenError::CustomModuleMissing { .. })
/// ));
/// ```
pub fn compose_with_custom(
    pass_name: &str,
    defines: &[String],
    custom_density: Option<&CustomModule>,
) -> Result<naga::Module, CodegenError> {
    let pass = manifest::pass(pass_name).ok_or_else(|| {
        CodegenError::Define(format!(
            "unknown pass {pass_name}; passes: {}",
            PASSES.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let defines = Defines::parse(pass, defines)?;
    let modules: Vec<_> = custom_density
        .filter(|_| defines.contains(CUSTOM_DENSITY.define))
        .map(|m| (&CUSTOM_DENSITY, m))
        .into_iter()
        .collect();
    volfog_codegen::custom::compose_with(pass, &defines, &modules)
}
