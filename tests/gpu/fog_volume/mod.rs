//! Analytic box and ellipsoid fog volumes (`volfog::fog_volume`, Wenzel 2007 "Fog
//! Volumes") on the GPU: ray entry/exit and fog against the CPU mirror and against an
//! independent f64 reference (the inside/outside boundary found by bisection of the
//! shape's distance function along the segment, the density integrated by Simpson's
//! rule), with the camera inside or outside and the segment clipped by the scene
//! depth; back-to-front compositing of several volumes; finiteness for adversarial
//! inputs. Here: the per-segment kernel, its cases and random volumes.

mod composite;
mod reference;
mod single;

use crate::common::{Rng, gpu, run_f32};
use glam::{Mat4, Vec3};
use volfog::cpu::fog_volume::*;
use volfog::uniforms::{FogVolume, VolumeShape};

/// Outputs per case: entry/exit (2), optical depth, fog rgba (4), ray_unit_box of the
/// raw local ray (2), ray_unit_sphere (2), padding.
const OUTPUTS: usize = 12;

const KERNEL: &str = r#"
#import volfog::types::FogVolume
#import volfog::fog_volume::{fog_volume, fog_volume_entry_exit, fog_volume_optical_depth,
    ray_unit_box, ray_unit_sphere}

struct Case { volume: FogVolume, eye: vec4<f32>, point: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let o = i * 12u;
    let t = fog_volume_entry_exit(c.volume, c.eye.xyz, c.point.xyz);
    output[o + 0u] = t.x;
    output[o + 1u] = t.y;
    output[o + 2u] = fog_volume_optical_depth(c.volume, c.eye.xyz, c.point.xyz);
    let f = fog_volume(c.volume, c.eye.xyz, c.point.xyz);
    output[o + 3u] = f.x;
    output[o + 4u] = f.y;
    output[o + 5u] = f.z;
    output[o + 6u] = f.w;
    // The raw intersections with the eye and point read as a local-space ray.
    let b = ray_unit_box(c.eye.xyz, c.point.xyz);
    let s = ray_unit_sphere(c.eye.xyz, c.point.xyz);
    output[o + 7u] = b.x;
    output[o + 8u] = b.y;
    output[o + 9u] = s.x;
    output[o + 10u] = s.y;
    output[o + 11u] = 0.0;
}
"#;

#[derive(Clone, Copy, Debug)]
struct Case {
    volume: FogVolume,
    eye: Vec3,
    point: Vec3,
}

fn volume_floats(v: &FogVolume) -> Vec<f32> {
    let bytes = v.to_bytes();
    assert_eq!(bytes.len(), 128, "FogVolume is 128 bytes");
    bytemuck::cast_slice(&bytes).to_vec()
}

impl Case {
    fn cpu(&self) -> [f32; OUTPUTS] {
        let t = fog_volume_entry_exit(&self.volume, self.eye, self.point);
        let f = fog_volume(&self.volume, self.eye, self.point);
        let b = ray_unit_box(self.eye, self.point);
        let s = ray_unit_sphere(self.eye, self.point);
        [
            t.x,
            t.y,
            fog_volume_optical_depth(&self.volume, self.eye, self.point),
            f.x,
            f.y,
            f.z,
            f.w,
            b.x,
            b.y,
            s.x,
            s.y,
            0.0,
        ]
    }
}

fn run_gpu(cases: &[Case]) -> Vec<[f32; OUTPUTS]> {
    let gpu = gpu();
    let mut input = Vec::new();
    for c in cases {
        input.extend(volume_floats(&c.volume));
        input.extend(c.eye.extend(0.0).to_array());
        input.extend(c.point.extend(0.0).to_array());
    }
    let out = run_f32(
        gpu,
        KERNEL,
        &input,
        cases.len() * OUTPUTS,
        cases.len() as u32,
    );
    out.chunks_exact(OUTPUTS)
        .map(|c| c.try_into().unwrap())
        .collect()
}

/// A general affine volume: translation * rotation * scale * rotation (any shear).
fn random_volume(rng: &mut Rng, shape: VolumeShape, center_range: f32) -> (FogVolume, Mat4) {
    let scale = Vec3::new(rng.log(0.5, 20.0), rng.log(0.5, 20.0), rng.log(0.5, 20.0));
    let world_from_local = Mat4::from_translation(rng.vec(center_range))
        * Mat4::from_quat(rng.quat())
        * Mat4::from_scale(scale)
        * Mat4::from_quat(rng.quat());
    let volume = FogVolume::new(
        world_from_local,
        shape,
        Vec3::new(rng.f(), rng.f(), rng.f()) * 3.0,
        rng.log(1e-3, 1.0),
    )
    .unwrap()
    .with_gradient(rng.unit(), rng.range(-0.2, 0.2), rng.range(-10.0, 10.0))
    .unwrap();
    (volume, world_from_local)
}

/// A local point inside the shape (within 0.9 of its extent).
fn inside(rng: &mut Rng, shape: VolumeShape) -> Vec3 {
    match shape {
        VolumeShape::Box => rng.vec(0.9),
        VolumeShape::Ellipsoid => rng.unit() * 0.9 * rng.f().cbrt(),
        VolumeShape::Cylinder | VolumeShape::Cone | VolumeShape::Plane => loop {
            let p = rng.vec(0.9);
            if reference::phi(shape as u32, reference::v64(p)) <= -0.1 {
                break p;
            }
        },
    }
}

fn cases() -> Vec<(&'static str, Case)> {
    let mut rng = Rng(0xf09_b0c5);
    let mut out = Vec::new();
    let shapes = [
        VolumeShape::Box,
        VolumeShape::Ellipsoid,
        VolumeShape::Cylinder,
        VolumeShape::Cone,
    ];
    for i in 0..12000 {
        let shape = shapes[i % 4];
        let (volume, w) = random_volume(&mut rng, shape, 100.0);
        let at = |p: Vec3| w.transform_point3(p);
        let (kind, eye, point) = match (i / 4) % 6 {
            0 => (
                "camera outside, through",
                at(rng.vec(3.0)),
                at(rng.vec(3.0)),
            ),
            1 => (
                "camera inside",
                at(inside(&mut rng, shape)),
                at(rng.vec(3.0)),
            ),
            2 => (
                "point inside (scene depth)",
                at(rng.vec(3.0)),
                at(inside(&mut rng, shape)),
            ),
            3 => (
                "both inside",
                at(inside(&mut rng, shape)),
                at(inside(&mut rng, shape)),
            ),
            4 => {
                let eye = at(rng.vec(3.0));
                ("far point", eye, eye + rng.unit() * rng.log(50.0, 2000.0))
            }
            _ => {
                let eye = at(rng.vec(2.0));
                if rng.f() < 0.3 {
                    ("zero-length", eye, eye)
                } else {
                    ("short", eye, eye + rng.unit() * rng.log(1e-4, 1.0))
                }
            }
        };
        out.push((kind, Case { volume, eye, point }));
    }
    out
}
