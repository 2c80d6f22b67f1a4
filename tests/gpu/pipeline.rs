//! `VolumetricFog` as an object: typed errors for every invalid configuration field,
//! input and texture and for a device without a needed capability, the frame contract
//! (no encoding before `prepare`, shadow maps checked against the cascades,
//! `reconfigure` keeping what the user set), memory measured by wgpu's own counters,
//! and no growth of GPU objects across reconfigurations and repeated frames.

use crate::common;

use common::gpu;
use common::scene::{overhead_sun, projection, shadow_map, small_config, view};
use glam::{UVec3, Vec3};
use volfog::options::Filtering;
use volfog::pipeline::FogPass;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, VolumetricFog};
use volfog_testkit::Gpu;

/// A device of its own (wgpu's counters are per device, and the shared device is busy
/// with other tests), with `features`.
fn private_device(gpu: &Gpu, features: wgpu::Features, limits: wgpu::Limits) -> wgpu::Device {
    pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("private"),
        required_features: features,
        required_limits: limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap()
    .0
}

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

/// `memory_bytes` against the texture and buffer memory wgpu's Vulkan backend
/// allocates for the object (its internal counters), the budget of the default
/// configuration, and no history volumes without temporal reprojection.
#[test]
fn memory_matches_what_the_device_allocates() {
    let gpu = gpu();
    let device = private_device(gpu, wgpu::Features::empty(), wgpu::Limits::default());
    let allocated = |config: &FogConfig| {
        let before = live(&device);
        let fog = VolumetricFog::new(&device, config).unwrap();
        let after = live(&device);
        let bytes = (after.3 - before.3) + (after.4 - before.4);
        (fog.memory_bytes(), bytes as u64)
    };
    let (default_bytes, default_allocated) = allocated(&FogConfig::default());
    let (plain_bytes, plain_allocated) = allocated(&FogConfig {
        temporal: false,
        ..FogConfig::default()
    });
    let mib = |b: u64| b as f64 / 1048576.0;
    eprintln!(
        "default configuration: memory_bytes {:.2} MiB, device allocations {:.2} MiB (budget 48 MiB); without temporal {:.2} / {:.2} MiB",
        mib(default_bytes),
        mib(default_allocated),
        mib(plain_bytes),
        mib(plain_allocated)
    );
    assert!(default_bytes <= 48 * 1024 * 1024, "{default_bytes}");
    for (reported, allocated) in [
        (default_bytes, default_allocated),
        (plain_bytes, plain_allocated),
    ] {
        // Allocations pad resources to the backend's alignment (lavapipe pads the 3D
        // volumes by up to a megabyte): within 5 %.
        assert!(
            reported <= allocated && allocated as f64 <= reported as f64 * 1.05,
            "memory_bytes {reported} vs allocated {allocated}"
        );
    }
    // Without temporal reprojection: one volume (and the history states) fewer.
    let volume = 160 * 90 * 128 * 8;
    assert_eq!(default_bytes - plain_bytes, volume + 2 * 80);
    assert!(default_allocated - plain_allocated >= volume);
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
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("counted"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::default(),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap();
    let mut fog = VolumetricFog::new(&device, &small_config()).unwrap();
    let frame = |fog: &mut VolumetricFog, t: f32| {
        fog.prepare(&queue, &FrameInputs::new(view(2.0, 0.0), projection(), t))
            .unwrap();
        let mut encoder = device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        queue.submit([encoder.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    };
    for i in 0..5 {
        frame(&mut fog, i as f32);
    }
    let baseline = live(&device);
    assert!(
        baseline.3 > 0,
        "the counters are live (wgpu feature `counters`)"
    );
    for i in 0..30 {
        frame(&mut fog, i as f32);
    }
    let after_frames = live(&device);
    // Resize the volume back and forth, then return to the first configuration.
    for size in [
        UVec3::new(64, 36, 64),
        UVec3::new(16, 9, 16),
        small_config().volume_size,
    ] {
        fog.reconfigure(
            &device,
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
    let after_resizes = live(&device);
    eprintln!(
        "live (texture views, buffers, bind groups, texture bytes, buffer bytes): after warm-up {baseline:?}, after 30 frames {after_frames:?}, after 3 reconfigurations {after_resizes:?}"
    );
    assert_eq!(
        after_frames, baseline,
        "repeated frames allocate nothing that lives on"
    );
    assert_eq!(
        after_resizes, baseline,
        "reconfiguring releases what it replaces"
    );
}

#[test]
fn encoding_before_prepare_is_a_typed_error() {
    let gpu = gpu();
    let fog = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(matches!(
        fog.encode(&mut encoder),
        Err(FogError::NotPrepared)
    ));
    assert_eq!(fog.frame_index(), None);
}

/// Shadow maps are checked against the configuration (size, layers, format, usage),
/// and frames with cascades need one.
#[test]
fn shadow_maps_are_checked_against_the_cascades() {
    let gpu = gpu();
    let config = small_config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let (cascades, layers) = overhead_sun(&config, None);
    let inputs = FrameInputs {
        cascades,
        ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
    };
    match fog.prepare(&gpu.queue, &inputs) {
        Err(FogError::Invalid(e)) => assert_eq!(e.field, "ShadowCascades.count", "{e}"),
        other => panic!("cascades without a shadow map: {other:?}"),
    }
    let side = config.esm_resolution * 4;
    let texture = |size: u32, layers: u32, format, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let depth = wgpu::TextureFormat::Depth32Float;
    let binding = wgpu::TextureUsages::TEXTURE_BINDING;
    for (bad, property) in [
        (texture(side / 2, 2, depth, binding), "size"),
        (texture(side, 1, depth, binding), "layer count"),
        (
            texture(side, 2, wgpu::TextureFormat::Rgba8Unorm, binding),
            "format",
        ),
        (
            texture(side, 2, depth, wgpu::TextureUsages::RENDER_ATTACHMENT),
            "usage",
        ),
    ] {
        match fog.set_shadow_map(&gpu.device, &bad) {
            Err(FogError::Texture { property: p, .. }) => assert_eq!(p, property),
            other => panic!("{property}: expected a texture error, got {other:?}"),
        }
    }
    fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
        .unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
}

/// A scene depth for culling must be single-sampled, 2D, in a depth format or
/// R32Float, have the mip level read and TEXTURE_BINDING usage, and the fog must cull;
/// each mismatch is a typed error naming the property.
#[test]
fn scene_depths_are_checked() {
    let gpu = gpu();
    let texture = |format, usage, mips: u32, samples: u32| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene depth"),
            size: wgpu::Extent3d {
                width: 64,
                height: 36,
                depth_or_array_layers: 1,
            },
            mip_level_count: mips,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let depth = wgpu::TextureFormat::Depth32Float;
    let binding = wgpu::TextureUsages::TEXTURE_BINDING;
    let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let good = texture(depth, binding | attachment, 1, 1);
    let mut plain = VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            depth_cull: false,
            ..small_config()
        },
    )
    .unwrap();
    match plain.set_scene_depth(&gpu.device, &good, 0) {
        Err(FogError::Invalid(e)) => assert_eq!(e.field, "FogConfig.depth_cull", "{e}"),
        other => panic!("a fog without culling took a scene depth: {other:?}"),
    }
    let mut fog = VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            depth_cull: true,
            ..small_config()
        },
    )
    .unwrap();
    for (bad, mip, property) in [
        (
            texture(wgpu::TextureFormat::Rgba8Unorm, binding, 1, 1),
            0,
            "format",
        ),
        (texture(depth, attachment, 1, 1), 0, "usage"),
        (
            texture(depth, binding | attachment, 1, 4),
            0,
            "sample count",
        ),
        (
            texture(depth, binding | attachment, 1, 1),
            1,
            "mip level count",
        ),
    ] {
        match fog.set_scene_depth(&gpu.device, &bad, mip) {
            Err(FogError::Texture { property: p, .. }) => assert_eq!(p, property),
            other => panic!("{property}: expected a texture error, got {other:?}"),
        }
    }
    fog.set_scene_depth(&gpu.device, &good, 0).unwrap();
    let r32 = texture(wgpu::TextureFormat::R32Float, binding, 2, 1);
    fog.set_scene_depth(&gpu.device, &r32, 1).unwrap();
}

/// `reconfigure` keeps the shadow map and the density texture (and, when the new
/// configuration cannot take them, fails and changes nothing).
#[test]
fn reconfigure_keeps_what_the_user_set() {
    use wgpu::util::DeviceExt;
    let gpu = gpu();
    let config = FogConfig {
        density_texture: true,
        ..small_config()
    };
    let (cascades, layers) = overhead_sun(&config, None);
    let density = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("density"),
            size: wgpu::Extent3d {
                width: 2,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &[40, 200],
    );
    let inputs = FrameInputs {
        cascades,
        ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
    };
    let run = |fog: &mut VolumetricFog| {
        fog.prepare(&gpu.queue, &inputs).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);
        gpu.read_texture_rgba16f(fog.integrated_texture()).unwrap()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
        .unwrap();
    fog.set_density_texture(&gpu.device, &density).unwrap();
    let before = run(&mut fog);
    fog.reconfigure(
        &gpu.device,
        &FogConfig {
            history_weight: 0.5,
            ..config.clone()
        },
    )
    .unwrap();
    assert_eq!(
        run(&mut fog),
        before,
        "same shadow map and density texture after reconfigure"
    );
    let unit = run(&mut VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            density_texture: true,
            ..small_config()
        },
    )
    .map(|mut f| {
        f.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
            .unwrap();
        f
    })
    .unwrap());
    assert_ne!(unit, before, "the density texture changes the fog");
    // A larger ESM cannot read this shadow map: the error leaves the fog as it was.
    let err = fog.reconfigure(
        &gpu.device,
        &FogConfig {
            esm_resolution: 256,
            ..config.clone()
        },
    );
    assert!(
        matches!(
            err,
            Err(FogError::Texture {
                property: "size",
                ..
            })
        ),
        "{err:?}"
    );
    assert_eq!(fog.config().esm_resolution, config.esm_resolution);
    assert_eq!(run(&mut fog), before);
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

/// An apply pipeline reads the fog groups it was built for: after a reconfiguration
/// to manual filtering it is refused with a typed error.
#[test]
fn apply_pipelines_match_their_fog() {
    let gpu = gpu();
    let mut fog = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    let apply = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    fog.prepare(
        &gpu.queue,
        &FrameInputs::new(view(2.0, 0.0), projection(), 0.0),
    )
    .unwrap();
    fog.reconfigure(
        &gpu.device,
        &FogConfig {
            apply_filtering: Filtering::Manual,
            ..small_config()
        },
    )
    .unwrap();
    fog.prepare(
        &gpu.queue,
        &FrameInputs::new(view(2.0, 0.0), projection(), 0.0),
    )
    .unwrap();
    let target = gpu.texture_2d_rgba16f("target", [4, 4], &[]);
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, 4, 4, &[0.5; 16]).unwrap();
    let depth_group = apply.depth_bind_group(
        &gpu.device,
        &depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        }),
    );
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let err = fog.record_apply(
        &mut encoder,
        &apply,
        &target.create_view(&Default::default()),
        &depth_group,
    );
    assert!(
        matches!(err, Err(FogError::ApplyMismatch { .. })),
        "{err:?}"
    );
}

/// The bench submits every pass alone with `encode_pass`: over frames with shadows and
/// temporal reprojection this must leave the same volumes as `encode`.
#[test]
fn passes_submitted_alone_match_encode() {
    let gpu = gpu();
    let config = FogConfig {
        temporal: true,
        jitter: true,
        ..small_config()
    };
    let slab = common::scene::Slab {
        x: (-6.0, 6.0),
        z: (-30.0, -10.0),
        top: 6.0,
    };
    let (cascades, layers) = common::scene::overhead_sun(&config, Some(slab));
    let shadow = shadow_map(gpu, &layers);
    let mut whole = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut split = VolumetricFog::new(&gpu.device, &config).unwrap();
    whole.set_shadow_map(&gpu.device, &shadow).unwrap();
    split.set_shadow_map(&gpu.device, &shadow).unwrap();
    for frame in 0..3 {
        let inputs = FrameInputs {
            cascades,
            sun: volfog::uniforms::DirectionalLight {
                direction: Vec3::Y,
                ..Default::default()
            },
            ..FrameInputs::new(
                view(2.0, -0.1 + 0.02 * frame as f32),
                projection(),
                frame as f32,
            )
        };
        whole.prepare(&gpu.queue, &inputs).unwrap();
        split.prepare(&gpu.queue, &inputs).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        whole.encode(&mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);
        for pass in FogPass::ALL {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            split.encode_pass(&mut encoder, pass).unwrap();
            gpu.queue.submit([encoder.finish()]);
        }
        assert_eq!(whole.frame_index(), split.frame_index());
        let a = common::scene::read_volume(gpu, whole.integrated_texture());
        let b = common::scene::read_volume(gpu, split.integrated_texture());
        assert!(a.iter().any(|v| v.w < 0.99), "the fog attenuates");
        assert_eq!(a, b, "frame {frame}: integrated volumes differ");
        let a = common::scene::read_esm(gpu, &whole);
        let b = common::scene::read_esm(gpu, &split);
        assert!(
            a.iter().zip(&b).all(|(a, b)| a.texels == b.texels),
            "frame {frame}: ESM differs"
        );
    }
}
