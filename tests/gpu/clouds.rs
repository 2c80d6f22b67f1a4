//! Clouds (`volfog::clouds`, Wenzel 2007 "Clouds", "Cloud Shadows", "Distance
//! Clouds") on the GPU: against the CPU mirror on a random map; distance clouds of a
//! uniform layer against the slant-path closed form; self-shadowing that darkens the
//! side away from the sun; the soft clip at geometry against the soft-particle
//! formula; the cloud-shadow pass on a rendered ground against the CPU; the clouds'
//! shadow in the froxel fog against the inject mirror; finiteness.

use crate::common;

use common::{Rng, compose, gpu};
use glam::{Vec2, Vec3, Vec4};
use volfog::cpu::clouds::{CloudMap, cloud_layer, cloud_shadow, distance_clouds};
use volfog::cpu::soft_particles::soft_particle_box_fade;
use volfog::uniforms::CloudLayer;

const KERNEL: &str = r#"
#import volfog::types::CloudLayer
#import volfog::clouds::{cloud_shadow, distance_clouds, cloud_layer}

struct Case { layer: CloudLayer, eye: vec4<f32>, dir: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;
@group(0) @binding(2) var map: texture_2d<f32>;
@group(0) @binding(3) var map_sampler: sampler;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    // eye.w: the scene's distance along the ray.
    output[i * 3u] = vec4<f32>(cloud_shadow(map, map_sampler, c.layer, c.eye.xyz + c.dir.xyz * c.eye.w), 0.0, 0.0, 0.0);
    output[i * 3u + 1u] = distance_clouds(map, map_sampler, c.layer, c.eye.xyz, c.dir.xyz, c.eye.w);
    output[i * 3u + 2u] = cloud_layer(map, map_sampler, c.layer, c.eye.xyz, c.dir.xyz, c.eye.w);
}
"#;

#[derive(Clone, Copy, Debug)]
struct Case {
    layer: CloudLayer,
    eye: Vec3,
    dir: Vec3,
    distance: f32,
}

/// A map texture (r16float) holding `map`'s texels (rounded to f16 in `map` too).
fn map_texture(map: &CloudMap) -> wgpu::Texture {
    let gpu = gpu();
    volfog::pipeline::clouds::cloud_map_texture(
        &gpu.device,
        &gpu.queue,
        (map.width, map.height),
        &map.texels,
    )
    .unwrap()
}

fn random_map(rng: &mut Rng, size: u32) -> CloudMap {
    let texels = (0..size * size)
        .map(|_| half::f16::from_f32(rng.f()).to_f32())
        .collect();
    CloudMap {
        width: size,
        height: size,
        texels,
    }
}

fn run(map: &CloudMap, cases: &[Case]) -> Vec<[Vec4; 3]> {
    let gpu = gpu();
    let texture = map_texture(map);
    let sampler = volfog::pipeline::clouds::cloud_map_sampler(&gpu.device);
    let mut input: Vec<u8> = Vec::new();
    for c in cases {
        let bytes = c.layer.to_bytes();
        assert_eq!(bytes.len(), 80, "CloudLayer is 80 bytes");
        input.extend_from_slice(&bytes);
        input.extend_from_slice(bytemuck::cast_slice(&c.eye.extend(c.distance).to_array()));
        input.extend_from_slice(bytemuck::cast_slice(&c.dir.extend(0.0).to_array()));
    }
    let module = gpu.shader_from_naga("clouds", compose(KERNEL, &[]));
    let out = gpu
        .run_kernel_with(
            &module,
            "main",
            &input,
            (cases.len() * 48) as u64,
            cases.len() as u32,
            &[
                wgpu::BindingResource::TextureView(&texture.create_view(&Default::default())),
                wgpu::BindingResource::Sampler(&sampler),
            ],
        )
        .unwrap();
    let v: &[[f32; 4]] = bytemuck::cast_slice(&out);
    v.chunks_exact(3)
        .map(|c| {
            [
                Vec4::from_array(c[0]),
                Vec4::from_array(c[1]),
                Vec4::from_array(c[2]),
            ]
        })
        .collect()
}

fn layer(rng: &mut Rng) -> CloudLayer {
    CloudLayer {
        view_samples: 12,
        sun_samples: 4,
        rim: 2.0,
        ..CloudLayer::new(
            rng.range(300.0, 2000.0),
            rng.range(50.0, 600.0),
            rng.log(1e-4, 0.05),
            rng.range(500.0, 5000.0),
        )
        .unwrap()
        .with_sun(
            Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(0.05, 1.0),
                rng.range(-1.0, 1.0),
            )
            .normalize(),
            Vec3::new(
                rng.range(1.0, 8.0),
                rng.range(1.0, 8.0),
                rng.range(1.0, 8.0),
            ),
            Vec3::new(rng.f(), rng.f(), rng.f()),
            rng.range(-0.5, 0.9),
        )
        .unwrap()
        .with_wind(
            Vec2::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0)),
            rng.range(0.0, 100.0),
        )
        .unwrap()
    }
    .validated()
    .unwrap()
}

/// GPU against the CPU mirror on a random 32 x 32 map (relative, with a floor of 0.05
/// under small values).
#[test]
fn clouds_match_cpu() {
    let mut rng = Rng(808);
    let map = random_map(&mut rng, 32);
    let cases: Vec<Case> = (0..300)
        .map(|_| {
            let layer = layer(&mut rng);
            let eye = Vec3::new(
                rng.range(-500.0, 500.0),
                rng.range(0.0, 2500.0),
                rng.range(-500.0, 500.0),
            );
            let dir = rng.unit();
            Case {
                layer,
                eye,
                dir,
                distance: rng.log(10.0, 2e5),
            }
        })
        .collect();
    let got = run(&map, &cases);
    let mut worst = [0.0f32; 3];
    for (i, (c, g)) in cases.iter().zip(&got).enumerate() {
        let want = [
            Vec4::new(
                cloud_shadow(&map, &c.layer, c.eye + c.dir * c.distance),
                0.0,
                0.0,
                0.0,
            ),
            distance_clouds(&map, &c.layer, c.eye, c.dir, c.distance),
            cloud_layer(&map, &c.layer, c.eye, c.dir, c.distance, map.width),
        ];
        for k in 0..3 {
            assert!(g[k].is_finite(), "case {i}: {:?}", g[k]);
            let e = ((g[k] - want[k]).abs() / want[k].abs().max(Vec4::splat(0.05))).max_element();
            worst[k] = worst[k].max(e);
            assert!(
                e <= 1e-3,
                "case {i} output {k}: gpu {} cpu {} for {c:?}",
                g[k],
                want[k]
            );
        }
    }
    eprintln!(
        "clouds, 300 rays on a random map: gpu vs cpu worst rel shadow {:.1e}, distance clouds \
         {:.1e}, cloud layer {:.1e} (bound 1e-3)",
        worst[0], worst[1], worst[2]
    );
}

/// A uniform layer: the distance clouds' transmittance is exp(-sigma thickness / |dir.y|)
/// for a ray crossing the whole slab, whatever the sample counts.
#[test]
fn uniform_distance_clouds_match_the_slant_path() {
    let map = CloudMap::uniform(1.0);
    let base = CloudLayer::new(1000.0, 300.0, 0.004, 2000.0).unwrap();
    let cases: Vec<Case> = [90.0f32, 60.0, 30.0, 10.0, 3.0]
        .iter()
        .map(|e| {
            let e = e.to_radians();
            Case {
                layer: base,
                eye: Vec3::new(0.0, 2.0, 0.0),
                dir: Vec3::new(e.cos(), e.sin(), 0.0),
                distance: 1e9,
            }
        })
        .collect();
    let got = run(&map, &cases);
    let mut worst = 0.0f32;
    for (c, g) in cases.iter().zip(&got) {
        let want = (-c.layer.extinction * c.layer.thickness / c.dir.y).exp();
        let e = (g[1].w - want).abs() / want;
        worst = worst.max(e);
        assert!(
            e <= 1e-5,
            "elevation {}: {} vs {want}",
            c.dir.y.asin().to_degrees(),
            g[1].w
        );
    }
    eprintln!(
        "uniform layer, slant paths from 90 to 3 degrees: transmittance vs closed form worst rel {worst:.1e} (bound 1e-5)"
    );
}

/// A round cloud lit from the side: seen from below, its edge towards the sun
/// scatters more sunlight than the edge away from it, where the sun's light has
/// crossed the cloud.
#[test]
fn self_shadowing_darkens_the_far_side() {
    let n = 64u32;
    let texels = (0..n * n)
        .map(|i| {
            let (x, y) = (
                (i % n) as f32 + 0.5 - n as f32 / 2.0,
                (i / n) as f32 + 0.5 - n as f32 / 2.0,
            );
            half::f16::from_f32((-(x * x + y * y) / (2.0 * 8.0 * 8.0)).exp()).to_f32()
        })
        .collect();
    let map = CloudMap {
        width: n,
        height: n,
        texels,
    };
    // Map 6.4 km wide, the cloud around the origin; the sun low in the +x direction.
    let layer = CloudLayer {
        view_samples: 16,
        sun_samples: 16,
        ..CloudLayer::new(1000.0, 400.0, 0.01, 6400.0)
            .unwrap()
            .with_sun(
                Vec3::new(1.0, 0.35, 0.0).normalize(),
                Vec3::splat(5.0),
                Vec3::ZERO,
                0.0,
            )
            .unwrap()
    };
    // Straight up through points 800 m either side of the centre (equal density there);
    // the map's centre is world (3200, 3200).
    let cases: Vec<Case> = [800.0f32, -800.0]
        .iter()
        .map(|x| Case {
            layer,
            eye: Vec3::new(3200.0 + x, 0.0, 3200.0),
            dir: Vec3::Y,
            distance: 1e9,
        })
        .collect();
    let got = run(&map, &cases);
    let (sun_side, far_side) = (got[0][1], got[1][1]);
    let ratio = sun_side.x / far_side.x;
    eprintln!(
        "self-shadowing: in-scatter towards the sun's side {:.4}, far side {:.4} (ratio {ratio:.2}); \
         transmittance {:.3} and {:.3}",
        sun_side.x, far_side.x, sun_side.w, far_side.w
    );
    assert!(
        (sun_side.w - far_side.w).abs() < 1e-3,
        "the same cloud either side"
    );
    assert!(ratio > 1.5, "{ratio}");
    let cpu = distance_clouds(&map, &layer, cases[0].eye, Vec3::Y, 1e9).x
        / distance_clouds(&map, &layer, cases[1].eye, Vec3::Y, 1e9).x;
    assert!((cpu - ratio).abs() <= 0.02 * cpu, "cpu ratio {cpu}");
}

/// Clouds around a mountain: the lit layer fades where the scene stands inside the
/// slab, by the share of the slab's ray segment in front of the scene (the
/// soft-particle formula), for a uniform map exactly.
#[test]
fn cloud_layer_soft_clips_like_a_soft_particle() {
    let map = CloudMap::uniform(0.7);
    let layer = CloudLayer::new(500.0, 200.0, 0.01, 3000.0)
        .unwrap()
        .with_sun(
            Vec3::new(0.3, 0.8, 0.2).normalize(),
            Vec3::splat(3.0),
            Vec3::splat(0.3),
            0.5,
        )
        .unwrap();
    let dir = Vec3::new(0.6, 0.8, 0.0);
    let eye = Vec3::ZERO;
    // The slab spans t in [625, 875] along this ray; scene points before, inside, after.
    let distances = [100.0f32, 625.0, 650.0, 700.0, 750.0, 800.0, 875.0, 2000.0];
    let mut cases: Vec<Case> = distances
        .iter()
        .map(|d| Case {
            layer,
            eye,
            dir,
            distance: *d,
        })
        .collect();
    cases.push(Case {
        layer,
        eye,
        dir,
        distance: 1e9,
    });
    let got = run(&map, &cases);
    let open = 1.0 - got[distances.len()][2].w;
    let mut worst = 0.0f32;
    for (d, g) in distances.iter().zip(&got) {
        let fade = soft_particle_box_fade(625.0, 875.0, *d);
        let opacity = 1.0 - g[2].w;
        let e = (opacity - open * fade).abs();
        worst = worst.max(e);
        assert!(
            e <= 1e-5,
            "scene at {d}: opacity {opacity} vs {open} x {fade}"
        );
    }
    eprintln!(
        "cloud layer soft clip: opacity vs soft-particle fade worst abs {worst:.1e} (bound 1e-5), unclipped opacity {open:.3}"
    );
}

/// The cloud-shadow pass over a rendered ground: each pixel's world position from the
/// depth buffer through the corner rays, the shadow multiplied into the lit colour,
/// against the CPU mirror per pixel; a striped map casts striped shadows.
#[test]
fn cloud_shadow_pass_on_the_ground() {
    use volfog::cpu::frustum::{
        frustum_is_sky, frustum_ray, frustum_view_depth, frustum_world_position,
    };
    use volfog::pipeline::clouds::{CloudDraw, CloudPasses};
    use volfog::uniforms::FrustumRays;
    let gpu = gpu();
    let (w, h) = (96u32, 54u32);
    let eye = Vec3::new(0.0, 20.0, 0.0);
    let proj = glam::camera::rh::proj::directx::perspective(1.0, w as f32 / h as f32, 0.5, 2000.0);
    let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::new(0.0, 0.0, -120.0), Vec3::Y);
    let world_from_view = view.inverse();
    // Depths of the ground plane y = 0 (sky beyond the horizon at depth 1).
    let clip_from_world = proj * view;
    let world_from_clip = clip_from_world.inverse();
    let mut depths = Vec::new();
    let mut ground = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let ndc = Vec2::new(
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            );
            let near = world_from_clip.project_point3(ndc.extend(0.0));
            let far = world_from_clip.project_point3(ndc.extend(1.0));
            let d = (far - near).normalize();
            if d.y < -1e-3 {
                let p = near + d * (-near.y / d.y);
                let c = clip_from_world * p.extend(1.0);
                depths.push((c.z / c.w).min(1.0));
                ground.push(Some(p));
            } else {
                depths.push(1.0);
                ground.push(None);
            }
        }
    }
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depths).unwrap();
    // Stripes 8 texels wide across x.
    let n = 32u32;
    let texels = (0..n * n)
        .map(|i| {
            if ((i % n) / 8).is_multiple_of(2) {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let map = CloudMap {
        width: n,
        height: n,
        texels,
    };
    let layer = CloudLayer::new(400.0, 100.0, 0.02, 640.0)
        .unwrap()
        .with_sun(
            Vec3::new(0.3, 0.9, -0.2).normalize(),
            Vec3::ONE,
            Vec3::ZERO,
            0.0,
        )
        .unwrap()
        .with_wind(Vec2::new(10.0, 0.0), 3.0)
        .unwrap();
    let passes = CloudPasses::new(&gpu.device, wgpu::TextureFormat::Rgba16Float).unwrap();
    let texture = map_texture(&map);
    let group = passes.bind_group(
        &gpu.device,
        &texture.create_view(&Default::default()),
        &depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        }),
    );
    let rays = FrustumRays::new(world_from_view, proj).unwrap();
    passes.prepare(&gpu.queue, &rays, &layer).unwrap();
    let target = gpu.texture_2d_rgba16f("lit", [w, h], &vec![Vec4::ONE; (w * h) as usize]);
    let target_view = target.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        passes.draw(&mut pass, &group, CloudDraw::Shadow);
    }
    gpu.queue.submit([encoder.finish()]);
    let got = gpu.read_texture_rgba16f(&target).unwrap();
    let (mut worst, mut dark, mut lit) = (0.0f32, 0, 0);
    for (i, p) in ground.iter().enumerate() {
        // The CPU mirror of the pass: the position from the same depth value.
        let uv = Vec2::new(
            ((i as u32 % w) as f32 + 0.5) / w as f32,
            ((i as u32 / w) as f32 + 0.5) / h as f32,
        );
        let view_depth = frustum_view_depth(&rays, depths[i]);
        let q = frustum_world_position(&rays, frustum_ray(&rays, uv), view_depth);
        let sky = frustum_is_sky(&rays, view_depth);
        assert_eq!(sky, p.is_none(), "pixel {i}: the sky is the sky");
        let want = if sky {
            1.0
        } else {
            cloud_shadow(&map, &layer, q)
        };
        let e = (got[i].x - want).abs();
        worst = worst.max(e);
        assert!(e <= 2e-3, "pixel {i} at {p:?}: {} vs {want}", got[i].x);
        if p.is_some() {
            dark += (want < 0.3) as usize;
            lit += (want > 0.9) as usize;
        }
    }
    eprintln!(
        "cloud_shadow pass on a {w}x{h} ground: vs cpu worst abs {worst:.1e} (bound 2e-3, rgba16float); \
         {dark} pixels in cloud shadow, {lit} lit"
    );
    assert!(dark > 300 && lit > 300, "stripes of shadow and light");
}

/// The clouds' shadow in the fog: `VolumetricFog` with `FogConfig::cloud_shadow` and
/// a striped cloud map, its inject output against the CPU mirror (with the same map
/// and layer), and the fog shadowed in stripes: the sun's in-scattering of froxels
/// under the clouds falls by the cloud's transmittance.
#[test]
fn fog_carries_the_cloud_shadows() {
    use common::scene::{index, medium, projection, read_volume, run_frames, small_config, view};
    use volfog::cpu::inject::{InjectInputs, froxel_scattering, froxel_world_position};
    use volfog::pipeline::{FrameInputs, VolumetricFog};
    use volfog::uniforms::DirectionalLight;
    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        cloud_shadow: true,
        depth_cull: false,
        ..small_config()
    };
    let n = 16u32;
    let texels = (0..n * n)
        .map(|i| {
            if ((i % n) / 4).is_multiple_of(2) {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let map = CloudMap {
        width: n,
        height: n,
        texels,
    };
    let texture = map_texture(&map);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_cloud_map(&gpu.device, &texture).unwrap();
    let sun_dir = Vec3::new(0.2, 0.9, 0.1).normalize();
    let layer = CloudLayer::new(30.0, 6.0, 0.4, 64.0)
        .unwrap()
        .with_sun(sun_dir, Vec3::ONE, Vec3::ZERO, 0.0)
        .unwrap()
        .with_wind(Vec2::new(2.0, 1.0), 1.5)
        .unwrap();
    let medium = medium();
    let frame_inputs = |f: u32| FrameInputs {
        medium,
        sun: DirectionalLight {
            direction: sun_dir,
            ..DirectionalLight::default()
        },
        clouds: layer,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 1.5 + f as f32)
    };
    let mut captured = None;
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        captured = Some(read_volume(gpu, fog.scattering_texture()));
    });
    let scattering = captured.unwrap();
    let u = common::scene::expected_uniforms(&config, &frame_inputs(0), 0);
    let inputs = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &[],
        local_volumes: &[],
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: Some((&map, &layer)),
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let size = config.volume_size;
    let (mut worst, mut shadowed, mut open) = (0.0f32, 0, 0);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = glam::UVec3::new(x, y, z);
                let want = froxel_scattering(&inputs, id);
                let got = scattering[index(size, x, y, z)];
                let scale = want.truncate().max_element().max(1e-4);
                let e = ((got - want).truncate().abs().max_element() / scale)
                    .max((got.w - want.w).abs() / want.w.max(1e-4));
                worst = worst.max(e);
                assert!(e <= 4e-3, "froxel {x},{y},{z}: gpu {got} cpu {want}");
                let (world, _) = froxel_world_position(&u.froxels, &u.frame, id, false);
                let t = cloud_shadow(&map, &layer, world);
                shadowed += (t < 0.2) as usize;
                open += (t > 0.95) as usize;
            }
        }
    }
    eprintln!(
        "fog under striped clouds: inject vs cpu worst rel {worst:.1e} (bound 4e-3); {shadowed} \
         froxels under cloud (T < 0.2), {open} open"
    );
    assert!(
        shadowed > 1000 && open > 1000,
        "the fog is shadowed in stripes"
    );
}

/// Suns below the horizon or at the zenith, views straight up, down and along the
/// layer, eyes below, inside and above it: finite output, transmittance in [0, 1].
#[test]
fn clouds_are_finite_for_every_sun_and_view() {
    let mut rng = Rng(9);
    let map = random_map(&mut rng, 8);
    let mut cases = Vec::new();
    for sun in [
        Vec3::new(0.0, -0.3, 1.0).normalize(),
        Vec3::Y,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.005, 1.0).normalize(),
    ] {
        let layer = CloudLayer::new(100.0, 50.0, 0.05, 500.0)
            .unwrap()
            .with_sun(sun, Vec3::splat(4.0), Vec3::splat(0.2), 0.8)
            .unwrap();
        for eye_y in [0.0f32, 125.0, 100.0, 300.0] {
            for dir in [
                Vec3::Y,
                -Vec3::Y,
                Vec3::X,
                Vec3::new(1.0, 1e-7, 0.0).normalize(),
            ] {
                for distance in [0.0f32, 120.0, 1e30] {
                    cases.push(Case {
                        layer,
                        eye: Vec3::new(3.0, eye_y, -7.0),
                        dir,
                        distance,
                    });
                }
            }
        }
    }
    let got = run(&map, &cases);
    for (c, g) in cases.iter().zip(&got) {
        for v in g {
            assert!(
                v.is_finite() && v.truncate().min_element() >= 0.0,
                "{c:?}: {g:?}"
            );
            assert!((0.0..=1.0).contains(&v.w), "{c:?}: {g:?}");
        }
    }
}

/// Bad inputs to the sky and cloud runtimes come back as typed errors that name the
/// field and its range, never a panic.
#[test]
fn bad_sky_and_cloud_inputs_are_typed_errors() {
    use volfog::pipeline::clouds::{CloudPasses, cloud_map_texture};
    use volfog::pipeline::sky::SkyLight;
    use volfog::uniforms::{FrustumRays, SkyAtmosphere};
    let gpu = gpu();
    let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
    let rays = FrustumRays::new(glam::Mat4::IDENTITY, proj).unwrap();
    let clouds = CloudPasses::new(&gpu.device, wgpu::TextureFormat::Rgba16Float).unwrap();
    let good = CloudLayer::new(500.0, 100.0, 0.01, 1000.0).unwrap();
    let bad_layer = CloudLayer {
        extinction: f32::NAN,
        ..good
    };
    let e = clouds.prepare(&gpu.queue, &rays, &bad_layer).unwrap_err();
    assert_eq!(e.field, "CloudLayer.extinction", "{e}");
    let mut bad_rays = rays;
    bad_rays.corners[2].x = f32::INFINITY;
    let e = clouds.prepare(&gpu.queue, &bad_rays, &good).unwrap_err();
    assert_eq!(e.field, "FrustumRays", "{e}");
    let e = cloud_map_texture(&gpu.device, &gpu.queue, (4, 4), &[0.5; 15]).unwrap_err();
    assert!(e.to_string().contains("16 values"), "{e}");
    let mut sky = SkyLight::new(&gpu.device, wgpu::TextureFormat::Rgba16Float).unwrap();
    let e = sky.prepare(&gpu.queue, &rays, 0).unwrap_err();
    assert!(e.to_string().contains("1..=64"), "{e}");
    let e = sky
        .set_atmosphere(SkyAtmosphere {
            view_samples: 0,
            ..SkyAtmosphere::earth(Vec3::Y).unwrap()
        })
        .unwrap_err();
    assert_eq!(e.field, "SkyAtmosphere.view_samples", "{e}");
    // Corner rays to view depth 1 need a perspective projection.
    let ortho = glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0);
    let e = FrustumRays::new(glam::Mat4::IDENTITY, ortho).unwrap_err();
    assert_eq!(e.field, "FrustumRays.clip_from_view", "{e}");
}
