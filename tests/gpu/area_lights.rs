//! Area lights in the fog (`VOLFOG_INJECT_AREA_LIGHTS`): the inject variant through
//! `VolumetricFog` against the CPU mirror (`volfog::cpu::area`), the range culling per
//! block, and typed errors for bad emitters.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::area::add_area_lights;
use volfog::cpu::inject::{InjectInputs, froxel_scattering};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{AreaLight, DirectionalLight};

fn config() -> FogConfig {
    FogConfig {
        light_transmittance: true,
        max_area_lights: 4,
        ..small_config()
    }
}

fn dark_sun() -> DirectionalLight {
    DirectionalLight {
        color: Vec3::ZERO,
        ..DirectionalLight::default()
    }
}

fn inputs(area_lights: &[AreaLight]) -> FrameInputs<'_> {
    FrameInputs {
        medium: medium(),
        sun: dark_sun(),
        ambient: AmbientSh::constant(Vec3::ZERO),
        area_lights,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    }
}

/// A 2 m x 1 m panel facing down and a disk of radius 0.7 m facing the camera, both in
/// the small scene's view.
fn emitters() -> [AreaLight; 2] {
    let down = Vec3::new(0.2, -1.0, 0.1).normalize();
    let (ax, ay) = down.any_orthonormal_pair();
    [
        AreaLight::rect(
            Vec3::new(1.0, 5.0, -10.0),
            ax,
            ay,
            1.0,
            0.5,
            Vec3::new(40.0, 30.0, 20.0),
            20.0,
        ),
        AreaLight::disk(
            Vec3::new(-2.0, 2.5, -8.0),
            Vec3::new(0.1, 0.0, 1.0).normalize(),
            0.7,
            Vec3::new(20.0, 40.0, 60.0),
            15.0,
        ),
    ]
}

/// The CPU mirror of one frame: inject without the area lights, then their term.
fn mirror(config: &FogConfig, area_lights: &[AreaLight]) -> (Vec<Vec4>, Vec<Vec4>) {
    let frame = inputs(area_lights);
    let u = expected_uniforms(config, &frame, 0);
    let cpu = InjectInputs {
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
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let size = config.volume_size;
    let base: Vec<Vec4> = (0..size.x * size.y * size.z)
        .map(|i| {
            let id = UVec3::new(i % size.x, (i / size.x) % size.y, i / (size.x * size.y));
            froxel_scattering(&cpu, id)
        })
        .collect();
    let mut lit = base.clone();
    add_area_lights(
        &u.froxels,
        &u.frame,
        &u.medium,
        config.light_transmittance,
        config.jitter,
        area_lights,
        &mut lit,
    );
    (base, lit)
}

/// The GPU's volume with a rectangle and a disk light against the mirror, relative to
/// each froxel's largest channel; the lights light a good part of the volume (the
/// test cannot pass on a variant that ignores them).
#[test]
fn area_lights_match_the_cpu_mirror() {
    let gpu = gpu();
    let config = config();
    let lights = emitters();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut got = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(&lights),
        |_, fog| got = read_volume(gpu, fog.scattering_texture()),
    );
    let (base, want) = mirror(&config, &lights);
    let mut worst = 0.0f32;
    let mut lit = 0;
    for ((g, w), b) in got.iter().zip(&want).zip(&base) {
        assert!(g.is_finite(), "{g}");
        let scale = w.truncate().max_element().max(1e-4);
        worst = worst.max(((*g - *w).truncate().abs() / scale).max_element());
        if w.truncate().max_element() > 2.0 * b.truncate().max_element() + 1e-4 {
            lit += 1;
        }
    }
    eprintln!(
        "area lights (rect + disk) vs CPU mirror: worst relative error {worst:e} \
         (bound 4e-3) over {} froxels, {lit} lit mainly by them",
        got.len()
    );
    assert!(lit > 500, "the emitters light the fog: {lit} froxels");
    assert!(worst <= 4e-3, "{worst}");
}

/// A block the emitter's range sphere misses skips it (its light there is exactly 0,
/// so the culled volume equals the mirror's), and slots left unused light nothing: a
/// fog with room for four area lights and none equals one without the variant.
#[test]
fn area_lights_are_culled_by_range_and_unused_slots_light_nothing() {
    let gpu = gpu();
    let near = [AreaLight {
        range: 3.0,
        ..emitters()[1]
    }];
    let config = config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut got = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(&near),
        |_, fog| got = read_volume(gpu, fog.scattering_texture()),
    );
    let (base, want) = mirror(&config, &near);
    let touched = want.iter().zip(&base).filter(|(w, b)| w.x > b.x).count();
    let mut worst = 0.0f32;
    for (g, w) in got.iter().zip(&want) {
        worst = worst
            .max(((*g - *w).truncate().abs() / w.truncate().max_element().max(1e-4)).max_element());
    }
    eprintln!("short-range disk: {touched} froxels lit, worst relative error {worst:e}");
    assert!(touched > 20 && touched * 10 < want.len(), "{touched}");
    assert!(worst <= 4e-3, "{worst}");

    let mut empty = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(&[]),
        |_, fog| empty = read_volume(gpu, fog.scattering_texture()),
    );
    let mut plain_fog = VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            max_area_lights: 0,
            ..config
        },
    )
    .unwrap();
    let mut plain = Vec::new();
    run_frames(
        gpu,
        &mut plain_fog,
        1,
        |_| inputs(&[]),
        |_, fog| plain = read_volume(gpu, fog.scattering_texture()),
    );
    assert_eq!(empty, plain, "unused slots change nothing");
}

/// A zero-area emitter, NaN axes and more lights than the capacity are typed errors
/// naming the field.
#[test]
fn bad_area_lights_are_typed_errors_naming_the_field() {
    let config = config();
    let good = emitters()[0];
    let field = |lights: &[AreaLight]| inputs(lights).validate(&config).unwrap_err().field;
    assert!(inputs(&[good]).validate(&config).is_ok());
    assert_eq!(
        field(&[AreaLight {
            half_x: 0.0,
            ..good
        }]),
        "AreaLight.half_x"
    );
    assert_eq!(
        field(&[AreaLight {
            half_y: 0.0,
            ..good
        }]),
        "AreaLight.half_y"
    );
    assert_eq!(
        field(&[AreaLight {
            axis_x: Vec3::new(f32::NAN, 0.0, 0.0),
            ..good
        }]),
        "AreaLight.axis_x"
    );
    assert_eq!(
        field(&[AreaLight {
            axis_y: Vec3::splat(f32::NAN),
            ..good
        }]),
        "AreaLight.axis_y"
    );
    assert_eq!(field(&[good; 5]), "FrameInputs.area_lights");
    let too_many = FogConfig {
        max_area_lights: volfog::limits::MAX_AREA_LIGHTS + 1,
        ..config
    };
    let Err(err) = VolumetricFog::new(&gpu().device, &too_many) else {
        panic!("FogConfig.max_area_lights above the limit is accepted");
    };
    assert!(
        err.to_string().contains("FogConfig.max_area_lights"),
        "{err}"
    );
}
