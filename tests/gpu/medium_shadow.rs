//! Shadows the medium casts on itself (`FogConfig::medium_shadows`,
//! `VOLFOG_INJECT_MEDIUM_SHADOW`): the `medium_shadow` pass against its CPU twin
//! (`volfog::cpu::medium_shadow`), inject reading it against the CPU mirror, a dense
//! slab's shadow against its closed form, and the typed errors.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{Mat4, UVec3, Vec2, Vec3};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering};
use volfog::cpu::medium_shadow::MediumShadowVolume;
use volfog::pipeline::{FogConfig, FogError, FrameInputs, VolumetricFog};
use volfog::uniforms::{
    DirectionalLight, FogMedium, FogParticle, LocalVolume, MediumShadow, MediumShadowConfig,
    VolumeShape,
};
use volfog_testkit::rng::Rng;

fn config() -> FogConfig {
    FogConfig {
        light_transmittance: true,
        medium_shadows: Some(MediumShadowConfig {
            size: UVec3::new(32, 32, 48),
            distance: 32.0,
            reach: 32.0,
            march_steps: 8,
        }),
        ..small_config()
    }
}

/// The small scene's noisy medium, lights and local volumes (a dense box and a
/// subtractive ellipsoid) under a sun low in the south-west.
fn inputs<'a>(
    lights: &'a [volfog::uniforms::FogLight],
    volumes: &'a [LocalVolume],
) -> FrameInputs<'a> {
    FrameInputs {
        medium: FogMedium {
            local_volume_count: volumes.len() as u32,
            ..medium()
        },
        sun: DirectionalLight {
            direction: Vec3::new(-0.5, 0.6, 0.4).normalize(),
            color: Vec3::new(3.0, 2.8, 2.5),
            fog_intensity: 1.0,
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::constant(Vec3::ZERO),
        lights,
        local_volumes: volumes,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    }
}

/// The medium-shadow volume read back: (tau, excess) per texel.
fn read_medium_shadow(fog: &VolumetricFog) -> Vec<Vec2> {
    let texture = fog.medium_shadow_texture().expect("medium shadows are on");
    read_volume(gpu(), texture)
        .iter()
        .map(|t| Vec2::new(t.x, t.y))
        .collect()
}

fn cpu_inputs<'a>(
    config: &FogConfig,
    u: &'a volfog::pipeline::FrameUniforms,
    lights: &'a [volfog::uniforms::FogLight],
    volumes: &'a [LocalVolume],
    medium_shadow: Option<&'a MediumShadowVolume>,
) -> InjectInputs<'a> {
    InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights,
        local_volumes: volumes,
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow,
    }
}

fn placement(config: &FogConfig, u: &volfog::pipeline::FrameUniforms) -> MediumShadow {
    MediumShadow::fit(
        &config.medium_shadows.expect("on"),
        u.frame.world_from_view,
        u.froxels.view_from_clip,
        u.froxels.far,
        u.lighting.sun.direction,
    )
    .expect("a valid placement")
}

/// 300 smoke particles (radius 0.5 to 3 m, 0.05 to 1 / m) in the view.
fn smoke(seed: u64) -> Vec<FogParticle> {
    let mut rng = Rng(seed);
    (0..300)
        .map(|_| {
            let z = rng.range(4.0, 40.0);
            FogParticle {
                position: Vec3::new(rng.range(-0.8, 0.8) * z, rng.range(0.5, 10.0), -z),
                radius: rng.log(0.5, 3.0),
                extinction: rng.log(0.05, 1.0),
                falloff: rng.f(),
                ..FogParticle::default()
            }
        })
        .collect()
}

/// The pass's volume (with the scene's volumes and 300 particles) against its CPU
/// twin: beyond one rgba16float unit in the last
/// place (2^-10 relative; lavapipe's store truncates), the excess extinction within
/// 1e-5 of max(|excess|, 1 / m) (f32 differences of the noise and the exponential),
/// the optical depth within 1e-4 of max(|tau|, 1) (the sum of 48 such differences
/// over a column).
#[test]
fn the_volume_matches_the_cpu_mirror() {
    let gpu = gpu();
    let config = FogConfig {
        max_particles: 300,
        ..config()
    };
    let (lights, volumes, particles) = (lights(), local_volumes(), smoke(7));
    let frame = FrameInputs {
        particles: &particles,
        ..inputs(&lights, &volumes)
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut got = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| frame.clone(),
        |_, fog| got = read_medium_shadow(fog),
    );
    let u = expected_uniforms(&config, &frame, 0);
    let params = placement(&config, &u);
    let want = MediumShadowVolume::fill(
        &cpu_inputs(&config, &u, &lights, &volumes, None),
        None,
        &particles,
        &params,
    );
    let without = MediumShadowVolume::fill(
        &cpu_inputs(&config, &u, &lights, &volumes, None),
        None,
        &[],
        &params,
    );
    let (mut worst_excess, mut worst_tau, mut dense, mut compared) = (0.0f32, 0.0f32, 0, 0);
    let mut smoky = 0;
    let s = params.size;
    for (i, (g, w)) in got.iter().zip(&want.texels).enumerate() {
        assert!(g.is_finite(), "{g}");
        // Texels below the ground (y < 0), where the profile grows large, are left out:
        // the sun is above the horizon, so no texel above the ground sums them.
        let i = i as u32;
        let texel = UVec3::new(i % s.x, (i / s.x) % s.y, i / (s.x * s.y));
        let uvw = (texel.as_vec3() + 0.5) / s.as_vec3();
        if params.world_from_volume.transform_point3(uvw).y < 0.0 {
            continue;
        }
        compared += 1;
        let excess = ((g.y - w.y).abs() - w.y.abs() * 2f32.powi(-10)) / w.y.abs().max(1.0);
        let tau = ((g.x - w.x).abs() - w.x.abs() * 2f32.powi(-10)) / w.x.abs().max(1.0);
        worst_excess = worst_excess.max(excess);
        worst_tau = worst_tau.max(tau);
        dense += usize::from(w.y > 0.05);
        smoky += usize::from(w.y > without.texels[i as usize].y + 0.01);
    }
    eprintln!(
        "medium shadow volume vs CPU mirror: excess worst {worst_excess:e} /m beyond \
         rounding (bound 1e-5), optical depth {worst_tau:e} (bound 1e-4); {dense} of {} \
         texels above the ground in the dense box, {smoky} thickened by the particles",
        compared
    );
    assert!(smoky > 100, "the particles are in the volume: {smoky}");
    assert!(dense >= 4, "the box is in the volume: {dense}");
    assert!(worst_excess <= 1e-5, "{worst_excess}");
    assert!(worst_tau <= 1e-4, "{worst_tau}");
}

/// Inject reading the volume against the CPU mirror reading the same (read-back)
/// volume, relative to each froxel's largest channel: within 4e-3 (rgba16float output,
/// the sampler's fixed-point weights on a volume whose optical depth changes by up to
/// 0.2 a texel). The medium's shadow changes more than 1 % of the froxels by more than
/// 1 % (the test cannot pass on a variant that ignores it).
#[test]
fn inject_matches_the_cpu_mirror() {
    let gpu = gpu();
    let config = config();
    let (lights, volumes) = (lights(), local_volumes());
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let (mut got, mut texels) = (Vec::new(), Vec::new());
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(&lights, &volumes),
        |_, fog| {
            got = read_volume(gpu, fog.scattering_texture());
            texels = read_medium_shadow(fog);
        },
    );
    let frame = inputs(&lights, &volumes);
    let u = expected_uniforms(&config, &frame, 0);
    let volume = MediumShadowVolume {
        params: placement(&config, &u),
        texels,
    };
    let shadowed = cpu_inputs(&config, &u, &lights, &volumes, Some(&volume));
    let bare = cpu_inputs(&config, &u, &lights, &volumes, None);
    let size = config.volume_size;
    let (mut worst, mut changed) = (0.0f32, 0);
    for (i, g) in got.iter().enumerate() {
        let i = i as u32;
        let id = UVec3::new(i % size.x, (i / size.x) % size.y, i / (size.x * size.y));
        let want = froxel_scattering(&shadowed, id);
        let without = froxel_scattering(&bare, id);
        assert!(g.is_finite(), "{g}");
        let scale = want.truncate().max_element().max(1e-4);
        worst = worst.max(((*g - want).truncate().abs() / scale).max_element());
        let change = ((without - want).truncate().abs()
            / without.truncate().max_element().max(1e-4))
        .max_element();
        changed += usize::from(change > 0.01);
    }
    eprintln!(
        "inject with medium shadows vs CPU mirror: worst {worst:e} (bound 4e-3); {changed} \
         of {} froxels changed > 1 % by the medium's shadow",
        got.len()
    );
    assert!(changed * 100 > got.len(), "{changed}");
    assert!(worst <= 4e-3, "{worst}");
}

/// A horizontal slab 10 m thick (0.1 / m, edge 0.05 of its half height) overhead in
/// homogeneous fog under a sun straight above, over the left half of the near view:
/// below it the sun's in-scattering falls by exp(-tau), tau = 0.1 * 5 m * (2 - 0.05)
/// (the linear fade takes half its width off each face), within what the volume's
/// slices allow (each face inside a slice of length h shifts tau by at most
/// 0.1 h / (2 * 4) with four points a slice, plus 1e-3 for rgba16float); beside it
/// nothing changes (within 1e-3).
#[test]
fn a_slab_shadows_the_fog_below_by_its_closed_form() {
    let gpu = gpu();
    let config = FogConfig {
        medium_shadows: Some(MediumShadowConfig {
            size: UVec3::new(32, 32, 128),
            distance: 16.0,
            reach: 16.0,
            march_steps: 8,
        }),
        ..config()
    };
    let slab = [LocalVolume::new(
        Mat4::from_scale_rotation_translation(
            Vec3::new(10.0, 5.0, 25.0),
            glam::Quat::IDENTITY,
            Vec3::new(-10.0, 12.0, -30.0),
        ),
        VolumeShape::Box,
        0.1,
        0.05,
    )
    .unwrap()];
    let frame = |volumes: &'static [LocalVolume]| FrameInputs {
        medium: FogMedium {
            density: 0.02,
            height_falloff: 0.0,
            noise_strength: 0.0,
            // The sun's light enters the homogeneous medium here.
            top_height: 20.0,
            local_volume_count: volumes.len() as u32,
            ..FogMedium::default()
        },
        sun: DirectionalLight {
            direction: Vec3::Y,
            color: Vec3::splat(3.0),
            fog_intensity: 1.0,
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::constant(Vec3::ZERO),
        local_volumes: volumes,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    };
    let slab: &'static [LocalVolume] = Box::leak(Box::new(slab));
    let render = |config: &FogConfig| {
        let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
        let mut got = Vec::new();
        run_frames(
            gpu,
            &mut fog,
            1,
            |_| frame(slab),
            |_, fog| got = read_volume(gpu, fog.scattering_texture()),
        );
        got
    };
    let with = render(&config);
    let without = render(&FogConfig {
        medium_shadows: None,
        ..config.clone()
    });
    let u = expected_uniforms(&config, &frame(slab), 0);
    let step = placement(&config, &u).step;
    let expected = (-0.1f32 * 5.0 * (2.0 - 0.05)).exp();
    let bound = (0.1 * step / 4.0 + 1e-3f32).exp() - 1.0;
    let size = config.volume_size;
    let (mut under, mut beside, mut worst_under, mut worst_beside) = (0, 0, 0.0f32, 0.0f32);
    for (i, (w, o)) in with.iter().zip(&without).enumerate() {
        let i = i as u32;
        let id = UVec3::new(i % size.x, (i / size.x) % size.y, i / (size.x * size.y));
        let (world, depth) =
            volfog::cpu::inject::froxel_world_position(&u.froxels, &u.frame, id, false);
        // Below the slab, within the volume's ball (view depth 16 m).
        if world.y > 6.0 || depth > 15.0 || o.x < 1e-5 {
            continue;
        }
        let ratio = w.x / o.x;
        if world.x < -3.0 && world.z < -7.0 {
            under += 1;
            worst_under = worst_under.max((ratio / expected - 1.0).abs());
        } else if world.x > 3.0 {
            beside += 1;
            worst_beside = worst_beside.max((ratio - 1.0).abs());
        }
    }
    eprintln!(
        "slab shadow: {under} froxels under it at {worst_under:e} of exp(-tau) = {expected} \
         (bound {bound:e}, slices of {step} m), {beside} beside it within {worst_beside:e} \
         of 1 (bound 1e-3)"
    );
    assert!(under > 100 && beside > 100, "{under} {beside}");
    assert!(worst_under <= bound, "{worst_under}");
    assert!(worst_beside <= 1e-3, "{worst_beside}");
}

/// Bad settings get typed errors naming the field.
#[test]
fn bad_settings_are_typed_errors() {
    let gpu = gpu();
    let bad = |m: MediumShadowConfig, transmittance: bool| {
        let config = FogConfig {
            medium_shadows: Some(m),
            light_transmittance: transmittance,
            ..small_config()
        };
        match VolumetricFog::new(&gpu.device, &config) {
            Err(FogError::Invalid(e)) => e.field,
            other => panic!("expected a typed error, got {other:?}"),
        }
    };
    let good = MediumShadowConfig::default();
    assert_eq!(
        bad(
            MediumShadowConfig {
                size: UVec3::new(64, 1, 64),
                ..good
            },
            true
        ),
        "MediumShadowConfig.size.y"
    );
    assert_eq!(
        bad(
            MediumShadowConfig {
                distance: f32::NAN,
                ..good
            },
            true
        ),
        "MediumShadowConfig.distance"
    );
    assert_eq!(
        bad(
            MediumShadowConfig {
                reach: -1.0,
                ..good
            },
            true
        ),
        "MediumShadowConfig.reach"
    );
    assert_eq!(
        bad(
            MediumShadowConfig {
                march_steps: 0,
                ..good
            },
            true
        ),
        "MediumShadowConfig.march_steps"
    );
    // Without light transmittance nothing dims the light: the medium's shadows are
    // ignored, no pass runs.
    let ignored = FogConfig {
        medium_shadows: Some(good),
        light_transmittance: false,
        ..small_config()
    };
    let fog = VolumetricFog::new(&gpu.device, &ignored).unwrap();
    assert!(fog.medium_shadow_texture().is_none());
}
