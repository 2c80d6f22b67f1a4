//! Temporal reprojection fused into inject (`FogConfig::fuse_temporal`,
//! `VOLFOG_INJECT_TEMPORAL`) against the separate temporal pass, frame by frame with a
//! moving camera: the stabilised volumes (next frame's history) and the integrated
//! volumes agree within rgba16float rounding. The separate pass is itself held
//! against the CPU mirror (`temporal.rs`, `culling.rs`), so the fused one is too.
//! Both run the ESM filter here: with the compare filter the fused pass takes more
//! shadow taps where a froxel has no history, which the separate pass cannot know
//! (`shadow_filter.rs` checks that choice against the CPU mirror).

use crate::common;
use crate::culling::{SCREEN, frame, integrated, pipeline_inputs, scene_depth};

use common::gpu;
use common::scene::*;
use glam::Vec4;
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, VolumetricFog};

/// Largest difference relative to the larger texel (floored at 1e-3) and the mean
/// absolute difference of two volumes.
fn differences(a: &[Vec4], b: &[Vec4]) -> (f32, f64) {
    let mut worst = 0.0f32;
    let mut sum = 0.0f64;
    for (a, b) in a.iter().zip(b) {
        let d = (*a - *b).abs().max_element();
        worst = worst.max(d / a.abs().max(b.abs()).max_element().max(1e-3));
        sum += f64::from(d);
    }
    (worst, sum / a.len() as f64)
}

#[test]
fn fused_temporal_matches_the_separate_pass() {
    let gpu = gpu();
    let (w, h) = SCREEN;
    let cases = [
        (
            "temporal, jittered",
            FogConfig {
                shadow_filter: ShadowFilter::Esm,
                temporal: true,
                jitter: true,
                ..small_config()
            },
        ),
        (
            "the cheap path: checkerboard, depth culling, noise texture",
            FogConfig {
                shadow_filter: ShadowFilter::Esm,
                temporal: true,
                jitter: true,
                amortize: true,
                depth_cull: true,
                noise_texture: true,
                ..small_config()
            },
        ),
    ];
    for (label, base) in cases {
        let (cascades, layers) = overhead_sun(&base, Some(SLAB));
        let shadow = shadow_map(gpu, &layers);
        // [fused, separate], and the same without temporal reprojection (this frame's
        // injection alone, to show the history is used).
        let mut fogs = [true, false].map(|fuse_temporal| {
            let config = FogConfig {
                fuse_temporal,
                ..base.clone()
            };
            let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
            fog.set_shadow_map(&gpu.device, &shadow).unwrap();
            fog
        });
        assert!(fogs[0].config().fused_temporal() && !fogs[1].config().fused_temporal());
        let (lights, volumes) = (lights(), local_volumes());
        let (mut worst_history, mut worst_integrated, mut mean_integrated) = (0.0f32, 0.0f32, 0.0);
        let mut history_weight_seen = 0.0f64;
        let frames = 8;
        for f in 0..frames {
            // The camera rises and turns a little every frame.
            let view = view(1.6 + 0.05 * f as f32, -0.05 + 0.01 * f as f32);
            if f == 1 && base.depth_cull {
                let depth = volfog_testkit::selfcheck::depth_texture(
                    gpu,
                    w,
                    h,
                    &scene_depth(view, projection()),
                )
                .unwrap();
                for fog in &mut fogs {
                    fog.set_scene_depth(&gpu.device, &depth, 0).unwrap();
                }
            }
            let inputs = pipeline_inputs(view, &lights, &volumes, medium(), cascades);
            let [a, b] = &mut fogs;
            frame(gpu, [a, b], &inputs);
            let stabilised = fogs
                .each_ref()
                .map(|fog| read_volume(gpu, fog.stabilised_texture().unwrap()));
            let (history, _) = differences(&stabilised[0], &stabilised[1]);
            let done = fogs.each_ref().map(|fog| integrated(gpu, fog));
            let (worst, mean) = differences(&done[0], &done[1]);
            worst_history = worst_history.max(history);
            worst_integrated = worst_integrated.max(worst);
            mean_integrated = f64::max(mean_integrated, mean);
            if f == frames - 1 {
                // The last frame's stabilised volume against a fog without history.
                let mut plain = VolumetricFog::new(
                    &gpu.device,
                    &FogConfig {
                        temporal: false,
                        amortize: false,
                        ..base.clone()
                    },
                )
                .unwrap();
                plain.set_shadow_map(&gpu.device, &shadow).unwrap();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                // Frame f of the plain fog: the same jitter as the others.
                for _ in 0..=f {
                    plain.prepare(&gpu.queue, &inputs).unwrap();
                }
                plain.encode(&mut encoder).unwrap();
                gpu.queue.submit([encoder.finish()]);
                let now = read_volume(gpu, plain.scattering_texture());
                history_weight_seen = differences(&stabilised[0], &now).1;
            }
        }
        eprintln!(
            "{label}: over {frames} frames with a moving camera, fused vs separate temporal: \
             stabilised volumes differ by at most {worst_history:.2e} relative (bound 4e-3), \
             integrated volumes by at most {worst_integrated:.2e} relative (bound 4e-3), mean \
             absolute {mean_integrated:.2e}; the last stabilised volume differs from that \
             frame's injection alone by {history_weight_seen:.2e} on average"
        );
        assert!(worst_history <= 4e-3, "{label}: {worst_history}");
        assert!(worst_integrated <= 4e-3, "{label}: {worst_integrated}");
        assert!(
            history_weight_seen > 1e-3,
            "{label}: the history is used ({history_weight_seen})"
        );
    }
}
