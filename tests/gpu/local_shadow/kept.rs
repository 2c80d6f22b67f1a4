//! Lights whose shadow maps are unchanged keep their filtering in the atlas
//! (`ShadowedLight::map_unchanged`): a frame of only such lights fills no layer and
//! draws the same fog bit for bit, a light whose map changed is filtered again into a
//! free layer while the others keep theirs (also when the order of the lights
//! changes), and the fog equals that of a fog that filters every map afresh.

use super::*;
use volfog_testkit::selfcheck::write_f32_layer;

/// An R32Float depth array the test can write layer by layer.
fn writable_maps(layers: &[Vec<f32>], size: u32) -> wgpu::Texture {
    let gpu = gpu();
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("writable shadow maps"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers.len() as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (layer, texels) in layers.iter().enumerate() {
        write_f32_layer(gpu, &texture, layer as u32, texels);
    }
    texture
}

fn stats(fog: &VolumetricFog) -> (u32, u32) {
    let s = fog.local_shadow_stats();
    (s.layers, s.kept)
}

fn same_bits(a: &[Vec4], b: &[Vec4]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits))
}

#[test]
fn unchanged_maps_keep_their_atlas_layers_and_changed_maps_are_filtered_again() {
    let gpu = gpu();
    let local = LocalShadowConfig {
        spot_shadows: 2,
        point_shadows: 1,
        resolution: 32,
        exponent: 80.0,
    };
    let config = config(local, false);
    let map = 64;
    // Two spot lights and the point light of the atlas test's scene.
    let [a, b, _, c] = pillar_lights();
    let lights = [a, b, c];
    let cameras = [
        LightCamera::spot(&lights[0], 0.2).unwrap(),
        LightCamera::spot(&lights[1], 0.2).unwrap(),
        LightCamera::point(&lights[2], 0.1).unwrap(),
    ];
    let before = pillars();
    let mut spot_maps: Vec<Vec<f32>> = cameras[..2]
        .iter()
        .flat_map(|c| render_camera(&before, c, map))
        .collect();
    let point_maps = render_camera(&before, &cameras[2], map);
    let spots = writable_maps(&spot_maps, map);
    let points = writable_maps(&point_maps, map);
    let new_fog = || {
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_spot_shadow_maps(&gpu.device, &spots).unwrap();
        fog.set_point_shadow_maps(&gpu.device, &points).unwrap();
        fog
    };
    let shadowed = |i: usize| ShadowedLight::new(i as u32, cameras[i]).with_shadow(i as u32 % 2);
    let view = camera(Vec3::new(0.0, 2.0, 1.0), Vec3::new(0.0, 1.5, -10.0));
    let mut fog = new_fog();

    // Frame 1: every map filtered (2 spot layers, 6 cube faces).
    let first = [shadowed(0), shadowed(1), shadowed(2)];
    let got1 = run(&mut fog, &inputs(view, medium(0.06), &lights, &first, &[]));
    assert_eq!(stats(&fog), (8, 0));
    let atlas1 = read_atlas(&fog);

    // Frame 2: every map unchanged: nothing filtered, the same atlas and fog.
    let kept: Vec<ShadowedLight> = first.iter().map(|s| s.with_unchanged_map()).collect();
    let got2 = run(&mut fog, &inputs(view, medium(0.06), &lights, &kept, &[]));
    assert_eq!(stats(&fog), (0, 8));
    assert!(
        read_atlas(&fog)
            .iter()
            .zip(&atlas1)
            .all(|(a, b)| a.texels == b.texels)
    );
    assert!(same_bits(&got2, &got1));

    // Frame 3: a slab under light 1 now shades part of its cone, and its map is
    // filtered again into its layer 1 (blurred as a run of layers that starts past 0);
    // the cube and light 0 keep their layers although the order changed.
    let mut after = pillars();
    after.push(Occluder::aabb(
        Vec3::new(1.0, 3.4, -8.0),
        Vec3::new(4.5, 3.6, -5.0),
    ));
    spot_maps[1] = render_camera(&after, &cameras[1], map).remove(0);
    write_f32_layer(gpu, &spots, 1, &spot_maps[1]);
    let third = [
        shadowed(2).with_unchanged_map(),
        shadowed(0).with_unchanged_map(),
        shadowed(1),
    ];
    let frame3 = inputs(view, medium(0.06), &lights, &third, &[]);
    let got3 = run(&mut fog, &frame3);
    assert_eq!(stats(&fog), (1, 7));

    // A fog that filters every map of frame 3 afresh draws the same fog bit for bit
    // (its layers lie elsewhere: from 0 in the frame's order).
    let mut fresh = new_fog();
    let got_fresh = run(
        &mut fresh,
        &inputs(view, medium(0.06), &lights, &first, &[]),
    );
    assert_eq!(stats(&fresh), (8, 0));
    let fresh_third = [shadowed(2), shadowed(0), shadowed(1)];
    let got_fresh3 = run(
        &mut fresh,
        &inputs(view, medium(0.06), &lights, &fresh_third, &[]),
    );
    assert_eq!(stats(&fresh), (8, 0));
    assert!(same_bits(&got3, &got_fresh3));
    // (The fresh fog's first frame saw the new map of light 1 too.)
    assert!(!same_bits(&got_fresh, &got1));

    // And the CPU mirror of frame 3, its atlas filtered from the new maps.
    let (atlas, projections) = cpu_atlas(&config, &lights, &third, &spot_maps, &point_maps, map);
    let want = cpu_volume(&config, &frame3, &atlas, &projections, &[]);
    let worst = worst_relative(&got3, &want, 1e-3);
    // Where the slab shades light 1, frame 3 differs from frame 1.
    let moved = got3
        .iter()
        .zip(&got1)
        .filter(|(a, b)| {
            (a.truncate() - b.truncate()).abs().max_element()
                > 0.05 * b.truncate().max_element() + 1e-3
        })
        .count();
    eprintln!(
        "kept atlas layers: frame 3 (1 layer filled, 7 kept) vs CPU {worst:.2e} relative (bound 4e-3); {moved} froxels changed by the slab"
    );
    assert!(worst <= 4e-3, "{worst}");
    assert!(moved > 100, "{moved}");

    // New depth maps forget every filtering: the unchanged lights are filtered.
    fog.set_spot_shadow_maps(&gpu.device, &spots).unwrap();
    run(&mut fog, &inputs(view, medium(0.06), &lights, &kept, &[]));
    assert_eq!(stats(&fog), (8, 0));
}
