//! The `volfog` command line: shader export (through `volfog_codegen`), the GPU
//! self-check, the demo scene, the benchmark, the cost on a GPU compiler and the
//! comparison with Mitsuba 3. The binary is `src/main.rs`; the
//! demo and bench are a library so their tests can drive them.
#![warn(missing_docs)]

pub mod bench;
pub mod demo;
pub mod gpu_cost;
pub mod truth;
