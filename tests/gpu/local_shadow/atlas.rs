//! The local-light atlas and the inject pass against the CPU mirror: spot lights with
//! standard, reversed and infinite reversed depth, a point light's cube, shadow maps
//! 1, 2, 3 and 4 times the atlas resolution (3: blocks the gathers overhang), linear
//! and log-space ESM; and the compare filter's taps against the same maps.

use super::*;

/// The scene's shadowed lights: three spot lights whose cameras have standard,
/// reversed and infinite reversed depth (Bevy's), and a point light, with their depth
/// maps of `map` texels ray traced from the pillars.
struct Scene {
    lights: [FogLight; 4],
    shadowed: Vec<ShadowedLight>,
    spot_maps: Vec<Vec<f32>>,
    point_maps: Vec<Vec<f32>>,
}

fn scene(map: u32) -> Scene {
    use glam::camera::rh::proj::directx;
    let occluders = pillars();
    let lights = pillar_lights();
    // The three depth conventions of the spot cameras, all with the same view.
    let spot = |i: usize, kind: u32| {
        let LightCamera::Spot {
            view_from_world, ..
        } = LightCamera::spot(&lights[i], 0.2).unwrap()
        else {
            unreachable!()
        };
        let fov = 2.0 * lights[i].cos_outer.acos() * 1.05;
        let clip_from_view = match kind {
            0 => directx::perspective(fov, 1.0, 0.2, lights[i].range),
            1 => directx::perspective(fov, 1.0, lights[i].range, 0.2),
            _ => directx::perspective_infinite_reverse(fov, 1.0, 0.2),
        };
        LightCamera::Spot {
            view_from_world,
            clip_from_view,
        }
    };
    let cameras = [
        spot(0, 0),
        spot(1, 1),
        spot(2, 2),
        LightCamera::point(&lights[3], 0.1).unwrap(),
    ];
    let shadowed: Vec<ShadowedLight> = cameras
        .iter()
        .enumerate()
        .map(|(i, c)| {
            ShadowedLight::new(i as u32, *c).with_shadow(if i == 3 { 0 } else { i as u32 })
        })
        .collect();
    let spot_maps: Vec<Vec<f32>> = cameras[..3]
        .iter()
        .flat_map(|c| render_camera(&occluders, c, map))
        .collect();
    let point_maps = render_camera(&occluders, &cameras[3], map);
    Scene {
        lights,
        shadowed,
        spot_maps,
        point_maps,
    }
}

/// The scene's frame: the camera among the pillars.
fn frame<'a>(lights: &'a [FogLight], shadowed: &'a [ShadowedLight]) -> FrameInputs<'a> {
    inputs(
        camera(Vec3::new(0.0, 2.0, 1.0), Vec3::new(0.0, 1.5, -10.0)),
        medium(0.06),
        lights,
        shadowed,
        &[],
    )
}

#[test]
fn atlas_and_inject_match_the_cpu_mirror() {
    let gpu = gpu();
    for (log_space, factor, exponent) in [
        (false, 2, 80.0),
        (true, 1, 300.0),
        (false, 4, 40.0),
        (true, 3, 120.0),
    ] {
        let local = LocalShadowConfig {
            spot_shadows: 3,
            point_shadows: 1,
            resolution: 32,
            exponent,
        };
        let config = config(local, log_space);
        let map = local.resolution * factor;
        let Scene {
            lights,
            shadowed,
            spot_maps,
            point_maps,
        } = scene(map);

        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_spot_shadow_maps(&gpu.device, &depth_texture(&spot_maps, map))
            .unwrap();
        fog.set_point_shadow_maps(&gpu.device, &depth_texture(&point_maps, map))
            .unwrap();
        let frame = frame(&lights, &shadowed);
        let got = run(&mut fog, &frame);
        let stats = fog.local_shadow_stats();
        assert_eq!(
            (
                stats.spot_shadows,
                stats.point_shadows,
                stats.unshadowed,
                stats.layers
            ),
            (3, 1, 0, 9)
        );

        let (atlas, projections) =
            cpu_atlas(&config, &lights, &shadowed, &spot_maps, &point_maps, map);
        let gpu_atlas = read_atlas(&fog);
        let mut atlas_error = 0.0f32;
        for (layer, (g, w)) in gpu_atlas.iter().zip(&atlas.atlas).enumerate() {
            for (a, b) in g.texels.iter().zip(&w.texels) {
                let e = if log_space {
                    (a - b).abs()
                } else {
                    (a - b).abs() / b.abs().max(1e-30)
                };
                assert!(e.is_finite(), "layer {layer}");
                atlas_error = atlas_error.max(e);
            }
        }
        let want = cpu_volume(&config, &frame, &atlas, &projections, &[]);
        let worst = worst_relative(&got, &want, 1e-3);
        // How much the shadows take from the lights: the same frame unshadowed.
        let open = cpu_volume(&config, &frame, &atlas, &unshadowed(&projections), &[]);
        let shadowed_froxels = got
            .iter()
            .zip(&open)
            .filter(|(g, o)| g.truncate().max_element() < 0.5 * o.truncate().max_element())
            .count();
        eprintln!(
            "local shadows (log space {log_space}, maps {factor}x the atlas, c = {exponent}): atlas vs CPU {atlas_error:.2e} ({}; bound 1e-4), inject vs CPU {worst:.2e} relative (bound 4e-3); {shadowed_froxels} froxels lose more than half their light to the shadows",
            if log_space {
                "absolute, log space"
            } else {
                "relative"
            },
        );
        assert!(atlas_error <= 1e-4, "{atlas_error}");
        assert!(worst <= 4e-3, "{worst}");
        assert!(shadowed_froxels > 1000, "{shadowed_froxels}");
    }
}

/// The compare filter against the CPU mirror on the same lights and maps: the three
/// spot cameras' depth conventions and the point light's cube faces, maps of sizes the
/// atlas would not take, one and two taps (four and eight per froxel without a
/// temporal blend) at jittered positions; no atlas is made.
#[test]
fn compare_filter_matches_the_cpu_mirror() {
    let gpu = gpu();
    for (taps, map) in [(1, 96), (2, 50)] {
        let local = LocalShadowConfig {
            spot_shadows: 3,
            point_shadows: 1,
            ..LocalShadowConfig::default()
        };
        let config = compare_config(local, taps);
        let Scene {
            lights,
            shadowed,
            spot_maps,
            point_maps,
        } = scene(map);
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_spot_shadow_maps(&gpu.device, &depth_texture(&spot_maps, map))
            .unwrap();
        fog.set_point_shadow_maps(&gpu.device, &depth_texture(&point_maps, map))
            .unwrap();
        let frame = frame(&lights, &shadowed);
        let got = run(&mut fog, &frame);
        let stats = fog.local_shadow_stats();
        assert_eq!(
            (stats.spot_shadows, stats.point_shadows, stats.layers),
            (3, 1, 0)
        );
        assert!(fog.local_shadow_atlas().is_none());
        let (maps, projections) =
            cpu_atlas(&config, &lights, &shadowed, &spot_maps, &point_maps, map);
        assert_eq!(
            projections.iter().map(|p| p.layer).collect::<Vec<_>>(),
            [0, 1, 2, 0]
        );
        let want = cpu_volume(&config, &frame, &maps, &projections, &[]);
        let worst = worst_relative(&got, &want, 1e-3);
        let open = cpu_volume(&config, &frame, &maps, &unshadowed(&projections), &[]);
        let shadowed_froxels = got
            .iter()
            .zip(&open)
            .filter(|(g, o)| g.truncate().max_element() < 0.5 * o.truncate().max_element())
            .count();
        eprintln!(
            "compare filter ({taps} taps, {}-texel maps): inject vs CPU {worst:.2e} relative (bound 4e-3); {shadowed_froxels} froxels lose more than half their light to the shadows",
            map
        );
        assert!(worst <= 4e-3, "{worst}");
        assert!(shadowed_froxels > 1000, "{shadowed_froxels}");
    }
}
