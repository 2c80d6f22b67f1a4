//! The kinds of `FogLight` beyond point and spot: a directional light
//! (`FOG_LIGHT_DIRECTIONAL`) against the unshadowed sun, which reaches the froxels by a
//! different code path, and the squared cone falloff (`FOG_LIGHT_SPOT_SQUARED`)
//! against the CPU mirror and against the smoothstep cone it replaces.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FOG_LIGHT_SPOT_SQUARED, FogLight};
use volfog_testkit::Gpu;

/// One frame of the small scene lit by `sun` and `lights` (no shadows, no ambient),
/// with the medium's transmittance on the lights' way: the scattering volume.
fn scattering(
    gpu: &Gpu,
    config: &FogConfig,
    sun: DirectionalLight,
    lights: &[FogLight],
) -> Vec<Vec4> {
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    let mut volume = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(sun, lights),
        |_, fog| volume = read_volume(gpu, fog.scattering_texture()),
    );
    volume
}

fn inputs(sun: DirectionalLight, lights: &[FogLight]) -> FrameInputs<'_> {
    FrameInputs {
        medium: medium(),
        sun,
        ambient: AmbientSh::constant(Vec3::ZERO),
        lights,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    }
}

fn config() -> FogConfig {
    FogConfig {
        light_transmittance: true,
        ..small_config()
    }
}

/// Largest difference over the volume relative to each froxel's largest channel.
fn worst_relative(got: &[Vec4], want: impl Fn(usize) -> Vec4) -> f32 {
    let mut worst = 0.0f32;
    for (i, g) in got.iter().enumerate() {
        let w = want(i);
        assert!(g.is_finite(), "froxel {i} is not finite: {g}");
        let scale = w.truncate().max_element().max(1e-4);
        for c in 0..3 {
            worst = worst.max((g[c] - w[c]).abs() / scale);
        }
    }
    worst
}

/// A directional `FogLight` with the sun's direction, colour and fog intensity gives the
/// volume the sun gives without a shadow map: the sun's path (`sun_inscatter`, the
/// height profile towards `sun.direction`) and the light loop's are independent code.
#[test]
fn a_directional_fog_light_lights_the_fog_as_the_unshadowed_sun() {
    let gpu = gpu();
    let config = config();
    let toward = Vec3::new(0.4, 0.8, -0.3).normalize();
    let sun = DirectionalLight {
        direction: toward,
        color: Vec3::new(2.0, 1.5, 1.0),
        fog_intensity: 0.7,
        ..DirectionalLight::default()
    };
    let dark = DirectionalLight {
        color: Vec3::ZERO,
        ..sun
    };
    let light = [FogLight {
        fog_intensity: 0.7,
        ..FogLight::directional(toward, sun.color)
    }];
    let by_sun = scattering(gpu, &config, sun, &[]);
    let by_light = scattering(gpu, &config, dark, &light);
    let worst = worst_relative(&by_light, |i| by_sun[i]);
    let lit = by_sun.iter().filter(|v| v.x > 1e-4).count();
    eprintln!(
        "directional FogLight vs the unshadowed sun: worst relative difference {worst:e} \
         (bound 2e-3, two rgba16float ulps) over {} froxels, {lit} lit",
        by_sun.len()
    );
    assert!(lit * 2 > by_sun.len(), "the sun lights most of the volume");
    assert!(worst <= 2e-3, "{worst}");
}

/// Squared and smoothstep spot cones and a directional light together, against the CPU
/// mirror; the squared cone changes the image (the flag is read).
#[test]
fn squared_spot_cones_and_directional_lights_match_the_cpu_mirror() {
    let gpu = gpu();
    let config = config();
    let spot = FogLight::spot(
        Vec3::new(1.0, 6.0, -16.0),
        Vec3::new(0.1, -1.0, -0.1),
        Vec3::new(60.0, 40.0, 20.0),
        25.0,
        0.2,
        0.7,
    );
    let squared = FogLight {
        flags: FOG_LIGHT_SPOT_SQUARED,
        ..spot
    };
    let moon = FogLight::directional(Vec3::new(-0.5, 0.7, 0.5).normalize(), Vec3::splat(0.3));
    let sun = DirectionalLight {
        color: Vec3::ZERO,
        ..DirectionalLight::default()
    };
    let lights = [squared, moon];
    let got = scattering(gpu, &config, sun, &lights);
    let frame = inputs(sun, &lights);
    let u = expected_uniforms(&config, &frame, 0);
    let cpu = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &lights,
        local_volumes: &[],
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let size = config.volume_size;
    let froxel = |i: usize| {
        let i = i as u32;
        UVec3::new(i % size.x, (i / size.x) % size.y, i / (size.x * size.y))
    };
    let worst = worst_relative(&got, |i| froxel_scattering(&cpu, froxel(i)));
    // The same scene with the smoothstep cone: the squared cone is dimmer between the
    // cones (t^2 < t^2 (3 - 2 t) for 0 < t < 1).
    let smooth = scattering(gpu, &config, sun, &[spot, moon]);
    let dimmer = got
        .iter()
        .zip(&smooth)
        .filter(|(q, s)| q.x < s.x * 0.9)
        .count();
    let brighter = got
        .iter()
        .zip(&smooth)
        .filter(|(q, s)| q.x > s.x * 1.001 + 1e-4)
        .count();
    eprintln!(
        "squared spot + directional light vs CPU mirror: worst relative error {worst:e} \
         (bound 4e-3); {dimmer} froxels dimmer than with the smoothstep cone, {brighter} brighter"
    );
    assert!(worst <= 4e-3, "{worst}");
    assert!(
        dimmer > 20,
        "the squared cone is read: {dimmer} froxels dimmer"
    );
    assert_eq!(
        brighter, 0,
        "the squared cone is never brighter than the smoothstep"
    );
}
