//! Your own density in WGSL (`FogConfig::custom_density`, `VOLFOG_INJECT_CUSTOM_DENSITY`):
//! a linear and a Gaussian density (moving with time, set by the frame's parameters)
//! through inject and the scan against the closed form of their optical depth along
//! every froxel column; a noisy scene with lights, local volumes of every blend mode
//! and a mixed albedo against the CPU mirror (the same functions in Rust); and a
//! function that returns NaN, infinities and negative values, which leaves the volume
//! finite.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{Mat4, Quat, UVec3, Vec2, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{
    CustomMedium, InjectInputs, froxel_scattering_with, froxel_world_position,
};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::shaders::CustomModule;
use volfog::uniforms::{
    BlendMode, DirectionalLight, FogCustomParams, FogMedium, FogSample, LocalVolume,
    ShadowCascades, VolumeShape,
};

/// Extinction `k + g . world` (`params.values[0]` = (g, k)), albedo
/// `params.values[1].rgb`, emission `params.values[2].rgb` times the extinction.
const LINEAR: &str = "#import volfog::types::{FogSample, FogCustomParams}

fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {
    let g = params.values[0];
    let extinction = g.w + dot(g.xyz, world);
    return FogSample(params.values[1].rgb, extinction, params.values[2].rgb * extinction);
}
";

/// The Rust twin of [`LINEAR`].
fn linear(world: Vec3, _time: f32, params: &FogCustomParams) -> FogSample {
    let g = params.values[0];
    let extinction = g.w + g.truncate().dot(world);
    FogSample {
        albedo: params.values[1].truncate(),
        extinction,
        emission: params.values[2].truncate() * extinction,
    }
}

/// A horizontal Gaussian layer rising with time, written with WESL's import statement
/// (as a Bevy shader would be): `params.values[0]` = (peak extinction, height at time
/// 0, rise per second, standard deviation).
const GAUSSIAN: &str = "import volfog::types::{FogSample, FogCustomParams};

fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {
    let g = params.values[0];
    let h = world.y - (g.y + g.z * time);
    return FogSample(vec3<f32>(0.6, 0.7, 0.8), g.x * exp(-0.5 * h * h / (g.w * g.w)), vec3<f32>(0.0));
}
";

/// The Rust twin of [`GAUSSIAN`].
fn gaussian(world: Vec3, time: f32, params: &FogCustomParams) -> FogSample {
    let g = params.values[0];
    let h = world.y - (g.y + g.z * time);
    FogSample {
        albedo: Vec3::new(0.6, 0.7, 0.8),
        extinction: g.x * (-0.5 * h * h / (g.w * g.w)).exp(),
        emission: Vec3::ZERO,
    }
}

/// erf(x) (Abramowitz and Stegun 7.1.26, |error| < 1.5e-7).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x < 0.0 { -y } else { y }
}

/// A fog with no medium of its own (density 0) and the custom density `source`, run
/// one frame at `time` with `params`; its integrated volume, and the uniforms.
fn run_custom(
    config: &FogConfig,
    source: &str,
    file: &str,
    params: FogCustomParams,
    time: f32,
    pitch: f32,
) -> (Vec<Vec4>, FrameInputs<'static>) {
    let gpu = gpu();
    let config = FogConfig {
        custom_density: Some(CustomModule::new(file, source)),
        ..config.clone()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let inputs = FrameInputs {
        medium: FogMedium {
            density: 0.0,
            noise_strength: 0.0,
            ..FogMedium::default()
        },
        sun: DirectionalLight {
            color: Vec3::ZERO,
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::default(),
        cascades: ShadowCascades::default(),
        custom_params: params,
        ..FrameInputs::new(view(2.0, pitch), projection(), time)
    };
    let mut integrated = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs.clone(),
        |_, fog| integrated = read_volume(gpu, fog.integrated_texture()),
    );
    (integrated, inputs)
}

/// Along every froxel column, the scan's transmittance against `exp(-tau)` with `tau`
/// the closed form `optical_depth(c, v, t0, t1)` from the near plane to the back of
/// each slice (c the camera, v the column's unit ray, t the distance along it): the
/// worst relative error.
fn worst_against(
    config: &FogConfig,
    integrated: &[Vec4],
    inputs: &FrameInputs<'_>,
    optical_depth: impl Fn(Vec3, Vec3, f64, f64) -> f64,
) -> (f64, f64) {
    let u = expected_uniforms(config, inputs, 0);
    let f = &u.froxels;
    let size = config.volume_size;
    let (mut worst, mut deepest) = (0.0f64, 0.0f64);
    for y in 0..size.y {
        for x in 0..size.x {
            let uv =
                (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(size.x as f32, size.y as f32);
            let scale = volfog::cpu::froxel::ray_scale(uv, f.view_from_clip) as f64;
            let (world, _) = froxel_world_position(f, &u.frame, UVec3::new(x, y, 0), false);
            let c = u.frame.camera_position;
            let v = (world - c).normalize();
            let t0 = f.near as f64 * scale;
            for z in 0..size.z {
                let back = volfog::cpu::froxel::slice_depth(
                    (z + 1) as f32 / size.z as f32,
                    f.near,
                    f.far,
                    f.curve,
                );
                let tau = optical_depth(c, v, t0, back as f64 * scale);
                deepest = deepest.max(tau);
                let t = (-tau).exp();
                let got = integrated[index(size, x, y, z)].w as f64;
                worst = worst.max((got - t).abs() / t);
            }
        }
    }
    (worst, deepest)
}

/// Slices linear in depth, so each froxel's sample is the middle of its piece of the
/// column's ray and the scan's sum of piecewise-constant steps is exact for a linear
/// density.
fn linear_slices() -> FogConfig {
    FogConfig {
        slice_curve: 0.0,
        ..small_config()
    }
}

/// A linear density `k + g . p` integrates to `(k + g . c)(t1 - t0) + g . v (t1^2 -
/// t0^2) / 2` along the ray `c + v t`: the scan holds it within fp16 rounding.
#[test]
fn a_linear_custom_density_integrates_to_its_closed_form() {
    let config = linear_slices();
    let (g, k) = (Vec3::new(0.0002, 0.0015, -0.0004), 0.01f32);
    let params = FogCustomParams::new(&[
        g.extend(k),
        Vec4::new(0.5, 0.6, 0.7, 0.0),
        Vec4::new(0.01, 0.02, 0.03, 0.0),
    ])
    .unwrap();
    let (integrated, inputs) = run_custom(&config, LINEAR, "linear.wgsl", params, 0.0, 0.4);
    // Positive at every froxel, so the pass's clamp at 0 leaves it linear.
    let u = expected_uniforms(&config, &inputs, 0);
    let s = config.volume_size;
    for i in 0..s.x * s.y * s.z {
        let id = UVec3::new(i % s.x, (i / s.x) % s.y, i / (s.x * s.y));
        let (world, _) = froxel_world_position(&u.froxels, &u.frame, id, false);
        assert!(linear(world, 0.0, &params).extinction > 0.0, "{world}");
    }
    let (g, k) = (g.as_dvec3(), k as f64);
    let (worst, deepest) = worst_against(&config, &integrated, &inputs, |c, v, t0, t1| {
        let (c, v) = (c.as_dvec3(), v.as_dvec3());
        (k + g.dot(c)) * (t1 - t0) + g.dot(v) * (t1 * t1 - t0 * t0) / 2.0
    });
    // The scattering volume holds each froxel's extinction and the integrated volume
    // the transmittance as rgba16float: 2^-11 relative each, so up to (1 + tau) 2^-11.
    let bound = (1.0 + deepest) * 2f64.powi(-11);
    eprintln!(
        "linear custom density: transmittance within {:.4}% of the closed form (optical \
         depth up to {deepest:.2}; bound {:.3}%, fp16 rounding)",
        worst * 100.0,
        bound * 100.0
    );
    assert!(deepest > 1.0, "the fog is dense enough to test: {deepest}");
    assert!(worst <= bound, "{worst}");
}

/// A Gaussian layer `A exp(-(y - y0(t))^2 / (2 s^2))` (its height moving with the
/// frame's time) integrates to `A s sqrt(pi / 2) / v_y [erf((y(t1) - y0) / (s
/// sqrt(2))) - erf((y(t0) - y0) / (s sqrt(2)))]` along a ray climbing `v_y` per metre;
/// the scan's midpoint steps hold it within fp16 rounding plus 0.2 % (the midpoint rule
/// errs by about h^2 / 24 times the change of the density's slope, here 0.19 % of
/// optical depth with steps of h = 1.6 m along the ray and a slope of at most
/// 0.018 / m^2).
#[test]
fn a_gaussian_layer_integrates_to_its_erf_closed_form() {
    let config = linear_slices();
    // 0.15 / m at its peak, 4 m high at time 0, rising 0.5 m/s, s = 5 m; seen at t = 6 s
    // (y0 = 7 m) from a camera looking 0.8 rad up, every ray climbing.
    let (a, y_start, rise, s) = (0.15f32, 4.0f32, 0.5f32, 5.0f32);
    let time = 6.0;
    let params = FogCustomParams::new(&[Vec4::new(a, y_start, rise, s)]).unwrap();
    let (integrated, inputs) = run_custom(&config, GAUSSIAN, "layer.wesl", params, time, 0.8);
    let (a, s, y0) = (a as f64, s as f64, (y_start + rise * time) as f64);
    let (worst, deepest) = worst_against(&config, &integrated, &inputs, |c, v, t0, t1| {
        let vy = v.y as f64;
        assert!(vy > 0.2, "every ray climbs");
        let e = |t: f64| erf((c.y as f64 + vy * t - y0) / (s * 2f64.sqrt()));
        a * s * (std::f64::consts::PI / 2.0).sqrt() / vy * (e(t1) - e(t0))
    });
    let bound = (1.0 + deepest) * 2f64.powi(-11) + 0.002;
    eprintln!(
        "Gaussian custom density (WESL imports, moving with time): transmittance within \
         {:.4}% of the erf closed form (optical depth up to {deepest:.2}; bound {:.3}%)",
        worst * 100.0,
        bound * 100.0
    );
    assert!(deepest > 1.0, "{deepest}");
    assert!(worst <= bound, "{worst}");
}

/// The custom density in a lit, noisy, glowing medium with local volumes of every blend
/// mode after it, jittered: the GPU's scattering volume against the CPU mirror with the
/// Rust twin of the function (the albedo mixed by extinction, the volumes blended over
/// the sum); the mirror without the custom density is far from it.
#[test]
fn the_custom_density_matches_the_cpu_mirror() {
    let gpu = gpu();
    let config = FogConfig {
        jitter: true,
        max_local_volumes: 6,
        custom_density: Some(CustomModule::new("layer.wesl", GAUSSIAN)),
        ..small_config()
    };
    let params = FogCustomParams::new(&[Vec4::new(0.08, 1.0, 0.3, 3.0)]).unwrap();
    let volumes: Vec<LocalVolume> = BlendMode::ALL
        .iter()
        .enumerate()
        .map(|(i, blend)| {
            let at = Vec3::new(-6.0 + 2.4 * i as f32, 2.0, -12.0 - 3.0 * i as f32);
            let m = Mat4::from_scale_rotation_translation(Vec3::splat(3.0), Quat::IDENTITY, at);
            let density = if *blend == BlendMode::Multiply {
                0.3
            } else {
                0.05
            };
            LocalVolume::new(m, VolumeShape::Ellipsoid, density, 0.4)
                .and_then(|v| v.with_blend(*blend))
                .unwrap()
        })
        .collect();
    let lights = lights();
    let medium = FogMedium {
        emission: Vec3::new(0.001, 0.002, 0.0),
        albedo: Vec3::new(0.95, 0.9, 0.85),
        ..medium()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let frame_inputs = |f: u32| FrameInputs {
        medium,
        sun: DirectionalLight {
            direction: Vec3::new(0.2, 0.9, -0.3).normalize(),
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::sky_ground(Vec3::new(0.2, 0.3, 0.5), Vec3::splat(0.05), Vec3::Y),
        lights: &lights,
        local_volumes: &volumes,
        cascades: ShadowCascades::default(),
        custom_params: params,
        ..FrameInputs::new(view(2.0, -0.05), projection(), 2.5 + f as f32)
    };
    let mut scattering = Vec::new();
    run_frames(gpu, &mut fog, 3, frame_inputs, |f, fog| {
        if f == 2 {
            scattering = read_volume(gpu, fog.scattering_texture());
        }
    });
    let u = expected_uniforms(&config, &frame_inputs(2), 2);
    let inputs = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &lights,
        local_volumes: &volumes,
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let custom = CustomMedium {
        density: &gaussian,
        params: &params,
    };
    let size = config.volume_size;
    let (mut worst, mut control) = (0.0f32, 0.0f32);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = UVec3::new(x, y, z);
                let got = scattering[index(size, x, y, z)];
                let error = |want: Vec4| {
                    let scale = want.truncate().max_element().max(1e-4);
                    let rgb = (got.truncate() - want.truncate()).abs().max_element() / scale;
                    rgb.max((got.w - want.w).abs() / want.w.max(1e-4))
                };
                let taps = inputs.shadow_taps.count;
                worst = worst.max(error(froxel_scattering_with(
                    &inputs,
                    id,
                    taps,
                    Some(custom),
                )));
                control = control.max(error(froxel_scattering_with(&inputs, id, taps, None)));
            }
        }
    }
    eprintln!(
        "custom density with lights, noise and volumes of every blend mode: worst relative \
         error vs CPU {worst:e} (bound 4e-3); the mirror without it {control:.3}"
    );
    assert!(worst <= 4e-3, "{worst}");
    assert!(control > 0.5, "{control}");
}

/// A density that returns NaN (left of x = 0), +Inf (right of it), a negative and a NaN
/// albedo channel and an infinite emission: every froxel stays finite, and the GPU
/// agrees with the CPU mirror's clamping (NaN reads 0, +Inf the maximum 1e3).
#[test]
fn a_custom_density_that_returns_nonsense_leaves_the_volume_finite() {
    const NONSENSE: &str = "#import volfog::types::{FogSample, FogCustomParams}

fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {
    let nan = sqrt(-1.0 - world.x * world.x);
    let inf = exp(200.0 + world.y * world.y);
    return FogSample(vec3<f32>(-1.0, 2.0, nan), select(nan, inf, world.x >= 0.0), vec3<f32>(inf));
}
";
    let gpu = gpu();
    let config = FogConfig {
        custom_density: Some(CustomModule::new("nonsense.wgsl", NONSENSE)),
        ..small_config()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let inputs = FrameInputs {
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(2.0, 0.0), projection(), 1.0)
    };
    let (mut scattering, mut integrated) = (Vec::new(), Vec::new());
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs.clone(),
        |_, fog| {
            scattering = read_volume(gpu, fog.scattering_texture());
            integrated = read_volume(gpu, fog.integrated_texture());
        },
    );
    let u = expected_uniforms(&config, &inputs, 0);
    let size = config.volume_size;
    let (mut cleared, mut capped) = (0, 0);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let i = index(size, x, y, z);
                assert!(
                    scattering[i].is_finite() && integrated[i].is_finite(),
                    "{x},{y},{z}"
                );
                let (world, _) =
                    froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), false);
                if world.x < -0.01 {
                    // NaN reads 0: only the medium's own extinction.
                    assert!(scattering[i].w < 0.2, "{}", scattering[i].w);
                    cleared += 1;
                } else if world.x > 0.01 {
                    assert!(scattering[i].w >= 999.0, "{}", scattering[i].w);
                    capped += 1;
                }
            }
        }
    }
    eprintln!(
        "nonsense custom density: every froxel finite; {cleared} froxels with NaN read no \
         custom extinction, {capped} with +Inf read the maximum 1e3"
    );
    assert!(cleared > 1000 && capped > 1000);
}
