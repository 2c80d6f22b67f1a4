//! The inject pass against the CPU mirror: a full scene (lights, local volumes,
//! shadows, noise) and the density-texture variant.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{UVec3, Vec3};
use volfog::cpu;
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering, froxel_world_position};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogMedium, ShadowCascades};

/// Both shadow filters: the ESM (linear and log space) and the compare filter (one and
/// two taps a froxel with history, so four and eight here without a temporal blend,
/// at jittered and centred samples).
#[test]
fn inject_matches_cpu_mirror_for_a_full_scene() {
    let gpu = gpu();
    let esm = ShadowFilter::Esm;
    for (jitter, two_color, log_space, octaves, filter) in [
        (true, false, false, 1, esm),
        (true, true, true, 3, esm),
        (false, false, false, 2, esm),
        (true, false, false, 1, ShadowFilter::Compare { taps: 1 }),
        (false, true, false, 2, ShadowFilter::Compare { taps: 2 }),
    ] {
        let config = volfog::pipeline::FogConfig {
            shadow_filter: filter,
            jitter,
            two_color_phase: two_color,
            esm_log_space: log_space,
            esm_exponent: if log_space { 150.0 } else { 80.0 },
            noise_octaves: octaves,
            ..small_config()
        };
        let (cascades, depth_layers) = overhead_sun(&config, Some(SLAB));
        let shadow = shadow_map(gpu, &depth_layers);
        let lights = lights();
        let volumes = local_volumes();
        let medium = medium();
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_shadow_map(&gpu.device, &shadow).unwrap();
        let frame_inputs = |f: u32| FrameInputs {
            medium,
            sun: DirectionalLight {
                direction: Vec3::Y,
                ..DirectionalLight::default()
            },
            ambient: AmbientSh::sky_ground(
                Vec3::new(0.2, 0.3, 0.5),
                Vec3::new(0.05, 0.04, 0.03),
                Vec3::Y,
            ),
            lights: &lights,
            local_volumes: &volumes,
            cascades,
            ..FrameInputs::new(view(3.0, -0.1), projection(), 1.5 + f as f32)
        };
        let mut captured = None;
        run_frames(gpu, &mut fog, 3, frame_inputs, |f, fog| {
            if f == 2 {
                captured = Some((
                    read_volume(gpu, fog.scattering_texture()),
                    read_esm(gpu, fog),
                ));
            }
        });
        let (scattering, esm_layers) = captured.unwrap();
        // The compare filter reads the shadow map itself.
        let esm_layers = if filter.compares() {
            depth_layers.clone()
        } else {
            esm_layers
        };
        let u = expected_uniforms(&config, &frame_inputs(2), 2);
        let inputs = InjectInputs {
            froxels: &u.froxels,
            frame: &u.frame,
            medium: &u.medium,
            lighting: &u.lighting,
            cascades: &u.cascades,
            esm: &esm_layers,
            shadow_taps: &u.shadow_taps,
            lights: &lights,
            local_volumes: &volumes,
            options: config.inject_options(),
            density_texture: None,
            noise_texture: None,
            clouds: None,
            local_shadows: None,
            scene_depth: None,
            medium_shadow: None,
        };
        let size = config.volume_size;
        let mut worst = 0.0f32;
        let mut shadowed = 0;
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    let want = froxel_scattering(&inputs, UVec3::new(x, y, z));
                    let got = scattering[index(size, x, y, z)];
                    assert!(got.is_finite(), "non-finite froxel {x},{y},{z}");
                    let scale = want.truncate().max_element().max(1e-4);
                    for c in 0..3 {
                        let e = (got[c] - want[c]).abs() / scale;
                        worst = worst.max(e);
                    }
                    let e = (got.w - want.w).abs() / want.w.max(1e-4);
                    worst = worst.max(e);
                    let (world, depth) =
                        froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), jitter);
                    let lit = if filter.compares() {
                        let c = cpu::esm::esm_cascade(depth, u.cascades.splits, u.cascades.count);
                        cpu::shadow::shadow_cascade_compare(
                            &esm_layers[c as usize],
                            u.cascades.light_from_world[c as usize],
                            world,
                            false,
                        )
                    } else {
                        cpu::esm::esm_shadow(&esm_layers, &u.cascades, world, depth, log_space)
                    };
                    if lit < 0.5 {
                        shadowed += 1;
                    }
                }
            }
        }
        eprintln!(
            "inject {filter:?} jitter={jitter} two_color={two_color} log_space={log_space} octaves={octaves}: worst relative error vs CPU {worst:e} (bound 4e-3), {shadowed} shadowed froxels"
        );
        assert!(shadowed > 100, "the slab shadows part of the volume");
        assert!(worst <= 4e-3, "{worst}");
    }
}

/// The density-texture variant: a user 3D texture scrolled by the wind multiplies the
/// density; GPU against the CPU mirror's trilinear, repeat-addressed sample.
#[test]
fn density_texture_variant_matches_cpu_mirror() {
    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        density_texture: true,
        ..small_config()
    };
    // Stored as f16: the CPU mirror samples the rounded values.
    let (texture, reference) = super::density_texture([16, 8, 12], |x, y, z| {
        0.5 + 0.5
            * ((x as f32 * 0.8).sin() * (y as f32 * 1.1).cos() + 0.3 * (z as f32 * 0.5).sin())
                .clamp(-1.0, 1.0)
    });
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_density_texture(&gpu.device, &texture).unwrap();
    let medium = FogMedium {
        density: 0.05,
        height_falloff: 0.0,
        noise_strength: 0.0,
        texture_scale: Vec3::new(0.07, 0.2, 0.05),
        texture_offset: Vec3::new(0.3, 0.1, 0.7),
        wind: Vec3::new(2.0, 0.0, -1.0),
        ..FogMedium::default()
    };
    let mut scattering = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(2.0, 0.0), projection(), 3.5)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        scattering = read_volume(gpu, fog.scattering_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let inputs = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &[],
        local_volumes: &[],
        options: config.inject_options(),
        density_texture: Some(&reference),
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let s = config.volume_size;
    let (mut worst, mut lo, mut hi) = (0.0f32, f32::MAX, 0.0f32);
    for z in 0..s.z {
        for y in 0..s.y {
            for x in 0..s.x {
                let want = froxel_scattering(&inputs, UVec3::new(x, y, z)).w;
                let got = scattering[index(s, x, y, z)].w;
                lo = lo.min(got);
                hi = hi.max(got);
                // The sampler's filter weights are fixed point (8 bits on lavapipe):
                // up to 1/256 of the neighbouring texel difference, plus fp16 output.
                worst = worst.max((got - want).abs() / 0.05);
            }
        }
    }
    eprintln!(
        "density texture: sigma_t from {lo:.4} to {hi:.4}; worst difference vs CPU {:.3}% of the base density (bound 0.5%)",
        worst * 100.0
    );
    assert!(hi > 2.0 * lo, "the texture modulates the density");
    assert!(worst <= 5e-3, "{worst}");
    // Without the define the texture cannot be set.
    let mut plain = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    assert!(plain.set_density_texture(&gpu.device, &texture).is_err());
}
