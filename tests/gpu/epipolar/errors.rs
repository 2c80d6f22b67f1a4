//! Invalid sampling, input textures and views of the shafts as typed errors.

use super::{Scene, occluders, sun_direction};
use crate::common::gpu;
use volfog::pipeline::epipolar::{EpipolarError, EpipolarMode, EpipolarShafts};
use volfog::uniforms::{EpipolarSampling, EpipolarView};

#[test]
fn bad_sampling_and_inputs_are_typed_errors() {
    let gpu = gpu();
    let scene = Scene::new(64, 36, 128, &occluders(), sun_direction());
    for (bad, field) in [
        (
            EpipolarSampling {
                samples: 200,
                ..scene.sampling()
            },
            "samples",
        ),
        (
            EpipolarSampling {
                initial_step: 4,
                ..scene.sampling()
            },
            "initial_step",
        ),
        (
            EpipolarSampling {
                downscale: 3,
                ..scene.sampling()
            },
            "downscale",
        ),
        (
            EpipolarSampling {
                shadow_size: 1000,
                ..scene.sampling()
            },
            "shadow_size",
        ),
        (
            EpipolarSampling {
                depth_threshold: f32::NAN,
                ..scene.sampling()
            },
            "depth_threshold",
        ),
        (
            EpipolarSampling {
                width: 0,
                ..scene.sampling()
            },
            "width",
        ),
    ] {
        match EpipolarShafts::new(&gpu.device, bad) {
            Err(EpipolarError::Invalid(e)) => assert!(e.field.ends_with(field), "{e}"),
            other => panic!("{field}: {other:?}"),
        }
    }
    let mut shafts = EpipolarShafts::new(&gpu.device, scene.sampling()).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(matches!(
        shafts.encode(&mut encoder, EpipolarMode::Tree),
        Err(EpipolarError::NotReady("set_inputs"))
    ));
    let (depth, shadow) = scene.textures(gpu);
    match shafts.set_inputs(&gpu.device, &shadow, &shadow) {
        Err(EpipolarError::Texture {
            property: "size", ..
        }) => {}
        other => panic!("a depth buffer of the wrong size: {other:?}"),
    }
    shafts.set_inputs(&gpu.device, &depth, &shadow).unwrap();
    assert!(matches!(
        shafts.encode(&mut encoder, EpipolarMode::Tree),
        Err(EpipolarError::NotReady("prepare"))
    ));
    let bad_view = EpipolarView {
        max_depth: -1.0,
        ..scene.view(0.0)
    };
    match shafts.prepare(&gpu.queue, &bad_view, &scene.medium()) {
        Err(EpipolarError::Invalid(e)) => assert_eq!(e.field, "EpipolarView.max_depth"),
        other => panic!("{other:?}"),
    }
    let perspective_light = EpipolarView {
        light_from_world: scene.clip_from_view,
        ..scene.view(0.0)
    };
    match shafts.prepare(&gpu.queue, &perspective_light, &scene.medium()) {
        Err(EpipolarError::Invalid(e)) => assert_eq!(e.field, "EpipolarView.light_from_world"),
        other => panic!("{other:?}"),
    }
    assert!(shafts.memory_bytes() > 0);
}
