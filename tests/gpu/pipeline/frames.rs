//! The frame contract: no encoding before `prepare`, `reconfigure` keeping what the
//! user set, apply pipelines tied to their fog, and passes submitted alone matching
//! `encode`.

use crate::common::scene::{overhead_sun, projection, shadow_map, small_config, view};
use crate::common::{self, gpu};
use glam::Vec3;
use volfog::options::Filtering;
use volfog::pipeline::FogPass;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, VolumetricFog};

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
            shadow_filter: volfog::options::ShadowFilter::Esm,
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
