//! The final shaft image against the per-pixel brute-force reference (full and half
//! resolution; without and with the sun's transmittance), and the main job's
//! self-check of the shafts.

use super::{Scene, occluders, run, sun_direction};
use crate::common::gpu;
use glam::{Vec2, Vec3, Vec4};
use volfog::cpu::epipolar as cpu;
use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
use volfog::uniforms::{EpipolarFrame, EpipolarSampling};

/// Mean of S over pixels selected by `keep`.
fn mean_where(s: &[Vec4], keep: impl Fn(usize) -> bool) -> (f32, usize) {
    let (sum, n) = s
        .iter()
        .enumerate()
        .filter(|(i, _)| keep(*i))
        .fold((0.0f64, 0), |(a, n), (_, v)| (a + f64::from(v.x), n + 1));
    ((sum / n.max(1) as f64) as f32, n)
}

#[test]
fn final_image_matches_the_per_pixel_reference() {
    for transmittance in [false, true] {
        final_image_case(transmittance);
    }
}

fn final_image_case(transmittance: bool) {
    let gpu = gpu();
    let scene =
        Scene::new(192, 108, 512, &occluders(), sun_direction()).with_transmittance(transmittance);
    let open = Scene::new(192, 108, 512, &[], sun_direction()).with_transmittance(transmittance);
    let sampling = scene.sampling();
    let read = |s: &EpipolarShafts| gpu.read_texture_rgba16f(s.shaft_texture()).unwrap();
    let (reference, _) = run(gpu, &scene, sampling, EpipolarMode::Reference, None);
    let reference = read(&reference);
    let (open_reference, _) = run(gpu, &open, sampling, EpipolarMode::Reference, None);
    let open_reference = read(&open_reference);
    for downscale in [1u32, 2] {
        let sampling = EpipolarSampling {
            downscale,
            ..sampling
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, None);
        let image = read(&shafts);
        let (fixed_resolve, fixed_upscale) = shafts.read_corrected(&gpu.device).unwrap();
        assert!(image.iter().all(|p| p.is_finite()), "no NaN");
        let medium = EpipolarFrame::medium(&scene.medium(), scene.view_from_world);
        let (mut err, mut err_light, mut worst) = (0.0f64, 0.0f64, 0.0f32);
        let mut light_scale = 0.0f64;
        for (i, (got, want)) in image.iter().zip(&reference).enumerate() {
            let e = (got.x - want.x).abs();
            err += f64::from(e);
            worst = worst.max(e);
            let (x, y) = (i as u32 % scene.width, i as u32 / scene.width);
            let ndc = Vec2::new(
                (x as f32 + 0.5) / scene.width as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / scene.height as f32 * 2.0,
            );
            let ray = cpu::view_ray(frame.view_from_clip, ndc);
            let lit = cpu::fog(&frame, &medium, ray * want.w, want.truncate());
            let got_lit = cpu::fog(&frame, &medium, ray * want.w, got.truncate());
            let dark = cpu::fog(&frame, &medium, ray * want.w, Vec3::ZERO);
            err_light += f64::from((got_lit - lit).abs().max_element());
            // The sun's light P F R (1 - T) of the reference.
            light_scale += f64::from((lit - dark).truncate().max_element());
        }
        let n = image.len() as f64;
        // The occluders' shafts: pixels whose reference S drops by more than 20 % when
        // the occluders are present, against pixels where it does not change, both
        // among sky pixels (same march length).
        let sky = |i: usize| scene.depth[i] >= 1.0;
        let shadowed = |i: usize| sky(i) && reference[i].x < 0.8 * open_reference[i].x;
        let lit = |i: usize| sky(i) && reference[i].x > 0.98 * open_reference[i].x;
        let (ref_shadowed, n_shadowed) = mean_where(&reference, shadowed);
        let (ref_lit, n_lit) = mean_where(&reference, lit);
        let (got_shadowed, _) = mean_where(&image, shadowed);
        let (got_lit, _) = mean_where(&image, lit);
        let (ratio_ref, ratio_got) = (ref_lit / ref_shadowed, got_lit / got_shadowed);
        eprintln!(
            "sun transmittance {transmittance}, downscale {downscale}: lit fraction mean abs error {:.2e} (bound 1e-2), worst {worst:.3}; in-scattered light mean abs error {:.2e} = {:.2} % of the sun's mean (bound 1 %); corrected pixels {fixed_resolve} (resolve) + {fixed_upscale} (upscale); shaft ratio lit/shadowed (sky, {n_lit} / {n_shadowed} px) reference {ratio_ref:.2}, epipolar {ratio_got:.2}",
            err / n,
            err_light / n,
            100.0 * err_light / light_scale,
        );
        // F spans [0, 1]; its error sits on shaft edges, where linear interpolation
        // along a slice and between slices blurs an edge over a few pixels, and in the
        // reference's own steps (1024 per ray).
        assert!(err / n <= 1e-2, "{}", err / n);
        assert!(
            err_light / light_scale <= 0.01,
            "{}",
            err_light / light_scale
        );
        assert!(n_shadowed > 50 && n_lit > 50);
        assert!(
            ratio_ref > 1.2,
            "the occluders cast visible shafts: {ratio_ref}"
        );
        assert!(
            (ratio_got / ratio_ref - 1.0).abs() <= 0.1,
            "{ratio_got} vs {ratio_ref}"
        );
    }
}

/// The main job's self-check of the shafts holds its bounds.
#[test]
fn self_check_of_the_shafts_holds() {
    let check = volfog_testkit::selfcheck::epipolar_check(gpu()).unwrap();
    eprintln!("{check:?}");
    assert!(check.unshadowed <= 1e-3, "{check:?}");
    assert!(check.tree_vs_steps <= 1e-5, "{check:?}");
    assert!(check.partly_shadowed > 100, "{check:?}");
}
