//! The inject pass against independent answers: homogeneous sunlit fog in closed form,
//! with and without an occluder, and a height-fog column by numerical integration.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{UVec3, Vec3};
use volfog::cpu;
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::froxel_world_position;
use volfog::options::ShadowFilter;
use volfog::pipeline::{FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogMedium, ShadowCascades};

/// Homogeneous fog of depth `top`, sun without occluders: every column is a closed
/// form. Without the light's transmittance L = albedo E p(theta) (1 - e^(-sigma_t d)),
/// T = e^(-sigma_t d). With it, a point at height y receives E e^(-sigma (top - y) / mu)
/// (mu the sun's elevation sine) and along a ray from y0 rising v_y per metre
/// L = albedo E p e^(-sigma (top - y0) / mu) (1 - e^(-sigma r d)) / r, r = 1 - v_y / mu.
#[test]
fn homogeneous_sunlit_fog_matches_closed_form() {
    let gpu = gpu();
    let sigma_t = 0.04;
    let g = 0.6;
    // Above every froxel of the volume (64 m far, 30 degrees up at most).
    let top = 60.0;
    let medium = FogMedium {
        density: sigma_t,
        height_falloff: 0.0,
        noise_strength: 0.0,
        albedo: Vec3::splat(0.8),
        phase_g: g,
        top_height: top,
        ..FogMedium::default()
    };
    let sun = DirectionalLight {
        direction: Vec3::new(0.3, 0.8, -0.5).normalize(),
        color: Vec3::new(2.0, 1.5, 1.0),
        ..DirectionalLight::default()
    };
    for through in [false, true] {
        let config = volfog::pipeline::FogConfig {
            light_transmittance: through,
            ..small_config()
        };
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let mut integrated = Vec::new();
        let frame_inputs = |_| FrameInputs {
            medium,
            sun,
            ambient: AmbientSh::default(),
            cascades: ShadowCascades::default(),
            ..FrameInputs::new(view(2.0, 0.05), projection(), 0.0)
        };
        run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
            integrated = read_volume(gpu, fog.integrated_texture())
        });
        let u = expected_uniforms(&config, &frame_inputs(0), 0);
        let f = &u.froxels;
        let size = config.volume_size;
        let mu = sun.direction.y as f64;
        let sigma = sigma_t as f64;
        let (mut worst_l, mut worst_t) = (0.0f64, 0.0f64);
        for y in 0..size.y {
            for x in 0..size.x {
                let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                    / glam::Vec2::new(size.x as f32, size.y as f32);
                let scale = cpu::froxel::ray_scale(uv, f.view_from_clip);
                // The column's ray from the near plane: where it starts and how fast it
                // climbs (per metre along it).
                let (world, _) = froxel_world_position(f, &u.frame, UVec3::new(x, y, 0), false);
                let view_dir = (world - u.frame.camera_position).normalize();
                let phase = cpu::phase::phase_hg(view_dir.dot(sun.direction), g) as f64;
                let y0 = (u.frame.camera_position + view_dir * (f.near * scale)).y as f64;
                let r = 1.0 - view_dir.y as f64 / mu;
                for z in 0..size.z {
                    let back = cpu::froxel::slice_depth(
                        (z + 1) as f32 / size.z as f32,
                        f.near,
                        f.far,
                        f.curve,
                    );
                    let d = ((back - f.near) * scale) as f64;
                    let t = (-sigma * d).exp();
                    let lit = if through {
                        (-sigma * (top as f64 - y0) / mu).exp() * (1.0 - (-sigma * r * d).exp()) / r
                    } else {
                        1.0 - t
                    };
                    let got = integrated[index(size, x, y, z)];
                    for c in 0..3 {
                        let l = (medium.albedo[c] * sun.color[c]) as f64 * phase * lit;
                        worst_l = worst_l.max((got[c] as f64 - l).abs() / l);
                    }
                    worst_t = worst_t.max((got.w as f64 - t).abs() / t);
                }
            }
        }
        eprintln!(
            "sunlit homogeneous fog (light transmittance {through}) vs closed form: in-scatter \
             {:.4}%, transmittance {:.4}% (bound 0.5%)",
            worst_l * 100.0,
            worst_t * 100.0
        );
        assert!(worst_l <= 0.005 && worst_t <= 0.005);
    }
}

/// A slab between the sun and part of the volume: froxels in its shadow keep only the
/// ambient term, froxels outside get sun + ambient, the sun attenuated by the fog above
/// them; above the fog's top nothing scatters. With the ESM the shadow's edge is moved
/// by the blur and the leak band, so froxels are classified by their centre with
/// margins for both and 5 % of the sun term is allowed. The compare filter's taps
/// cover the froxel, so a froxel counts as shadowed or lit when its whole extent (its
/// eight corners, widened by a shadow-map texel) is, and only fp16 rounding is allowed.
#[test]
fn occluder_shadow_drops_inscatter_to_ambient() {
    let gpu = gpu();
    for filter in [ShadowFilter::Esm, ShadowFilter::Compare { taps: 1 }] {
        slab_shadow(gpu, filter);
    }
}

fn slab_shadow(gpu: &volfog_testkit::Gpu, filter: ShadowFilter) {
    let config = volfog::pipeline::FogConfig {
        shadow_filter: filter,
        ..small_config()
    };
    let slab = Slab {
        x: (-22.0, 22.0),
        z: (-60.0, -8.0),
        top: 8.0,
    };
    let (cascades, depth_layers) = overhead_sun(&config, Some(slab));
    let shadow = shadow_map(gpu, &depth_layers);
    let g = 0.3;
    let medium = FogMedium {
        density: 0.03,
        height_falloff: 0.0,
        noise_strength: 0.0,
        phase_g: g,
        // The fog ends 20 m up: the overhead sun crosses 20 - y metres of it.
        top_height: 20.0,
        ..FogMedium::default()
    };
    let sun = DirectionalLight {
        direction: Vec3::Y,
        color: Vec3::splat(4.0),
        ..DirectionalLight::default()
    };
    let ambient_radiance = Vec3::new(0.1, 0.15, 0.2);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow).unwrap();
    let mut scattering = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::constant(ambient_radiance),
        cascades,
        ..FrameInputs::new(view(3.0, 0.0), projection(), 0.0)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        scattering = read_volume(gpu, fog.scattering_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let size = config.volume_size;
    let esm = !filter.compares();
    // Depth range of the light is 60 m; c = 80 gives a leak band of 3 / 80 * 60 = 2.25 m.
    let leak_margin = 3.0 / config.esm_exponent * 60.0;
    // The blur spans 11 ESM texels (0.55 m in cascade 0, 1.1 m in cascade 1) plus the
    // bilinear footprint: 8 m from the edges. A shadow-map texel is at most 0.27 m
    // (cascade 1: 140 m over 512 texels).
    let (margin, top_margin) = if esm { (8.0, 0.5) } else { (0.3, 0.0) };
    let (mut shadowed, mut lit, mut worst) = (0, 0, 0.0f32);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = UVec3::new(x, y, z);
                let (world, _) = froxel_world_position(&u.froxels, &u.frame, id, false);
                // The points the classification looks at: the centre (ESM) or the
                // froxel's corners (compare).
                let points: Vec<Vec3> = if esm {
                    vec![world]
                } else {
                    (0..8)
                        .map(|k| {
                            let o = Vec3::new(
                                if k & 1 == 0 { -0.5 } else { 0.5 },
                                if k & 2 == 0 { -0.5 } else { 0.5 },
                                if k & 4 == 0 { -0.5 } else { 0.5 },
                            );
                            let f = &u.froxels;
                            let view = cpu::froxel::froxel_view_position(
                                id,
                                o,
                                f.size,
                                f.view_from_clip,
                                f.near,
                                f.far,
                                f.curve,
                            );
                            u.frame.world_from_view.transform_point3(view)
                        })
                        .collect()
                };
                let view_dir = (world - u.frame.camera_position).normalize();
                let fogged = world.y <= medium.top_height;
                let sigma_s = medium.albedo * if fogged { medium.density } else { 0.0 };
                let through = (-medium.density * (medium.top_height - world.y).max(0.0)).exp();
                let sun_term =
                    sun.color * (cpu::phase::phase_hg(view_dir.dot(sun.direction), g) * through);
                let under = |p: &Vec3| {
                    p.x > slab.x.0 + margin
                        && p.x < slab.x.1 - margin
                        && p.z > slab.z.0 + margin
                        && p.z < slab.z.1 - margin
                        && p.y < slab.top - if esm { leak_margin } else { 0.0 }
                };
                let clear = |p: &Vec3| {
                    p.x < slab.x.0 - margin
                        || p.x > slab.x.1 + margin
                        || p.z < slab.z.0 - margin
                        || p.z > slab.z.1 + margin
                        || p.y > slab.top + top_margin
                };
                let got = scattering[index(size, x, y, z)].truncate();
                let (want, label) = if points.iter().all(under) {
                    shadowed += 1;
                    (sigma_s * ambient_radiance, "shadowed")
                } else if points.iter().all(clear) {
                    lit += 1;
                    (sigma_s * (ambient_radiance + sun_term), "lit")
                } else {
                    continue;
                };
                // Allowed: the ESM leak (5 % of the sun term) plus fp16 rounding.
                let leak = if esm { 0.05 } else { 0.0 };
                let tolerance =
                    leak * (sigma_s * sun_term).max_element() + 2e-3 * want.max_element();
                let err = (got - want).abs().max_element();
                if !fogged {
                    assert_eq!(got, Vec3::ZERO, "froxel above the fog's top at {world}");
                    continue;
                }
                worst = worst.max(err / (sigma_s * sun_term).max_element());
                assert!(
                    err <= tolerance,
                    "{filter:?}: {label} froxel at {world}: {got} vs {want}"
                );
            }
        }
    }
    eprintln!(
        "slab occluder, {filter:?}: {shadowed} shadowed froxels at the ambient term, {lit} lit; worst deviation {:.2}% of the sun term (bound {})",
        worst * 100.0,
        if esm { "5%" } else { "fp16 rounding" }
    );
    assert!(
        shadowed > 200 && lit > 200,
        "{shadowed} shadowed, {lit} lit"
    );
}

/// Exponential height fog seen from above at an angle: the integrated transmittance
/// of every column against a numerical integral of the same density (f64, 20000
/// steps per ray), within 1 %.
#[test]
fn height_fog_column_matches_numerical_integration() {
    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        volume_size: UVec3::new(16, 9, 128),
        ..small_config()
    };
    let medium = FogMedium {
        density: 0.05,
        height_falloff: 0.1,
        base_height: 0.0,
        noise_strength: 0.0,
        ..FogMedium::default()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut integrated = Vec::new();
    let frame_inputs = |_| FrameInputs {
        medium,
        cascades: ShadowCascades::default(),
        ..FrameInputs::new(view(6.0, -0.25), projection(), 0.0)
    };
    run_frames(gpu, &mut fog, 1, frame_inputs, |_, fog| {
        integrated = read_volume(gpu, fog.integrated_texture())
    });
    let u = expected_uniforms(&config, &frame_inputs(0), 0);
    let f = &u.froxels;
    let size = config.volume_size;
    let mut worst = 0.0f64;
    for y in 0..size.y {
        for x in 0..size.x {
            let uv = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                / glam::Vec2::new(size.x as f32, size.y as f32);
            let n = cpu::froxel::ndc_from_uv(uv);
            let ray_view = cpu::froxel::view_from_ndc(Vec3::new(n.x, n.y, 0.5), f.view_from_clip);
            let dir_per_depth = (ray_view / ray_view.z.abs()).as_dvec3();
            let world_from_view = u.frame.world_from_view.as_dmat4();
            let density = |depth: f64| {
                let p = world_from_view.transform_point3(dir_per_depth * depth);
                0.05 * (-0.1 * p.y).clamp(-80.0, 80.0).exp()
            };
            let scale = dir_per_depth.length();
            let mut tau = 0.0f64;
            let mut front = f.near as f64;
            for z in 0..size.z {
                let back = cpu::froxel::slice_depth(
                    (z + 1) as f32 / size.z as f32,
                    f.near,
                    f.far,
                    f.curve,
                ) as f64;
                let steps = 20000 / size.z as usize;
                let h = (back - front) / steps as f64;
                for s in 0..steps {
                    tau += density(front + (s as f64 + 0.5) * h) * h * scale;
                }
                front = back;
                let want = (-tau).exp();
                let got = integrated[index(size, x, y, z)].w as f64;
                // Below 1e-3 the fp16 transmittance nears its subnormal range: compare
                // absolutely there.
                let e = (got - want).abs() / want.max(1e-3);
                worst = worst.max(e);
                assert!(e <= 0.01, "column {x},{y} slice {z}: T {got} vs {want}");
            }
        }
    }
    eprintln!(
        "height fog column: worst relative transmittance error {:.4}% (bound 1%)",
        worst * 100.0
    );
}
