//! The blend modes of local volumes (add, subtract, multiply, min, max, overwrite):
//! each mode through the inject pass against the CPU mirror, volumes of every mode in
//! one buffer (the gathered ones in buffer order, and more than a block gathers), and
//! a box of each mode inside uniform glowing fog against the closed form of the
//! scan's transmittance and emission along every froxel column.

use crate::common::scene::*;
use crate::common::{Rng, gpu};
use glam::{Mat4, Quat, UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering, froxel_world_position};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{
    BlendMode, DirectionalLight, FogMedium, LocalVolume, ShadowCascades, VolumeShape,
};

/// A volume of `shape` placed by scale, rotation about y and position, blended by
/// `blend` with `density` and `emission`.
fn volume(
    shape: VolumeShape,
    scale: Vec3,
    turn: f32,
    at: Vec3,
    blend: BlendMode,
    density: f32,
    emission: Vec3,
) -> LocalVolume {
    let m = Mat4::from_scale_rotation_translation(scale, Quat::from_rotation_y(turn), at);
    LocalVolume::new(m, shape, density, 0.3)
        .and_then(|v| v.with_emission(emission))
        .and_then(|v| v.with_blend(blend))
        .expect("a valid volume")
}

/// The inject pass's scattering volume for `volumes` in a noisy glowing medium lit by
/// the scene's lights, the sun and the sky, against the CPU mirror of it with
/// `mirrored` in place of the volumes: the worst relative error over every froxel (rgb
/// relative to the froxel's largest channel, a to its extinction, floors 1e-4), for
/// each of `mirrored`.
fn mirror_errors(
    config: &FogConfig,
    volumes: &[LocalVolume],
    mirrored: &[&[LocalVolume]],
) -> Vec<f32> {
    let gpu = gpu();
    let lights = lights();
    let medium = FogMedium {
        emission: Vec3::new(0.002, 0.001, 0.0005),
        ..medium()
    };
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    let frame_inputs = |f: u32| FrameInputs {
        medium,
        sun: DirectionalLight {
            direction: Vec3::new(0.2, 0.9, -0.3).normalize(),
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::sky_ground(
            Vec3::new(0.2, 0.3, 0.5),
            Vec3::new(0.05, 0.04, 0.03),
            Vec3::Y,
        ),
        lights: &lights,
        local_volumes: volumes,
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(2.0, -0.05), projection(), 0.7 + f as f32)
    };
    let mut scattering = Vec::new();
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        scattering = read_volume(gpu, fog.scattering_texture())
    });
    let u = expected_uniforms(config, &frame_inputs(0), 0);
    let size = config.volume_size;
    mirrored
        .iter()
        .map(|mirrored| {
            let inputs = InjectInputs {
                froxels: &u.froxels,
                frame: &u.frame,
                medium: &u.medium,
                lighting: &u.lighting,
                cascades: &u.cascades,
                esm: &[],
                shadow_taps: &u.shadow_taps,
                lights: &lights,
                local_volumes: mirrored,
                options: config.inject_options(),
                density_texture: None,
                noise_texture: None,
                clouds: None,
                local_shadows: None,
                scene_depth: None,
                medium_shadow: None,
            };
            let mut worst = 0.0f32;
            for z in 0..size.z {
                for y in 0..size.y {
                    for x in 0..size.x {
                        let want = froxel_scattering(&inputs, UVec3::new(x, y, z));
                        let got = scattering[index(size, x, y, z)];
                        assert!(got.is_finite(), "non-finite froxel {x},{y},{z}");
                        let scale = want.truncate().max_element().max(1e-4);
                        for c in 0..3 {
                            worst = worst.max((got[c] - want[c]).abs() / scale);
                        }
                        worst = worst.max((got.w - want.w).abs() / want.w.max(1e-4));
                    }
                }
            }
            worst
        })
        .collect()
}

/// The extinction and emission of the CPU mirror's medium at `p` after `volumes`, and
/// before them.
fn medium_at(volumes: &[LocalVolume], p: Vec3, m: Vec4) -> (Vec4, Vec4) {
    let after = volumes
        .iter()
        .fold(m, |m, v| volfog::cpu::density::local_volume_blend(m, v, p));
    (m, after)
}

/// Each mode between two additive volumes (one before it, one after it, both
/// overlapping it): the GPU matches the CPU mirror, and the mode changes the medium
/// where it holds (checked on the mirror at the volume's centre, as the mode's
/// definition gives it).
#[test]
fn each_blend_mode_matches_the_cpu_mirror() {
    let config = FogConfig {
        max_local_volumes: 4,
        ..small_config()
    };
    let centre = Vec3::new(0.5, 2.0, -16.0);
    for blend in BlendMode::ALL {
        let (density, emission) = match blend {
            BlendMode::Add => (0.08, Vec3::new(0.01, 0.02, 0.0)),
            BlendMode::Subtract => (0.1, Vec3::splat(0.01)),
            BlendMode::Multiply => (0.3, Vec3::ZERO),
            BlendMode::Min => (0.02, Vec3::new(0.0, 0.004, 0.0)),
            BlendMode::Max => (0.2, Vec3::new(0.03, 0.0, 0.0)),
            BlendMode::Overwrite => (0.05, Vec3::new(0.0, 0.0, 0.02)),
        };
        let volumes = [
            volume(
                VolumeShape::Box,
                Vec3::new(4.0, 2.0, 3.0),
                0.4,
                Vec3::new(1.0, 1.5, -15.0),
                BlendMode::Add,
                0.15,
                Vec3::new(0.02, 0.01, 0.0),
            ),
            volume(
                VolumeShape::Ellipsoid,
                Vec3::new(5.0, 3.0, 6.0),
                -0.3,
                centre,
                blend,
                density,
                emission,
            ),
            volume(
                VolumeShape::Cylinder,
                Vec3::new(1.5, 3.0, 1.5),
                0.0,
                Vec3::new(-1.0, 2.0, -18.0),
                BlendMode::Add,
                0.05,
                Vec3::ZERO,
            ),
            volume(
                VolumeShape::Cone,
                Vec3::new(3.0, 4.0, 3.0),
                0.7,
                Vec3::new(3.0, 3.0, -30.0),
                blend,
                density,
                emission,
            ),
        ];
        // At the ellipsoid's centre (outside the box and the cylinder) the mode gives
        // the medium's new value from the old one.
        let m = Vec4::new(0.01, 0.02, 0.03, 0.06);
        let (before, after) = medium_at(&volumes[1..2], centre, m);
        let v = emission.extend(density);
        let want = match blend {
            BlendMode::Add => before + v,
            BlendMode::Subtract => (before - v).max(Vec4::ZERO),
            BlendMode::Multiply => before * density,
            BlendMode::Min => before.min(v),
            BlendMode::Max => before.max(v),
            BlendMode::Overwrite => v,
        };
        assert!(
            (after - want).abs().max_element() < 1e-6,
            "{blend:?}: {after} != {want}"
        );
        // The control: the mirror with these volumes adding instead (or, for add,
        // subtracting) is far from the GPU's froxels.
        let other = if blend == BlendMode::Add {
            BlendMode::Subtract
        } else {
            BlendMode::Add
        };
        let control: Vec<LocalVolume> = volumes
            .iter()
            .map(|v| LocalVolume {
                blend: if v.blend == blend as u32 {
                    other as u32
                } else {
                    v.blend
                },
                ..*v
            })
            .collect();
        let errors = mirror_errors(&config, &volumes, &[&volumes, &control]);
        eprintln!(
            "blend {blend:?}: worst relative error vs CPU {:e} (bound 4e-3); against the \
             mirror with {other:?} in its place {:.3}",
            errors[0], errors[1]
        );
        assert!(errors[0] <= 4e-3, "{blend:?}: {}", errors[0]);
        assert!(errors[1] > 0.05, "{blend:?}: the control is {}", errors[1]);
    }
}

/// 72 volumes of random modes around one point: the blocks there gather more than
/// their 64 and evaluate every volume, the blocks around them gather a few and put
/// them back in buffer order; the GPU matches the CPU mirror, which blends in buffer
/// order. (Where the gathered order is already the buffer order, as on a CPU driver
/// that runs a workgroup's invocations one after another, this holds the blend; on a
/// GPU whose waves gather in any order it also holds the sort.)
#[test]
fn volumes_of_every_mode_blend_in_buffer_order() {
    let config = FogConfig {
        max_local_volumes: 72,
        ..small_config()
    };
    let mut rng = Rng(41);
    let shapes = [
        VolumeShape::Box,
        VolumeShape::Ellipsoid,
        VolumeShape::Cylinder,
        VolumeShape::Cone,
    ];
    let volumes: Vec<LocalVolume> = (0..72)
        .map(|i| {
            let blend = BlendMode::ALL[(rng.f() * 6.0) as usize % 6];
            let density = match blend {
                BlendMode::Add => rng.range(-0.05, 0.15),
                BlendMode::Multiply => rng.range(0.0, 2.0),
                _ => rng.range(0.0, 0.15),
            };
            let emission = if blend == BlendMode::Multiply {
                Vec3::ZERO
            } else {
                Vec3::new(rng.f(), rng.f(), rng.f()) * 0.01
            };
            volume(
                shapes[i % 4],
                Vec3::new(
                    rng.range(2.5, 6.0),
                    rng.range(2.5, 5.0),
                    rng.range(2.5, 6.0),
                ),
                rng.range(0.0, 3.0),
                Vec3::new(0.0, 2.0, -14.0) + rng.vec(1.5),
                blend,
                density,
                emission,
            )
        })
        .collect();
    let modes: Vec<usize> = BlendMode::ALL
        .iter()
        .map(|b| volumes.iter().filter(|v| v.blend == *b as u32).count())
        .collect();
    assert!(
        modes.iter().all(|n| *n >= 5),
        "every mode is there: {modes:?}"
    );
    // Some block (a sphere around a froxel near the point) touches more than 64.
    let near = Vec3::new(0.0, 2.0, -14.0);
    let touching = volumes
        .iter()
        .filter(|v| volfog::cpu::density::local_volume_touches_sphere(v, near, 0.5))
        .count();
    assert!(touching > 64, "{touching} volumes touch the centre");
    // The control: the same volumes in reverse order blend to another medium.
    let reversed: Vec<LocalVolume> = volumes.iter().rev().copied().collect();
    let errors = mirror_errors(&config, &volumes, &[&volumes, &reversed]);
    eprintln!(
        "72 volumes ({modes:?} per mode, {touching} at the centre): worst relative error \
         vs CPU {:e} (bound 4e-3); against the mirror of them in reverse order {:.3}",
        errors[0], errors[1]
    );
    assert!(errors[0] <= 4e-3, "{}", errors[0]);
    assert!(errors[1] > 0.05, "the order matters: {}", errors[1]);
}

/// A box of each mode in uniform fog that glows (no light): its near and far faces lie
/// on slice boundaries and its side passes through the camera, so every froxel column
/// either crosses it from face to face or misses it. Along each column the scan's
/// transmittance and in-scattered light (here the emission) are the closed form of
/// piecewise-constant fog: T = exp(-sum sigma_k d_k), L = sum T_k E_k (1 - exp(-sigma_k
/// d_k)) / sigma_k, with the box's extinction and emission from the mode's definition
/// (not from the mirror). A subtractive box denser than the fog clears exactly its
/// interior: the optical depth through it is that of the fog outside it.
#[test]
fn a_box_of_each_mode_in_uniform_fog_matches_the_closed_form() {
    let gpu = gpu();
    let config = FogConfig {
        max_local_volumes: 1,
        ..small_config()
    };
    let (sigma, glow) = (0.05f64, 0.004f64);
    let medium = FogMedium {
        density: sigma as f32,
        height_falloff: 0.0,
        noise_strength: 0.0,
        emission: Vec3::splat(glow as f32),
        ..FogMedium::default()
    };
    let size = config.volume_size;
    let depth = |k: u32| {
        volfog::cpu::froxel::slice_depth(
            k as f32 / size.z as f32,
            config.near,
            config.far,
            config.slice_curve,
        )
    };
    let (k0, k1) = (30, 40);
    let (z0, z1) = (depth(k0), depth(k1));
    // x from 0 (through the camera) to 50 m, y from -40 to 44 m: wider than the frustum
    // between z0 and z1; a thin edge (a few cm) inside the faces.
    let box_from = Mat4::from_scale_rotation_translation(
        Vec3::new(25.0, 42.0, 0.5 * (z1 - z0)),
        Quat::IDENTITY,
        Vec3::new(25.0, 2.0, -0.5 * (z0 + z1)),
    );
    // (mode, density, emission per channel, the box's extinction and emission).
    let s = sigma;
    let cases: [(BlendMode, f64, f64, f64, f64); 7] = [
        (BlendMode::Add, 0.03, 0.002, s + 0.03, glow + 0.002),
        (BlendMode::Subtract, 0.2, 0.01, 0.0, 0.0),
        (BlendMode::Subtract, 0.02, 0.001, s - 0.02, glow - 0.001),
        (BlendMode::Multiply, 0.4, 0.0, s * 0.4, glow * 0.4),
        (BlendMode::Min, 0.01, 0.006, 0.01, glow),
        (BlendMode::Max, 0.12, 0.001, 0.12, glow),
        (BlendMode::Overwrite, 0.07, 0.009, 0.07, 0.009),
    ];
    for (blend, density, emission, inside_sigma, inside_glow) in cases {
        let boxed = LocalVolume::new(box_from, VolumeShape::Box, density as f32, 0.002)
            .and_then(|v| v.with_emission(Vec3::splat(emission as f32)))
            .and_then(|v| v.with_blend(blend))
            .unwrap();
        let volumes = [boxed];
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let frame_inputs = |_| FrameInputs {
            medium,
            sun: DirectionalLight {
                color: Vec3::ZERO,
                ..DirectionalLight::default()
            },
            ambient: AmbientSh::default(),
            local_volumes: &volumes,
            cascades: ShadowCascades::default(),
            ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
        };
        let mut integrated = Vec::new();
        run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
            integrated = read_volume(gpu, fog.integrated_texture())
        });
        let u = expected_uniforms(&config, &frame_inputs(0), 0);
        let f = &u.froxels;
        let (mut worst_t, mut worst_l, mut crossing) = (0.0f64, 0.0f64, 0);
        for y in 0..size.y {
            for x in 0..size.x {
                let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                    / glam::Vec2::new(size.x as f32, size.y as f32);
                let scale = volfog::cpu::froxel::ray_scale(uv, f.view_from_clip) as f64;
                // The column's ray is right of the camera (x > 0) or left of it.
                let (world, _) = froxel_world_position(f, &u.frame, UVec3::new(x, y, 0), false);
                let crosses = world.x > 0.0;
                crossing += usize::from(crosses);
                let (mut tau, mut light) = (0.0f64, 0.0f64);
                for z in 0..size.z {
                    let inside = crosses && (k0..k1).contains(&z);
                    let (sig, e) = if inside {
                        (inside_sigma, inside_glow)
                    } else {
                        (sigma, glow)
                    };
                    let d = (depth(z + 1) - depth(z)) as f64 * scale;
                    let held = if sig > 0.0 {
                        (1.0 - (-sig * d).exp()) / sig
                    } else {
                        d
                    };
                    light += (-tau).exp() * e * held;
                    tau += sig * d;
                    let got = integrated[index(size, x, y, z)];
                    let t = (-tau).exp();
                    worst_t = worst_t.max((got.w as f64 - t).abs() / t);
                    for c in 0..3 {
                        worst_l = worst_l.max((got[c] as f64 - light).abs() / light);
                    }
                }
            }
        }
        eprintln!(
            "{blend:?} box (density {density}, emission {emission}) in uniform fog: {crossing} \
             of {} columns cross it; transmittance {:.4}%, emission {:.4}% from the closed \
             form (bound 0.5%)",
            size.x * size.y,
            worst_t * 100.0,
            worst_l * 100.0
        );
        assert!(crossing > 100 && crossing < (size.x * size.y) as usize - 100);
        assert!(worst_t <= 0.005 && worst_l <= 0.005, "{blend:?}");
    }
}
