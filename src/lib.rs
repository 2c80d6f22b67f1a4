//! volfog: real-time volumetric fog as a library.
//!
//! How much fog lies between a player and a lamp, asked on the CPU with the closed form
//! the shaders use ([`cpu`]), from the Rust twin of a WGSL uniform ([`uniforms`]):
//!
//! ```
//! use volfog::cpu::height_fog::height_fog;
//! use volfog::glam::Vec3;
//! use volfog::uniforms::HeightFog;
//!
//! // Valley fog: 0.05 / m on the ground (+Y up), halving every 14 m of height, grey.
//! let fog = HeightFog::new(Vec3::splat(0.6), 0.05, Vec3::Y, 0.05, 0.0)?;
//! let eye = Vec3::new(0.0, 2.0, 0.0);
//! let lamp = Vec3::new(80.0, 2.0, 0.0);
//! let seen = height_fog(&fog, eye, lamp - eye);
//! // w: the fraction of the lamp's light that reaches the eye. On a level segment the
//! // density is the same everywhere, 0.05 exp(-0.05 * 2) / m, over 80 m.
//! let expected = (-0.05 * (-0.05f32 * 2.0).exp() * 80.0).exp();
//! assert!((seen.w - expected).abs() < 1e-5);
//! // rgb: the fog colour laid over what is left of the lamp.
//! assert!((seen.x - 0.6 * (1.0 - seen.w)).abs() < 1e-5);
//! // The same 80 m on a ridge 40 m higher crosses thinner fog.
//! let ridge = Vec3::new(0.0, 40.0, 0.0);
//! assert!(height_fog(&fog, eye + ridge, lamp - eye).w > seen.w);
//!
//! // The bytes of the WGSL uniform `volfog::types::HeightFog`, for a GPU buffer.
//! assert_eq!(fog.to_bytes().len(), 80);
//! // A value the shaders cannot handle is refused, naming the field.
//! let err = HeightFog::new(Vec3::splat(0.6), -1.0, Vec3::Y, 0.05, 0.0).unwrap_err();
//! assert_eq!(err.field, "HeightFog.density");
//! # Ok::<(), volfog::limits::InvalidValue>(())
//! ```
//!
//! On the GPU, [`pipeline::VolumetricFog`] runs the froxel pipeline and applies it over
//! the lit colour (this needs a wgpu device, so here it is compiled, not run):
//!
//! ```no_run
//! use volfog::glam::Mat4;
//! use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
//!
//! fn fog_frames(
//!     device: &wgpu::Device,
//!     queue: &wgpu::Queue,
//!     lit_color_view: &wgpu::TextureView,
//!     scene_depth_view: &wgpu::TextureView,
//!     frames: impl Iterator<Item = (Mat4, Mat4, f32)>,
//! ) -> Result<(), Box<dyn std::error::Error>> {
//!     let mut fog = VolumetricFog::new(device, &FogConfig::default())?; // 160x90x128, 4 cascades
//!     let apply = fog.create_apply(device, wgpu::TextureFormat::Rgba16Float)?;
//!     let depth_group = apply.depth_bind_group(device, scene_depth_view);
//!     // every frame, once the lit colour and its depth are drawn:
//!     for (view_from_world, clip_from_view, time) in frames {
//!         fog.prepare(queue, &FrameInputs::new(view_from_world, clip_from_view, time))?;
//!         let mut encoder = device.create_command_encoder(&Default::default());
//!         fog.encode(&mut encoder)?;
//!         fog.record_apply(&mut encoder, &apply, lit_color_view, &depth_group)?; // colour * T + L
//!         queue.submit([encoder.finish()]);
//!     }
//!     Ok(())
//! }
//! ```
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
