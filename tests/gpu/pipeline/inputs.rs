//! The textures a user sets, checked: shadow maps against the cascades, scene depths
//! for culling against what the pass reads.

use crate::common::gpu;
use crate::common::scene::{overhead_sun, projection, shadow_map, small_config, view};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, VolumetricFog};

/// Shadow maps are checked against the configuration (size, layers, format, usage),
/// and frames with cascades need one. The compare filter (the default) reads any
/// square map; the ESM needs 4x its resolution.
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
                height: size / 2 * 2,
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
        (texture(side + 1, 2, depth, binding), "size"),
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
    // Any square size suits the compare filter; the ESM wants 4x its resolution.
    fog.set_shadow_map(&gpu.device, &texture(side / 2, 2, depth, binding))
        .unwrap();
    let mut esm = VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            shadow_filter: ShadowFilter::Esm,
            ..config.clone()
        },
    )
    .unwrap();
    match esm.set_shadow_map(&gpu.device, &texture(side / 2, 2, depth, binding)) {
        Err(FogError::Texture { property: p, .. }) => assert_eq!(p, "size"),
        other => panic!("ESM size: expected a texture error, got {other:?}"),
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
