//! [`FroxelFogDensity`]: your own density in a camera's fog, a WGSL or WESL shader
//! asset that defines volfog's `volfog_custom_density`, composed into the camera's
//! inject pass (`volfog::pipeline::FogConfig::custom_density`).

use bevy::prelude::*;
use bevy::shader::{Shader, Source};
use volfog::glam as vg;
use volfog::limits::InvalidValue;
use volfog::shaders::CustomModule;
use volfog::uniforms::FogCustomParams;

/// Your own density in the fog of the [`FroxelFog`](crate::FroxelFog) camera it is on:
/// a shader that defines
///
/// ```text
/// fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample
/// ```
///
/// written in WESL (`import volfog::types::{FogSample, FogCustomParams};`, the package
/// the plugin registers) or in naga_oil's WGSL (`#import volfog::types::...`), e.g.
/// `asset_server.load("fog/portal.wesl")`. Its sample at each froxel (extinction in
/// 1/m, albedo, and emission per metre in the fog's units, those of the lit image after
/// the camera's exposure: pass the exposure in `params` to scale it) is added to the
/// medium before the [`FroxelFogVolume`](crate::FroxelFogVolume)s blend; `params` is
/// what its third argument holds this frame and `time` the app's elapsed seconds
/// (wrapped), as the fog's noise reads it. Until the shader has loaded the fog runs
/// without it. A shader that does not compose (no such function, another signature,
/// an error in it) turns the fog off for the camera with one warning that names the
/// shader's path, line and column and the required signature.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct FroxelFogDensity {
    /// The shader (WGSL or WESL source).
    pub shader: Handle<Shader>,
    /// The function's `params.values`, finite.
    pub params: [Vec4; 8],
}

impl FroxelFogDensity {
    /// The density of `shader` with every parameter 0.
    pub fn new(shader: Handle<Shader>) -> Self {
        Self {
            shader,
            params: [Vec4::ZERO; 8],
        }
    }
}

/// The module and parameters a camera's [`FroxelFogDensity`] gives its fog: `None`
/// without one or while its shader loads; an error naming
/// `FroxelFogDensity.params` when a parameter is not finite.
pub(crate) fn custom_density(
    density: Option<&FroxelFogDensity>,
    shaders: &Assets<Shader>,
) -> Result<Option<(CustomModule, FogCustomParams)>, InvalidValue> {
    let Some(density) = density else {
        return Ok(None);
    };
    let values: Vec<vg::Vec4> = density
        .params
        .iter()
        .map(|v| vg::Vec4::from_array(v.to_array()))
        .collect();
    let params = FogCustomParams::new(&values).map_err(|e| InvalidValue {
        field: "FroxelFogDensity.params",
        ..e
    })?;
    let Some(shader) = shaders.get(&density.shader) else {
        return Ok(None);
    };
    let source = match &shader.source {
        Source::Wgsl(text) | Source::Wesl(text) => text.to_string(),
        Source::SpirV(_) => {
            return Err(InvalidValue {
                field: "FroxelFogDensity.shader",
                value: shader.path.clone(),
                expected: "a WGSL or WESL shader (SPIR-V has no source to compose)".into(),
            });
        }
    };
    Ok(Some((
        CustomModule::new(shader.path.clone(), source),
        params,
    )))
}
