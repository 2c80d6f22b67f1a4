//! Phase functions on the GPU: against the CPU mirror, against their normalisation
//! integral over the sphere, and the SH forms against closed forms.

use crate::common;

use common::{gpu, rel_err, run_f32};
use glam::{Vec3, Vec4};
use volfog::cpu::phase::*;

/// Every phase function evaluated per (cos_theta, g), 13 outputs per item.
const EVAL_KERNEL: &str = r#"
#import volfog::phase::{phase_isotropic, phase_hg, phase_schlick, schlick_k,
    phase_cornette_shanks, phase_rayleigh, phase_hg_two_lobe, phase_hg_zonal_sh, phase_hg_sh_l1}

@group(0) @binding(0) var<storage, read> input: array<vec2<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i].x;
    let g = input[i].y;
    let o = i * 13u;
    output[o + 0u] = phase_isotropic();
    output[o + 1u] = phase_hg(c, g);
    output[o + 2u] = phase_schlick(c, schlick_k(g));
    output[o + 3u] = phase_cornette_shanks(c, g);
    output[o + 4u] = phase_rayleigh(c);
    output[o + 5u] = phase_hg_two_lobe(c, g, -0.5 * g, 0.3);
    let z = phase_hg_zonal_sh(g);
    output[o + 6u] = z.x;
    output[o + 7u] = z.y;
    output[o + 8u] = z.z;
    let s = sqrt(max(1.0 - c * c, 0.0));
    let sh = phase_hg_sh_l1(vec3<f32>(s * 0.6, c, s * 0.8), g);
    output[o + 9u] = sh.x;
    output[o + 10u] = sh.y;
    output[o + 11u] = sh.z;
    output[o + 12u] = sh.w;
}
"#;

fn cpu_eval(c: f32, g: f32) -> [f32; 13] {
    let z = phase_hg_zonal_sh(g);
    let s = (1.0 - c * c).max(0.0).sqrt();
    let sh = phase_hg_sh_l1(Vec3::new(s * 0.6, c, s * 0.8), g);
    [
        phase_isotropic(),
        phase_hg(c, g),
        phase_schlick(c, schlick_k(g)),
        phase_cornette_shanks(c, g),
        phase_rayleigh(c),
        phase_hg_two_lobe(c, g, -0.5 * g, 0.3),
        z.x,
        z.y,
        z.z,
        sh.x,
        sh.y,
        sh.z,
        sh.w,
    ]
}

fn g_values() -> Vec<f32> {
    (0..=38).map(|i| -0.95 + 0.05 * i as f32).collect()
}

#[test]
fn phase_functions_match_cpu_mirror() {
    let gpu = gpu();
    let mut inputs = Vec::new();
    for g in g_values() {
        for i in 0..=100 {
            inputs.push(-1.0 + 0.02 * i as f32);
            inputs.push(g);
        }
    }
    let n = inputs.len() / 2;
    let out = run_f32(gpu, EVAL_KERNEL, &inputs, n * 13, n as u32);
    let mut worst = 0.0f32;
    for i in 0..n {
        let want = cpu_eval(inputs[2 * i], inputs[2 * i + 1]);
        for k in 0..13 {
            // SH coefficients cross zero; compare them against the band constant.
            let e = rel_err(out[i * 13 + k], want[k], 1e-3);
            worst = worst.max(e);
            assert!(
                e <= 1e-4,
                "output {k} at cos={} g={}: gpu {} cpu {} (rel {e:e})",
                inputs[2 * i],
                inputs[2 * i + 1],
                out[i * 13 + k],
                want[k]
            );
        }
    }
    eprintln!(
        "phase: {} evaluations x 13 outputs, worst relative error {worst:e} (bound 1e-4)",
        n
    );
}

/// Integrates a phase function over the sphere on the GPU: composite Simpson in theta
/// with 4096 intervals, 2 pi sin(theta) p(cos theta).
const NORM_KERNEL: &str = r#"
#import volfog::phase::{phase_isotropic, phase_hg, phase_schlick, phase_cornette_shanks,
    phase_rayleigh, phase_hg_two_lobe}

@group(0) @binding(0) var<storage, read> input: array<vec2<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

fn eval(which: u32, c: f32, g: f32) -> f32 {
    switch which {
        case 0u: { return phase_isotropic(); }
        case 1u: { return phase_hg(c, g); }
        case 2u: { return phase_schlick(c, g); }
        case 3u: { return phase_cornette_shanks(c, g); }
        case 4u: { return phase_rayleigh(c); }
        default: { return phase_hg_two_lobe(c, g, -0.5 * g, 0.3); }
    }
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let which = u32(input[i].x);
    let g = input[i].y;
    let n = 4096u;
    let pi = 3.14159265358979;
    let h = pi / f32(n);
    var sum = 0.0;
    for (var k = 0u; k <= n; k++) {
        let theta = f32(k) * h;
        var w = select(2.0, 4.0, (k & 1u) == 1u);
        if k == 0u || k == n { w = 1.0; }
        sum += w * sin(theta) * eval(which, cos(theta), g);
    }
    output[i] = 2.0 * pi * sum * h / 3.0;
}
"#;

#[test]
fn phase_functions_integrate_to_one_on_gpu() {
    let gpu = gpu();
    let names = [
        "isotropic",
        "hg",
        "schlick(k=g)",
        "cornette-shanks",
        "rayleigh",
        "two-lobe hg",
    ];
    let mut inputs = Vec::new();
    for which in 0..names.len() {
        for g in g_values() {
            inputs.push(which as f32);
            inputs.push(g);
        }
    }
    let n = inputs.len() / 2;
    let out = run_f32(gpu, NORM_KERNEL, &inputs, n, n as u32);
    let mut worst = vec![0.0f32; names.len()];
    for i in 0..n {
        let which = inputs[2 * i] as usize;
        let err = (out[i] - 1.0).abs();
        worst[which] = worst[which].max(err);
        assert!(
            err <= 1e-3,
            "{} with g={} integrates to {} over the sphere",
            names[which],
            inputs[2 * i + 1],
            out[i]
        );
    }
    for (name, w) in names.iter().zip(worst) {
        eprintln!("normalisation {name:16} max |integral - 1| = {w:e} (g in [-0.95, 0.95])");
    }
}

/// In-scattered radiance of an L1 environment L(w) = a + b.w through the rotated HG
/// SH: the exact answer is a + g (b.dir), since HG's mean cosine is g.
const SH_KERNEL: &str = r#"
#import volfog::phase::{phase_hg_sh_l1, phase_sh_l1_radiance}

struct Case { dir: vec4<f32>, sh_r: vec4<f32>, sh_g: vec4<f32>, sh_b: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let phase = phase_hg_sh_l1(c.dir.xyz, c.dir.w);
    output[i] = vec4<f32>(phase_sh_l1_radiance(phase, c.sh_r, c.sh_g, c.sh_b), 0.0);
}
"#;

/// SH projection (Y00, Y1-1, Y10, Y11) of L(w) = a + b.w.
fn project_linear(a: f32, b: Vec3) -> Vec4 {
    let four_pi = 4.0 * std::f32::consts::PI;
    let k1 = SH_Y1 * four_pi / 3.0;
    Vec4::new(a * four_pi.sqrt(), k1 * b.y, k1 * b.z, k1 * b.x)
}

#[test]
fn hg_sh_l1_matches_closed_form_on_gpu() {
    let gpu = gpu();
    let mut inputs: Vec<f32> = Vec::new();
    let mut expected = Vec::new();
    let mut seed = 12345u32;
    let mut rnd = || {
        seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
        (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    };
    for _ in 0..256 {
        let dir = Vec3::new(rnd(), rnd(), rnd()).normalize_or(Vec3::Z);
        let g = 0.95 * rnd();
        let env: Vec<(f32, Vec3)> = (0..3)
            .map(|_| (1.0 + rnd().abs(), Vec3::new(rnd(), rnd(), rnd()) * 0.9))
            .collect();
        inputs.extend(dir.extend(g).to_array());
        for (a, b) in &env {
            inputs.extend(project_linear(*a, *b).to_array());
        }
        expected.push(Vec3::from_array(std::array::from_fn(|c| {
            env[c].0 + g * env[c].1.dot(dir)
        })));
    }
    let out = run_f32(
        gpu,
        SH_KERNEL,
        &inputs,
        expected.len() * 4,
        expected.len() as u32,
    );
    let mut worst = 0.0f32;
    for (i, want) in expected.iter().enumerate() {
        for c in 0..3 {
            let e = rel_err(out[i * 4 + c], want[c], 1e-2);
            worst = worst.max(e);
            assert!(
                e <= 1e-4,
                "case {i} channel {c}: gpu {} closed form {}",
                out[i * 4 + c],
                want[c]
            );
        }
    }
    eprintln!("HG L1 SH vs closed form a + g b.dir: worst relative error {worst:e} (bound 1e-4)");
}

/// The zonal coefficients against a high-resolution projection of HG onto
/// Y_l0 = sqrt((2l+1)/(4 pi)) P_l (f64 midpoint rule, 200000 intervals in theta).
#[test]
fn hg_zonal_sh_matches_numerical_projection() {
    let gpu = gpu();
    let gs: Vec<f32> = (0..=18).map(|i| -0.9 + 0.1 * i as f32).collect();
    let inputs: Vec<f32> = gs.iter().flat_map(|&g| [0.3, g]).collect();
    let out = run_f32(gpu, EVAL_KERNEL, &inputs, gs.len() * 13, gs.len() as u32);
    for (i, &g) in gs.iter().enumerate() {
        let g64 = g as f64;
        let n = 200_000;
        let h = std::f64::consts::PI / n as f64;
        let mut z = [0.0f64; 3];
        for k in 0..n {
            let theta = (k as f64 + 0.5) * h;
            let c = theta.cos();
            let d = 1.0 + g64 * g64 - 2.0 * g64 * c;
            let p = (1.0 - g64 * g64) / (4.0 * std::f64::consts::PI * d * d.sqrt());
            let legendre = [1.0, c, 0.5 * (3.0 * c * c - 1.0)];
            for l in 0..3 {
                let y = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt() * legendre[l];
                z[l] += 2.0 * std::f64::consts::PI * p * y * theta.sin() * h;
            }
        }
        for l in 0..3 {
            let got = out[i * 13 + 6 + l] as f64;
            assert!(
                (got - z[l]).abs() <= 1e-4 * z[0],
                "g={g} band {l}: gpu {got} numerical {}",
                z[l]
            );
        }
    }
}
