//! The per-workgroup culling of local volumes against spheres: GPU against the CPU
//! mirror, and conservative against dense sampling of the density.

use crate::common::{self, gpu};
use glam::{Mat4, Vec3};

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
    let volume = LocalVolume(m, vec3<f32>(0.0), 1.0, 0.5, 0u, 0u, vec3<f32>(0.0), 0u);
    output[i] = select(0.0, 1.0, local_volume_touches_sphere(volume, sphere.xyz, sphere.w));
}
"#;

/// The per-workgroup culling of local volumes: the GPU agrees with the CPU mirror, and
/// the test is conservative: no point of a sphere said not to touch a volume (box,
/// ellipsoid, cylinder or cone, rotated, scaled) gets extinction from it (dense sampling of each sphere).
#[test]
fn local_volume_culling_is_conservative_and_matches_cpu() {
    use volfog::cpu::density::{local_volume_density, local_volume_touches_sphere};
    use volfog::uniforms::{LocalVolume, VolumeShape};
    let gpu = gpu();
    let mut rng = common::Rng(21);
    let mut cases = Vec::new();
    for i in 0..2000 {
        let shape = [
            VolumeShape::Box,
            VolumeShape::Ellipsoid,
            VolumeShape::Cylinder,
            VolumeShape::Cone,
        ][i % 4];
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
