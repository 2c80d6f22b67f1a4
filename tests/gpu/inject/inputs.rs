//! Extreme and invalid frame inputs: lights exactly at froxel centres stay finite, and
//! bad inputs are typed errors naming their field.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{Mat4, UVec3, Vec3, Vec4};
use volfog::cpu::inject::froxel_world_position;
use volfog::pipeline::{FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogLight, FogMedium, ShadowCascades};

/// Lights exactly at froxel sample positions (distance 0) and the extreme inputs a
/// light allows: every froxel stays finite.
#[test]
fn lights_at_froxel_centres_stay_finite() {
    let gpu = gpu();
    let config = small_config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    // Place lights at the sample positions of a few froxels of the first frame.
    let u = expected_uniforms(
        &config,
        &FrameInputs::new(view(2.0, 0.0), projection(), 0.0),
        0,
    );
    let at = |x, y, z| froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), false).0;
    let lights = [
        FogLight {
            radius: 1e-6,
            ..FogLight::point(at(5, 5, 5), Vec3::splat(1.0e4), 3.0)
        },
        FogLight {
            radius: 1e-6,
            ..FogLight::spot(
                at(20, 9, 30),
                Vec3::NEG_Z,
                Vec3::splat(1.0e4),
                30.0,
                0.1,
                0.1,
            )
        },
        FogLight::point(at(0, 0, 0), Vec3::splat(50.0), 1e-3),
        FogLight::point(u.frame.camera_position, Vec3::splat(50.0), 10.0),
    ];
    let mut volumes = (Vec::new(), Vec::new());
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| FrameInputs {
            lights: &lights,
            ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
        },
        |_, fog| {
            volumes = (
                read_volume(gpu, fog.scattering_texture()),
                read_volume(gpu, fog.integrated_texture()),
            )
        },
    );
    let size = config.volume_size;
    for (name, v) in [("scattering", &volumes.0), ("integrated", &volumes.1)] {
        assert!(
            v.iter().all(|t| t.is_finite()),
            "{name} volume has NaN or Inf"
        );
    }
    let centre = volumes.0[index(size, 5, 5, 5)];
    let neighbour = volumes.0[index(size, 6, 5, 5)];
    eprintln!("light at a froxel centre: that froxel {centre}, its neighbour {neighbour}");
    assert!(
        centre.x > neighbour.x,
        "the froxel holding the light is the brightest"
    );
}

#[test]
fn bad_frame_inputs_are_typed_errors() {
    let gpu = gpu();
    let config = small_config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let base = || FrameInputs::new(view(2.0, 0.0), projection(), 0.0);
    let too_many = vec![FogLight::point(Vec3::ZERO, Vec3::ONE, 1.0); 9];
    let bad_light = [FogLight {
        range: -1.0,
        ..FogLight::point(Vec3::ZERO, Vec3::ONE, 1.0)
    }];
    let cases: Vec<(FrameInputs, &str)> = vec![
        (
            FrameInputs {
                medium: FogMedium {
                    phase_g: 1.0,
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.phase_g",
        ),
        (
            FrameInputs {
                medium: FogMedium {
                    density: -0.1,
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.density",
        ),
        (
            FrameInputs {
                medium: FogMedium {
                    albedo: Vec3::new(f32::NAN, 0.5, 0.5),
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.albedo",
        ),
        (
            FrameInputs {
                lights: &too_many,
                ..base()
            },
            "FrameInputs.lights",
        ),
        (
            FrameInputs {
                lights: &bad_light,
                ..base()
            },
            "FogLight.range",
        ),
        (
            FrameInputs {
                clip_from_view: Mat4::ZERO,
                ..base()
            },
            "Froxels.clip_from_view",
        ),
        (
            FrameInputs {
                time: f32::INFINITY,
                ..base()
            },
            "FrameInputs.time",
        ),
        (
            FrameInputs {
                cascades: ShadowCascades {
                    count: 1,
                    exponent: 120.0,
                    light_from_world: [Mat4::IDENTITY; 4],
                    splits: Vec4::new(10.0, 20.0, 30.0, 40.0),
                },
                ..base()
            },
            "ShadowCascades.exponent",
        ),
        (
            FrameInputs {
                sun: DirectionalLight {
                    direction: Vec3::ZERO,
                    ..DirectionalLight::default()
                },
                ..base()
            },
            "DirectionalLight.direction",
        ),
    ];
    for (inputs, field) in cases {
        match fog.prepare(&gpu.queue, &inputs) {
            Err(volfog::pipeline::FogError::Invalid(e)) => assert_eq!(e.field, field, "{e}"),
            other => panic!("{field}: expected a typed error, got {other:?}"),
        }
    }
}
