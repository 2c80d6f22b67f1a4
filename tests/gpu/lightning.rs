//! Closed-form volumetric light of a point source (`volfog::lightning`, Wenzel 2007
//! eq. 3) on the GPU: against the CPU mirror, against adaptive numerical integration in
//! f64 (generic segments, segments through the light, a vanishing discriminant from a
//! tiny attenuation or a tiny segment, zero-length segments), and finiteness for
//! adversarial inputs.

use crate::common;

use common::Rng;

use common::{gpu, rel_err, run_f32};
use glam::Vec3;
use volfog::cpu::lightning::*;

const KERNEL: &str = r#"
#import volfog::lightning::{lightning_integral, volumetric_lightning, lightning_density}

struct Case { light: vec4<f32>, origin: vec4<f32>, segment: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let a = c.light.w;
    let intensity = c.origin.w;
    output[i] = vec4<f32>(
        lightning_integral(a, c.light.xyz, c.origin.xyz, c.segment.xyz),
        volumetric_lightning(intensity, a, c.light.xyz, c.origin.xyz, c.segment.xyz),
        lightning_density(intensity, a, c.light.xyz, c.origin.xyz + 0.5 * c.segment.xyz),
        0.0);
}
"#;

#[derive(Clone, Copy, Debug)]
struct Case {
    i: f32,
    a: f32,
    light: Vec3,
    origin: Vec3,
    segment: Vec3,
}

impl Case {
    fn cpu(&self) -> [f32; 3] {
        [
            lightning_integral(self.a, self.light, self.origin, self.segment),
            volumetric_lightning(self.i, self.a, self.light, self.origin, self.segment),
            lightning_density(self.i, self.a, self.light, self.origin + 0.5 * self.segment),
        ]
    }
}

fn run_gpu(cases: &[Case]) -> Vec<[f32; 3]> {
    let mut input = Vec::new();
    for c in cases {
        input.extend(c.light.extend(c.a).to_array());
        input.extend(c.origin.extend(c.i).to_array());
        input.extend(c.segment.extend(0.0).to_array());
    }
    let out = run_f32(gpu(), KERNEL, &input, cases.len() * 4, cases.len() as u32);
    out.chunks_exact(4).map(|c| [c[0], c[1], c[2]]).collect()
}

fn cases() -> Vec<(&'static str, Case)> {
    let mut rng = Rng(0x11647);
    let mut out = Vec::new();
    for k in 0..7000 {
        let i = rng.log(0.01, 100.0);
        let a = rng.log(1e-4, 10.0);
        let origin = rng.vec(50.0);
        let (kind, c) = match k % 7 {
            0 => (
                "generic",
                Case {
                    i,
                    a,
                    light: rng.vec(20.0),
                    origin,
                    segment: rng.unit() * rng.log(0.01, 200.0),
                },
            ),
            1 => {
                // The light on the segment (up to f32 rounding), steep attenuation.
                let segment = rng.unit() * rng.log(0.1, 200.0);
                let light = origin + segment * rng.range(0.02, 0.98);
                (
                    "through the light",
                    Case {
                        i,
                        a: rng.log(1e-2, 1e4),
                        light,
                        origin,
                        segment,
                    },
                )
            }
            2 => {
                let segment = rng.unit() * rng.log(0.1, 200.0);
                let light = if rng.f() < 0.5 {
                    origin
                } else {
                    origin + segment
                };
                (
                    "light at an end",
                    Case {
                        i,
                        a: rng.log(1e-2, 1e4),
                        light,
                        origin,
                        segment,
                    },
                )
            }
            3 => (
                "tiny attenuation (4uw - v^2 -> 0)",
                Case {
                    i,
                    a: rng.log(1e-12, 1e-5),
                    light: rng.vec(20.0),
                    origin,
                    segment: rng.unit() * rng.log(0.01, 200.0),
                },
            ),
            4 => (
                "tiny segment (4uw - v^2 -> 0)",
                Case {
                    i,
                    a,
                    light: origin + rng.vec(5.0),
                    origin,
                    segment: rng.unit() * rng.log(1e-6, 1e-2),
                },
            ),
            5 => (
                "distant light",
                Case {
                    i,
                    a,
                    light: origin + rng.unit() * rng.log(1e3, 1e5),
                    origin,
                    segment: rng.unit() * rng.log(0.01, 100.0),
                },
            ),
            _ => {
                if rng.f() < 0.5 {
                    (
                        "zero-length",
                        Case {
                            i,
                            a,
                            light: rng.vec(20.0),
                            origin,
                            segment: Vec3::ZERO,
                        },
                    )
                } else {
                    (
                        "a = 0",
                        Case {
                            i,
                            a: 0.0,
                            light: rng.vec(20.0),
                            origin,
                            segment: rng.unit() * rng.log(0.01, 200.0),
                        },
                    )
                }
            }
        };
        out.push((kind, c));
    }
    out
}

/// One panel of adaptive Simpson: the interval, its end and midpoint values, and the
/// Simpson estimate over it.
#[derive(Clone, Copy)]
struct Panel {
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
}

/// Adaptive Simpson quadrature in f64 (absolute tolerance, halved per split).
fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    fn rec(f: &dyn Fn(f64) -> f64, p: Panel, tol: f64, depth: u32) -> f64 {
        let m = 0.5 * (p.a + p.b);
        let (lm, rm) = (0.5 * (p.a + m), 0.5 * (m + p.b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - p.a) / 6.0 * (p.fa + 4.0 * flm + p.fm);
        let right = (p.b - m) / 6.0 * (p.fm + 4.0 * frm + p.fb);
        let delta = left + right - p.whole;
        if depth == 0 || delta.abs() <= 15.0 * tol {
            return left + right + delta / 15.0;
        }
        let l = Panel {
            a: p.a,
            b: m,
            fa: p.fa,
            fm: flm,
            fb: p.fm,
            whole: left,
        };
        let r = Panel {
            a: m,
            b: p.b,
            fa: p.fm,
            fm: frm,
            fb: p.fb,
            whole: right,
        };
        rec(f, l, 0.5 * tol, depth - 1) + rec(f, r, 0.5 * tol, depth - 1)
    }
    if b <= a {
        return 0.0;
    }
    let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let panel = Panel {
        a,
        b,
        fa,
        fm,
        fb,
        whole,
    };
    rec(f, panel, tol, 50)
}

/// The integral of 1 / (1 + a |l - o - t d|^2) |d| over t in [0, 1] in f64, split at the
/// point closest to the light so the peak is sampled.
fn numeric_integral(c: &Case) -> f64 {
    let v = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let (l, o, d, a) = (v(c.light), v(c.origin), v(c.segment), c.a as f64);
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if dd == 0.0 {
        return 0.0;
    }
    let len = dd.sqrt();
    let f = move |t: f64| {
        let q = [0, 1, 2].map(|k| l[k] - o[k] - t * d[k]);
        len / (1.0 + a * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]))
    };
    let tc =
        (((l[0] - o[0]) * d[0] + (l[1] - o[1]) * d[1] + (l[2] - o[2]) * d[2]) / dd).clamp(0.0, 1.0);
    // Rough size of the whole integral sets the absolute tolerance.
    let scale = f(tc).max(f(0.0)).max(f(1.0)) * 1e-13;
    adaptive_simpson(&f, 0.0, tc, scale) + adaptive_simpson(&f, tc, 1.0, scale)
}

#[test]
fn lightning_matches_cpu_mirror() {
    let cases: Vec<Case> = cases().into_iter().map(|(_, c)| c).collect();
    let gpu = run_gpu(&cases);
    let mut worst = [0.0f32; 3];
    for (c, g) in cases.iter().zip(&gpu) {
        let want = c.cpu();
        for k in 0..3 {
            let e = rel_err(g[k], want[k], 1e-30);
            worst[k] = worst[k].max(e);
            assert!(
                e <= 1e-5,
                "output {k}: gpu {} cpu {} (rel {e:e}) for {c:?}",
                g[k],
                want[k]
            );
        }
    }
    eprintln!(
        "lightning gpu vs cpu: worst relative error integral {:e}, lightning {:e}, density \
         {:e} (bound 1e-5)",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn lightning_matches_numerical_integration() {
    let cases = cases();
    let plain: Vec<Case> = cases.iter().map(|(_, c)| *c).collect();
    let gpu = run_gpu(&plain);
    let mut worst: std::collections::BTreeMap<&str, f64> = Default::default();
    for ((kind, c), g) in cases.iter().zip(&gpu) {
        let want = numeric_integral(c);
        for (side, out) in [("gpu", *g), ("cpu", c.cpu())] {
            assert!(
                out.iter().all(|v| v.is_finite()),
                "{side} {kind}: non-finite {out:?} for {c:?}"
            );
            if want == 0.0 {
                assert_eq!(out[0], 0.0, "{side} {kind}: zero-length gives {}", out[0]);
                assert_eq!(out[1], 0.0, "{side} {kind}: zero-length gives {}", out[1]);
                continue;
            }
            let e = (out[0] as f64 - want).abs() / want;
            let e_i = (out[1] as f64 - c.i as f64 * want).abs() / (c.i as f64 * want);
            assert!(
                e <= 1e-3 && e_i <= 1e-3,
                "{side} {kind}: integral {} lightning {} numerical {want} x i = {} (rel {e:e}) \
                 for {c:?}",
                out[0],
                out[1],
                c.i
            );
            if side == "gpu" {
                let w = worst.entry(kind).or_default();
                *w = w.max(e).max(e_i);
            }
        }
    }
    for (kind, w) in worst {
        eprintln!(
            "lightning vs f64 adaptive Simpson ({kind:34}): worst relative error {w:e} (bound 1e-3)"
        );
    }
}

/// Known answers: a = 0 gives i |d|; a segment of half-length L centred on the light
/// gathers (2 i / sqrt(a)) atan(sqrt(a) L).
#[test]
fn lightning_limits() {
    let c0 = Case {
        i: 2.0,
        a: 0.0,
        light: Vec3::ZERO,
        origin: Vec3::new(1.0, 2.0, 3.0),
        segment: Vec3::new(3.0, 4.0, 0.0),
    };
    let line = Case {
        i: 1.0,
        a: 4.0,
        light: Vec3::ZERO,
        origin: Vec3::new(-1e4, 0.0, 0.0),
        segment: Vec3::new(2e4, 0.0, 0.0),
    };
    let gpu = run_gpu(&[c0, line]);
    for (side, a, b) in [("gpu", gpu[0], gpu[1]), ("cpu", c0.cpu(), line.cpu())] {
        assert!((a[1] - 10.0).abs() < 1e-5, "{side}: a = 0 gives {}", a[1]);
        let want = (2e4f64).atan() as f32; // (2 / sqrt(4)) atan(sqrt(4) 1e4)
        assert!(
            (b[1] - want).abs() < 1e-5,
            "{side}: line through the light gathers {}, expected {want}",
            b[1]
        );
    }
}

#[test]
fn lightning_is_finite_for_adversarial_inputs() {
    let scalars = [
        0.0f32, 1e-30, -1e-30, 1e-7, 1.0, -1.0, 1e6, 1e9, -1e9, 1e30, -1e30, 3.4e38, -3.4e38,
    ];
    let vectors = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(1e-30, -1e-30, 0.0),
        Vec3::new(1e30, -1e30, 1e30),
        Vec3::splat(3.4e38),
        Vec3::new(-3.4e38, 0.0, 3.4e38),
        Vec3::new(1e9, 1.0, -1e9),
        Vec3::new(-1e9, -1e9, -1e9),
    ];
    let mut rng = Rng(5);
    let mut cases = Vec::new();
    for _ in 0..20000 {
        let pick =
            |rng: &mut Rng| scalars[(rng.f() * scalars.len() as f32) as usize % scalars.len()];
        let pickv =
            |rng: &mut Rng| vectors[(rng.f() * vectors.len() as f32) as usize % vectors.len()];
        let origin = pickv(&mut rng);
        let segment = pickv(&mut rng);
        let light = match rng.f() {
            s if s < 0.3 => origin,
            s if s < 0.5 => origin + segment * 0.5,
            _ => pickv(&mut rng),
        };
        cases.push(Case {
            i: pick(&mut rng),
            a: pick(&mut rng),
            light,
            origin,
            segment,
        });
    }
    let gpu = run_gpu(&cases);
    for (c, g) in cases.iter().zip(&gpu) {
        for (side, out) in [("gpu", *g), ("cpu", c.cpu())] {
            assert!(
                out.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{side}: {out:?} for {c:?}"
            );
        }
    }
    eprintln!(
        "lightning: {} adversarial cases finite and >= 0 on gpu and cpu",
        cases.len()
    );
}
