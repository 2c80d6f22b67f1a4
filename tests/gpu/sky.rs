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

/// The sky_solve pass spread over four frames of 16 rows fills the texture with the
/// CPU mirror's values (within rgba16float rounding), and sky_horizon averages the
/// horizon row as the CPU does.
#[test]
fn sky_passes_match_cpu() {
    use volfog::cpu::sky::{
        SKY_TEXTURE_HEIGHT, SKY_TEXTURE_WIDTH, sky_horizon, sky_texel_direction,
    };
    use volfog::pipeline::sky::SkyLight;
    use volfog::uniforms::FrustumRays;
    let gpu = gpu();
    let mut sky = SkyLight::new(&gpu.device, wgpu::TextureFormat::Rgba16Float).unwrap();
    let atmosphere = SkyAtmosphere::earth(sun(20.0)).unwrap();
    sky.set_atmosphere(atmosphere).unwrap();
    let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
    let rays = FrustumRays::new(glam::Mat4::IDENTITY, proj).unwrap();
    for _ in 0..4 {
        sky.prepare(&gpu.queue, &rays, 16).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        sky.encode_solve(&mut encoder);
        sky.encode_horizon(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
    }
    let texels = gpu.read_texture_rgba16f(sky.texture()).unwrap();
    let layer = (SKY_TEXTURE_WIDTH * SKY_TEXTURE_HEIGHT) as usize;
    assert_eq!(texels.len(), 2 * layer);
    let mut worst = 0.0f32;
    for y in 0..SKY_TEXTURE_HEIGHT {
        for x in 0..SKY_TEXTURE_WIDTH {
            let want =
                sky_single_scattering(&atmosphere, sky_texel_direction(glam::UVec2::new(x, y)));
            let i = (y * SKY_TEXTURE_WIDTH + x) as usize;
            for (got, want) in [
                (texels[i].truncate(), want.rayleigh),
                (texels[layer + i].truncate(), want.mie),
            ] {
                // rgba16float keeps 11 bits (4.9e-4 relative).
                let e = ((got - want).abs() / want.abs().max(Vec3::splat(1e-4))).max_element();
                worst = worst.max(e);
                assert!(e <= 1e-3, "texel {x},{y}: {got} vs {want}");
            }
        }
    }
    let raw = gpu.read_buffer(sky.horizon_buffer()).unwrap();
    let h: &[f32] = bytemuck::cast_slice(&raw);
    let want = sky_horizon(&atmosphere);
    let got_r = Vec3::from_slice(&h[0..3]);
    let got_m = Vec3::from_slice(&h[4..7]);
    let e = ((got_r - want.rayleigh).abs() / want.rayleigh)
        .max((got_m - want.mie).abs() / want.mie)
        .max_element();
    eprintln!(
        "sky_solve in 4 bands of 16 rows: {} texels vs cpu worst rel {worst:.1e} (bound 1e-3); \
         sky_horizon vs cpu rel {e:.1e} (bound 1e-4)",
        2 * layer
    );
    assert!(e <= 1e-4, "{got_r} {got_m} vs {want:?}");
}

fn chromaticity(c: Vec3) -> Vec3 {
    c / (c.x + c.y + c.z)
}

/// Noon: the zenith is bluer than the horizon. Sunset: the horizon towards the sun is
/// redder than the horizon away from it and than the zenith.
#[test]
fn sky_colours_follow_the_sun() {
    let noon = SkyAtmosphere::earth(sun(60.0)).unwrap();
    let sunset = SkyAtmosphere::earth(sun(2.0)).unwrap();
    let cases = [
        (noon, dir(90.0, 0.0)),
        (noon, dir(1.0, 90.0)),
        (sunset, dir(1.0, 0.0)),
        (sunset, dir(1.0, 180.0)),
        (sunset, dir(90.0, 0.0)),
    ];
    let got = gpu_sky(&cases);
    let c: Vec<Vec3> = got.iter().map(|(_, r)| chromaticity(*r)).collect();
    eprintln!(
        "chromaticity (r, g, b): noon zenith {:.3}, noon horizon (90 deg from the sun) {:.3}; \
         sunset horizon towards the sun {:.3}, away {:.3}, zenith {:.3}",
        c[0], c[1], c[2], c[3], c[4]
    );
    assert!(c[0].z > c[1].z + 0.05, "noon: the zenith is bluer");
    assert!(
        c[2].x > c[3].x + 0.05 && c[2].x > c[4].x + 0.05,
        "sunset: redder towards the sun"
    );
    assert!(c[2].x > c[2].z, "the sunset horizon is red before blue");
}

const SPOT_KERNEL: &str = r#"
#import volfog::types::SkyAtmosphere
#import volfog::sky::sky_sample

struct Input { atmosphere: SkyAtmosphere, dirs: array<vec4<f32>> }
@group(0) @binding(0) var<storage, read> input: Input;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;
@group(0) @binding(2) var sky: texture_2d_array<f32>;
@group(0) @binding(3) var sky_sampler: sampler;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input.dirs) { return; }
    output[i] = vec4<f32>(sky_sample(sky, sky_sampler, input.dirs[i].xyz, input.atmosphere), 0.0);
}
"#;

/// Width (degrees) of the part of the peak of `values` at or above 90 % of its maximum,
/// sampled every `step` degrees; the offset of the peak; the peak value.
fn peak(values: &[f32], step: f32) -> (f32, f32, f32) {
    let (peak_i, peak) =
        values.iter().enumerate().fold(
            (0, f32::MIN),
            |(bi, bv), (i, v)| if *v > bv { (i, *v) } else { (bi, bv) },
        );
    let above = values.iter().filter(|v| **v >= 0.9 * peak).count();
    (
        above as f32 * step,
        (peak_i as f32 - (values.len() / 2) as f32) * step,
        peak,
    )
}

/// The sun's spot, from the solved texture with the phase applied per pixel: its peak
/// sits on the sun, and its height and width (at 90 % of the peak) are the analytic
/// phase's on the CPU mirror's scattering at the sun; with the phase baked into the
/// 128 x 64 texels the peak is lower and shifted.
#[test]
fn sun_spot_from_the_per_pixel_phase() {
    use volfog::cpu::sky::{
        SKY_TEXTURE_HEIGHT, SKY_TEXTURE_WIDTH, sky_texel_direction, sky_texture_uv,
    };
    use volfog::pipeline::sky::SkyLight;
    use volfog::uniforms::FrustumRays;
    let gpu = gpu();
    let sun_dir = sun(25.0);
    let atmosphere = SkyAtmosphere::earth(sun_dir).unwrap();
    let mut sky = SkyLight::new(&gpu.device, wgpu::TextureFormat::Rgba16Float).unwrap();
    sky.set_atmosphere(atmosphere).unwrap();
    let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
    sky.prepare(
        &gpu.queue,
        &FrustumRays::new(glam::Mat4::IDENTITY, proj).unwrap(),
        64,
    )
    .unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    sky.encode_solve(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    // An arc through the sun along its elevation, +-15 degrees of azimuth in 0.02 steps.
    let step = 0.02f32;
    let dirs: Vec<Vec3> = (-750..=750).map(|k| dir(25.0, k as f32 * step)).collect();
    let mut input: Vec<u8> = atmosphere.to_bytes();
    for d in &dirs {
        input.extend_from_slice(bytemuck::cast_slice(&d.extend(0.0).to_array()));
    }
    let module = gpu.shader_from_naga("spot", common::compose(SPOT_KERNEL, &[]));
    let out = gpu
        .run_kernel_with(
            &module,
            "main",
            &input,
            (dirs.len() * 16) as u64,
            dirs.len() as u32,
            &[
                wgpu::BindingResource::TextureView(sky.view()),
                wgpu::BindingResource::Sampler(sky.sampler()),
            ],
        )
        .unwrap();
    let out: &[[f32; 4]] = bytemuck::cast_slice(&out);
    let measured: Vec<f32> = out.iter().map(|v| v[0] + v[1] + v[2]).collect();
    // The analytic spot: the scattering at the sun (CPU) with the exact phases.
    let at_sun = sky_single_scattering(&atmosphere, sun_dir);
    let analytic: Vec<f32> = dirs
        .iter()
        .map(|d| {
            let c = d.dot(sun_dir);
            let r = atmosphere.sun_intensity
                * (at_sun.rayleigh * phase_rayleigh(c)
                    + at_sun.mie * phase_cornette_shanks(c, atmosphere.mie_g));
            r.x + r.y + r.z
        })
        .collect();
    // The phase baked into the texels and filtered bilinearly, as a CPU-only sky would.
    let baked: Vec<f32> = dirs
        .iter()
        .map(|d| {
            let uv = sky_texture_uv(*d);
            let x = uv.x * SKY_TEXTURE_WIDTH as f32 - 0.5;
            let y = (uv.y * SKY_TEXTURE_HEIGHT as f32 - 0.5)
                .clamp(0.0, SKY_TEXTURE_HEIGHT as f32 - 1.0);
            let (x0, y0) = (x.floor(), y.floor());
            let texel = |i: f32, j: f32| {
                let t = glam::UVec2::new(
                    (i as i32).rem_euclid(SKY_TEXTURE_WIDTH as i32) as u32,
                    (j as u32).min(SKY_TEXTURE_HEIGHT - 1),
                );
                let td = sky_texel_direction(t);
                let r = sky_radiance(
                    &sky_single_scattering(&atmosphere, td),
                    td.dot(sun_dir),
                    &atmosphere,
                );
                r.x + r.y + r.z
            };
            let (fx, fy) = (x - x0, y - y0);
            let top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1.0, y0) * fx;
            let bottom = texel(x0, y0 + 1.0) * (1.0 - fx) + texel(x0 + 1.0, y0 + 1.0) * fx;
            top * (1.0 - fy) + bottom * fy
        })
        .collect();
    let (w_measured, offset, p_measured) = peak(&measured, step);
    let (w_analytic, _, p_analytic) = peak(&analytic, step);
    let (w_baked, offset_baked, p_baked) = peak(&baked, step);
    eprintln!(
        "sun spot (sun 25 deg up, Mie g 0.76): per-pixel phase peak {p_measured:.2} at \
         {offset:+.2} deg, width at 90 % {w_measured:.2} deg; analytic {p_analytic:.2}, \
         {w_analytic:.2} deg; phase baked into the texels {p_baked:.2} at {offset_baked:+.2} deg, \
         {w_baked:.2} deg"
    );
    assert!(
        offset.abs() <= 2.0 * step,
        "the peak sits on the sun: {offset}"
    );
    assert!(
        (w_measured - w_analytic).abs() <= 0.05 * w_analytic,
        "{w_measured} vs {w_analytic}"
    );
    let (e_pixel, e_baked) = (
        (p_measured - p_analytic).abs(),
        (p_baked - p_analytic).abs(),
    );
    assert!(e_pixel <= 0.01 * p_analytic, "{p_measured} vs {p_analytic}");
    assert!(
        e_baked > 3.0 * e_pixel,
        "baking the phase loses the spot: {p_baked}"
    );
}

/// Suns below the horizon, on it and at the zenith, views straight up, down and along
/// the horizon: finite, non-negative light.
#[test]
fn sky_is_finite_for_every_sun_and_view() {
    let mut cases = Vec::new();
    for s in [-30.0f32, -5.0, -0.5, 0.0, 0.5, 89.99] {
        let mut a = SkyAtmosphere::earth(sun(s)).unwrap();
        if s > 89.0 {
            a.sun_direction = Vec3::Y;
        }
        for d in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::X,
            Vec3::new(0.0, -0.01, -1.0).normalize(),
            dir(0.0, 0.0),
            dir(45.0, 180.0),
        ] {
            cases.push((a, d));
        }
    }
    let got = gpu_sky(&cases);
    for ((a, d), (s, r)) in cases.iter().zip(&got) {
        for v in [s.rayleigh, s.mie, *r] {
            assert!(
                v.is_finite() && v.min_element() >= 0.0,
                "sun {} view {d}: {v}",
                a.sun_direction
            );
        }
    }
    // Deep night: no sun light anywhere in the sky.
    let night = &got[0..6];
    assert!(
        night.iter().all(|(_, r)| r.max_element() < 1e-6),
        "{night:?}"
    );
}

const FOG_KERNEL: &str = r#"
#import volfog::types::{SkyAtmosphere, HeightFog}
#import volfog::sky::{sky_height_fog, sky_scattering}

struct Input { atmosphere: SkyAtmosphere, fog: HeightFog, rayleigh: vec4<f32>, mie: vec4<f32>, segments: array<vec4<f32>> }
@group(0) @binding(0) var<storage, read> input: Input;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input.segments) { return; }
    let horizon = sky_scattering(input.rayleigh.xyz, input.mie.xyz);
    output[i] = sky_height_fog(input.fog, horizon, input.atmosphere, vec3<f32>(0.0, 1.0, 0.0), input.segments[i].xyz);
}
"#;

/// Height fog lit by the sky (`sky_height_fog`) on the GPU against the CPU, and dense
/// fog along the horizon against the sky at the horizon: they agree on average around
/// the horizon (the fog takes the horizon's average scattering with each view's
/// phase), per direction within the sky's own variation with azimuth.
#[test]
fn height_fog_takes_its_colour_from_the_sky() {
    use volfog::cpu::sky::{sky_height_fog, sky_horizon};
    use volfog::uniforms::HeightFog;
    let atmosphere = SkyAtmosphere::earth(sun(8.0)).unwrap();
    let horizon = sky_horizon(&atmosphere);
    let fog = HeightFog::new(Vec3::ZERO, 0.05, Vec3::Y, 0.02, 0.0).unwrap();
    // Horizontal views every 5 degrees of azimuth through 2 km of fog (optical depth
    // about 100: the fog's colour alone).
    let azimuths: Vec<f32> = (0..72).map(|k| k as f32 * 5.0).collect();
    let segments: Vec<Vec3> = azimuths.iter().map(|a| dir(0.0, *a) * 2000.0).collect();
    let mut input = atmosphere.to_bytes();
    input.extend(fog.to_bytes());
    for v in [horizon.rayleigh, horizon.mie] {
        input.extend_from_slice(bytemuck::cast_slice(&v.extend(0.0).to_array()));
    }
    for s in &segments {
        input.extend_from_slice(bytemuck::cast_slice(&s.extend(0.0).to_array()));
    }
    let module = gpu().shader_from_naga("sky fog", common::compose(FOG_KERNEL, &[]));
    let out = gpu()
        .run_kernel(
            &module,
            "main",
            &input,
            (segments.len() * 16) as u64,
            segments.len() as u32,
        )
        .unwrap();
    let out: &[[f32; 4]] = bytemuck::cast_slice(&out);
    let sky = gpu_sky(
        &azimuths
            .iter()
            .map(|a| (atmosphere, dir(0.0, *a)))
            .collect::<Vec<_>>(),
    );
    let (mut worst_cpu, mut sum_fog, mut sum_sky, mut worst_dir) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for (k, s) in segments.iter().enumerate() {
        let got = glam::Vec4::from_array(out[k]);
        let want = sky_height_fog(&fog, &horizon, &atmosphere, Vec3::Y, *s);
        let e = ((got - want).abs() / want.abs().max(glam::Vec4::splat(1e-4))).max_element();
        worst_cpu = worst_cpu.max(e);
        assert!(e <= 1e-4, "{s}: gpu {got} cpu {want}");
        let (fog_l, sky_l) = (got.truncate().element_sum(), sky[k].1.element_sum());
        sum_fog += fog_l;
        sum_sky += sky_l;
        worst_dir = worst_dir.max((fog_l - sky_l).abs() / sky_l);
    }
    let mean = (sum_fog - sum_sky).abs() / sum_sky;
    eprintln!(
        "sky-lit height fog: gpu vs cpu worst rel {worst_cpu:.1e} (bound 1e-4); dense fog vs \
         the sky along the horizon (sun 8 deg up): mean over azimuth {mean:.3}, worst direction \
         {worst_dir:.3}"
    );
    assert!(mean <= 0.05, "{mean}");
}
