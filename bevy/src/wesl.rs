//! The `volfog` WESL package: volfog's shader modules, generated at build time from
//! the same WGSL sources the library composes with naga_oil
//! (`volfog_codegen::wesl`), and registered with Bevy's shader system so a Bevy
//! shader can write `import volfog::apply::{fog_sample, ...};`.
//!
//! Defines of the WGSL modules are WESL features (`@if(VOLFOG_...)`), set as Bevy
//! shader defs; `volfog::bindings` places its group at the WESL constant
//! `constants::VOLFOG_FOG_GROUP` when that def is set (see
//! [`crate::material::set_fog_group`]), at group 0 otherwise.

use bevy::prelude::*;
use bevy::shader::Shader;

/// The package's modules: (module name, WESL source), in dependency order.
pub const MODULES: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/wesl/modules.rs"));

/// The package's name in WESL import paths.
pub const PACKAGE: &str = "volfog";

/// The asset path a module is registered at: `embedded://volfog/<module>.wesl`, which
/// Bevy resolves as the import path `volfog::<module>`.
pub fn module_path(name: &str) -> String {
    format!("embedded://{PACKAGE}/{name}.wesl")
}

/// Keeps the package's shader assets alive.
#[derive(Resource)]
pub struct WeslPackage {
    /// One handle per module, in [`MODULES`] order.
    pub handles: Vec<Handle<Shader>>,
}

/// Registers [`MODULES`] as shader assets (part of
/// [`VolumetricFogPlugin`](crate::VolumetricFogPlugin)).
pub struct WeslPackagePlugin;

impl Plugin for WeslPackagePlugin {
    fn build(&self, app: &mut App) {
        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
        let handles = MODULES
            .iter()
            .map(|(name, source)| shaders.add(Shader::from_wesl(*source, module_path(name))))
            .collect();
        app.insert_resource(WeslPackage { handles });
    }
}
