//! Soft particles (`volfog::soft_particles`, Wenzel 2007): the fade of a particle
//! treated as a view-aligned box, on the GPU against the CPU mirror, against the share
//! of an oblique view ray's length inside the box measured by sampling in f64, known
//! values, monotonicity in the scene depth, and finiteness for adversarial inputs.

use crate::common;

use common::Rng;

use common::{gpu, run_f32};
use volfog::cpu::soft_particles::*;

const KERNEL: &str = r#"
#import volfog::soft_particles::{soft_particle_fade, soft_particle_box_fade}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<vec2<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    // x particle depth, y scene depth, z thickness; the box form uses its own span.
    output[i] = vec2<f32>(soft_particle_fade(c.x, c.y, c.z),
                          soft_particle_box_fade(c.x - 0.5 * c.z, c.x + 0.5 * c.z, c.y));
}
"#;

fn run_gpu(cases: &[[f32; 3]]) -> Vec<[f32; 2]> {
    let input: Vec<f32> = cases.iter().flat_map(|c| [c[0], c[1], c[2], 0.0]).collect();
    let out = run_f32(gpu(), KERNEL, &input, cases.len() * 2, cases.len() as u32);
    out.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

fn cpu(c: &[f32; 3]) -> [f32; 2] {
    [
        soft_particle_fade(c[0], c[1], c[2]),
        soft_particle_box_fade(c[0] - 0.5 * c[2], c[0] + 0.5 * c[2], c[1]),
    ]
}

/// (particle depth, scene depth, thickness, cosine of the view ray to the view axis).
fn random_cases() -> Vec<([f32; 3], f32)> {
    let mut rng = Rng(0x50f7);
    (0..5000)
        .map(|k| {
            let z = rng.range(-2.0, 50.0);
            let t = rng.log(1e-3, 10.0);
            let scene = match k % 3 {
                0 => z + rng.range(-1.0, 1.0) * t, // near the particle
                1 => rng.range(-5.0, 60.0),
                _ => z + rng.range(-0.5, 0.5) * t,
            };
            ([z, scene, t], rng.range(0.2, 1.0))
        })
        .collect()
}

#[test]
fn soft_particles_match_cpu_mirror() {
    let cases: Vec<[f32; 3]> = random_cases().into_iter().map(|(c, _)| c).collect();
    let gpu = run_gpu(&cases);
    let mut worst = 0.0f32;
    for (c, g) in cases.iter().zip(&gpu) {
        let want = cpu(c);
        for k in 0..2 {
            let e = (g[k] - want[k]).abs();
            worst = worst.max(e);
            assert!(
                e <= 1e-6,
                "output {k}: gpu {} cpu {} for {c:?}",
                g[k],
                want[k]
            );
        }
    }
    eprintln!("soft particles gpu vs cpu: worst abs error {worst:e} (bound 1e-6)");
}

/// The share of the view ray's length inside the box (view depths [z - t/2, z + t/2])
/// that lies between the eye and the scene point, measured along an oblique ray (view
/// depth = distance * cos) with 2e4 midpoint samples in f64.
fn sampled_fade(c: &[f32; 3], cos: f32) -> f64 {
    let (z, scene, t, cos) = (c[0] as f64, c[1] as f64, c[2] as f64, cos as f64);
    let (front, back) = (z - 0.5 * t, z + 0.5 * t);
    // Ray distance covering the box's whole depth range (including behind the eye).
    let (s0, s1) = (front / cos, back / cos);
    let n = 20_000;
    let ds = (s1 - s0) / n as f64;
    let mut visible = 0usize;
    for k in 0..n {
        let s = s0 + (k as f64 + 0.5) * ds;
        let depth = s * cos;
        if depth >= 0.0 && depth <= scene {
            visible += 1;
        }
    }
    visible as f64 / n as f64
}

#[test]
fn soft_particles_match_sampled_ray_share() {
    let cases = random_cases();
    let plain: Vec<[f32; 3]> = cases.iter().map(|(c, _)| *c).collect();
    let gpu = run_gpu(&plain);
    let mut worst = 0.0f64;
    for ((c, cos), g) in cases.iter().zip(&gpu) {
        let want = sampled_fade(c, *cos);
        // Box faces z -+ t/2 are rounded to f32: 2 ulp of the depth, relative to t.
        let depth = c[0].abs().max(c[1].abs()) as f64;
        let f32_limit = 2.0 * depth * f32::EPSILON as f64 / c[2] as f64;
        for (side, got) in [("gpu", g[0]), ("cpu", cpu(c)[0])] {
            let e = (got as f64 - want).abs();
            worst = worst.max(e - f32_limit);
            assert!(
                e <= 1e-3 + f32_limit,
                "{side}: fade {got}, sampled share {want} along a ray at cos {cos} for {c:?}"
            );
        }
    }
    eprintln!(
        "soft particles vs sampled share of an oblique ray (2e4 samples): worst abs error \
         beyond f32 depth rounding {worst:e} (bound 1e-3 + 2 ulp(depth) / thickness)"
    );
}

#[test]
fn soft_particle_known_values_and_monotonic() {
    // 1 m thick particle at 10 m: (scene depth, fade).
    let known = [
        (100.0f32, 1.0f32),
        (10.5, 1.0),
        (10.25, 0.75),
        (10.0, 0.5),
        (9.75, 0.25),
        (9.5, 0.0),
        (1.0, 0.0),
        (-3.0, 0.0),
    ];
    let mut cases: Vec<[f32; 3]> = known.iter().map(|(s, _)| [10.0, *s, 1.0]).collect();
    // Camera inside the box: a 4 m particle at 1 m spans [-1, 3]; 3 m of it are visible.
    cases.push([1.0, 100.0, 4.0]);
    // Zero thickness: a hard depth test.
    cases.push([5.0, 5.5, 0.0]);
    cases.push([5.0, 4.5, 0.0]);
    let gpu = run_gpu(&cases);
    let expected: Vec<f32> = known
        .iter()
        .map(|(_, f)| *f)
        .chain([0.75, 1.0, 0.0])
        .collect();
    for ((c, g), want) in cases.iter().zip(&gpu).zip(&expected) {
        for (side, got) in [("gpu", g[0]), ("cpu", cpu(c)[0])] {
            assert!(
                (got - want).abs() < 1e-6,
                "{side}: fade {got} expected {want} for {c:?}"
            );
        }
    }
    // Monotonic in the scene depth and in [0, 1].
    let sweep: Vec<[f32; 3]> = (0..2001)
        .map(|i| [3.0, -1.0 + 0.005 * i as f32, 2.0])
        .collect();
    let out = run_gpu(&sweep);
    for w in out.windows(2) {
        assert!(w[1][0] >= w[0][0], "fade falls as the scene recedes: {w:?}");
    }
    assert!(out.iter().all(|o| (0.0..=1.0).contains(&o[0])));
}

#[test]
fn soft_particles_are_finite_for_adversarial_inputs() {
    let scalars = [
        0.0f32, 1e-30, -1e-30, 1e-7, 1.0, -1.0, 1e9, -1e9, 1e30, -1e30, 3.4e38, -3.4e38,
    ];
    let mut cases = Vec::new();
    for a in scalars {
        for b in scalars {
            for c in scalars {
                cases.push([a, b, c]);
            }
        }
    }
    let gpu = run_gpu(&cases);
    for (c, g) in cases.iter().zip(&gpu) {
        for (side, out) in [("gpu", *g), ("cpu", cpu(c))] {
            assert!(
                out.iter().all(|v| (0.0..=1.0).contains(v)),
                "{side}: {out:?} for {c:?}"
            );
        }
    }
    eprintln!(
        "soft particles: {} adversarial cases in [0, 1] on gpu and cpu",
        cases.len()
    );
}
