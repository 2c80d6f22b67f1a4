//! Cylinder and cone local volumes: the density functions on the GPU against their CPU
//! twins, and the optical depth the froxel volume integrates through them against
//! their analytic chords (`ray_unit_cylinder`, `ray_unit_cone`).

use super::*;
use crate::common::{Rng, run_f32};
use volfog::cpu::density::local_volume_sample;
use volfog::cpu::fog_volume::{ray_unit_cone, ray_unit_cylinder};
use volfog::uniforms::VolumeShape;

const SAMPLE_KERNEL: &str = r#"
#import volfog::types::LocalVolume
#import volfog::density::local_volume_sample

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&output) { return; }
    let m = mat4x4<f32>(input[7u * i], input[7u * i + 1u], input[7u * i + 2u], input[7u * i + 3u]);
    let e = input[7u * i + 4u];
    let params = input[7u * i + 5u];
    let volume = LocalVolume(m, e.xyz, params.x, params.y, u32(params.z), 0u, vec3<f32>(0.0), 0u);
    output[i] = local_volume_sample(volume, input[7u * i + 6u].xyz);
}
"#;

#[test]
fn volume_shapes_match_their_cpu_twins() {
    let gpu = gpu();
    let mut rng = Rng(31);
    let shapes = [
        VolumeShape::Box,
        VolumeShape::Ellipsoid,
        VolumeShape::Cylinder,
        VolumeShape::Cone,
    ];
    let mut cases = Vec::new();
    for i in 0..4000 {
        let shape = shapes[i % 4];
        let world_from_local = Mat4::from_scale_rotation_translation(
            Vec3::new(
                rng.range(0.5, 4.0),
                rng.range(0.5, 4.0),
                rng.range(0.5, 4.0),
            ),
            rng.quat(),
            rng.vec(5.0),
        );
        let volume = LocalVolume::new(
            world_from_local,
            shape,
            rng.range(-1.0, 2.0),
            rng.range(0.05, 1.0),
        )
        .unwrap()
        .with_emission(Vec3::new(rng.f(), rng.f(), rng.f()))
        .unwrap();
        let point = world_from_local.transform_point3(rng.vec(1.3));
        cases.push((volume, point));
    }
    let input: Vec<f32> = cases
        .iter()
        .flat_map(|(v, p)| {
            let mut row = v.local_from_world.to_cols_array().to_vec();
            row.extend(v.emission.extend(0.0).to_array());
            row.extend([v.density, v.edge, v.shape as f32, 0.0]);
            row.extend(p.extend(1.0).to_array());
            row
        })
        .collect();
    let got = run_f32(
        gpu,
        SAMPLE_KERNEL,
        &input,
        4 * cases.len(),
        cases.len() as u32,
    );
    let (mut worst, mut partial) = (0.0f32, 0);
    for ((v, p), g) in cases.iter().zip(got.chunks_exact(4)) {
        let want = local_volume_sample(v, *p);
        let g = Vec4::from_slice(g);
        worst = worst.max((g - want).abs().max_element());
        if want.w != 0.0 && want.w.abs() < v.density.abs() {
            partial += 1;
        }
    }
    eprintln!(
        "local volume samples (box, ellipsoid, cylinder, cone), GPU vs CPU over {} points: worst {worst:.2e} (bound 1e-5), {partial} in the edge band",
        cases.len()
    );
    assert!(worst <= 1e-5, "{worst}");
    assert!(partial > 200, "{partial}");
}

#[test]
fn froxel_optical_depth_through_cylinders_and_cones_matches_their_chords() {
    let gpu = gpu();
    // Fine slices: the error of a chord is a slice at each end.
    let config = FogConfig {
        volume_size: UVec3::new(48, 27, 192),
        far: 16.0,
        ..config(LocalShadowConfig::default(), false)
    };
    let density = 0.4f32;
    let edge = 0.02;
    let cases = [
        (
            VolumeShape::Cylinder,
            ray_unit_cylinder as fn(Vec3, Vec3) -> glam::Vec2,
        ),
        (VolumeShape::Cone, ray_unit_cone),
    ];
    for (shape, chord_of) in cases {
        let world_from_local = Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 2.0, 1.5),
            glam::Quat::from_rotation_z(0.3) * glam::Quat::from_rotation_x(-0.2),
            Vec3::new(0.0, 1.5, -9.0),
        );
        let volume = LocalVolume::new(world_from_local, shape, density, edge).unwrap();
        let volumes = [volume];
        let frame = inputs(
            camera(Vec3::new(0.3, 1.6, -3.5), Vec3::new(0.0, 1.5, -9.0)),
            super::medium(0.0),
            &[],
            &[],
            &volumes,
        );
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let got = run_integrated(&mut fog, &frame);
        let size = config.volume_size;
        let (mut worst, mut hits, mut mean) = (0.0f32, 0, 0.0f64);
        for y in 0..size.y {
            for x in 0..size.x {
                let (chord, thickest) =
                    column_chord(&config, &frame, volume.local_from_world, chord_of, (x, y));
                // Both ends: a slice each and the edge band (edge times the largest
                // half extent, 2 m, at twice its width for oblique entries); and the
                // transmittance's rgba16float rounding.
                let transmittance = got[index(size, x, y, size.z - 1)].w;
                let slack =
                    density * (2.0 * thickest + 2.0 * (2.0 * edge * 2.0)) + 1e-3 / transmittance;
                let depth = -transmittance.ln();
                let err = (depth - density * chord).abs();
                if chord > 0.5 {
                    hits += 1;
                    mean += f64::from(err / (density * chord));
                }
                worst = worst.max(err / slack);
            }
        }
        eprintln!(
            "{shape:?} volume: froxel optical depth against density x analytic chord over {hits} columns through it: mean error {:.2} % of the chord's, worst {worst:.2} of the bound (the end slices, the edge band, rgba16float)",
            100.0 * mean / hits as f64
        );
        assert!(hits > 50, "{hits}");
        assert!(worst <= 1.0, "{worst}");
    }
}
