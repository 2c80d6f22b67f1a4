//! The fog-lit snippet (`volfog::fog_lit`): its functions on the GPU against the CPU
//! mirror, and the light it reads back from a fog `VolumetricFog` ran against the
//! light at the same points written out from the lights themselves.

use crate::common::scene::*;
use crate::common::{Rng, gpu, run_f32};
use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::apply::Volume;
use volfog::cpu::fog_lit::{fog_lit_coord_from_view, fog_lit_light};
use volfog::cpu::inject::froxel_world_position;
use volfog::cpu::lights::{ambient_inscatter, fog_light_inscatter, sun_inscatter};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{FogLight, Froxels};

const KERNEL: &str = r#"
#import volfog::types::Froxels
#import volfog::fog_lit::{fog_lit_coord_from_view, fog_lit_light}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 6u * i >= arrayLength(&output) { return; }
    let froxels = Froxels(
        mat4x4<f32>(input[0], input[1], input[2], input[3]),
        mat4x4<f32>(input[4], input[5], input[6], input[7]),
        vec3<u32>(input[8].xyz), input[8].w, input[9].x, input[9].y);
    let row = 10u + 4u * i;
    let coord = fog_lit_coord_from_view(input[row].xyz, froxels);
    let light = fog_lit_light(input[row + 1u], input[row + 2u].xyz, input[row + 3u].xyz);
    output[6u * i] = coord.x;
    output[6u * i + 1u] = coord.y;
    output[6u * i + 2u] = coord.z;
    output[6u * i + 3u] = light.x;
    output[6u * i + 4u] = light.y;
    output[6u * i + 5u] = light.z;
}
"#;

fn froxels() -> Froxels {
    let config = small_config();
    Froxels::new(
        projection(),
        config.volume_size,
        config.near,
        config.far,
        config.slice_curve,
    )
    .unwrap()
}

/// `fog_lit_coord_from_view` and `fog_lit_light` on the GPU against the CPU mirror:
/// 4,000 random view positions (in front of, inside and beyond the volume) and lit
/// volume samples (a quarter below the extinction threshold, some albedo channels 0),
/// within 1e-6 of the coordinate and 2e-6 relative of the light.
#[test]
fn fog_lit_functions_match_the_cpu_mirror() {
    let f = froxels();
    let mut inputs: Vec<f32> = Vec::new();
    for c in f.clip_from_view.to_cols_array_2d() {
        inputs.extend(c);
    }
    for c in f.view_from_clip.to_cols_array_2d() {
        inputs.extend(c);
    }
    inputs.extend([f.size.x as f32, f.size.y as f32, f.size.z as f32, f.near]);
    inputs.extend([f.far, f.curve, 0.0, 0.0]);
    let mut rng = Rng(42);
    let mut cases = Vec::new();
    for i in 0..4000 {
        let z = rng.log(0.05, 200.0);
        let view = Vec3::new(rng.range(-1.0, 1.0) * z, rng.range(-0.6, 0.6) * z, -z);
        let a = if i % 4 == 0 {
            rng.range(0.0, 2e-4)
        } else {
            rng.log(1e-4, 5.0)
        };
        let source = Vec4::new(
            rng.f() * a * 10.0,
            rng.f() * a * 10.0,
            rng.f() * a * 10.0,
            a,
        );
        let mut albedo = Vec3::new(rng.f(), rng.f(), rng.f());
        if i % 7 == 0 {
            albedo.y = 0.0;
        }
        let fallback = Vec3::new(rng.f(), rng.f(), rng.f());
        for v in [
            view.extend(0.0),
            source,
            albedo.extend(0.0),
            fallback.extend(0.0),
        ] {
            inputs.extend(v.to_array());
        }
        cases.push((view, source, albedo, fallback));
    }
    let got = run_f32(gpu(), KERNEL, &inputs, 6 * cases.len(), cases.len() as u32);
    let (mut worst_coord, mut worst_light, mut fallbacks) = (0.0f32, 0.0f32, 0);
    for (i, (view, source, albedo, fallback)) in cases.iter().enumerate() {
        let coord = fog_lit_coord_from_view(*view, &f);
        let light = fog_lit_light(*source, *albedo, *fallback);
        let g = &got[6 * i..6 * i + 6];
        worst_coord = worst_coord.max((Vec3::new(g[0], g[1], g[2]) - coord).abs().max_element());
        let gl = Vec3::new(g[3], g[4], g[5]);
        worst_light = worst_light
            .max(((gl - light).abs() / light.abs().max(Vec3::splat(1e-3))).max_element());
        fallbacks += usize::from(light == *fallback);
    }
    eprintln!(
        "fog_lit on the GPU vs CPU: worst coordinate error {worst_coord:e} (bound 1e-6), worst \
         light error {worst_light:e} relative (bound 2e-6); {fallbacks} of {} fell back",
        cases.len()
    );
    assert!(fallbacks > 500 && fallbacks < 2000, "{fallbacks}");
    assert!(worst_coord <= 1e-6, "{worst_coord}");
    assert!(worst_light <= 2e-6, "{worst_light}");
}

/// The lights of the fog test: a sun, a sky-and-ground ambient and two point lights.
fn lights() -> [FogLight; 2] {
    [
        FogLight::point(
            Vec3::new(-3.0, 2.5, -12.0),
            Vec3::new(30.0, 20.0, 10.0),
            15.0,
        ),
        FogLight::point(
            Vec3::new(4.0, 1.0, -25.0),
            Vec3::new(10.0, 25.0, 40.0),
            20.0,
        ),
    ]
}

/// The light at a world point written out from the lights (no shadows, no
/// transmittance in this fog): the sun, the ambient and the point lights, each
/// phase-weighted towards the camera with the medium's g.
fn light_at(frame: &FrameInputs<'_>, camera: Vec3, world: Vec3) -> Vec3 {
    let view_dir = (world - camera).normalize();
    let g = frame.medium.phase_g;
    let a = &frame.ambient.rgb;
    let mut light = sun_inscatter(&frame.sun, 1.0, view_dir, g)
        + ambient_inscatter(a[0], a[1], a[2], view_dir, g);
    for l in frame.lights {
        light += fog_light_inscatter(l, world, view_dir, g);
    }
    light
}

/// The fog's light read back through the snippet from a `VolumetricFog` frame
/// (no shadows, no transmittance) against the light written out from the lights: at
/// the froxels' own samples within 2.5e-3 of the largest channel (the two rgba16float
/// roundings of rgb and a, 2^-11 each, and the inject's f32 evaluation); at 2,000
/// random points between them, through the trilinear filter, the mean and 95th
/// percentile of the error relative to the largest channel within 1 % and 2 % (the
/// froxel-sized blur of the light's gradients near the lamps is the snippet's
/// approximation; its worst case, next to a lamp, is reported).
#[test]
fn fog_lit_reads_the_fogs_light_back() {
    let gpu = gpu();
    let config = FogConfig {
        light_transmittance: false,
        ..small_config()
    };
    let lights = lights();
    let frame = FrameInputs {
        medium: medium(),
        ambient: AmbientSh::sky_ground(
            Vec3::new(0.3, 0.4, 0.6),
            Vec3::new(0.1, 0.08, 0.05),
            Vec3::Y,
        ),
        lights: &lights,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut texels = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| frame.clone(),
        |_, fog| texels = read_volume(gpu, fog.lit_texture()),
    );
    let u = expected_uniforms(&config, &frame, 0);
    let camera = u.frame.camera_position;
    let size = config.volume_size;
    let albedo = frame.medium.albedo;

    let mut worst = 0.0f32;
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = UVec3::new(x, y, z);
                let (world, _) = froxel_world_position(&u.froxels, &u.frame, id, false);
                let got = fog_lit_light(texels[index(size, x, y, z)], albedo, Vec3::splat(-1.0));
                assert!(got.x >= 0.0, "froxel {id} carries no light");
                let want = light_at(&frame, camera, world);
                worst = worst.max((got - want).abs().max_element() / want.max_element());
            }
        }
    }
    let volume = Volume {
        size: size.to_array(),
        texels,
    };
    let mut rng = Rng(7);
    let mut errors = Vec::new();
    while errors.len() < 2000 {
        let z = rng.range(1.0, 60.0);
        let world = camera + Vec3::new(rng.range(-0.9, 0.9) * z, rng.range(-0.5, 0.5) * z, -z);
        let view_pos = u.frame.world_from_view.inverse().transform_point3(world);
        let coord = fog_lit_coord_from_view(view_pos, &u.froxels);
        if coord.x <= 0.0 || coord.x >= 1.0 || coord.y <= 0.0 || coord.y >= 1.0 {
            continue;
        }
        let got = fog_lit_light(volume.sample(coord), albedo, Vec3::ZERO);
        let want = light_at(&frame, camera, world);
        errors.push((got - want).abs().max_element() / want.max_element());
    }
    errors.sort_by(f32::total_cmp);
    let mean = errors.iter().sum::<f32>() / errors.len() as f32;
    let p95 = errors[errors.len() * 95 / 100];
    eprintln!(
        "fog_lit: at the froxels' samples worst {worst:e} of the largest channel (bound 2.5e-3); \
         between them (trilinear) mean {mean:e} (bound 1e-2), p95 {p95:e} (bound 2e-2), \
         worst {:e}",
        errors[errors.len() - 1]
    );
    assert!(worst <= 2.5e-3, "{worst}");
    assert!(mean <= 0.01 && p95 <= 0.02, "{mean} {p95}");
}
