//! The sun's light through the height fog (`volfog::height_fog::height_fog_lit_integral`
//! and `height_fog_light_optical_depth`): the CPU mirror against a 20k-step numerical
//! integration in f64 over random segments (climbing, descending and horizontal; the sun
//! from 2 to 90 degrees; with and without a top; uniform and exponential fog), and the
//! WGSL against the CPU mirror on the GPU.

use crate::common::{gpu, run_f32};
use glam::{DVec3, Vec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRunner};
use volfog::cpu::height_fog::{
    height_fog, height_fog_light_optical_depth, height_fog_lit_integral,
};
use volfog::limits::NO_TOP;
use volfog::uniforms::HeightFog;

/// One segment through a fog lit by a far light: extinction `b exp(-c (dot(p, up) - h0))`
/// below `top` (m along `up`), the segment from `origin` to `origin + segment` (m), the
/// unit direction `towards` the light.
#[derive(Debug, Clone, Copy)]
struct LitCase {
    b: f32,
    c: f32,
    h0: f32,
    up: Vec3,
    top: f32,
    origin: Vec3,
    segment: Vec3,
    towards: Vec3,
}

/// Two unit vectors completing the unit `up` to an orthonormal basis.
fn basis(up: Vec3) -> (Vec3, Vec3) {
    let a = if up.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let e1 = (a - up * a.dot(up)).normalize();
    (e1, up.cross(e1))
}

/// Parameters: medium kind (0 uniform, 1 exponential thinning upwards, 2 exponential
/// thickening upwards, always under a top), whether a top caps the fog, the light's
/// elevation (2 to 90 degrees, log-uniform) and azimuth, the segment's slope class (0 climbing, 1
/// descending, 2 horizontal or within 1e-3 of it), its slope (degrees) and azimuth, its
/// length (log10 m),
/// the start's height above h0 (m), the top's height above h0 (m), the density (1/m)
/// and |falloff| (1/m), the up axis (polar angles) and h0 (m).
#[allow(clippy::type_complexity)]
fn lit_case() -> impl Strategy<Value = LitCase> {
    (
        (
            0u32..3,
            any::<bool>(),
            0.0f32..1.0,
            0.0f32..std::f32::consts::TAU,
        ),
        (
            0u32..3,
            5.0f32..90.0,
            0.0f32..std::f32::consts::TAU,
            -1.0f32..2.6,
        ),
        (-20.0f32..60.0, 0.0f32..80.0, -4.0f32..-0.7, 0.005f32..0.3),
        (0.0f32..1.0, 0.0f32..std::f32::consts::TAU, -30.0f32..30.0),
    )
        .prop_filter_map(
            "exponents within +-40, the numerical integral resolved, no sliver under the top",
            |(
                (kind, capped, elevation, light_azimuth),
                (slope_class, slope, azimuth, log_length),
                (height, top_above, log_density, falloff),
                (cos_polar, polar_azimuth, h0),
            )| {
                // The up axis: within 60 degrees of +Y, any azimuth.
                let cos_polar = 0.5 + 0.5 * cos_polar;
                let sin_polar = (1.0 - cos_polar * cos_polar).sqrt();
                let up = Vec3::new(
                    sin_polar * polar_azimuth.cos(),
                    cos_polar,
                    sin_polar * polar_azimuth.sin(),
                )
                .normalize();
                let (e1, e2) = basis(up);
                // Log-uniform from 2 to 90 degrees: a quarter of the lights below 5.
                let elevation = 2.0 * 45f32.powf(elevation);
                let (el, s) = (elevation.to_radians(), slope.to_radians());
                let towards = (up * el.sin()
                    + (e1 * light_azimuth.cos() + e2 * light_azimuth.sin()) * el.cos())
                .normalize();
                let horizontal = e1 * azimuth.cos() + e2 * azimuth.sin();
                let v = match slope_class {
                    0 => s.sin(),
                    1 => -s.sin(),
                    // Exactly horizontal, or a slope within +-1e-3 of it.
                    _ if slope < 20.0 => 0.0,
                    _ => (slope - 55.0) / 35.0 * 1e-3,
                };
                let dir = (up * v + horizontal * (1.0 - v * v).max(0.0).sqrt()).normalize();
                let length = 10f32.powf(log_length);
                let (b, c) = match kind {
                    0 => (10f32.powf(log_density), 0.0),
                    1 => (10f32.powf(log_density), falloff),
                    _ => (10f32.powf(log_density), -falloff / 6.0),
                };
                let capped = capped || kind == 2;
                let top = if capped { h0 + top_above } else { NO_TOP };
                let origin = up * (h0 + height) + horizontal.cross(up) * 7.0;
                let segment = dir * length;
                let case = LitCase {
                    b,
                    c,
                    h0,
                    up,
                    top,
                    origin,
                    segment,
                    towards,
                };
                // The closed form's clamps stay idle (density exponents within +-40, as in
                // the height-fog tests), and the integrand varies by at most e^200 along
                // the segment so 20k midpoint steps resolve it (|r| tau <= 200).
                let e = |p: Vec3| -(c as f64) * (dot(p, up) - h0 as f64);
                let e_max = e(origin).max(e(origin + segment));
                let tau_bound = b as f64 * length as f64 * e_max.exp();
                let r = 1.0 - dot(dir, up) / dot(towards, up);
                // Neither end within 0.5 m of the top: the f32 rounding of a height (|h|
                // 1e-7 m) alone moves the part below the top, and the result with it, by
                // |h| 1e-7 / (top - h) relative, beyond 1e-4 for a sliver of a few mm.
                let clear = |p: Vec3| !capped || (dot(p, up) - top as f64).abs() > 0.5;
                (e(origin).abs() <= 40.0
                    && e(origin + segment).abs() <= 40.0
                    && r.abs() * tau_bound <= 200.0
                    && clear(origin)
                    && clear(origin + segment))
                .then_some(case)
            },
        )
}

fn dot(a: Vec3, b: Vec3) -> f64 {
    a.as_dvec3().dot(b.as_dvec3())
}

/// The integral over the segment of sigma(t) exp(-tau_view(t)) exp(-tau_light(t)) dt by
/// the midpoint rule with 20k steps in f64 over its part below the top, tau_view
/// accumulated by the same steps (at a midpoint from the half step before it, second
/// order) and tau_light(h) = integral from h to the top of sigma dh' / mu in closed form:
/// sigma(h) / (c mu) without a top (c > 0), (sigma(h) - sigma(top)) / (c mu) under one,
/// sigma (top - h) / mu for uniform fog. Also returns the smaller of F = tau_view +
/// tau_light at the ends of the part below the top.
fn numeric_lit(k: &LitCase) -> (f64, f64) {
    const STEPS: usize = 20_000;
    let (b, c, h0) = (f64::from(k.b), f64::from(k.c), f64::from(k.h0));
    let up: DVec3 = k.up.as_dvec3();
    let (o, d) = (k.origin.as_dvec3(), k.segment.as_dvec3());
    let top = f64::from(k.top);
    let capped = k.top < NO_TOP;
    let mu = k.towards.as_dvec3().dot(up);
    let sigma = |h: f64| b * (-c * (h - h0)).exp();
    let tau_light = |h: f64| {
        if c == 0.0 {
            // Without a top uniform fog never lets the light through.
            if capped {
                b * (top - h) / mu
            } else {
                f64::INFINITY
            }
        } else if capped {
            (sigma(h) - sigma(top)) / (c * mu)
        } else {
            sigma(h) / (c * mu)
        }
    };
    let (hs, dh) = (o.dot(up), d.dot(up));
    let (t0, t1) = if !capped {
        (0.0, 1.0)
    } else if dh == 0.0 {
        if hs <= top { (0.0, 1.0) } else { (0.0, 0.0) }
    } else if dh > 0.0 {
        (0.0, ((top - hs) / dh).clamp(0.0, 1.0))
    } else {
        (((top - hs) / dh).clamp(0.0, 1.0), 1.0)
    };
    if t1 <= t0 {
        return (0.0, 0.0);
    }
    let dt = (t1 - t0) / STEPS as f64;
    let ds = dt * d.length();
    let (mut tau, mut sum) = (0.0f64, 0.0f64);
    for i in 0..STEPS {
        let t = t0 + (i as f64 + 0.5) * dt;
        let h = hs + t * dh;
        let tau_mid = tau + sigma(hs + (t - 0.25 * dt) * dh) * 0.5 * ds;
        sum += sigma(h) * (-tau_mid - tau_light(h)).exp() * ds;
        tau += sigma(h) * ds;
    }
    let f_min = tau_light(hs + t0 * dh).min(tau + tau_light(hs + t1 * dh));
    (sum, f_min)
}

fn cpu_lit(k: &LitCase) -> f32 {
    height_fog_lit_integral(k.b, k.c, k.h0, k.up, k.top, k.origin, k.segment, k.towards)
}

/// Relative error of the closed form against the numerical integral; 1e-30 absolute
/// below (uniform fog without a top lets no light through: both are 0).
fn lit_error(got: f32, want: f64) -> f64 {
    ((f64::from(got) - want).abs() - 1e-30).max(0.0) / want.max(1e-30)
}

/// The bound on [`lit_error`]: 1e-4, widened by F / 20 where the light arrives
/// attenuated by more than e^-20 (F = tau_view + tau_light beyond 20): the relative
/// rounding of the f32 optical depths (about 1e-6) times F is the error of exp(-F).
/// Under a low light the rounding of mu = dot(towards, up) in f32 adds its own: a few
/// ulps of a unit product (5e-7 here) over mu, relative, in tau_light, so F 5e-7 / mu
/// more (2.7e-4 at F = 23.5 with the light 2.5 degrees up).
fn lit_bound(f_min: f64, mu: f64) -> f64 {
    1e-4 * (f_min / 20.0).max(1.0) + f_min * 5e-7 / mu
}

/// A case a random run once found beyond the bound without the mu term: thickening fog
/// under a top, the light 2.5 degrees up, F = 23.5 (error 1.33e-4, of which the rounding
/// of mu gives 5.7e-6 relative in tau_light).
#[test]
fn height_fog_lit_integral_under_a_low_light_through_deep_fog() {
    let k = LitCase {
        b: 0.002_076_764_8,
        c: -0.046_487_87,
        h0: 0.0,
        up: Vec3::new(-0.283_918_3, 0.514_117_54, 0.809_366_1),
        top: 67.684_73,
        origin: Vec3::new(5.111_879_3, -15.165_276, -10.819_162),
        segment: Vec3::new(0.979_944_94, 0.106_844_38, 0.168_203_23),
        towards: Vec3::new(0.236_434_07, -0.752_561_87, 0.614_613_4),
    };
    let (want, f_min) = numeric_lit(&k);
    let got = cpu_lit(&k);
    let (e, bound) = (lit_error(got, want), lit_bound(f_min, dot(k.towards, k.up)));
    eprintln!("low light, F = {f_min:.2}: relative error {e:.2e}, bound {bound:.2e}");
    assert!(
        f_min > 20.0 && e <= bound,
        "{got} against {want}: {e:e} > {bound:e}"
    );
}

#[test]
fn height_fog_lit_integral_matches_numerical_integration() {
    let mut runner = TestRunner::new(Config {
        cases: 2000,
        failure_persistence: None,
        ..Config::default()
    });
    let worst = std::cell::Cell::new((0.0f64, 0u32));
    // The worst relative error where the light arrives attenuated by e^-20 at most.
    let worst_lit = std::cell::Cell::new(0.0f64);
    // Cases per class: uniform, thinning, thickening upwards; capped; climbing,
    // descending, horizontal (|v| <= 1e-3); crossing the top; the light below 5 degrees.
    let seen = std::cell::RefCell::new([0u32; 9]);
    runner
        .run(&lit_case(), |k| {
            let (want, f_min) = numeric_lit(&k);
            let got = cpu_lit(&k);
            let e = lit_error(got, want);
            let bound = lit_bound(f_min, dot(k.towards, k.up));
            let (w, n) = worst.get();
            worst.set((w.max(e / bound), n + 1));
            if f_min <= 20.0 {
                worst_lit.set(worst_lit.get().max(e));
            }
            let v = dot(k.segment, k.up) / f64::from(k.segment.length());
            let (h_start, h_end) = (dot(k.origin, k.up), dot(k.origin + k.segment, k.up));
            let top = f64::from(k.top);
            let classes = [
                k.c == 0.0,
                k.c > 0.0,
                k.c < 0.0,
                k.top < NO_TOP,
                v > 1e-3,
                v < -1e-3,
                v.abs() <= 1e-3,
                (h_start - top) * (h_end - top) < 0.0,
                dot(k.towards, k.up) < 5f64.to_radians().sin(),
            ];
            for (count, hit) in seen.borrow_mut().iter_mut().zip(classes) {
                *count += u32::from(hit);
            }
            prop_assert!(got.is_finite() && got >= 0.0, "{got} for {k:?}");
            prop_assert!(
                e <= bound,
                "closed form {got}, numerical {want} (rel {e:e}, bound {bound:e}) for {k:?}"
            );
            Ok(())
        })
        .unwrap();
    let (w, n) = worst.get();
    let seen = seen.into_inner();
    eprintln!(
        "height_fog_lit_integral (CPU) vs f64 20k-step midpoint integral over {n} random \
         segments (uniform {}, thinning {}, thickening {}; capped {}; climbing {}, \
         descending {}, horizontal {}; crossing the top {}; light below 5 degrees {}): \
         worst relative error {w:.3} of its bound (1e-4 x max(1, F / 20) + F 5e-7 / mu); {:.2e} where F <= 20",
        seen[0],
        seen[1],
        seen[2],
        seen[3],
        seen[4],
        seen[5],
        seen[6],
        seen[7],
        seen[8],
        worst_lit.get()
    );
    assert!(seen.iter().all(|&count| count >= 30), "{seen:?}");
}

const KERNEL: &str = r#"
#import volfog::types::HeightFog
#import volfog::height_fog::{height_fog, height_fog_lit_integral, height_fog_light_optical_depth}

struct Case { fog: HeightFog, segment: vec4<f32>, origin: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let f = c.fog;
    let o = c.origin.xyz;
    let d = c.segment.xyz;
    output[4u * i] = height_fog_lit_integral(f.density, f.falloff, f.base_height, f.up,
        f.top_height, o, d, f.sun_direction);
    output[4u * i + 1u] = height_fog_light_optical_depth(f.density, f.falloff, f.base_height,
        f.up, f.top_height, o, f.sun_direction);
    output[4u * i + 2u] = height_fog_light_optical_depth(f.density, f.falloff, f.base_height,
        f.up, f.top_height, o + d, f.sun_direction);
    output[4u * i + 3u] = height_fog(f, o, d).x;
}
"#;

/// The case as a height fog lit by the sun alone (sun colour 1, isotropic lobe, the
/// sun's transmittance on): `height_fog`'s red channel is `HG * lit integral`.
fn case_fog(k: &LitCase) -> HeightFog {
    HeightFog {
        color: Vec3::ZERO,
        density: k.b,
        up: k.up,
        falloff: k.c,
        sun_direction: k.towards,
        base_height: k.h0,
        sun_color: Vec3::ONE,
        sun_g: 0.0,
        top_height: k.top,
        sun_transmittance: 1,
    }
}

#[test]
fn height_fog_lit_integral_wgsl_matches_the_cpu() {
    let mut runner = TestRunner::deterministic();
    let strategy = lit_case();
    let cases: Vec<LitCase> = (0..4000)
        .map(|_| strategy.new_tree(&mut runner).unwrap().current())
        .collect();
    let mut input = Vec::new();
    for k in &cases {
        input.extend(
            case_fog(k)
                .to_bytes()
                .chunks_exact(4)
                .map(|w| f32::from_le_bytes([w[0], w[1], w[2], w[3]])),
        );
        input.extend(k.segment.extend(0.0).to_array());
        input.extend(k.origin.extend(0.0).to_array());
    }
    assert_eq!(input.len(), cases.len() * 28, "Case is 112 bytes in WGSL");
    let out = run_f32(gpu(), KERNEL, &input, cases.len() * 4, cases.len() as u32);
    // Shader exp is exact to 3 + 2|x| ulp (Vulkan). The lit integral carries
    // exp(-min(F0, F1)) and the density's exp(e): 1e-5 relative plus that many ulp with
    // x = F + |e|, and F's own rounding (a few ulp of F, times F through exp): 6 + 6 F +
    // 2 |e| ulp in all; the light's optical depths carry exp(e) alone.
    let ulp = f64::from(f32::EPSILON);
    let (mut worst_lit, mut worst_od, mut worst_fog, mut worst_numeric) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, got) in cases.iter().zip(out.chunks_exact(4)) {
        let fog = case_fog(k);
        let e = |p: Vec3| (-(k.c as f64) * (dot(p, k.up) - k.h0 as f64)).abs();
        let e_max = e(k.origin).max(e(k.origin + k.segment));
        let f0 = height_fog_light_optical_depth(k.b, k.c, k.h0, k.up, k.top, k.origin, k.towards);
        let f1 = height_fog_light_optical_depth(
            k.b,
            k.c,
            k.h0,
            k.up,
            k.top,
            k.origin + k.segment,
            k.towards,
        );
        let lit = cpu_lit(k);
        let hg = 1.0 / (4.0 * std::f64::consts::PI);
        let want_fog = height_fog(&fog, k.origin, k.segment).x;
        let bound_lit = 1e-5 + (6.0 + 6.0 * f64::from(f0.min(f1)) + 2.0 * e_max) * ulp;
        let bound_od = 1e-5 + (3.0 + 2.0 * e_max) * ulp;
        let rel = |g: f32, w: f32| f64::from((g - w).abs()) / f64::from(w.abs().max(1e-30));
        let checks = [
            ("lit integral", got[0], lit, bound_lit),
            ("light OD at the start", got[1], f0, bound_od),
            ("light OD at the end", got[2], f1, bound_od),
            (
                "height_fog with the sun's transmittance",
                got[3],
                want_fog,
                bound_lit,
            ),
        ];
        for (name, g, w, bound) in checks {
            let r = rel(g, w);
            assert!(
                g.is_finite() && r <= bound,
                "{name}: gpu {g} cpu {w} (rel {r:e}, bound {bound:e}) for {k:?}"
            );
        }
        worst_lit = worst_lit.max(rel(got[0], lit) / bound_lit);
        worst_od = worst_od
            .max(rel(got[1], f0) / bound_od)
            .max(rel(got[2], f1) / bound_od);
        worst_fog = worst_fog.max(rel(got[3], want_fog) / bound_lit);
        // The GPU against the numerical integral too, and height_fog's sun lobe: the
        // isotropic phase times the lit integral.
        let (want, f_min) = numeric_lit(k);
        let bound = lit_bound(f_min, dot(k.towards, k.up));
        worst_numeric = worst_numeric.max(lit_error(got[0], want) / bound);
        assert!(
            lit_error(got[0], want) <= bound,
            "gpu {} numerical {want} for {k:?}",
            got[0]
        );
        assert!(
            (f64::from(want_fog) - hg * f64::from(lit)).abs() <= 1e-5 * hg * f64::from(lit) + 1e-30,
            "height_fog's sun lobe {want_fog} against HG x {lit}"
        );
    }
    eprintln!(
        "{} segments, WGSL vs CPU worst error as a share of its bound (1e-5 + (6 + 6 F + 2 |e|) ulp \
         for the lit integral and height_fog, 1e-5 + (3 + 2|e|) ulp for the light's optical depth): \
         lit integral {worst_lit:.3}, light OD {worst_od:.3}, height_fog {worst_fog:.3}; \
         WGSL vs the f64 integral worst {worst_numeric:.3} of its bound (1e-4 x max(1, F / 20) + F 5e-7 / mu)",
        cases.len()
    );
}
