//! volfog: real-time volumetric fog as a library.
//!
//! The layers point one way: [`limits`] and [`options`] <- [`uniforms`] <- [`cpu`] <-
//! [`pipeline`].
//!
//! - [`shaders`]: the composable WGSL modules (`volfog::phase`, `volfog::scan`,
//!   `volfog::apply`, ...), for an engine's naga_oil composer, and the variants the
//!   runtime composes; translation to other languages lives in
//!   [`volfog_codegen`] (feature `translate`).
//! - [`limits`]: every range volfog checks, and the error naming a value outside one.
//! - [`options`]: the options that select a shader variant.
//! - [`uniforms`]: Rust twins (encase + glam) of the WGSL uniform structs.
//! - [`cpu`]: the same formulas in Rust, the oracle of the GPU tests and a gameplay API.
//! - [`pipeline`]: the wgpu runtime: each pass, and [`pipeline::VolumetricFog`], which
//!   runs the whole froxel pipeline.
#![warn(missing_docs)]

pub mod cpu;
pub mod limits;
pub mod options;
pub mod pipeline;
pub mod shaders;
pub mod uniforms;

/// The glam version of volfog's public types (vectors and matrices).
pub use glam;
pub use volfog_codegen;
