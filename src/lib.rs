//! volfog: real-time volumetric fog as a library.
//!
//! - [`shaders`]: composable WGSL modules (`volfog::phase`, `volfog::scan`,
//!   `volfog::apply`, ...), every pass prebuilt and validated in WGSL, SPIR-V, GLSL,
//!   HLSL and MSL, and custom compositions.
//! - [`uniforms`]: Rust twins (encase + glam) of the WGSL uniform structs.
//! - [`cpu`]: the same formulas in Rust, the oracle of the GPU tests and a gameplay API.
//! - [`gpu`]: adapter selection and small helpers to run the passes with wgpu.
//! - [`export`]: writes every target plus the JSON binding manifest to a folder.
#![warn(missing_docs)]

pub mod codegen;
pub mod cpu;
pub mod export;
pub mod gpu;
pub mod manifest;
pub mod pipeline;
pub mod selfcheck;
pub mod shaders;
pub mod uniforms;
