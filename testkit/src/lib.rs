//! Test support for volfog: the adapter (one per process, failing with the install
//! command when there is none), a compute harness for shader kernels that import
//! volfog modules, deterministic inputs, a small froxel scene, and the self-check
//! runners that `volfog selfcheck` and the tests share.
#![warn(missing_docs)]

pub mod gpu;
pub mod kernel;
pub mod rng;
pub mod scene;
pub mod selfcheck;
pub mod truth;

pub use gpu::{Gpu, GpuError, INSTALL_HINT};
