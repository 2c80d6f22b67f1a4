//! The inject pass through `VolumetricFog`: against the CPU mirror for a full scene,
//! against closed forms (homogeneous fog lit by the sun, with and without an occluder),
//! against numerical integration (a height-fog column), and with lights placed exactly
//! at froxel centres.

use crate::common;

use common::gpu;
use common::scene::*;
use glam::{Mat4, UVec3, Vec3, Vec4};
use volfog::cpu;
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering, froxel_world_position};
use volfog::pipeline::{FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogLight, FogMedium, ShadowCascades};

#[test]
fn inject_matches_cpu_mirror_for_a_full_scene() {
    let gpu = gpu();
    for (jitter, two_color, log_space, octaves) in [
        (true, false, false, 1),
        (true, true, true, 3),
        (false, false, false, 2),
    ] {
        let config = volfog::pipeline::FogConfig {
            jitter,
            two_color_phase: two_color,
            esm_log_space: log_space,
            esm_exponent: if log_space { 150.0 } else { 80.0 },
            noise_octaves: octaves,
            ..small_config()
        };
        let (cascades, depth_layers) = overhead_sun(&config, Some(SLAB));
        let shadow = shadow_map(gpu, &depth_layers);
        let lights = lights();
        let volumes = local_volumes();
        let medium = medium();
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_shadow_map(&gpu.device, &shadow).unwrap();
        let frame_inputs = |f: u32| FrameInputs {
            medium,
            sun: DirectionalLight {
                direction: Vec3::Y,
                ..DirectionalLight::default()
            },
            ambient: AmbientSh::sky_ground(
                Vec3::new(0.2, 0.3, 0.5),
                Vec3::new(0.05, 0.04, 0.03),
                Vec3::Y,
            ),
            lights: &lights,
            local_volumes: &volumes,
            cascades,
            ..FrameInputs::new(view(3.0, -0.1), projection(), 1.5 + f as f32)
        };
        let mut captured = None;
        run_frames(gpu, &mut fog, 3, frame_inputs, |f, fog| {
            if f == 2 {
                captured = Some((
                    read_volume(gpu, fog.scattering_texture()),
                    read_esm(gpu, fog),
                ));
            }
        });
        let (scattering, esm_layers) = captured.unwrap();
        let u = expected_uniforms(&config, &frame_inputs(2), 2);
        let inputs = InjectInputs {
            froxels: &u.froxels,
            frame: &u.frame,
            medium: &u.medium,
            lighting: &u.lighting,
            cascades: &u.cascades,
            esm: &esm_layers,
            lights: &lights,
            local_volumes: &volumes,
            options: config.inject_options(),
            density_texture: None,
            noise_texture: None,
            clouds: None,
        };
        let size = config.volume_size;
        let mut worst = 0.0f32;
        let mut shadowed = 0;
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    let want = froxel_scattering(&inputs, UVec3::new(x, y, z));
                    let got = scattering[index(size, x, y, z)];
                    assert!(got.is_finite(), "non-finite froxel {x},{y},{z}");
                    let scale = want.truncate().max_element().max(1e-4);
                    for c in 0..3 {
                        let e = (got[c] - want[c]).abs() / scale;
                        worst = worst.max(e);
                    }
                    let e = (got.w - want.w).abs() / want.w.max(1e-4);
                    worst = worst.max(e);
                    let (world, depth) =
                        froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), jitter);
                    if cpu::esm::esm_shadow(&esm_layers, &u.cascades, world, depth, log_space) < 0.5
                    {
                        shadowed += 1;
                    }
                }
            }
        }
        eprintln!(
            "inject jitter={jitter} two_color={two_color} log_space={log_space} octaves={octaves}: worst relative error vs CPU {worst:e} (bound 4e-3), {shadowed} shadowed froxels"
        );
        assert!(shadowed > 100, "the slab shadows part of the volume");
        assert!(worst <= 4e-3, "{worst}");
    }
}

/// Homogeneous fog, sun without occluders: every column is the closed form
/// L = albedo E p(theta) (1 - e^(-sigma_t d)), T = e^(-sigma_t d).
#[test]
fn homogeneous_sunlit_fog_matches_closed_form() {
    let gpu = gpu();
    let config = small_config();
    let sigma_t = 0.04;
    let g = 0.6;
    let medium = FogMedium {
        density: sigma_t,
        height_falloff: 0.0,
        noise_strength: 0.0,
        albedo: Vec3::splat(0.8),
        phase_g: g,
        ..FogMedium::default()
    };
    let sun = DirectionalLight {
        direction: Vec3::new(0.3, 0.4, -0.866).normalize(),
        color: Vec3::new(2.0, 1.5, 1.0),
        ..DirectionalLight::default()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut integrated = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::default(),
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(2.0, 0.05), projection(), 0.0)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        integrated = read_volume(gpu, fog.integrated_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let f = &u.froxels;
    let size = config.volume_size;
    let (mut worst_l, mut worst_t) = (0.0f32, 0.0f32);
    for y in 0..size.y {
        for x in 0..size.x {
            let (world, _) = froxel_world_position(f, &u.frame, UVec3::new(x, y, 0), false);
            let view_dir = (world - u.frame.camera_position).normalize();
            let phase = cpu::phase::phase_hg(view_dir.dot(sun.direction), g);
            let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                / glam::Vec2::new(size.x as f32, size.y as f32);
            let scale = cpu::froxel::ray_scale(uv, f.view_from_clip);
            for z in 0..size.z {
                let back = cpu::froxel::slice_depth(
                    (z + 1) as f32 / size.z as f32,
                    f.near,
                    f.far,
                    f.curve,
                );
                let d = (back - f.near) * scale;
                let t = (-(sigma_t as f64) * d as f64).exp() as f32;
                let l = medium.albedo * sun.color * phase * (1.0 - t);
                let got = integrated[index(size, x, y, z)];
                for c in 0..3 {
                    worst_l = worst_l.max((got[c] - l[c]).abs() / l[c]);
                }
                worst_t = worst_t.max((got.w - t).abs() / t);
            }
        }
    }
    eprintln!(
        "sunlit homogeneous fog vs closed form: in-scatter {:.4}%, transmittance {:.4}% (bound 0.5%)",
        worst_l * 100.0,
        worst_t * 100.0
    );
    assert!(worst_l <= 0.005 && worst_t <= 0.005);
}

/// A slab between the sun and part of the volume: froxels in its shadow keep only the
/// ambient term (within the ESM leak), froxels outside get sun + ambient.
#[test]
fn occluder_shadow_drops_inscatter_to_ambient() {
    let gpu = gpu();
    let config = small_config();
    let slab = Slab {
        x: (-22.0, 22.0),
        z: (-60.0, -8.0),
        top: 8.0,
    };
    let (cascades, depth_layers) = overhead_sun(&config, Some(slab));
    let shadow = shadow_map(gpu, &depth_layers);
    let g = 0.3;
    let medium = FogMedium {
        density: 0.03,
        height_falloff: 0.0,
        noise_strength: 0.0,
        phase_g: g,
        ..FogMedium::default()
    };
    let sun = DirectionalLight {
        direction: Vec3::Y,
        color: Vec3::splat(4.0),
        ..DirectionalLight::default()
    };
    let ambient_radiance = Vec3::new(0.1, 0.15, 0.2);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow).unwrap();
    let mut scattering = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::constant(ambient_radiance),
        cascades,
        ..FrameInputs::new(view(3.0, 0.0), projection(), 0.0)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        scattering = read_volume(gpu, fog.scattering_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let size = config.volume_size;
    // Depth range of the light is 60 m; c = 80 gives a leak band of 3 / 80 * 60 = 2.25 m.
    let leak_margin = 3.0 / config.esm_exponent * 60.0;
    let (mut shadowed, mut lit, mut worst) = (0, 0, 0.0f32);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let (world, _) =
                    froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), false);
                let view_dir = (world - u.frame.camera_position).normalize();
                let sigma_s = medium.albedo * medium.density;
                let sun_term = sun.color * cpu::phase::phase_hg(view_dir.dot(sun.direction), g);
                // The blur spans 11 ESM texels (0.55 m in cascade 0, 1.1 m in cascade 1)
                // plus the bilinear footprint: keep 8 m from the edges.
                let margin = 8.0;
                let inside = world.x > slab.x.0 + margin
                    && world.x < slab.x.1 - margin
                    && world.z > slab.z.0 + margin
                    && world.z < slab.z.1 - margin
                    && world.y < slab.top - leak_margin;
                let outside = world.x < slab.x.0 - margin
                    || world.x > slab.x.1 + margin
                    || world.z < slab.z.0 - margin
                    || world.z > slab.z.1 + margin
                    || world.y > slab.top + 0.5;
                let got = scattering[index(size, x, y, z)].truncate();
                let (want, label) = if inside {
                    shadowed += 1;
                    (sigma_s * ambient_radiance, "shadowed")
                } else if outside {
                    lit += 1;
                    (sigma_s * (ambient_radiance + sun_term), "lit")
                } else {
                    continue;
                };
                // Allowed: the ESM leak (5 % of the sun term) plus fp16 rounding.
                let tolerance =
                    0.05 * (sigma_s * sun_term).max_element() + 2e-3 * want.max_element();
                let err = (got - want).abs().max_element();
                worst = worst.max(err / (sigma_s * sun_term).max_element());
                assert!(
                    err <= tolerance,
                    "{label} froxel at {world}: {got} vs {want}"
                );
            }
        }
    }
    eprintln!(
        "slab occluder: {shadowed} shadowed froxels at the ambient term, {lit} lit; worst deviation {:.2}% of the sun term (bound 5%)",
        worst * 100.0
    );
    assert!(
        shadowed > 200 && lit > 200,
        "{shadowed} shadowed, {lit} lit"
    );
}

/// Exponential height fog seen from above at an angle: the integrated transmittance
/// of every column against a numerical integral of the same density (f64, 20000
/// steps per ray), within 1 %.
#[test]
fn height_fog_column_matches_numerical_integration() {
    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        volume_size: UVec3::new(16, 9, 128),
        ..small_config()
    };
    let medium = FogMedium {
        density: 0.05,
        height_falloff: 0.1,
        base_height: 0.0,
        noise_strength: 0.0,
        ..FogMedium::default()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut integrated = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(6.0, -0.25), projection(), 0.0)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        integrated = read_volume(gpu, fog.integrated_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let f = &u.froxels;
    let size = config.volume_size;
    let mut worst = 0.0f64;
    for y in 0..size.y {
        for x in 0..size.x {
            let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                / glam::Vec2::new(size.x as f32, size.y as f32);
            let n = cpu::froxel::ndc_from_uv(uv);
            let ray_view = cpu::froxel::view_from_ndc(Vec3::new(n.x, n.y, 0.5), f.view_from_clip);
            let dir_per_depth = (ray_view / ray_view.z.abs()).as_dvec3();
            let world_from_view = u.frame.world_from_view.as_dmat4();
            let density = |depth: f64| {
                let p = world_from_view.transform_point3(dir_per_depth * depth);
                0.05 * (-0.1 * p.y).clamp(-80.0, 80.0).exp()
            };
            let scale = dir_per_depth.length();
            let mut tau = 0.0f64;
            let mut front = f.near as f64;
            for z in 0..size.z {
                let back = cpu::froxel::slice_depth(
                    (z + 1) as f32 / size.z as f32,
                    f.near,
                    f.far,
                    f.curve,
                ) as f64;
                let steps = 20000 / size.z as usize;
                let h = (back - front) / steps as f64;
                for s in 0..steps {
                    tau += density(front + (s as f64 + 0.5) * h) * h * scale;
                }
                front = back;
                let want = (-tau).exp();
                let got = integrated[index(size, x, y, z)].w as f64;
                // Below 1e-3 the fp16 transmittance nears its subnormal range: compare
                // absolutely there.
                let e = (got - want).abs() / want.max(1e-3);
                worst = worst.max(e);
                assert!(e <= 0.01, "column {x},{y} slice {z}: T {got} vs {want}");
            }
        }
    }
    eprintln!(
        "height fog column: worst relative transmittance error {:.4}% (bound 1%)",
        worst * 100.0
    );
}

/// Lights exactly at froxel sample positions (distance 0) and the extreme inputs a
/// light allows: every froxel stays finite.
#[test]
fn lights_at_froxel_centres_stay_finite() {
    let gpu = gpu();
    let config = small_config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    // Place lights at the sample positions of a few froxels of the first frame.
    let u = expected_uniforms(
        &config,
        &FrameInputs::new(view(2.0, 0.0), projection(), 0.0),
        0,
    );
    let at = |x, y, z| froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), false).0;
    let lights = [
        FogLight {
            radius: 1e-6,
            ..FogLight::point(at(5, 5, 5), Vec3::splat(1.0e4), 3.0)
        },
        FogLight {
            radius: 1e-6,
            ..FogLight::spot(
                at(20, 9, 30),
                Vec3::NEG_Z,
                Vec3::splat(1.0e4),
                30.0,
                0.1,
                0.1,
            )
        },
        FogLight::point(at(0, 0, 0), Vec3::splat(50.0), 1e-3),
        FogLight::point(u.frame.camera_position, Vec3::splat(50.0), 10.0),
    ];
    let mut volumes = (Vec::new(), Vec::new());
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| FrameInputs {
            lights: &lights,
            ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
        },
        |_, fog| {
            volumes = (
                read_volume(gpu, fog.scattering_texture()),
                read_volume(gpu, fog.integrated_texture()),
            )
        },
    );
    let size = config.volume_size;
    for (name, v) in [("scattering", &volumes.0), ("integrated", &volumes.1)] {
        assert!(
            v.iter().all(|t| t.is_finite()),
            "{name} volume has NaN or Inf"
        );
    }
    let centre = volumes.0[index(size, 5, 5, 5)];
    let neighbour = volumes.0[index(size, 6, 5, 5)];
    eprintln!("light at a froxel centre: that froxel {centre}, its neighbour {neighbour}");
    assert!(
        centre.x > neighbour.x,
        "the froxel holding the light is the brightest"
    );
}

#[test]
fn bad_frame_inputs_are_typed_errors() {
    let gpu = gpu();
    let config = small_config();
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let base = || FrameInputs::new(view(2.0, 0.0), projection(), 0.0);
    let too_many = vec![FogLight::point(Vec3::ZERO, Vec3::ONE, 1.0); 9];
    let bad_light = [FogLight {
        range: -1.0,
        ..FogLight::point(Vec3::ZERO, Vec3::ONE, 1.0)
    }];
    let cases: Vec<(FrameInputs, &str)> = vec![
        (
            FrameInputs {
                medium: FogMedium {
                    phase_g: 1.0,
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.phase_g",
        ),
        (
            FrameInputs {
                medium: FogMedium {
                    density: -0.1,
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.density",
        ),
        (
            FrameInputs {
                medium: FogMedium {
                    albedo: Vec3::new(f32::NAN, 0.5, 0.5),
                    ..FogMedium::default()
                },
                ..base()
            },
            "FogMedium.albedo",
        ),
        (
            FrameInputs {
                lights: &too_many,
                ..base()
            },
            "FrameInputs.lights",
        ),
        (
            FrameInputs {
                lights: &bad_light,
                ..base()
            },
            "FogLight.range",
        ),
        (
            FrameInputs {
                clip_from_view: Mat4::ZERO,
                ..base()
            },
            "Froxels.clip_from_view",
        ),
        (
            FrameInputs {
                time: f32::INFINITY,
                ..base()
            },
            "FrameInputs.time",
        ),
        (
            FrameInputs {
                cascades: ShadowCascades {
                    count: 1,
                    exponent: 120.0,
                    light_from_world: [Mat4::IDENTITY; 4],
                    splits: Vec4::new(10.0, 20.0, 30.0, 40.0),
                },
                ..base()
            },
            "ShadowCascades.exponent",
        ),
        (
            FrameInputs {
                sun: DirectionalLight {
                    direction: Vec3::ZERO,
                    ..DirectionalLight::default()
                },
                ..base()
            },
            "DirectionalLight.direction",
        ),
    ];
    for (inputs, field) in cases {
        match fog.prepare(&gpu.queue, &inputs) {
            Err(volfog::pipeline::FogError::Invalid(e)) => assert_eq!(e.field, field, "{e}"),
            other => panic!("{field}: expected a typed error, got {other:?}"),
        }
    }
}

/// The density-texture variant: a user 3D texture scrolled by the wind multiplies the
/// density; GPU against the CPU mirror's trilinear, repeat-addressed sample.
#[test]
fn density_texture_variant_matches_cpu_mirror() {
    use volfog::cpu::inject::DensityTexture;
    use wgpu::util::DeviceExt;
    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        density_texture: true,
        ..small_config()
    };
    let size = [16u32, 8, 12];
    let texels: Vec<f32> = (0..size[0] * size[1] * size[2])
        .map(|i| {
            let (x, y, z) = (
                i % size[0],
                (i / size[0]) % size[1],
                i / (size[0] * size[1]),
            );
            0.5 + 0.5
                * ((x as f32 * 0.8).sin() * (y as f32 * 1.1).cos() + 0.3 * (z as f32 * 0.5).sin())
                    .clamp(-1.0, 1.0)
        })
        .collect();
    // Stored as f16: the CPU mirror samples the rounded values.
    let halfs: Vec<half::f16> = texels.iter().map(|v| half::f16::from_f32(*v)).collect();
    let reference = DensityTexture {
        size,
        texels: halfs.iter().map(|h| h.to_f32()).collect(),
    };
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("density"),
            size: wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: size[2],
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&halfs),
    );
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_density_texture(&gpu.device, &texture).unwrap();
    let medium = FogMedium {
        density: 0.05,
        height_falloff: 0.0,
        noise_strength: 0.0,
        texture_scale: Vec3::new(0.07, 0.2, 0.05),
        texture_offset: Vec3::new(0.3, 0.1, 0.7),
        wind: Vec3::new(2.0, 0.0, -1.0),
        ..FogMedium::default()
    };
    let mut scattering = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(2.0, 0.0), projection(), 3.5)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        scattering = read_volume(gpu, fog.scattering_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let inputs = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        lights: &[],
        local_volumes: &[],
        options: config.inject_options(),
        density_texture: Some(&reference),
        noise_texture: None,
        clouds: None,
    };
    let s = config.volume_size;
    let (mut worst, mut lo, mut hi) = (0.0f32, f32::MAX, 0.0f32);
    for z in 0..s.z {
        for y in 0..s.y {
            for x in 0..s.x {
                let want = froxel_scattering(&inputs, UVec3::new(x, y, z)).w;
                let got = scattering[index(s, x, y, z)].w;
                lo = lo.min(got);
                hi = hi.max(got);
                // The sampler's filter weights are fixed point (8 bits on lavapipe):
                // up to 1/256 of the neighbouring texel difference, plus fp16 output.
                worst = worst.max((got - want).abs() / 0.05);
            }
        }
    }
    eprintln!(
        "density texture: sigma_t from {lo:.4} to {hi:.4}; worst difference vs CPU {:.3}% of the base density (bound 0.5%)",
        worst * 100.0
    );
    assert!(hi > 2.0 * lo, "the texture modulates the density");
    assert!(worst <= 5e-3, "{worst}");
    // Without the define the texture cannot be set.
    let mut plain = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    assert!(plain.set_density_texture(&gpu.device, &texture).is_err());
}

const TOUCH_KERNEL: &str = r#"
#import volfog::types::LocalVolume
#import volfog::density::local_volume_touches_sphere

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&output) { return; }
    let m = mat4x4<f32>(input[5u * i], input[5u * i + 1u], input[5u * i + 2u], input[5u * i + 3u]);
    let sphere = input[5u * i + 4u];
    let volume = LocalVolume(m, 1.0, 0.5, 0u);
    output[i] = select(0.0, 1.0, local_volume_touches_sphere(volume, sphere.xyz, sphere.w));
}
"#;

/// The per-workgroup culling of local volumes: the GPU agrees with the CPU mirror, and
/// the test is conservative: no point of a sphere said not to touch a volume (box or
/// ellipsoid, rotated, scaled) gets extinction from it (dense sampling of each sphere).
#[test]
fn local_volume_culling_is_conservative_and_matches_cpu() {
    use volfog::cpu::density::{local_volume_density, local_volume_touches_sphere};
    use volfog::uniforms::{LocalVolume, VolumeShape};
    let gpu = gpu();
    let mut rng = common::Rng(21);
    let mut cases = Vec::new();
    for i in 0..2000 {
        let shape = if i % 2 == 0 {
            VolumeShape::Box
        } else {
            VolumeShape::Ellipsoid
        };
        let position = rng.vec(10.0);
        let world_from_local = Mat4::from_scale_rotation_translation(
            Vec3::new(
                rng.range(0.5, 6.0),
                rng.range(0.5, 6.0),
                rng.range(0.5, 6.0),
            ),
            rng.quat(),
            position,
        );
        let volume = LocalVolume::new(world_from_local, shape, 1.0, 0.5).unwrap();
        let center = position + rng.vec(12.0);
        let radius = rng.log(0.05, 6.0);
        cases.push((volume, center, radius));
    }
    let inputs: Vec<f32> = cases
        .iter()
        .flat_map(|(v, c, r)| {
            let mut row = v.local_from_world.to_cols_array().to_vec();
            row.extend([c.x, c.y, c.z, *r]);
            row
        })
        .collect();
    let got = common::run_f32(gpu, TOUCH_KERNEL, &inputs, cases.len(), cases.len() as u32);
    let (mut touching, mut disagree, mut samples) = (0, 0, 0);
    for ((volume, center, radius), gpu_touch) in cases.iter().zip(&got) {
        let touch = local_volume_touches_sphere(volume, *center, *radius);
        if (*gpu_touch == 1.0) != touch {
            disagree += 1;
        }
        touching += usize::from(touch);
        if !touch {
            // Points throughout the sphere, its surface included.
            for k in 0..200 {
                let t = if k % 4 == 0 { 1.0 } else { rng.f().cbrt() };
                let p = *center + rng.unit() * *radius * t;
                samples += 1;
                assert_eq!(
                    local_volume_density(volume, p),
                    0.0,
                    "a point of a sphere culled from a volume has density"
                );
            }
        }
    }
    eprintln!(
        "local volume culling: {touching} of {} spheres touch their volume, GPU and CPU \
         disagree on {disagree} (bound 2, rounding at the boundary); {samples} sampled \
         points of the others have no extinction",
        cases.len()
    );
    assert!(touching > 100 && touching < cases.len() - 100);
    assert!(disagree <= 2, "{disagree}");
}
