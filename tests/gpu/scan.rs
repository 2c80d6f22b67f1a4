//! The scan pass on the GPU: a homogeneous medium against the closed form, both steps
//! at 32, 64 and 128 slices, and a heterogeneous medium against the CPU mirror.

use crate::common;

use common::gpu;
use glam::Vec4;
use volfog::options::ScanStep;
use volfog_testkit::selfcheck::{cpu_scan, run_scan, scan_vs_closed_form, test_froxels};

#[test]
fn homogeneous_scan_matches_closed_form() {
    let gpu = gpu();
    eprintln!("max relative error vs closed form (rows: sigma_t, slices):");
    eprintln!("sigma_t  slices  energy-conserving L / T      wronski L / T");
    for sigma_t in [0.002, 0.01, 0.03] {
        for slices in [32, 64, 128] {
            let ec = scan_vs_closed_form(gpu, ScanStep::EnergyConserving, slices, sigma_t).unwrap();
            let wr = scan_vs_closed_form(gpu, ScanStep::Wronski, slices, sigma_t).unwrap();
            eprintln!(
                "{sigma_t:7}  {slices:6}  {:8.4}% / {:8.4}%     {:8.4}% / {:8.4}%",
                ec.inscatter * 100.0,
                ec.transmittance * 100.0,
                wr.inscatter * 100.0,
                wr.transmittance * 100.0
            );
            // fp16 storage of input and output bounds the energy-conserving step.
            assert!(
                ec.inscatter <= 0.005,
                "in-scatter error {} at {slices} slices",
                ec.inscatter
            );
            assert!(
                ec.transmittance <= 0.005,
                "transmittance error {}",
                ec.transmittance
            );
            // Wronski's step leaves each slice's in-scattering unattenuated by its own
            // extinction: its error must exceed the energy-conserving one.
            assert!(
                wr.inscatter > ec.inscatter,
                "Wronski {} vs {}",
                wr.inscatter,
                ec.inscatter
            );
        }
    }
}

#[test]
fn heterogeneous_scan_matches_cpu_mirror() {
    let gpu = gpu();
    let froxels = test_froxels([24, 14], 64);
    let [sx, sy, sz] = froxels.size.to_array();
    let mut medium = Vec::new();
    for z in 0..sz {
        for y in 0..sy {
            for x in 0..sx {
                let h = ((x * 7 + y * 13 + z * 29) % 17) as f32 / 17.0;
                let sigma_t = 0.05 * h * h + if z % 9 == 0 { 0.0 } else { 0.002 };
                medium.push(
                    Vec4::new(0.6 + h, 0.5, 1.0 - 0.5 * h, 1.0)
                        .truncate()
                        .extend(1.0)
                        * Vec4::new(sigma_t * 0.8, sigma_t * 0.8, sigma_t * 0.8, 0.0)
                        + Vec4::new(0.0, 0.0, 0.0, sigma_t),
                );
            }
        }
    }
    for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
        let gpu_out = run_scan(gpu, step, &froxels, &medium).unwrap();
        let cpu_out = cpu_scan(step, &froxels, &medium);
        let mut worst = 0.0f32;
        for (g, c) in gpu_out.iter().zip(&cpu_out) {
            for k in 0..4 {
                let e = (g[k] - c[k]).abs() / c[k].abs().max(1e-3);
                worst = worst.max(e);
                assert!(e <= 2e-3, "{step:?}: gpu {g} cpu {c}");
            }
        }
        eprintln!(
            "{step:?}: GPU vs CPU mirror worst relative error {worst:e} (bound 2e-3, fp16 output)"
        );
    }
}

/// The depth-culling variant: the slices in front of each column's live count equal
/// the full scan, and the texels behind hold the value at the last live slice.
#[test]
fn culled_scan_matches_full_scan_in_front_and_holds_behind() {
    let gpu = gpu();
    let froxels = test_froxels([24, 14], 40);
    let [sx, sy, sz] = froxels.size.to_array();
    let medium: Vec<Vec4> = (0..sx * sy * sz)
        .map(|i| {
            let h = ((i * 7) % 23) as f32 / 23.0;
            Vec4::new(0.02 * h, 0.03, 0.01 + 0.02 * h, 0.01 + 0.04 * h)
        })
        .collect();
    let live: Vec<u32> = (0..sx * sy).map(|c| 2 + (c * 11) % (sz - 1)).collect();
    let full = run_scan(gpu, ScanStep::EnergyConserving, &froxels, &medium).unwrap();
    let culled = volfog_testkit::selfcheck::run_scan_culled(
        gpu,
        ScanStep::EnergyConserving,
        &froxels,
        &medium,
        Some(&live),
    )
    .unwrap();
    let (mut in_front, mut behind) = (0, 0);
    for z in 0..sz {
        for y in 0..sy {
            for x in 0..sx {
                let i = ((z * sy + y) * sx + x) as usize;
                let l = live[(y * sx + x) as usize];
                if z < l {
                    assert_eq!(culled[i], full[i], "live texel {x},{y},{z}");
                    in_front += 1;
                } else {
                    let last = (((l - 1) * sy + y) * sx + x) as usize;
                    assert_eq!(culled[i], full[last], "held texel {x},{y},{z}");
                    behind += 1;
                }
            }
        }
    }
    eprintln!(
        "culled scan: {in_front} live texels equal the full scan, {behind} hold the last live value"
    );
    assert!(in_front > 0 && behind > 0);
}
