//! Closed-form height fog (`volfog::height_fog`, Wenzel 2007 eq. 2) on the GPU: against
//! the CPU mirror, against high-resolution numerical integration in f64 (generic,
//! near-horizontal, steep, tiny and zero-length segments), continuity across the
//! near-horizontal series switch, and finiteness for adversarial inputs.

use crate::common;

use common::Rng;

use common::{gpu, rel_err, run_f32};
use glam::Vec3;
use volfog::cpu::height_fog::*;
use volfog::uniforms::HeightFog;

/// Outputs per case: optical depth, transmittance, height_fog rgba, E(origin.w),
/// fog_inscatter(1, segment.w).
const OUTPUTS: usize = 8;

const KERNEL: &str = r#"
#import volfog::types::HeightFog
#import volfog::height_fog::{height_fog, height_fog_optical_depth, height_fog_transmittance,
    exp_segment_average, fog_inscatter}

struct Case { fog: HeightFog, origin: vec4<f32>, segment: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let f = c.fog;
    let o = i * 8u;
    output[o + 0u] = height_fog_optical_depth(f.density, f.falloff, f.base_height, f.up,
                                              c.origin.xyz, c.segment.xyz);
    output[o + 1u] = height_fog_transmittance(f.density, f.falloff, f.base_height, f.up,
                                              c.origin.xyz, c.segment.xyz);
    let r = height_fog(f, c.origin.xyz, c.segment.xyz);
    output[o + 2u] = r.x;
    output[o + 3u] = r.y;
    output[o + 4u] = r.z;
    output[o + 5u] = r.w;
    output[o + 6u] = exp_segment_average(c.origin.w);
    output[o + 7u] = fog_inscatter(vec3<f32>(1.0), c.segment.w).x;
}
"#;

/// One evaluation: the fog, the segment and two scalars for the helpers.
#[derive(Clone, Copy, Debug)]
struct Case {
    fog: HeightFog,
    origin: Vec3,
    segment: Vec3,
    x: f32,
    od: f32,
}

impl Case {
    fn new(fog: HeightFog, origin: Vec3, segment: Vec3) -> Self {
        Self {
            fog,
            origin,
            segment,
            x: 0.0,
            od: 0.0,
        }
    }

    fn push(&self, out: &mut Vec<f32>) {
        // The uniform's own layout (encase), words as f32 bit patterns.
        out.extend(
            self.fog
                .to_bytes()
                .chunks_exact(4)
                .map(|w| f32::from_le_bytes([w[0], w[1], w[2], w[3]])),
        );
        out.extend(self.origin.extend(self.x).to_array());
        out.extend(self.segment.extend(self.od).to_array());
    }

    fn cpu(&self) -> [f32; OUTPUTS] {
        let f = &self.fog;
        let args = (f.density, f.falloff, f.base_height, f.up);
        let r = height_fog(f, self.origin, self.segment);
        [
            height_fog_optical_depth(args.0, args.1, args.2, args.3, self.origin, self.segment),
            height_fog_transmittance(args.0, args.1, args.2, args.3, self.origin, self.segment),
            r.x,
            r.y,
            r.z,
            r.w,
            exp_segment_average(self.x),
            fog_inscatter(Vec3::ONE, self.od).x,
        ]
    }
}

fn run_gpu(cases: &[Case]) -> Vec<[f32; OUTPUTS]> {
    let gpu = gpu();
    let mut input = Vec::new();
    for c in cases {
        c.push(&mut input);
    }
    assert_eq!(input.len(), cases.len() * 28, "Case is 112 bytes in WGSL");
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

/// A unit vector perpendicular to `up`.
fn perpendicular(up: Vec3, rng: &mut Rng) -> Vec3 {
    loop {
        let v = rng.unit();
        let p = v - up * v.dot(up);
        if p.length() > 0.1 {
            return p.normalize();
        }
    }
}

fn random_fog(rng: &mut Rng) -> HeightFog {
    HeightFog::new(
        Vec3::new(rng.f(), rng.f(), rng.f()) * 2.0,
        rng.log(1e-4, 1.0),
        rng.unit(),
        rng.range(-0.05, 0.3),
        rng.range(-50.0, 50.0),
    )
    .unwrap()
    .with_sun(
        rng.unit(),
        Vec3::new(rng.f(), rng.f(), rng.f()) * 20.0,
        rng.range(-0.9, 0.9),
    )
    .unwrap()
}

/// The largest exponent -c (dot(p, up) - h0) along the segment, in f64.
fn max_exponent(c: &Case) -> f64 {
    let f = &c.fog;
    let h = |p: Vec3| -(f.falloff as f64) * (dot64(p, f.up) - f.base_height as f64);
    h(c.origin).max(h(c.origin + c.segment))
}

fn dot64(a: Vec3, b: Vec3) -> f64 {
    a.x as f64 * b.x as f64 + a.y as f64 * b.y as f64 + a.z as f64 * b.z as f64
}

/// Segments of every kind the closed form must handle; exponents stay within
/// [-40, 40] so no clamp applies (the numerical reference has none).
fn numeric_cases() -> Vec<(&'static str, Case)> {
    let mut rng = Rng(0x05ee_df06);
    let mut cases = Vec::new();
    let add = |kind: &'static str, c: Case, cases: &mut Vec<(&'static str, Case)>| {
        if max_exponent(&c).abs() <= 40.0 {
            cases.push((kind, c));
        }
    };
    for _ in 0..1500 {
        let fog = random_fog(&mut rng);
        let o = rng.vec(100.0);
        let d = rng.unit() * rng.log(0.01, 400.0);
        add("generic", Case::new(fog, o, d), &mut cases);
    }
    for _ in 0..1500 {
        // Near-horizontal: the vertical part is a tiny (or zero) fraction of the length.
        let fog = random_fog(&mut rng);
        let o = rng.vec(100.0);
        let h = perpendicular(fog.up, &mut rng);
        let len = rng.log(0.1, 1000.0);
        let slope = match rng.f() {
            s if s < 0.2 => 0.0,
            s if s < 0.6 => rng.log(1e-9, 1e-2) * if rng.f() < 0.5 { -1.0 } else { 1.0 },
            _ => rng.range(-0.05, 0.05),
        };
        let d = (h + fog.up * slope) * len;
        add("near-horizontal", Case::new(fog, o, d), &mut cases);
    }
    for _ in 0..500 {
        // Steep: straight up or down through the layer, |c dz| up to tens.
        let fog = random_fog(&mut rng);
        let o = rng.vec(60.0);
        let sign = if rng.f() < 0.5 { -1.0 } else { 1.0 };
        let d = (fog.up * sign + rng.vec(0.1)) * rng.log(1.0, 150.0);
        add("steep", Case::new(fog, o, d), &mut cases);
    }
    for _ in 0..300 {
        let fog = random_fog(&mut rng);
        let o = rng.vec(100.0);
        let d = rng.unit() * rng.log(1e-7, 1e-3);
        add("tiny", Case::new(fog, o, d), &mut cases);
    }
    for _ in 0..100 {
        let fog = random_fog(&mut rng);
        add(
            "zero-length",
            Case::new(fog, rng.vec(100.0), Vec3::ZERO),
            &mut cases,
        );
    }
    for _ in 0..200 {
        // Uniform fog (c = 0): OD = b |d|.
        let mut fog = random_fog(&mut rng);
        fog.falloff = 0.0;
        let d = rng.unit() * rng.log(0.01, 400.0);
        add("uniform", Case::new(fog, rng.vec(100.0), d), &mut cases);
    }
    cases
}

/// Optical depth by composite Simpson in f64 with 2^14 intervals over t in [0, 1].
fn numeric_od(c: &Case) -> f64 {
    let f = &c.fog;
    let (b, k, h0) = (f.density as f64, f.falloff as f64, f.base_height as f64);
    let len = (dot64(c.segment, c.segment)).sqrt();
    let density = |t: f64| {
        let p = [0, 1, 2].map(|i| c.origin[i] as f64 + t * c.segment[i] as f64);
        let h = p[0] * f.up.x as f64 + p[1] * f.up.y as f64 + p[2] * f.up.z as f64;
        b * (-k * (h - h0)).exp()
    };
    let n = 1 << 14;
    let step = 1.0 / n as f64;
    let mut sum = density(0.0) + density(1.0);
    for i in 1..n {
        sum += density(i as f64 * step) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * step / 3.0 * len
}

/// In-scattered radiance by marching the transfer equation in f64 (2^14 steps, each
/// homogeneous at its midpoint density): dL = T sigma C ds, dT = -T sigma ds, with
/// C = color + sun_color HG(cos) and HG evaluated here from its definition.
fn numeric_inscatter(c: &Case) -> ([f64; 3], f64) {
    let f = &c.fog;
    let len = dot64(c.segment, c.segment).sqrt();
    let cos = if len > 0.0 {
        (dot64(c.segment, f.sun_direction) / len).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let g = f.sun_g as f64;
    let hg = (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * cos).powf(1.5));
    let radiance = [0, 1, 2].map(|i| f.color[i] as f64 + f.sun_color[i] as f64 * hg);
    let n = 1 << 14;
    let mut t = 1.0f64;
    let mut l = 0.0f64;
    for i in 0..n {
        let s = (i as f64 + 0.5) / n as f64;
        let p = [0, 1, 2].map(|j| c.origin[j] as f64 + s * c.segment[j] as f64);
        let h = p[0] * f.up.x as f64 + p[1] * f.up.y as f64 + p[2] * f.up.z as f64;
        let sigma = f.density as f64 * (-(f.falloff as f64) * (h - f.base_height as f64)).exp();
        let tau = sigma * len / n as f64;
        l += t * -(-tau).exp_m1();
        t *= (-tau).exp();
    }
    (radiance.map(|r| r * l), t)
}

#[test]
fn height_fog_matches_cpu_mirror() {
    let mut rng = Rng(42);
    let mut cases: Vec<Case> = numeric_cases().into_iter().map(|(_, c)| c).collect();
    for c in cases.iter_mut() {
        c.x = match rng.f() {
            s if s < 0.3 => rng.range(-1.5, 1.5),
            s if s < 0.6 => rng.log(1e-8, 1.0) * if rng.f() < 0.5 { -1.0 } else { 1.0 },
            _ => rng.range(-80.0, 200.0),
        };
        c.od = rng.log(1e-9, 100.0);
    }
    let gpu = run_gpu(&cases);
    // Shader exp is exact to 3 + 2|x| ulp (Vulkan); results carried by exp(x) get that
    // much on top of a 1e-5 relative bound: x is the density exponent for the optical
    // depth and in-scatter, the optical depth for the transmittance, x for E(x).
    let exp_tol = |x: f64| 1e-5 + (3.0 + 2.0 * x.abs()) * f32::EPSILON as f64;
    let names = [
        "optical depth",
        "transmittance",
        "rgb.r",
        "rgb.g",
        "rgb.b",
        "a",
        "E(x)",
        "1 - T",
    ];
    let mut worst = [0.0f64; OUTPUTS];
    for (c, got) in cases.iter().zip(&gpu) {
        let want = c.cpu();
        let e_max = max_exponent(c);
        let od = want[0] as f64;
        // T = exp(-OD) also turns the relative error of OD into od times as much.
        let t_tol = exp_tol(od) + od * exp_tol(e_max);
        let bounds = [
            exp_tol(e_max),
            t_tol,
            exp_tol(e_max),
            exp_tol(e_max),
            exp_tol(e_max),
            t_tol,
            exp_tol(c.x as f64),
            exp_tol(0.0),
        ];
        for k in 0..OUTPUTS {
            let e = rel_err(got[k], want[k], 1e-30) as f64;
            let bound = bounds[k];
            worst[k] = worst[k].max(e / bound);
            assert!(
                e <= bound,
                "{}: gpu {} cpu {} (rel {e:e}, bound {bound:e}) for {c:?}",
                names[k],
                got[k],
                want[k]
            );
        }
    }
    for (name, w) in names.iter().zip(worst) {
        eprintln!(
            "height fog gpu vs cpu {name:14} worst relative error {w:.3} of its bound \
             1e-5 + (3 + 2|x|) ulp (T: + OD x the OD bound)"
        );
    }
}

#[test]
fn height_fog_matches_numerical_integration() {
    let cases = numeric_cases();
    let plain: Vec<Case> = cases.iter().map(|(_, c)| *c).collect();
    let gpu = run_gpu(&plain);
    let mut worst: std::collections::BTreeMap<&str, (f64, f64)> = Default::default();
    for ((kind, c), got) in cases.iter().zip(&gpu) {
        let want_od = numeric_od(c);
        let (want_l, want_t) = numeric_inscatter(c);
        let cpu = c.cpu();
        for (side, out) in [("cpu", &cpu), ("gpu", got)] {
            assert!(
                out.iter().all(|v| v.is_finite()),
                "{side} {kind}: non-finite {out:?} for {c:?}"
            );
            let od = out[0] as f64;
            let e_od = if want_od == 0.0 {
                assert_eq!(od, 0.0, "{side} {kind}: zero-length segment gives {od}");
                0.0
            } else {
                (od - want_od).abs() / want_od
            };
            assert!(
                e_od <= 1e-3,
                "{side} {kind}: OD {od} numerical {want_od} (rel {e_od:e}) for {c:?}"
            );
            // Transmittance and in-scatter: relative to the fog actually present.
            // T near 1 is resolved to f32 spacing only (2^-24 below 1): allow 4 of those.
            let e_t = ((out[5] as f64 - want_t).abs() - 4.0 * 2f64.powi(-24)).max(0.0)
                / (1.0 - want_t).max(1e-30);
            let e_l = (0..3)
                .map(|i| (out[2 + i] as f64 - want_l[i]).abs() / (want_l[i].max(1e-30)))
                .fold(0.0f64, f64::max);
            let e_l = if want_od == 0.0 { 0.0 } else { e_l };
            assert!(
                e_t <= 1e-3,
                "{side} {kind}: T {} numerical {want_t} for {c:?}",
                out[5]
            );
            assert!(
                e_l <= 1e-3,
                "{side} {kind}: in-scatter {:?} numerical {want_l:?} (rel {e_l:e}) for {c:?}",
                &out[2..5]
            );
            if side == "gpu" {
                let w = worst.entry(kind).or_default();
                w.0 = w.0.max(e_od);
                w.1 = w.1.max(e_l);
            }
        }
    }
    for (kind, (od, l)) in worst {
        eprintln!(
            "height fog vs f64 numerical ({kind:15}): worst relative error OD {od:e}, \
             in-scatter {l:e} (bound 1e-3)"
        );
    }
}

/// Exact optical depth in f64 (the closed form with expm1, no series).
fn exact_od(b: f64, c: f64, h0: f64, up: Vec3, o: Vec3, d: Vec3) -> f64 {
    let h = dot64(o, up) - h0;
    let x = c * dot64(d, up);
    let mean = if x == 0.0 { 1.0 } else { -(-x).exp_m1() / x };
    b * dot64(d, d).sqrt() * (-c * h).exp() * mean
}

/// Sweeps the slope of a segment through 0 (vertical extent from -s to +s over a fixed
/// horizontal run) and checks the optical depth falls monotonically as the segment
/// tilts upwards, and that every step between neighbours matches the exact step within
/// 1e-6 of the value: a switch between formulas (the seed's hard slope threshold, or a
/// series/direct seam) would show as a jump.
fn check_sweep(label: &str, od: &[f32], exact: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..od.len() - 1 {
        let (a, b) = (od[i] as f64, od[i + 1] as f64);
        assert!(
            b <= a * (1.0 + 1e-6),
            "{label}: optical depth rises at step {i}: {a} -> {b}"
        );
        let step = (b - a) - (exact[i + 1] - exact[i]);
        let rel = step.abs() / exact[i];
        worst = worst.max(rel);
        assert!(
            rel <= 1e-6,
            "{label}: step {i} off by {rel:e} of the value ({a} -> {b}, exact {} -> {})",
            exact[i],
            exact[i + 1]
        );
    }
    worst
}

#[test]
fn height_fog_is_smooth_through_horizontal() {
    // Sweep A: +Y up, x = c * dz crosses 0 and the series limit |x| = 1 (x in [-3, 3]).
    // Sweep B: a tilted axis, slopes within +-1e-3 around exactly horizontal.
    let mut sweeps: Vec<(&str, HeightFog, Vec3, Vec<Vec3>)> = Vec::new();
    let n = 4001;
    let fog_a = HeightFog::new(Vec3::ONE, 0.02, Vec3::Y, 0.03, 0.0).unwrap();
    let a: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(100.0, -100.0 + 200.0 * i as f32 / (n - 1) as f32, 0.0))
        .collect();
    sweeps.push(("sweep A (+Y, |x| <= 3)", fog_a, Vec3::new(0.0, 2.0, 0.0), a));
    let up_b = Vec3::new(1.0, 2.0, 3.0).normalize();
    let fog_b = HeightFog::new(Vec3::ONE, 0.05, up_b, 0.02, 1.0).unwrap();
    let h = Vec3::new(3.0, 0.0, -1.0).normalize();
    let b: Vec<Vec3> = (0..n)
        .map(|i| (h + up_b * (-1e-3 + 2e-3 * i as f32 / (n - 1) as f32)) * 15.0)
        .collect();
    sweeps.push((
        "sweep B (tilted, |slope| <= 1e-3)",
        fog_b,
        Vec3::new(-4.0, 1.0, 2.0),
        b,
    ));

    for (label, fog, origin, segments) in sweeps {
        let cases: Vec<Case> = segments
            .iter()
            .map(|&d| Case::new(fog, origin, d))
            .collect();
        let gpu: Vec<f32> = run_gpu(&cases).iter().map(|o| o[0]).collect();
        let cpu: Vec<f32> = cases.iter().map(|c| c.cpu()[0]).collect();
        let exact: Vec<f64> = segments
            .iter()
            .map(|&d| {
                exact_od(
                    fog.density as f64,
                    fog.falloff as f64,
                    fog.base_height as f64,
                    fog.up,
                    origin,
                    d,
                )
            })
            .collect();
        let wg = check_sweep(&format!("{label} gpu"), &gpu, &exact);
        let wc = check_sweep(&format!("{label} cpu"), &cpu, &exact);
        eprintln!(
            "{label}: {n} slopes, worst step deviation gpu {wg:e}, cpu {wc:e} of the value \
             (bound 1e-6)"
        );
    }
}

#[test]
fn exp_segment_average_matches_f64_everywhere() {
    // E(x) = (1 - e^-x) / x against f64 expm1, log-spaced through both series limits.
    let mut xs = vec![0.0f32];
    for i in 0..=2000 {
        let m = 10f32.powf(-9.0 + 11.0 * i as f32 / 2000.0);
        xs.push(m);
        if m <= 80.0 {
            xs.push(-m);
        }
    }
    let cases: Vec<Case> = xs
        .iter()
        .map(|&x| {
            let mut c = Case::new(
                HeightFog::new(Vec3::ONE, 0.1, Vec3::Y, 0.1, 0.0).unwrap(),
                Vec3::ZERO,
                Vec3::X,
            );
            c.x = x;
            c.od = x.abs();
            c
        })
        .collect();
    let gpu = run_gpu(&cases);
    let mut worst = [0.0f64; 2];
    for (c, g) in cases.iter().zip(&gpu) {
        let x = c.x as f64;
        let want = if x == 0.0 { 1.0 } else { -(-x).exp_m1() / x };
        let od = c.od as f64;
        let want_fog = -(-od).exp_m1();
        // exp(-x) on the GPU is exact to 3 + 2|x| ulp (Vulkan); for x < 0 it carries E.
        let bound = 1e-6
            + if x < 0.0 {
                2.0 * x.abs() * f32::EPSILON as f64
            } else {
                0.0
            };
        for got in [g[6], c.cpu()[6]] {
            let e = (got as f64 - want).abs() / want;
            worst[0] = worst[0].max(e / bound);
            assert!(
                e <= bound,
                "E({x}) = {got}, f64 {want} (rel {e:e}, bound {bound:e})"
            );
        }
        for got in [g[7], c.cpu()[7]] {
            let e = (got as f64 - want_fog).abs() / want_fog.max(1e-30);
            worst[1] = worst[1].max(e / 1e-6);
            assert!(
                e <= 1e-6,
                "1 - exp(-{od}) = {got}, f64 {want_fog} (rel {e:e})"
            );
        }
    }
    eprintln!(
        "E(x) over x in [-80, 1e2]: worst error {:.3} of its bound 1e-6 (+ 2|x| ulp for \
         x < 0); 1 - T: {:.3} of 1e-6",
        worst[0], worst[1]
    );
}

#[test]
fn height_fog_is_finite_for_adversarial_inputs() {
    let scalars = [
        0.0f32, 1e-30, -1e-30, 1e-7, 1.0, -1.0, 80.0, -80.0, 1e3, -1e3, 1e9, -1e9, 1e30, -1e30,
        3.4e38, -3.4e38,
    ];
    let vectors = [
        Vec3::ZERO,
        Vec3::Y,
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(1e-30, 0.0, -1e-30),
        Vec3::new(1e30, -1e30, 1e30),
        Vec3::splat(3.4e38),
        Vec3::new(-3.4e38, 3.4e38, 1.0),
        Vec3::new(1e9, 1.0, -1e9),
        Vec3::new(5.0, 1e-7, 0.0),
    ];
    let mut rng = Rng(7);
    let mut cases = Vec::new();
    for _ in 0..20000 {
        let pick =
            |rng: &mut Rng| scalars[(rng.f() * scalars.len() as f32) as usize % scalars.len()];
        let pickv =
            |rng: &mut Rng| vectors[(rng.f() * vectors.len() as f32) as usize % vectors.len()];
        // Any finite geometry and coefficients; colours within their documented range.
        let fog = HeightFog {
            color: Vec3::new(1e9, 0.0, 1.0),
            density: pick(&mut rng),
            up: if rng.f() < 0.5 {
                rng.unit()
            } else {
                pickv(&mut rng)
            },
            falloff: pick(&mut rng),
            sun_direction: pickv(&mut rng),
            base_height: pick(&mut rng),
            sun_color: Vec3::new(1e9, 1.0, 0.0),
            sun_g: pick(&mut rng),
            top_height: pick(&mut rng),
            sun_transmittance: u32::from(rng.f() < 0.5),
        };
        let mut c = Case::new(fog, pickv(&mut rng), pickv(&mut rng));
        c.x = pick(&mut rng);
        c.od = pick(&mut rng);
        cases.push(c);
    }
    let gpu = run_gpu(&cases);
    for (c, g) in cases.iter().zip(&gpu) {
        for (side, out) in [("gpu", *g), ("cpu", c.cpu())] {
            assert!(
                out.iter().all(|v| v.is_finite()),
                "{side}: non-finite output {out:?} for {c:?}"
            );
            assert!(out[0] >= 0.0, "{side}: negative optical depth for {c:?}");
            for t in [out[1], out[5]] {
                assert!((0.0..=1.0).contains(&t), "{side}: T = {t} for {c:?}");
            }
            assert!(
                out[2..5].iter().all(|v| *v >= 0.0),
                "{side}: negative in-scatter {out:?} for {c:?}"
            );
        }
    }
    eprintln!(
        "height fog: {} adversarial cases finite on gpu and cpu",
        cases.len()
    );
}
