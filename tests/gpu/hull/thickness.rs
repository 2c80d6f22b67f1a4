//! The thickness pass against the exact chords in both sum formats and from the
//! resolved MSAA layout, and the rgba32float sum's capability reported and enforced.

use super::render::measure;
use super::scene::cases;
use crate::common::gpu;
use volfog::options::ApplyInput;
use volfog::pipeline::hull::{HullSumFormat, HullThicknessPass};

#[test]
fn float32_blendable_is_reported() {
    let gpu = gpu();
    let features = gpu.adapter.features();
    eprintln!(
        "FLOAT32_BLENDABLE: {}; hull sum format: {:?}",
        features.contains(wgpu::Features::FLOAT32_BLENDABLE),
        HullSumFormat::best(features)
    );
    let device_features = gpu.device.features();
    assert_eq!(
        HullThicknessPass::new(&gpu.device, HullSumFormat::Full).is_ok(),
        device_features.contains(wgpu::Features::FLOAT32_BLENDABLE)
    );
    // A device opened without the feature refuses the rgba32float sum with a typed error.
    let (plain, _) = pollster::block_on(gpu.adapter.request_device(&Default::default())).unwrap();
    assert!(matches!(
        HullThicknessPass::new(&plain, HullSumFormat::Full),
        Err(volfog::pipeline::hull::HullError::Float32BlendableMissing)
    ));
}

#[test]
fn thickness_matches_exact_chords_rgba16float() {
    let gpu = gpu();
    for case in cases() {
        // fp16 terms relative to the reference, split at the quantum (2^-8 m or less
        // here): 1 % of the chord per pixel, down to 1 mm chords.
        let e = measure(gpu, &case, HullSumFormat::Half, 1e-3, ApplyInput::Depth);
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_cpu <= 2e-3, "{}: {e:?}", case.name);
        // 1 % of the thickness moves T by at most density * 0.01 * chord * T <= 0.0023.
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}

#[test]
fn thickness_matches_exact_chords_rgba32float() {
    let gpu = gpu();
    gpu.require(wgpu::Features::FLOAT32_BLENDABLE);
    for case in cases() {
        // 1 % of the chord per pixel, down to 1 mm chords.
        let e = measure(gpu, &case, HullSumFormat::Full, 1e-3, ApplyInput::Depth);
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_cpu <= 2e-3, "{}: {e:?}", case.name);
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}

/// A multisampled scene: the thickness pass reads the scene's view depth from the
/// resolved MSAA fog layout (`VOLFOG_HULL_RESOLVED`, rg16float). Against the same
/// exact chords; rg16float keeps 11 bits of the view depth (0.05 %, a few millimetres
/// at these distances), so the bound is 1 % of the chord down to 0.5 m chords.
#[test]
fn thickness_from_the_resolved_msaa_layout_matches_exact_chords() {
    let gpu = gpu();
    for case in cases() {
        let e = measure(
            gpu,
            &case,
            HullSumFormat::Half,
            0.5,
            ApplyInput::ResolvedLayout,
        );
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}
