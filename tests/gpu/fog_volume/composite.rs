//! Several volumes composited back to front: against the CPU mirror, and disjoint
//! volumes against the radiative transfer through them marched in f64.

use super::reference::{M64, density64, m64, norm, phi, v64, xform};
use super::{random_volume, volume_floats};
use crate::common::{Rng, gpu, run_f32};
use glam::{Mat4, Vec3, Vec4};
use volfog::cpu::fog_volume::fog_volumes;
use volfog::uniforms::{FogVolume, VolumeShape};

const COMPOSITE_KERNEL: &str = r#"
#import volfog::types::FogVolume
#import volfog::fog_volume::{fog_volume, fog_over, FOG_NONE}

struct Ray { volumes: array<FogVolume, 4>, eye: vec4<f32>, point: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Ray>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let r = input[i];
    // Volumes arrive sorted farthest first.
    var acc = FOG_NONE;
    for (var k = 0u; k < 4u; k++) {
        acc = fog_over(fog_volume(r.volumes[k], r.eye.xyz, r.point.xyz), acc);
    }
    output[i] = acc;
}
"#;

fn composite_input(rays: &[(Vec<FogVolume>, Vec3, Vec3)]) -> Vec<f32> {
    let mut input = Vec::new();
    for (volumes, eye, point) in rays {
        // Farthest centre first, as the CPU's fog_volumes sorts them.
        let mut sorted = volumes.clone();
        sorted.sort_by(|a, b| {
            b.center
                .distance_squared(*eye)
                .total_cmp(&a.center.distance_squared(*eye))
        });
        assert_eq!(sorted.len(), 4);
        for v in &sorted {
            input.extend(volume_floats(v));
        }
        input.extend(eye.extend(0.0).to_array());
        input.extend(point.extend(0.0).to_array());
    }
    input
}

#[test]
fn composited_volumes_match_cpu() {
    let mut rng = Rng(99);
    let mut rays = Vec::new();
    for i in 0..2000 {
        let volumes: Vec<FogVolume> = (0..4)
            .map(|k| {
                let shape = if (i + k) % 2 == 0 {
                    VolumeShape::Box
                } else {
                    VolumeShape::Ellipsoid
                };
                random_volume(&mut rng, shape, 20.0).0
            })
            .collect();
        let eye = rng.vec(30.0);
        let point = eye + rng.unit() * rng.log(1.0, 100.0);
        rays.push((volumes, eye, point));
    }
    let out = run_f32(
        gpu(),
        COMPOSITE_KERNEL,
        &composite_input(&rays),
        rays.len() * 4,
        rays.len() as u32,
    );
    let mut worst = 0.0f32;
    for (i, (volumes, eye, point)) in rays.iter().enumerate() {
        let want = fog_volumes(volumes, *eye, *point);
        let got = Vec4::from_slice(&out[i * 4..i * 4 + 4]);
        let e = (got - want).abs().max_element();
        worst = worst.max(e);
        assert!(
            e <= 1e-4,
            "ray {i}: gpu {got} cpu {want} for {volumes:?} {eye} {point}"
        );
        assert!(want.w >= 0.0 && want.w <= 1.0);
    }
    eprintln!(
        "4 overlapping volumes composited, gpu vs cpu: worst abs error {worst:e} (bound 1e-4)"
    );
}

/// Volumes that do not overlap along the ray, composited back to front, against the
/// radiative transfer through all of them marched in f64 (inside tests by the shapes'
/// distance functions, 2e5 steps): exact apart from the march.
#[test]
fn composited_volumes_match_radiative_transfer() {
    let mut rng = Rng(2024);
    let mut rays = Vec::new();
    for i in 0..100 {
        let volumes: Vec<FogVolume> = (0..4)
            .map(|k| {
                let shape = if (i + k) % 2 == 0 {
                    VolumeShape::Box
                } else {
                    VolumeShape::Ellipsoid
                };
                // Bounding spheres of radius <= 5 sqrt(3) < 10 around centres 20 m apart.
                let w = Mat4::from_translation(Vec3::new(10.0 + 20.0 * k as f32, 0.0, 0.0))
                    * Mat4::from_quat(rng.quat())
                    * Mat4::from_scale(Vec3::new(
                        rng.range(2.0, 5.0),
                        rng.range(2.0, 5.0),
                        rng.range(2.0, 5.0),
                    ));
                FogVolume::new(
                    w,
                    shape,
                    Vec3::new(rng.f(), rng.f(), rng.f()) * 2.0,
                    rng.log(0.01, 0.2),
                )
                .unwrap()
                .with_gradient(rng.unit(), rng.range(-0.1, 0.1), rng.range(-2.0, 2.0))
                .unwrap()
            })
            .collect();
        // Camera on the left of the row (sometimes inside the first volume), the scene
        // point anywhere along it (clipping some volumes).
        let eye = Vec3::new(
            rng.range(-10.0, 11.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let point = Vec3::new(
            rng.range(15.0, 100.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        rays.push((volumes, eye, point));
    }
    let out = run_f32(
        gpu(),
        COMPOSITE_KERNEL,
        &composite_input(&rays),
        rays.len() * 4,
        rays.len() as u32,
    );
    let mut worst = 0.0f64;
    for (i, (volumes, eye, point)) in rays.iter().enumerate() {
        let e = v64(*eye);
        let seg = [0, 1, 2].map(|k| point[k] as f64 - e[k]);
        let len = norm(seg);
        let n = 200_000;
        let ds = len / n as f64;
        let local: Vec<M64> = volumes.iter().map(|v| m64(&v.local_from_world)).collect();
        let (mut t, mut l) = (1.0f64, [0.0f64; 3]);
        for s in 0..n {
            let u = (s as f64 + 0.5) / n as f64;
            let p = [0, 1, 2].map(|k| e[k] + u * seg[k]);
            let (mut sigma, mut source) = (0.0, [0.0; 3]);
            for (v, m) in volumes.iter().zip(&local) {
                if phi(v.shape, xform(m, p, 1.0)) <= 0.0 {
                    let d = density64(v, p);
                    sigma += d;
                    for (acc, c) in source.iter_mut().zip(v.color.to_array()) {
                        *acc += d * c as f64;
                    }
                }
            }
            if sigma > 0.0 {
                let absorbed = -(-sigma * ds).exp_m1();
                for k in 0..3 {
                    l[k] += t * absorbed * source[k] / sigma;
                }
                t *= 1.0 - absorbed;
            }
        }
        let want = [l[0], l[1], l[2], t];
        let cpu = fog_volumes(volumes, *eye, *point);
        let got = Vec4::from_slice(&out[i * 4..i * 4 + 4]);
        for (side, v) in [("gpu", got), ("cpu", cpu)] {
            for k in 0..4 {
                let e = (v[k] as f64 - want[k]).abs() / want[k].abs().max(1e-2);
                worst = worst.max(e);
                assert!(
                    e <= 1e-3,
                    "{side} ray {i} channel {k}: {} radiative transfer {} ({eye} -> {point})",
                    v[k],
                    want[k]
                );
            }
        }
    }
    eprintln!(
        "4 disjoint volumes composited back to front vs f64 radiative transfer: worst \
         relative error {worst:e} (bound 1e-3, floor 1e-2)"
    );
}
