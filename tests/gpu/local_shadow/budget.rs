//! The budget of shadowed lights (those past it light the fog unshadowed, in the order
//! given) and the typed errors of bad shadow maps, cookies and shadowed lights.

use super::*;
use volfog::pipeline::FogError;

/// Three shadowed spot lights above a row of pillars, a budget of two.
#[test]
fn lights_past_the_budget_light_the_fog_unshadowed_in_order() {
    let gpu = gpu();
    // Pillars wider than the blur's footprint (narrower ones it erases).
    let occluders: Vec<Occluder> = (0..4)
        .map(|k| {
            let x = -5.0 + 3.0 * k as f32;
            Occluder::aabb(Vec3::new(x, 0.0, -10.5), Vec3::new(x + 1.5, 3.0, -9.0))
        })
        .collect();
    let local = LocalShadowConfig {
        spot_shadows: 2,
        point_shadows: 0,
        resolution: 64,
        exponent: 80.0,
    };
    let config = config(local, false);
    let map = 128;
    let lights: Vec<FogLight> = [-3.0f32, 0.0, 3.0]
        .iter()
        .map(|&x| {
            FogLight::spot(
                Vec3::new(x, 4.0, -6.0),
                Vec3::new(0.0, -0.5, -1.0).normalize(),
                Vec3::splat(40.0),
                14.0,
                0.4,
                0.6,
            )
        })
        .collect();
    let cameras: Vec<LightCamera> = lights
        .iter()
        .map(|l| LightCamera::spot(l, 0.1).unwrap())
        .collect();
    let spot_maps: Vec<Vec<f32>> = cameras
        .iter()
        .flat_map(|c| render_camera(&occluders, c, map))
        .collect();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_spot_shadow_maps(&gpu.device, &depth_texture(&spot_maps, map))
        .unwrap();
    let view = camera(Vec3::new(0.0, 2.5, 0.0), Vec3::new(0.0, 1.0, -12.0));
    // The same lights in two priority orders: the last of each order goes unshadowed.
    for order in [[0u32, 1, 2], [2, 0, 1]] {
        let shadowed: Vec<ShadowedLight> = order
            .iter()
            .map(|&i| ShadowedLight::new(i, cameras[i as usize]).with_shadow(i))
            .collect();
        let frame = inputs(view, medium(0.05), &lights, &shadowed, &[]);
        let got = run(&mut fog, &frame);
        let stats = fog.local_shadow_stats();
        assert_eq!(
            (stats.spot_shadows, stats.unshadowed, stats.layers),
            (2, 1, 2)
        );
        let (atlas, projections) = cpu_atlas(&config, &lights, &shadowed, &spot_maps, &[], map);
        assert_eq!(projections[2].layer, LOCAL_SHADOW_NONE);
        let want = cpu_volume(&config, &frame, &atlas, &projections, &[]);
        // Against the frame with every light shadowed (a budget of three): the
        // difference is where the unshadowed light shines through the pillars.
        let all = LocalShadowConfig {
            spot_shadows: 3,
            ..local
        };
        let (atlas3, projections3) = cpu_atlas(
            &FogConfig {
                local_shadows: Some(all),
                ..config.clone()
            },
            &lights,
            &shadowed,
            &spot_maps,
            &[],
            map,
        );
        let every = cpu_volume(&config, &frame, &atlas3, &projections3, &[]);
        let worst = worst_relative(&got, &want, 1e-3);
        let brighter = got
            .iter()
            .zip(&every)
            .filter(|(g, e)| g.truncate().max_element() > 1.2 * e.truncate().max_element() + 1e-3)
            .count();
        eprintln!(
            "budget of 2 shadowed spot lights, order {order:?}: light {} unshadowed; inject vs CPU {worst:.2e} relative (bound 4e-3); {brighter} froxels brighter than with all three shadowed",
            order[2]
        );
        assert!(worst <= 4e-3, "{worst}");
        assert!(brighter > 100, "{brighter}");
    }
}

fn depth_array(
    width: u32,
    layers: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu().device.create_texture(&wgpu::TextureDescriptor {
        label: Some("bad shadow maps"),
        size: wgpu::Extent3d {
            width,
            height: width,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn texture_error(result: Result<(), FogError>) -> (&'static str, &'static str) {
    match result {
        Err(FogError::Texture {
            texture, property, ..
        }) => (texture, property),
        other => panic!("expected a texture error, got {other:?}"),
    }
}

fn field(result: Result<(), FogError>) -> &'static str {
    match result {
        Err(FogError::Invalid(e)) => e.field,
        other => panic!("expected an invalid value, got {other:?}"),
    }
}

#[test]
fn bad_shadow_maps_cookies_and_shadowed_lights_are_typed_errors() {
    use wgpu::TextureFormat::{Depth32Float, Rgba8Unorm};
    use wgpu::TextureUsages as U;
    let gpu = gpu();
    let device = &gpu.device;
    let local = LocalShadowConfig {
        spot_shadows: 2,
        point_shadows: 1,
        resolution: 32,
        exponent: 80.0,
    };
    let config = config(local, false);
    let mut fog = VolumetricFog::new(device, &config).unwrap();
    let usable = U::TEXTURE_BINDING | U::RENDER_ATTACHMENT;
    let spot = "the spot shadow maps";
    let point = "the point shadow maps";
    assert_eq!(
        texture_error(fog.set_spot_shadow_maps(device, &depth_array(48, 2, Depth32Float, usable))),
        (spot, "size")
    );
    assert_eq!(
        texture_error(
            fog.set_spot_shadow_maps(device, &depth_array(32 * 32, 1, Depth32Float, usable))
        ),
        (spot, "size")
    );
    assert_eq!(
        texture_error(
            fog.set_spot_shadow_maps(device, &depth_array(64, 2, Rgba8Unorm, U::TEXTURE_BINDING))
        ),
        (spot, "format")
    );
    assert_eq!(
        texture_error(fog.set_spot_shadow_maps(
            device,
            &depth_array(64, 2, Depth32Float, U::RENDER_ATTACHMENT)
        )),
        (spot, "usage")
    );
    assert_eq!(
        texture_error(fog.set_point_shadow_maps(device, &depth_array(64, 5, Depth32Float, usable))),
        (point, "layer count")
    );
    assert_eq!(
        texture_error(fog.set_cookies(device, &depth_array(64, 1, Depth32Float, usable))),
        ("the cookies", "format")
    );
    fog.set_spot_shadow_maps(device, &depth_array(64, 2, Depth32Float, usable))
        .unwrap();
    fog.set_point_shadow_maps(device, &depth_array(64, 6, Depth32Float, usable))
        .unwrap();

    let lights = [
        FogLight::spot(
            Vec3::new(0.0, 3.0, -5.0),
            Vec3::NEG_Y,
            Vec3::splat(10.0),
            8.0,
            0.3,
            0.5,
        ),
        FogLight::point(Vec3::new(2.0, 2.0, -6.0), Vec3::splat(10.0), 8.0),
    ];
    let spot_camera = LightCamera::spot(&lights[0], 0.1).unwrap();
    let point_camera = LightCamera::point(&lights[1], 0.1).unwrap();
    let view = camera(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 1.0, -8.0));
    let mut prepare = |shadowed: &[ShadowedLight]| {
        fog.prepare(
            &gpu.queue,
            &inputs(view, medium(0.05), &lights, shadowed, &[]),
        )
    };
    let ok = [
        ShadowedLight::new(0, spot_camera).with_shadow(1),
        ShadowedLight::new(1, point_camera).with_shadow(0),
    ];
    prepare(&ok).unwrap();
    assert_eq!(
        field(prepare(&[ShadowedLight::new(2, spot_camera)])),
        "ShadowedLight.light"
    );
    assert_eq!(field(prepare(&[ok[0], ok[0]])), "ShadowedLight.light");
    assert_eq!(
        field(prepare(
            &[ShadowedLight::new(0, spot_camera).with_shadow(2)]
        )),
        "ShadowedLight.shadow"
    );
    assert_eq!(
        field(prepare(&[
            ShadowedLight::new(1, point_camera).with_shadow(1)
        ])),
        "ShadowedLight.shadow"
    );
    assert_eq!(
        field(prepare(
            &[ShadowedLight::new(0, spot_camera).with_cookie(0)]
        )),
        "ShadowedLight.cookie"
    );
    assert_eq!(
        field(prepare(&[
            ShadowedLight::new(1, point_camera).with_cookie(0)
        ])),
        "ShadowedLight.cookie"
    );
    assert_eq!(
        field(prepare(&[ShadowedLight {
            bias: -1.0,
            ..ok[0]
        }])),
        "ShadowedLight.bias"
    );
    let skewed = LightCamera::Spot {
        view_from_world: Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0)),
        clip_from_view: spot_camera.clip_from_view(),
    };
    assert_eq!(
        field(prepare(&[ShadowedLight::new(0, skewed)])),
        "LightCamera::Spot.view_from_world"
    );
    let flat = LightCamera::Spot {
        view_from_world: Mat4::IDENTITY,
        clip_from_view: glam::camera::rh::proj::directx::orthographic(
            -1.0, 1.0, -1.0, 1.0, 0.1, 5.0,
        ),
    };
    assert_eq!(
        field(prepare(&[ShadowedLight::new(0, flat)])),
        "LightCamera::Spot.clip_from_view"
    );
    // A rejected frame changes nothing: the previous one is still prepared.
    assert_eq!(fog.local_shadow_stats().layers, 7);

    // Without local shadows in the configuration.
    let mut plain = VolumetricFog::new(
        device,
        &FogConfig {
            local_shadows: None,
            ..config.clone()
        },
    )
    .unwrap();
    assert_eq!(
        field(plain.set_spot_shadow_maps(device, &depth_array(64, 1, Depth32Float, usable))),
        "FogConfig.local_shadows"
    );
    let frame = inputs(view, medium(0.05), &lights, &ok, &[]);
    assert_eq!(
        field(plain.prepare(&gpu.queue, &frame)),
        "FrameInputs.shadowed_lights"
    );
    // Bad budgets and exponents.
    let bad = |l: LocalShadowConfig| match VolumetricFog::new(
        device,
        &FogConfig {
            local_shadows: Some(l),
            ..config.clone()
        },
    ) {
        Err(FogError::Invalid(e)) => e.field,
        other => panic!("{other:?}"),
    };
    assert_eq!(
        bad(LocalShadowConfig {
            spot_shadows: 17,
            ..local
        }),
        "LocalShadowConfig.spot_shadows"
    );
    assert_eq!(
        bad(LocalShadowConfig {
            point_shadows: 9,
            ..local
        }),
        "LocalShadowConfig.point_shadows"
    );
    assert_eq!(
        bad(LocalShadowConfig {
            resolution: 4,
            ..local
        }),
        "LocalShadowConfig.resolution"
    );
    assert_eq!(
        bad(LocalShadowConfig {
            exponent: 100.0,
            ..local
        }),
        "LocalShadowConfig.exponent"
    );
    assert_eq!(
        bad(LocalShadowConfig {
            exponent: f32::NAN,
            ..local
        }),
        "LocalShadowConfig.exponent"
    );
}
