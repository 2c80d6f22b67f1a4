//! The coordinate texture against the CPU mirror for epipoles inside, on the edge of
//! and outside the screen, and the refinement's interpolation sources never straddling
//! a depth break.

use super::{Scene, occluders, read_uvec2, read_vec4, run, sun_direction};
use crate::common::gpu;
use glam::Vec2;
use volfog::cpu::epipolar as cpu;
use volfog::pipeline::epipolar::EpipolarMode;
use volfog::uniforms::{EpipolarFrame, EpipolarSampling};

#[test]
fn coordinates_match_the_cpu_for_epipoles_inside_on_the_edge_and_outside() {
    let gpu = gpu();
    let scene = Scene::new(160, 90, 256, &occluders(), sun_direction());
    let sampling = scene.sampling();
    let base = EpipolarFrame::new(&sampling, &scene.view(0.0), scene.sun).unwrap();
    let cases = [
        ("inside", base.light_screen),
        ("on the right edge", Vec2::new(1.0, 0.3)),
        ("on a corner", Vec2::new(-1.0, 1.0)),
        ("outside", Vec2::new(1.8, 1.4)),
        ("far outside", Vec2::new(-40.0, 3.0)),
        ("behind (1e6)", Vec2::new(1e6, -2e5)),
    ];
    for (name, light) in cases {
        let frame = EpipolarFrame {
            light_screen: light,
            ..base
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, Some(frame));
        let got = read_vec4(gpu, shafts.coordinate_texture());
        let want = cpu::coordinates(&frame, |ndc| scene.view_depth_at(ndc));
        let (mut worst_xy, mut worst_z, mut valid, mut flags_differ) = (0.0f32, 0.0f32, 0, 0);
        let mut dead_slices = 0;
        for j in 0..frame.slices as usize {
            let row = j * frame.samples as usize..(j + 1) * frame.samples as usize;
            if want[row.clone()].iter().all(|c| c.w == 0.0) {
                dead_slices += 1;
            }
            for i in row {
                let (g, w) = (got[i], want[i]);
                if (g.w > 0.5) != (w.w > 0.5) {
                    // A sample on the border can fall either side of the tolerance.
                    if (w.x.abs().max(w.y.abs()) - 1.0).abs() > 1e-3 {
                        flags_differ += 1;
                    }
                    continue;
                }
                if w.w > 0.5 {
                    valid += 1;
                    worst_xy = worst_xy.max(
                        (g.truncate().truncate() - w.truncate().truncate())
                            .abs()
                            .max_element(),
                    );
                    worst_z = worst_z.max((g.z - w.z).abs() / w.z.max(1.0));
                }
            }
        }
        eprintln!(
            "epipole {name} {light}: {valid} valid samples, {dead_slices} of {} slices off the screen; worst |xy| {worst_xy:.2e} (bound 1e-4), view depth {worst_z:.2e} (bound 1e-3), validity differs off the border: {flags_differ}",
            frame.slices
        );
        assert_eq!(flags_differ, 0, "{name}");
        assert!(valid > 1000, "{name}: {valid}");
        assert!(worst_xy <= 1e-4, "{name}: {worst_xy}");
        assert!(worst_z <= 1e-3, "{name}: {worst_z}");
        if name.starts_with("outside") || name.starts_with("far") || name.starts_with("behind") {
            assert!(dead_slices > 0, "{name}: some slices miss the screen");
        }
        if name == "inside" {
            assert_eq!(dead_slices, 0);
        }
    }
}

#[test]
fn refinement_never_interpolates_across_a_depth_break() {
    let gpu = gpu();
    let scene = Scene::new(160, 90, 256, &occluders(), sun_direction());
    for step in [8u32, 16, 32, 64] {
        let sampling = EpipolarSampling {
            initial_step: step,
            ..scene.sampling()
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, None);
        let coords = read_vec4(gpu, shafts.coordinate_texture());
        let sources = read_uvec2(gpu, shafts.source_texture());
        let n = frame.samples as usize;
        let (mut marched, mut straddles, mut cpu_differs, mut breaks) = (0, 0, 0, 0);
        for j in 0..frame.slices as usize {
            let depths: Vec<f32> = coords[j * n..(j + 1) * n].iter().map(|c| c.z).collect();
            let want = cpu::refine_slice(&frame, &depths);
            for k in 0..n {
                let s = sources[j * n + k];
                if s != want[k] {
                    cpu_differs += 1;
                }
                if coords[j * n + k].w < 0.5 {
                    continue;
                }
                if s.x == s.y {
                    marched += 1;
                    assert_eq!(s.x as usize, k);
                    continue;
                }
                assert!(s.x as usize <= k && k <= s.y as usize);
                for m in s.x as usize..s.y as usize {
                    if !cpu::continuous(depths[m], depths[m + 1], frame.depth_threshold) {
                        straddles += 1;
                    }
                }
            }
            breaks += (0..n - 1)
                .filter(|&m| {
                    coords[j * n + m].w > 0.5
                        && coords[j * n + m + 1].w > 0.5
                        && !cpu::continuous(depths[m], depths[m + 1], frame.depth_threshold)
                })
                .count();
        }
        eprintln!(
            "initial step {step}: {marched} ray-marching samples, {breaks} depth breaks between valid samples, {straddles} interpolations across a break (bound 0), {cpu_differs} sources differ from the CPU mirror (bound 0)"
        );
        assert!(breaks > 100, "the scene has depth breaks");
        assert_eq!(straddles, 0);
        assert_eq!(cpu_differs, 0);
    }
}
