//! The `volfog` binary: export requests (exit codes, nothing left behind), the demo
//! through its probe output, and the benchmark's report and raymarch reference.

mod bench;
mod demo;
mod export;
