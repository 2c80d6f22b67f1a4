//! Property tests: for random valid media the scan never produces NaN or Inf,
//! transmittance stays in [0, 1] and never increases with depth, in-scattering never
//! decreases; phase functions stay finite and positive. The CPU mirror is checked per
//! case; the GPU scan is checked on a volume built from many random columns.

mod common;

use glam::{Vec3, Vec4};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use volfog::cpu::phase;
use volfog::cpu::scan::{scan_step, ScanStep, SCAN_START};
use volfog::selfcheck::{run_scan, test_froxels};

fn medium() -> impl Strategy<Value = Vec4> {
    // sigma_t in [0, 2] 1/m (clear air to dense smoke), albedo in [0, 1], light in [0, 100].
    (
        0.0f32..2.0,
        0.0f32..=1.0,
        0.0f32..100.0,
        0.0f32..100.0,
        0.0f32..100.0,
    )
        .prop_map(|(sigma_t, albedo, r, g, b)| {
            (Vec3::new(r, g, b) * albedo * sigma_t).extend(sigma_t)
        })
}

fn check_column(column: &[Vec4], label: &str) -> Result<(), TestCaseError> {
    let mut prev = SCAN_START;
    for (k, acc) in column.iter().enumerate() {
        prop_assert!(acc.is_finite(), "{label} slice {k}: {acc}");
        prop_assert!(
            (0.0..=1.0).contains(&acc.w),
            "{label} slice {k}: T = {}",
            acc.w
        );
        prop_assert!(
            acc.w <= prev.w,
            "{label} slice {k}: T rises {} -> {}",
            prev.w,
            acc.w
        );
        for c in 0..3 {
            prop_assert!(
                acc[c] >= prev[c],
                "{label} slice {k}: L falls {} -> {}",
                prev[c],
                acc[c]
            );
        }
        prev = *acc;
    }
    Ok(())
}

proptest! {
    #[test]
    fn cpu_scan_is_finite_and_monotonic(
        media in proptest::collection::vec(medium(), 1..64),
        ds in proptest::collection::vec(0.0f32..20.0, 64),
    ) {
        for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
            let mut acc = SCAN_START;
            let column: Vec<Vec4> = media
                .iter()
                .zip(&ds)
                .map(|(m, d)| {
                    acc = scan_step(acc, *m, *d, step);
                    acc
                })
                .collect();
            check_column(&column, &format!("{step:?}"))?;
        }
    }

    #[test]
    fn phase_functions_are_finite_and_positive(c in -1.0f32..=1.0, g in -0.99f32..=0.99) {
        let values = [
            phase::phase_hg(c, g),
            phase::phase_schlick(c, phase::schlick_k(g)),
            phase::phase_cornette_shanks(c, g),
            phase::phase_rayleigh(c),
            phase::phase_hg_two_lobe(c, g, -g, 0.5),
        ];
        for v in values {
            prop_assert!(v.is_finite() && v > 0.0, "c={c} g={g}: {v}");
        }
    }
}

#[test]
fn gpu_scan_of_random_media_is_finite_and_monotonic() {
    let gpu = common::gpu();
    let froxels = test_froxels([16, 16], 64);
    let count = (16 * 16 * 64) as usize;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let media: Vec<Vec4> = (0..count)
        .map(|_| medium().new_tree(&mut runner).unwrap().current())
        .collect();
    for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
        let out = run_scan(&gpu, step, &froxels, &media).unwrap();
        for y in 0..16 {
            for x in 0..16 {
                let column: Vec<Vec4> = (0..64).map(|z| out[(z * 16 + y) * 16 + x]).collect();
                // fp16 rounding can repeat a value, never reverse a trend.
                check_column(&column, &format!("{step:?} column ({x}, {y})")).unwrap();
            }
        }
    }
}
