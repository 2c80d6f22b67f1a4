//! Epipolar sun shafts (Yusov 2012; `volfog::epipolar`): [`EpipolarShafts`] owns the
//! epipolar textures, the min/max trees and the passes, and turns a depth buffer and a
//! cascaded shadow map into a shaft texture: alone, composited by its own fullscreen
//! pass ([`EpipolarApply`]), or as the far field of a
//! [`VolumetricFog`](super::VolumetricFog) (`VolumetricFog::create_apply_far_field`).

mod composite;
mod encode;
mod error;
mod inputs;
mod layouts;
mod passes;
mod pipelines;
mod shafts;
mod textures;

pub use composite::EpipolarApply;
pub use error::EpipolarError;
pub use passes::{EpipolarMode, EpipolarPass};
pub use shafts::EpipolarShafts;

/// Format of the shaft texture: rgb the lit fraction F in [0, 1] per colour channel (the
/// share of the medium's sun in-scattering along the pixel's ray that the sun reaches:
/// 1 unshadowed; the light's colour after stained glass for coloured shafts; with
/// `HeightFog::sun_transmittance` the share of the light attenuated by the fog on its
/// way from the sun, which the composite applies per pixel), a the view depth (m).
pub const SHAFT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Formats the depth buffer may have (read as unfilterable float).
pub const DEPTH_FORMATS: [wgpu::TextureFormat; 5] = super::SCENE_DEPTH_FORMATS;
/// Formats the shadow map may have (read as unfilterable float, like the ESM passes).
pub const SHADOW_FORMATS: [wgpu::TextureFormat; 3] = super::SHADOW_MAP_FORMATS;

const COORD_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const SOURCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const TREE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const TERM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Stride of the per-level uniforms of the tree build (the uniform offset alignment).
const LEVEL_STRIDE: u64 = 256;
