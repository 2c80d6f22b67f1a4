//! The fractal sum's statistics and the wind animation: noise_animated as the
//! advected noise_fbm, against the CPU mirror, and the pattern moving with the wind.

use super::{Rng, eval_gpu};
use crate::common::{gpu, run_f32};
use glam::Vec3;
use volfog::cpu::noise::noise_animated;

#[test]
fn noise_statistics_are_centred() {
    let gpu = gpu();
    let mut rng = Rng(31);
    let n = 1 << 18;
    // Points uniform over two full periods per axis, far apart compared with the
    // correlation length (1 lattice unit), so the samples are nearly independent.
    let pts: Vec<Vec3> = (0..n).map(|_| rng.vec(-256.0, 256.0)).collect();
    let mut report = Vec::new();
    for octaves in 1..=4u32 {
        let items: Vec<(Vec3, u32)> = pts.iter().map(|&p| (p, octaves)).collect();
        let out = eval_gpu(gpu, &items);
        let values: Vec<f64> = out.iter().map(|&(_, f)| f as f64).collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let std = var.sqrt();
        let positive = values.iter().filter(|&&v| v > 0.0).count() as f64 / n as f64;
        // Standard error of the mean is std / sqrt(n) ~ 4e-4: the bound is ~7 of them.
        assert!(mean.abs() < 3e-3, "octaves {octaves}: mean {mean}");
        assert!(
            (0.15..0.3).contains(&std),
            "octaves {octaves}: standard deviation {std}"
        );
        assert!(
            (positive - 0.5).abs() < 5e-3,
            "octaves {octaves}: fraction positive {positive}"
        );
        report.push(format!(
            "{octaves} octave(s): mean {mean:+.2e}, std {std:.4}, positive {positive:.4}"
        ));
    }
    eprintln!(
        "statistics over {n} points (|mean| < 3e-3, std in [0.15, 0.3], positive 0.5 +- 5e-3): {}",
        report.join("; ")
    );
}

/// noise_animated and noise_fbm of the advected point, per item: input (p, scale),
/// (wind, time), (octaves, 0, 0, 0); two outputs.
const ANIM_KERNEL: &str = r#"
#import volfog::noise::{noise_fbm, noise_animated}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 3u * i >= arrayLength(&input) { return; }
    let p = input[3u * i].xyz;
    let scale = input[3u * i].w;
    let wind = input[3u * i + 1u].xyz;
    let time = input[3u * i + 1u].w;
    let octaves = u32(input[3u * i + 2u].x);
    output[2u * i] = noise_animated(p, scale, wind, time, octaves);
    output[2u * i + 1u] = noise_fbm((p - wind * time) * scale, octaves);
}
"#;

#[test]
fn animated_noise_is_advected_fbm() {
    let gpu = gpu();
    let mut rng = Rng(41);
    let mut inputs: Vec<f32> = Vec::new();
    let mut cases = Vec::new();
    // Dyadic inputs (p in 1/64 m, wind in 1/16 m/s, time in 1/8 s, scale m / 2^k with
    // m odd < 8): (p - wind time) scale is exact in f32 however a compiler contracts
    // it, so the comparison sees the noise, not the rounding of its argument.
    let dyadic =
        |rng: &mut Rng, lo: f32, hi: f32, steps: f32| (rng.range(lo, hi) * steps).round() / steps;
    for i in 0..20_000 {
        let p = Vec3::new(
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
        );
        let scale = (1 + 2 * rng.int(0, 3)) as f32 / (1 << rng.int(2, 7)) as f32;
        let wind = Vec3::new(
            dyadic(&mut rng, -15.0, 15.0, 16.0),
            dyadic(&mut rng, -15.0, 15.0, 16.0),
            dyadic(&mut rng, -15.0, 15.0, 16.0),
        );
        let time = if i % 5 == 0 {
            0.0
        } else {
            dyadic(&mut rng, 0.0, 600.0, 8.0)
        };
        let octaves = 1 + (i % 4) as u32;
        inputs.extend_from_slice(&[p.x, p.y, p.z, scale, wind.x, wind.y, wind.z, time]);
        inputs.extend_from_slice(&[octaves as f32, 0.0, 0.0, 0.0]);
        cases.push((p, scale, wind, time, octaves));
    }
    let out = run_f32(
        gpu,
        ANIM_KERNEL,
        &inputs,
        2 * cases.len(),
        cases.len() as u32,
    );
    let tol = 1e-5f32;
    let (mut worst_same, mut worst_cpu) = (0.0f32, 0.0f32);
    for (k, &(p, s, w, t, o)) in cases.iter().enumerate() {
        let (anim, fbm) = (out[2 * k], out[2 * k + 1]);
        let cpu = noise_animated(p, s, w, t, o);
        worst_same = worst_same.max((anim - fbm).abs());
        worst_cpu = worst_cpu.max((anim - cpu).abs());
        assert!(
            (anim - fbm).abs() <= tol,
            "noise_animated {anim} vs fbm {fbm}"
        );
        assert!(
            (anim - cpu).abs() <= tol,
            "noise_animated gpu {anim} cpu {cpu}"
        );
    }

    // The pattern moves with the wind: at time t, the point p + wind t shows what p
    // showed at time 0. Values chosen so that every product and sum is exact in f32.
    let wind = Vec3::new(2.0, -0.5, 1.25);
    let mut inputs = Vec::new();
    let mut starts = Vec::new();
    for _ in 0..4096 {
        let p = (rng.vec(-100.0, 100.0) * 64.0).round() / 64.0;
        let t = rng.int(1, 300) as f32;
        starts.push(p);
        for (q, time) in [(p, 0.0), (p + wind * t, t)] {
            inputs.extend_from_slice(&[q.x, q.y, q.z, 0.25, wind.x, wind.y, wind.z, time]);
            inputs.extend_from_slice(&[3.0, 0.0, 0.0, 0.0]);
        }
    }
    let n = 2 * starts.len();
    let moved = run_f32(gpu, ANIM_KERNEL, &inputs, 2 * n, n as u32);
    let mut worst_move = 0.0f32;
    for k in 0..starts.len() {
        let (before, after) = (moved[4 * k], moved[4 * k + 2]);
        worst_move = worst_move.max((before - after).abs());
        assert!(
            (before - after).abs() <= 1e-6,
            "at {}: {before} at t = 0, {after} after advection",
            starts[k]
        );
    }
    eprintln!(
        "animation: {} cases, |noise_animated - noise_fbm((p - w t) s)| <= {worst_same:e}, \
         |gpu - cpu| <= {worst_cpu:e} (bound {tol:e}); advected pattern: max change {worst_move:e} \
         (bound 1e-6) over {} points",
        cases.len(),
        starts.len()
    );
}
