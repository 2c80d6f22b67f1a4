//! Sky light (`volfog::sky`, Nishita et al. 1993 as Wenzel 2007 eq. 1) on the GPU:
//! against the CPU mirror, against an independent f64 integration of eq. 1 (composite
//! Simpson on a quadratic substitution, not the shader's exponential spacing), the
//! colours physics expects (a blue zenith at noon, a red horizon towards the setting
//! sun), the sun's spot from the per-pixel phase, and finiteness for suns below the
//! horizon and at the zenith and for views straight up or down.

use crate::common;

use common::{gpu, run_f32};
use glam::{DVec3, Vec3};
use volfog::cpu::phase::{phase_cornette_shanks, phase_rayleigh};
use volfog::cpu::sky::{SkyScattering, sky_radiance, sky_single_scattering};
use volfog::uniforms::SkyAtmosphere;

const KERNEL: &str = r#"
#import volfog::types::SkyAtmosphere
#import volfog::sky::{sky_single_scattering, sky_radiance}

struct Case { atmosphere: SkyAtmosphere, dir: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let c = input[i];
    let s = sky_single_scattering(c.atmosphere, c.dir.xyz);
    output[i * 3u] = vec4<f32>(s.rayleigh, 0.0);
    output[i * 3u + 1u] = vec4<f32>(s.mie, 0.0);
    output[i * 3u + 2u] = vec4<f32>(sky_radiance(s, dot(c.dir.xyz, c.atmosphere.sun_direction), c.atmosphere), 0.0);
}
"#;

/// GPU scattering and radiance for each (atmosphere, direction).
pub(crate) fn gpu_sky(cases: &[(SkyAtmosphere, Vec3)]) -> Vec<(SkyScattering, Vec3)> {
    let mut input: Vec<f32> = Vec::new();
    for (a, d) in cases {
        let bytes = a.to_bytes();
        assert_eq!(bytes.len(), 80, "SkyAtmosphere is 80 bytes");
        input.extend_from_slice(bytemuck::cast_slice(&bytes));
        input.extend(d.extend(0.0).to_array());
    }
    let out = run_f32(gpu(), KERNEL, &input, cases.len() * 12, cases.len() as u32);
    out.chunks_exact(12)
        .map(|c| {
            (
                SkyScattering {
                    rayleigh: Vec3::from_slice(&c[0..3]),
                    mie: Vec3::from_slice(&c[4..7]),
                },
                Vec3::from_slice(&c[8..11]),
            )
        })
        .collect()
}

/// A sun at `elevation` degrees, azimuth along -Z.
fn sun(elevation: f32) -> Vec3 {
    let e = elevation.to_radians();
    Vec3::new(0.0, e.sin(), -e.cos())
}

/// A view direction at `elevation` and `azimuth` degrees (azimuth 0 along -Z, towards
/// the sun of [`sun`], 90 along +X).
fn dir(elevation: f32, azimuth: f32) -> Vec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

// ---- f64 reference ------------------------------------------------------------------

/// Composite Simpson over [0, length] on the substitution s = length x^2 (dense near the
/// start, where the air is densest), `n` (even) intervals in x.
fn simpson(length: f64, n: usize, mut f: impl FnMut(f64) -> DVec3) -> DVec3 {
    let h = 1.0 / n as f64;
    let mut sum = DVec3::ZERO;
    for k in 0..=n {
        let x = k as f64 * h;
        let w = if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += f(length * x * x) * (2.0 * length * x) * w;
    }
    sum * (h / 3.0)
}

struct Planet {
    r: f64,
    top: f64,
    hr: f64,
    hm: f64,
}

impl Planet {
    /// Distance from point p along unit d to the top of the atmosphere; None when the
    /// ray meets the ground first.
    fn exit(&self, p: DVec3, d: DVec3) -> Option<f64> {
        let b = p.dot(d);
        let c = p.length_squared();
        let ground = b * b - (c - self.r * self.r);
        if b < 0.0 && ground > 0.0 && (-b - ground.sqrt()) > 0.0 {
            return None;
        }
        Some(-b + (b * b - (c - self.top * self.top)).sqrt())
    }

    fn density(&self, p: DVec3) -> (f64, f64) {
        let h = p.length() - self.r;
        ((-h / self.hr).exp(), (-h / self.hm).exp())
    }

    /// Optical depths (Rayleigh, Mie) from p along unit d to the top.
    fn depth(&self, p: DVec3, d: DVec3, length: f64, n: usize) -> (f64, f64) {
        let v = simpson(length, n, |s| {
            let (a, b) = self.density(p + d * s);
            DVec3::new(a, b, 0.0)
        });
        (v.x, v.y)
    }
}

/// Eq. 1 without I_s and F in f64: Simpson over the view ray (2000 intervals), the
/// optical depth back to the camera by Simpson over [0, s] (400 intervals), towards the
/// sun likewise (400 intervals; no light where the planet blocks it).
fn reference(a: &SkyAtmosphere, view: Vec3) -> (DVec3, DVec3) {
    let planet = Planet {
        r: a.planet_radius as f64,
        top: a.atmosphere_radius as f64,
        hr: a.rayleigh_height as f64,
        hm: a.mie_height as f64,
    };
    let eye = DVec3::new(0.0, planet.r + a.camera_height as f64, 0.0);
    let v = view.as_dvec3().normalize();
    let sun = a.sun_direction.as_dvec3().normalize();
    let length = planet.exit(eye, v).expect("views above the horizon");
    let beta_r = a.rayleigh.as_dvec3();
    let beta_m = a.mie as f64;
    let beta_me = beta_m * a.mie_extinction_ratio as f64;
    let transmittance = |s: f64| -> Option<DVec3> {
        let p = eye + v * s;
        let to_sun = planet.exit(p, sun)?;
        let (vr, vm) = planet.depth(eye, v, s, 400);
        let (lr, lm) = planet.depth(p, sun, to_sun, 400);
        let tau = beta_r * (vr + lr) + DVec3::splat(beta_me * (vm + lm));
        Some(DVec3::new((-tau.x).exp(), (-tau.y).exp(), (-tau.z).exp()))
    };
    let rayleigh = simpson(length, 2000, |s| {
        let (dr, _) = planet.density(eye + v * s);
        transmittance(s).map_or(DVec3::ZERO, |t| t * dr)
    });
    let mie = simpson(length, 2000, |s| {
        let (_, dm) = planet.density(eye + v * s);
        transmittance(s).map_or(DVec3::ZERO, |t| t * dm)
    });
    (beta_r * rayleigh, mie * beta_m)
}

#[test]
fn sky_matches_cpu_and_an_f64_integration_of_eq_1() {
    let mut cases = Vec::new();
    for sun_elevation in [60.0f32, 20.0, 3.0] {
        let a = SkyAtmosphere::earth(sun(sun_elevation)).unwrap();
        for (e, az) in [
            (90.0, 0.0),
            (45.0, 0.0),
            (10.0, 0.0),
            (2.0, 0.0),
            (0.2, 0.0),
            (10.0, 90.0),
            (2.0, 180.0),
            (30.0, 135.0),
        ] {
            cases.push((a, dir(e, az)));
        }
    }
    let got = gpu_sky(&cases);
    let (mut worst_cpu, mut worst_ref) = (0.0f32, 0.0f64);
    for ((a, d), (g, radiance)) in cases.iter().zip(&got) {
        let c = sky_single_scattering(a, *d);
        for (x, y) in [(g.rayleigh, c.rayleigh), (g.mie, c.mie)] {
            let e = ((x - y).abs() / y.abs().max(Vec3::splat(1e-6))).max_element();
            worst_cpu = worst_cpu.max(e);
            assert!(e <= 1e-4, "{d} sun {}: gpu {x} cpu {y}", a.sun_direction);
        }
        let want = sky_radiance(&c, d.dot(a.sun_direction), a);
        assert!(((*radiance - want).abs() / want.max(Vec3::splat(1e-6))).max_element() <= 1e-4);
        let (r, m) = reference(a, *d);
        for (x, y, name) in [(g.rayleigh, r, "Rayleigh"), (g.mie, m, "Mie")] {
            let e = ((x.as_dvec3() - y).abs() / y.abs()).max_element();
            eprintln!(
                "sun {:>4.1} deg, view {d:.3}: {name} gpu {x:.4} f64 {y:.4} rel {e:.2e}",
                a.sun_direction.y.asin().to_degrees()
            );
            worst_ref = worst_ref.max(e);
        }
    }
    eprintln!(
        "sky, {} directions x 3 suns: gpu vs cpu worst rel {worst_cpu:.1e} (bound 1e-4); vs \
         f64 eq. 1 worst rel {worst_ref:.1e} (bound 1e-3)",
        cases.len() / 3
    );
    assert!(worst_ref <= 1e-3, "{worst_ref}");
}
