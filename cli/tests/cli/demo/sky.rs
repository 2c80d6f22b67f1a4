//! The sky behind the scene against the CPU mirror of `volfog::sky`.

use glam::Vec3;

use super::{HEIGHT, WIDTH, pixel_directions, read_f32, read_rgba, run};

/// The sky behind the scene is the solved Nishita sky with the phase per pixel
/// (`volfog::sky`): every 5th sky pixel away from the sun's disc against
/// `cpu::sky` evaluated exactly in its direction.
#[test]
fn sky_is_the_solved_atmosphere() {
    use volfog::cpu::sky::{sky_radiance, sky_single_scattering};
    let run = run();
    let atmosphere: volfog::uniforms::SkyAtmosphere =
        serde_json::from_value(run.probe["sky"]["atmosphere"].clone()).expect("SkyAtmosphere");
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let dirs = pixel_directions(run);
    let (mut n, mut worst, mut sum) = (0, 0.0f32, 0.0f32);
    let (mut toward, mut away) = (Vec3::ZERO, Vec3::ZERO);
    for i in (0..(WIDTH * HEIGHT) as usize).step_by(5) {
        let d = dirs[i];
        if depth[i] < 1.0 || d.y < 0.0 || d.dot(atmosphere.sun_direction) > 0.999 {
            continue;
        }
        let want = sky_radiance(
            &sky_single_scattering(&atmosphere, d),
            d.dot(atmosphere.sun_direction),
            &atmosphere,
        );
        let got = surface[i].truncate();
        // The texture's bilinear interpolation between 128 x 64 directions and f16.
        let e = ((got - want).abs() / want.max(Vec3::splat(1e-3))).max_element();
        worst = worst.max(e);
        sum += e;
        n += 1;
        assert!(e <= 0.01, "pixel {i} {d}: {got} vs {want}");
        if d.dot(atmosphere.sun_direction) > 0.9 {
            toward += got;
        } else {
            away += got;
        }
    }
    let (ct, ca) = (toward / toward.element_sum(), away / away.element_sum());
    eprintln!(
        "sky: {n} pixels vs cpu::sky worst rel {worst:.3} mean {:.4} (bound 0.01); chromaticity \
         towards the sun {ct:.3}, elsewhere {ca:.3}",
        sum / n as f32
    );
    assert!(n > 200, "the sky is in view: {n}");
    assert!(ct.x > ca.x, "redder towards the low sun");
}
