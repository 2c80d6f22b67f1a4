//! Improved Perlin noise on the GPU: against the CPU mirror and against an f64 port
//! of Perlin's reference implementation, its range, zeros on the lattice, continuity
//! across cells and periods, statistics, the wind animation, the gradient on the
//! lattice against the explicit gradient table of Green 2005, the baked noise texture
//! and its sampled fractal sum against the CPU bake, and the translation of kernels
//! using them to every target. Here: the evaluation kernel and the sample generator.

mod continuity;
mod fbm;
mod perlin;
mod reference;
mod texture;
mod translate;

use crate::common::run_f32;
use glam::Vec3;
use volfog_testkit::Gpu;

/// perlin_noise and noise_fbm per point: input (x, y, z, octaves), two outputs.
const EVAL_KERNEL: &str = r#"
#import volfog::noise::{perlin_noise, noise_fbm}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let p = input[i].xyz;
    output[2u * i] = perlin_noise(p);
    output[2u * i + 1u] = noise_fbm(p, u32(input[i].w));
}
"#;

/// Deterministic generator (splitmix64) for sample points.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    fn int(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1) as u64) as i32
    }
}

/// Runs EVAL_KERNEL: (perlin_noise(p), noise_fbm(p, octaves)) per point.
fn eval_gpu(gpu: &Gpu, points: &[(Vec3, u32)]) -> Vec<(f32, f32)> {
    let inputs: Vec<f32> = points
        .iter()
        .flat_map(|(p, o)| [p.x, p.y, p.z, *o as f32])
        .collect();
    let out = run_f32(
        gpu,
        EVAL_KERNEL,
        &inputs,
        2 * points.len(),
        points.len() as u32,
    );
    out.chunks(2).map(|c| (c[0], c[1])).collect()
}
