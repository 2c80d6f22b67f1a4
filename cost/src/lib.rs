//! `volfog-cost`: what volfog's passes cost, in one place that the bench, the
//! `volfog gpu-cost` report and the tests share.
//!
//! * [`floor`]: the memory floor of a pass — the textures its shader reads and writes
//!   and the bytes they hold for a configuration;
//! * [`worker`] and [`stats`]: a GPU compiler's own figures — every pipeline compiled
//!   by Mesa's RADV (ACO) on its null device for [`Chip::Bonaire`] (GCN2),
//!   [`Chip::Navi21`] (RDNA2) and [`Chip::Gfx1100`] (RDNA3), no GPU needed, with its
//!   registers, spills, occupancy, instruction count and ACO's cycle estimates
//!   (`VK_KHR_pipeline_executable_properties`, through `vkcheck`);
//! * [`loops`] and [`model`]: ACO's cycles with every loop counted by its real trip
//!   count instead of ACO's static weights, against the memory floor, on a named GPU
//!   ([`GpuModel`]);
//! * [`frame`]: the pipelines the runtime creates for a `FogConfig` and the passes of
//!   one frame with their dispatch sizes and trip counts; [`transient`]: the scan of a
//!   frame with transient lights; [`stereo`]: the frame of stereo fog, the shared
//!   passes once and each eye's resampling scan and apply.
//!
//! RADV chooses the chip its null device stands for from `RADV_FORCE_FAMILY` when a
//! Vulkan instance is created, so each chip compiles in a worker process of its own
//! ([`worker::Worker`]); the worker is a program that calls [`worker::serve`] (the
//! CLI's hidden `volfog radv-worker`). Requirements (Debian):
//!
//! ```text
//! apt-get install -y mesa-vulkan-drivers libvulkan1
//! ```

#![warn(missing_docs)]

pub mod chip;
mod error;
mod exported;
pub mod floor;
pub mod frame;
pub mod loops;
pub mod measure;
pub mod medium_shadow;
pub mod model;
pub mod pipeline;
pub mod stats;
pub mod stereo;
pub mod stereo_multiview;
pub mod transient;
pub mod worker;
pub mod workload;

pub use chip::{Chip, GpuModel, MODELS, RX_6800_XT, RX_7900_XTX, XBOX_ONE};
pub use error::*;
pub use stats::ShaderStats;
