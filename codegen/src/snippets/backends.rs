//! The HLSL, GLSL and MSL writers of a snippet module, with the snippet entry point as
//! the one entry point each backend needs.

use naga::back::{glsl, hlsl, msl};

use super::{ENTRY, FRAGMENT_ENTRY};

pub(super) fn write_hlsl(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> Result<String, String> {
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

pub(super) fn write_glsl(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> Result<String, String> {
    glsl_text(
        module,
        info,
        glsl::Version::Desktop(450),
        naga::ShaderStage::Compute,
        ENTRY,
    )
}

/// GLSL ES 3.00 (WebGL2) through the fragment entry point: ES 3.00 has no compute
/// stage.
pub(super) fn write_glsl_es(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> Result<String, String> {
    let version = glsl::Version::Embedded {
        version: 300,
        is_webgl: true,
    };
    glsl_text(
        module,
        info,
        version,
        naga::ShaderStage::Fragment,
        FRAGMENT_ENTRY,
    )
}

fn glsl_text(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    version: glsl::Version,
    shader_stage: naga::ShaderStage,
    entry: &str,
) -> Result<String, String> {
    let options = glsl::Options {
        version,
        ..Default::default()
    };
    let pipeline = glsl::PipelineOptions {
        shader_stage,
        entry_point: entry.to_string(),
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

pub(super) fn write_msl(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> Result<String, String> {
    let pipeline = msl::PipelineOptions {
        entry_point: Some((naga::ShaderStage::Compute, ENTRY.to_string())),
        ..Default::default()
    };
    msl::write_string(module, info, &msl::Options::default(), &pipeline)
        .map(|(text, _)| text)
        .map_err(|e| e.to_string())
}
