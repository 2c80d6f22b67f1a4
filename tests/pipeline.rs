//! `VolumetricFog` as an object: typed errors for every invalid configuration field
//! and for a device without a needed capability, the memory budget, and no growth of
//! GPU objects across reconfigurations and repeated frames.

mod common;

use common::gpu;
use common::scene::{projection, small_config, view};
use glam::UVec3;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, ShadowInputs, VolumetricFog};

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
    assert!(VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            esm_exponent: 300.0,
            esm_log_space: true,
            ..small_config()
        }
    )
    .is_ok());
}

#[test]
fn missing_device_capabilities_are_typed_errors() {
    let gpu = gpu();
    // Timestamps on a device opened without TIMESTAMP_QUERY.
    match VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            timestamps: true,
            ..small_config()
        },
    ) {
        Err(FogError::MissingCapability { what, .. }) => assert_eq!(what, "timestamp queries"),
        other => panic!("expected MissingCapability, got {other:?}"),
    }
    // A device with downlevel limits (3D textures up to 256, 2D up to 2048).
    let (device, _queue) =
        pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("downlevel"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .unwrap();
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
fn default_configuration_fits_the_memory_budget() {
    let gpu = gpu();
    let fog = VolumetricFog::new(&gpu.device, &FogConfig::default()).unwrap();
    let bytes = fog.memory_bytes();
    eprintln!(
        "default configuration (160x90x128 rgba16float, 4 x 256^2 ESM): {:.2} MiB (budget 48 MiB)",
        bytes as f64 / 1048576.0
    );
    assert!(bytes <= 48 * 1024 * 1024, "{bytes}");
    // Three volumes of 160 x 90 x 128 x 8 bytes dominate.
    assert!(bytes >= 3 * 160 * 90 * 128 * 8);
}

/// Live GPU objects: (texture views, buffers, bind groups, texture bytes, buffer bytes).
/// wgpu's Vulkan backend counts texture memory but not textures themselves.
fn live(device: &wgpu::Device) -> (isize, isize, isize, isize, isize) {
    let c = device.get_internal_counters().hal;
    (
        c.texture_views.read(),
        c.buffers.read(),
        c.bind_groups.read(),
        c.texture_memory.read(),
        c.buffer_memory.read(),
    )
}

#[test]
fn reconfigure_and_repeated_frames_do_not_grow_gpu_objects() {
    let gpu = gpu();
    let mut fog = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    let frame = |fog: &mut VolumetricFog, t: f32| {
        fog.prepare(
            &gpu.queue,
            &FrameInputs::new(view(2.0, 0.0), projection(), t),
        )
        .unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&gpu.device, &mut encoder, &ShadowInputs::default());
        gpu.queue.submit([encoder.finish()]);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .unwrap();
    };
    for i in 0..5 {
        frame(&mut fog, i as f32);
    }
    let baseline = live(&gpu.device);
    assert!(
        baseline.3 > 0,
        "the counters are live (wgpu feature `counters`)"
    );
    for i in 0..30 {
        frame(&mut fog, i as f32);
    }
    let after_frames = live(&gpu.device);
    // Resize the volume back and forth, then return to the first configuration.
    for size in [
        UVec3::new(64, 36, 64),
        UVec3::new(16, 9, 16),
        small_config().volume_size,
    ] {
        fog.reconfigure(
            &gpu.device,
            &FogConfig {
                volume_size: size,
                ..small_config()
            },
        )
        .unwrap();
        for i in 0..3 {
            frame(&mut fog, i as f32);
        }
    }
    let after_resizes = live(&gpu.device);
    eprintln!("live (texture views, buffers, bind groups, texture bytes, buffer bytes): after warm-up {baseline:?}, after 30 frames {after_frames:?}, after 3 reconfigurations {after_resizes:?}");
    assert_eq!(
        after_frames, baseline,
        "repeated frames allocate nothing that lives on"
    );
    assert_eq!(
        after_resizes, baseline,
        "reconfiguring releases what it replaces"
    );
}
