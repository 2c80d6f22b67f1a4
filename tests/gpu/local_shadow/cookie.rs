//! A spot light's cookie: a striped cookie's stripes appear in the froxels where its
//! camera projects them, in their colours.

use super::*;
use wgpu::util::DeviceExt;

const SIZE: u32 = 64;
const STRIPES: u32 = 8;
/// The stripes' colours: even stripes white, odd ones blue-green (8-bit values).
const EVEN: [u8; 4] = [255, 255, 255, 255];
const ODD: [u8; 4] = [0, 128, 255, 255];

/// Cookie layer 1: vertical stripes along u (layer 0 is plain white).
fn cookie_texels() -> Vec<u8> {
    let mut texels = vec![255u8; (SIZE * SIZE * 4) as usize];
    for _row in 0..SIZE {
        for x in 0..SIZE {
            texels.extend(if (x * STRIPES / SIZE).is_multiple_of(2) {
                EVEN
            } else {
                ODD
            });
        }
    }
    texels
}

/// Under both shadow filters (their inject variants bind different shadow textures
/// beside the same cookies).
#[test]
fn a_striped_cookie_lights_the_fog_in_stripes() {
    let esm = config(LocalShadowConfig::default(), false);
    let compare = FogConfig {
        jitter: false,
        ..compare_config(LocalShadowConfig::default(), 1)
    };
    for config in [compare, esm] {
        striped_cookie(&config);
    }
}

fn striped_cookie(config: &FogConfig) {
    let gpu = gpu();
    let texels = cookie_texels();
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("striped cookie"),
            size: wgpu::Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &texels,
    );
    let cookies: Vec<ColorLayer> = texels
        .chunks_exact((SIZE * SIZE * 4) as usize)
        .map(|layer| ColorLayer {
            width: SIZE,
            height: SIZE,
            texels: layer
                .chunks_exact(4)
                .map(|t| Vec4::new(t[0] as f32, t[1] as f32, t[2] as f32, t[3] as f32) / 255.0)
                .collect(),
        })
        .collect();
    let spot = FogLight::spot(
        Vec3::new(0.0, 4.0, -4.0),
        Vec3::new(0.0, -0.3, -1.0).normalize(),
        Vec3::splat(60.0),
        16.0,
        0.45,
        0.55,
    );
    let cam = LightCamera::spot(&spot, 0.1).unwrap();
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    fog.set_cookies(&gpu.device, &texture).unwrap();
    let lights = [spot];
    let shadowed = [ShadowedLight::new(0, cam).with_cookie(1)];
    let frame = inputs(
        camera(Vec3::new(3.0, 3.0, 0.0), Vec3::new(0.0, 2.0, -12.0)),
        medium(0.05),
        &lights,
        &shadowed,
        &[],
    );
    let got = run(&mut fog, &frame);
    let (atlas, projections) = cpu_atlas(config, &lights, &shadowed, &[], &[], 1);
    let want = cpu_volume(config, &frame, &atlas, &projections, &cookies);
    let plain: Vec<LightProjection> = projections
        .iter()
        .map(|p| LightProjection {
            cookie: LOCAL_SHADOW_NONE,
            ..*p
        })
        .collect();
    let uncookied = cpu_volume(config, &frame, &atlas, &plain, &[]);
    let mirror = worst_relative(&got, &want, 1e-2);

    let p = projections[0];
    let (mut counts, mut worst) = ([0usize; 2], 0.0f32);
    for ((g, u), world) in got
        .iter()
        .zip(&uncookied)
        .zip(froxel_positions(config, &frame))
    {
        let light = u.truncate();
        if light.max_element() < 1e-3 {
            continue;
        }
        let s = volfog::cpu::local_shadow::local_shadow_spot(p.light_from_world, world);
        // Stripe centres only: 1.5 texels from either edge of the stripe.
        let texel = s.x * SIZE as f32;
        let width = (SIZE / STRIPES) as f32;
        let within = texel - (texel / width).floor() * width;
        if !(1.5..=width - 1.5).contains(&within) || !(0.0..=1.0).contains(&s.y) {
            continue;
        }
        let stripe = (texel / width) as usize % 2;
        let colour = if stripe == 0 { EVEN } else { ODD };
        let expected =
            Vec3::from_array([colour[0], colour[1], colour[2]].map(|c| c as f32 / 255.0));
        let ratio = g.truncate() / light;
        worst = worst.max((ratio - expected).abs().max_element());
        counts[stripe] += 1;
    }
    eprintln!(
        "striped cookie, {:?}: inject vs CPU {mirror:.2e} (relative, bound 1e-2); {} froxels in white \
         and {} in blue-green stripe centres, their light / the uncookied light within {worst:.2e} \
         of the stripe's colour (bound 1e-2)",
        config.shadow_filter, counts[0], counts[1]
    );
    assert!(mirror <= 1e-2, "{mirror}");
    assert!(counts[0] > 200 && counts[1] > 200, "{counts:?}");
    assert!(worst <= 1e-2, "{worst}");
}
