//! The `volfog` binary: export requests (exit codes, nothing left behind), the demo
//! through its probe output, the benchmark's report and raymarch reference, and the
//! pipelines on a GPU compiler (`volfog gpu-cost`), and the images of the guides
//! against what the demo renders.

mod bench;
mod demo;
mod export;
mod gpu_cost;
mod images;
mod raymarch;
