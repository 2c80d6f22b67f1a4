//! Typed errors for every invalid configuration field, for a device without a needed
//! capability, and for orthographic projections.

use super::private_device;
use crate::common::gpu;
use crate::common::scene::{small_config, view};
use glam::{UVec3, Vec3};
use volfog::pipeline::{FogConfig, FogError, FrameInputs, VolumetricFog};

#[test]
fn every_invalid_config_field_is_a_typed_error() {
    let gpu = gpu();
    let d = FogConfig::default;
    let cases: Vec<(FogConfig, &str)> = vec![
        (
            FogConfig {
                volume_size: UVec3::new(0, 90, 128),
                ..d()
            },
            "FogConfig.volume_size",
        ),
        (
            FogConfig {
                volume_size: UVec3::new(4096, 90, 128),
                ..d()
            },
            "FogConfig.volume_size",
        ),
        (
            FogConfig {
                volume_size: UVec3::new(2048, 2048, 8),
                ..d()
            },
            "FogConfig.volume_size",
        ),
        (
            FogConfig {
                temporal: false,
                amortize: true,
                ..d()
            },
            "FogConfig.amortize",
        ),
        (FogConfig { near: 0.0, ..d() }, "FogConfig.near"),
        (
            FogConfig {
                near: f32::NAN,
                ..d()
            },
            "FogConfig.near",
        ),
        (FogConfig { far: 0.4, ..d() }, "FogConfig.far"),
        (
            FogConfig {
                far: f32::INFINITY,
                ..d()
            },
            "FogConfig.far",
        ),
        (
            FogConfig {
                slice_curve: -1.0,
                ..d()
            },
            "FogConfig.slice_curve",
        ),
        (
            FogConfig {
                slice_curve: 31.0,
                ..d()
            },
            "FogConfig.slice_curve",
        ),
        (
            FogConfig {
                esm_resolution: 2,
                ..d()
            },
            "FogConfig.esm_resolution",
        ),
        (FogConfig { cascades: 0, ..d() }, "FogConfig.cascades"),
        (FogConfig { cascades: 5, ..d() }, "FogConfig.cascades"),
        (
            FogConfig {
                esm_exponent: 89.0,
                ..d()
            },
            "FogConfig.esm_exponent",
        ),
        (
            FogConfig {
                esm_exponent: 0.0,
                ..d()
            },
            "FogConfig.esm_exponent",
        ),
        (
            FogConfig {
                esm_exponent: 2.0e4,
                esm_log_space: true,
                ..d()
            },
            "FogConfig.esm_exponent",
        ),
        (
            FogConfig {
                esm_blur_radius: 0,
                ..d()
            },
            "FogConfig.esm_blur_radius",
        ),
        (
            FogConfig {
                esm_blur_radius: 17,
                ..d()
            },
            "FogConfig.esm_blur_radius",
        ),
        (
            FogConfig {
                max_lights: 65,
                ..d()
            },
            "FogConfig.max_lights",
        ),
        (
            FogConfig {
                max_local_volumes: 257,
                ..d()
            },
            "FogConfig.max_local_volumes",
        ),
        (
            FogConfig {
                history_weight: 1.0,
                ..d()
            },
            "FogConfig.history_weight",
        ),
        (
            FogConfig {
                history_weight: -0.1,
                ..d()
            },
            "FogConfig.history_weight",
        ),
        (
            FogConfig {
                noise_octaves: 0,
                ..d()
            },
            "FogConfig.noise_octaves",
        ),
        (
            FogConfig {
                noise_octaves: 9,
                ..d()
            },
            "FogConfig.noise_octaves",
        ),
    ];
    for (config, field) in cases {
        match VolumetricFog::new(&gpu.device, &config) {
            Err(FogError::Invalid(e)) => {
                assert_eq!(e.field, field, "{e}");
                assert!(!e.expected.is_empty());
            }
            other => panic!("{field}: expected a typed error, got {other:?}"),
        }
    }
    // Log-space filtering lifts the exponent limit of 88.
    assert!(
        VolumetricFog::new(
            &gpu.device,
            &FogConfig {
                esm_exponent: 300.0,
                esm_log_space: true,
                ..small_config()
            }
        )
        .is_ok()
    );
}

#[test]
fn missing_device_capabilities_are_typed_errors() {
    let gpu = gpu();
    // Timestamps on a device opened without TIMESTAMP_QUERY.
    let plain = private_device(gpu, wgpu::Features::empty(), wgpu::Limits::default());
    match VolumetricFog::new(
        &plain,
        &FogConfig {
            timestamps: true,
            ..small_config()
        },
    ) {
        Err(FogError::MissingCapability { what, .. }) => assert_eq!(what, "timestamp queries"),
        other => panic!("expected MissingCapability, got {other:?}"),
    }
    // A device with downlevel limits (3D textures up to 256, 2D up to 2048).
    let device = private_device(
        gpu,
        wgpu::Features::empty(),
        wgpu::Limits::downlevel_defaults(),
    );
    for (config, what) in [
        (
            FogConfig {
                volume_size: UVec3::new(512, 90, 64),
                ..small_config()
            },
            "3D textures of the volume size",
        ),
        (
            FogConfig {
                esm_resolution: 1024,
                ..small_config()
            },
            "2D array textures of the shadow map size",
        ),
    ] {
        match VolumetricFog::new(&device, &config) {
            Err(FogError::MissingCapability { what: w, detail }) => {
                assert_eq!(w, what);
                eprintln!("{w}: {detail}");
            }
            other => panic!("expected MissingCapability for {what}, got {other:?}"),
        }
    }
}

#[test]
fn orthographic_projections_are_rejected() {
    let gpu = gpu();
    let mut fog = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    let ortho = glam::camera::rh::proj::directx::orthographic(-10.0, 10.0, -5.0, 5.0, 0.1, 100.0);
    match fog.prepare(&gpu.queue, &FrameInputs::new(view(2.0, 0.0), ortho, 0.0)) {
        Err(FogError::Invalid(e)) => {
            assert_eq!(e.field, "Froxels.clip_from_view");
            assert!(e.expected.contains("orthographic"), "{e}");
        }
        other => panic!("expected a typed error, got {other:?}"),
    }
    // A left-handed perspective (w = +z) is a perspective projection.
    let lh = glam::camera::lh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
    let lh_view = glam::camera::lh::view::look_to_mat4(Vec3::new(0.0, 2.0, 0.0), Vec3::Z, Vec3::Y);
    fog.prepare(&gpu.queue, &FrameInputs::new(lh_view, lh, 0.0))
        .unwrap();
}
