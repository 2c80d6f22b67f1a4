//! Emissive fog: the scan integrates the emission with the in-scattering. In a
//! homogeneous medium the emitted radiance reaching the eye is the closed form
//! `L = (e / sigma_t) (1 - exp(-sigma_t d))`; a glowing volume without extinction gives
//! `e` times its chord.

use super::*;

#[test]
fn emission_in_a_homogeneous_medium_matches_the_closed_form() {
    let gpu = gpu();
    let config = config(LocalShadowConfig::default(), false);
    let sigma = 0.12f32;
    let emission = Vec3::new(0.02, 0.05, 0.1);
    let medium = FogMedium {
        albedo: Vec3::ZERO,
        emission,
        ..super::medium(sigma)
    };
    let view = camera(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.3, 0.8, -10.0));
    let frame = inputs(view, medium, &[], &[], &[]);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let got = run_integrated(&mut fog, &frame);
    let size = config.volume_size;
    let backs = slice_backs(&config);
    let (mut worst_l, mut worst_t) = (0.0f32, 0.0f32);
    for y in 0..size.y {
        for x in 0..size.x {
            let (_, dir) = column_ray(&config, &frame, x, y);
            for z in 0..size.z {
                let d = (backs[z as usize] - config.near) * dir.length();
                let t = (-sigma * d).exp();
                let want = emission / sigma * (1.0 - t);
                let g = got[index(size, x, y, z)];
                worst_l =
                    worst_l.max(((g.truncate() - want).abs() / want.max_element()).max_element());
                worst_t = worst_t.max((g.w - t).abs());
            }
        }
    }
    // Beyond the far plane the tail of the medium (HeightFog::from_medium) carries the
    // emission on: the last slice followed by the tail against the closed form at 60 m.
    let u = crate::common::scene::expected_uniforms(&config, &frame, 0);
    let tail = volfog::uniforms::HeightFog::from_medium(&medium, Vec3::ZERO)
        .to_view_space(frame.view_from_world);
    let mut worst_tail = 0.0f32;
    for y in 0..size.y {
        for x in 0..size.x {
            let (_, dir) = column_ray(&config, &frame, x, y);
            let view_dir = frame.view_from_world.transform_vector3(dir);
            let point = view_dir * 60.0;
            let last = got[index(size, x, y, size.z - 1)];
            let fog = volfog::cpu::apply::fog_with_tail(
                last,
                volfog::cpu::apply::fog_tail(&u.froxels, &tail, point),
            );
            let d = (60.0 - config.near) * dir.length();
            let want = emission / sigma * (1.0 - (-sigma * d).exp());
            worst_tail =
                worst_tail.max(((fog.truncate() - want).abs() / want.max_element()).max_element());
        }
    }
    eprintln!(
        "emission e = {emission} in sigma_t = {sigma}/m: the integrated volume against \
         (e / sigma_t)(1 - exp(-sigma_t d)) within {worst_l:.2e} relative (bound 2e-3), \
         transmittance within {worst_t:.2e} (bound 1e-3), over {} froxels; with the tail \
         to 60 m within {worst_tail:.2e} (bound 2e-3)",
        size.x * size.y * size.z
    );
    assert!(worst_l <= 2e-3, "{worst_l}");
    assert!(worst_t <= 1e-3, "{worst_t}");
    assert!(worst_tail <= 2e-3, "{worst_tail}");
}

#[test]
fn a_glowing_volume_without_extinction_adds_its_emission_times_its_chord() {
    let gpu = gpu();
    let config = config(LocalShadowConfig::default(), false);
    let emission = Vec3::new(0.3, 0.2, 0.1);
    let world_from_local = Mat4::from_scale_rotation_translation(
        Vec3::new(2.0, 1.5, 2.5),
        glam::Quat::from_rotation_y(0.5),
        Vec3::new(0.5, 1.0, -9.0),
    );
    let edge = 0.02;
    let volume = LocalVolume::new(
        world_from_local,
        volfog::uniforms::VolumeShape::Box,
        0.0,
        edge,
    )
    .unwrap()
    .with_emission(emission)
    .unwrap();
    let medium = FogMedium {
        albedo: Vec3::ZERO,
        ..super::medium(0.0)
    };
    let volumes = [volume];
    let frame = inputs(
        camera(Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.5, 1.0, -9.0)),
        medium,
        &[],
        &[],
        &volumes,
    );
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let got = run_integrated(&mut fog, &frame);
    let size = config.volume_size;
    let (mut worst, mut hits, mut mean) = (0.0f32, 0, 0.0f64);
    for y in 0..size.y {
        for x in 0..size.x {
            let (chord, thickest) = column_chord(
                &config,
                &frame,
                volume.local_from_world,
                ray_unit_box,
                (x, y),
            );
            // Both ends: a slice each, and the edge band (edge times the largest half
            // extent, 2.5 m) at twice its width for oblique entries.
            let slack = 2.0 * thickest + 2.0 * (2.0 * edge * 2.5);
            let g = got[index(size, x, y, size.z - 1)].truncate();
            let err = (g / emission - Vec3::splat(chord)).abs().max_element();
            if chord > 0.5 {
                hits += 1;
                mean += f64::from(err);
            }
            worst = worst.max(err / slack.max(1e-6));
        }
    }
    eprintln!(
        "a glowing box without extinction: in-scatter / e against the analytic chord over \
         {hits} columns through it, mean error {:.3} m, worst {worst:.2} of the bound \
         (the two end slices plus the edge band)",
        mean / hits as f64
    );
    assert!(hits > 50, "{hits}");
    assert!(worst <= 1.0, "{worst}");
}
