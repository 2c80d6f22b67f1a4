//! The apply pass on the GPU against the CPU (`color * T + L` of the filtered
//! integrated volume), in both filtering modes.

mod common;

use common::gpu;
use volfog::pipeline::apply::Filtering;
use volfog::selfcheck::{max_abs_diff, run_apply, ApplyCase};

#[test]
fn fullscreen_apply_matches_cpu() {
    let gpu = gpu();
    let case = ApplyCase::synthetic(160, 90);
    let expected = case.expected();
    for filtering in [Filtering::Sampler, Filtering::Manual] {
        let got = run_apply(&gpu, filtering, &case).unwrap();
        let diff = max_abs_diff(&got, &expected);
        eprintln!("{filtering:?}: max abs difference vs CPU {diff:e} (bound 2e-3)");
        // fp16 output (2^-11 relative) plus the sampler's fixed-point filter weights.
        assert!(diff <= 2e-3, "{filtering:?}: {diff}");
    }
}
