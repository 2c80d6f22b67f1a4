//! Particles in the fog (`VOLFOG_INJECT_PARTICLES`): the inject variant through
//! `VolumetricFog` against the CPU mirror (`volfog::cpu::particles`), the scan through a
//! particle against its closed-form optical depth, and typed errors for bad particles.

use crate::common::scene::*;
use crate::common::{Rng, gpu};
use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::inject::{InjectInputs, froxel_scattering_particles, froxel_world_position};
use volfog::cpu::particles::particle_optical_depth;
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{FogMedium, FogParticle};

fn config(max_particles: u32) -> FogConfig {
    FogConfig {
        max_particles,
        ..small_config()
    }
}

fn inputs(particles: &[FogParticle]) -> FrameInputs<'_> {
    FrameInputs {
        medium: medium(),
        ambient: AmbientSh::constant(Vec3::new(0.3, 0.35, 0.4)),
        particles,
        ..FrameInputs::new(view(3.0, -0.1), projection(), 2.0)
    }
}

/// `n` random particles in the small scene's view (2 to 40 m ahead): radius 0.2 to
/// 2.5 m, extinction 0.02 to 2 /m, any albedo and falloff, one in four glowing.
fn random_particles(n: usize, seed: u64) -> Vec<FogParticle> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|i| {
            let z = rng.range(2.0, 40.0);
            FogParticle {
                position: Vec3::new(
                    rng.range(-0.9, 0.9) * z,
                    3.0 - 0.1 * z + rng.range(-0.5, 0.5) * z,
                    -z,
                ),
                radius: rng.log(0.2, 2.5),
                albedo: Vec3::new(rng.f(), rng.f(), rng.f()),
                extinction: rng.log(0.02, 2.0),
                emission: if i % 4 == 0 {
                    Vec3::new(rng.f(), rng.f(), rng.f()) * 2.0
                } else {
                    Vec3::ZERO
                },
                falloff: rng.f(),
            }
        })
        .collect()
}

/// The CPU mirror of one frame's inject.
fn mirror(config: &FogConfig, frame: &FrameInputs<'_>) -> Vec<Vec4> {
    let u = expected_uniforms(config, frame, 0);
    let cpu = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &[],
        local_volumes: &[],
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let size = config.volume_size;
    (0..size.x * size.y * size.z)
        .map(|i| {
            let id = UVec3::new(i % size.x, (i / size.x) % size.y, i / (size.x * size.y));
            froxel_scattering_particles(&cpu, id, 1, None, frame.particles)
        })
        .collect()
}

fn inject(config: &FogConfig, particles: &[FogParticle]) -> Vec<Vec4> {
    let gpu = gpu();
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    let mut got = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| inputs(particles),
        |_, fog| got = read_volume(gpu, fog.scattering_texture()),
    );
    got
}

/// The spacing of rgba16float values around `x`: 2^-10 of its power of two, 2^-24
/// among the subnormals.
fn half_step(x: f32) -> f32 {
    let x = x.abs();
    if x < 2f32.powi(-14) {
        2f32.powi(-24)
    } else {
        2f32.powi(x.log2().floor() as i32 - 10)
    }
}

/// 1,000 random particles: the GPU's volume against the CPU mirror, every channel
/// within two rgba16float steps of the mirror's value: rounding to rgba16float is half
/// a step, the rest is f32 evaluation (the medium's noise and exp differ by up to
/// about one step in this scene without particles, measured here too; then the order
/// of the particles' sum). The particles dominate a good part of the volume, so a
/// variant that ignored them could not pass; without particles the variant matches
/// the fog without it.
#[test]
fn particles_match_the_cpu_mirror() {
    let with_room = config(1000);
    let particles = random_particles(1000, 41);
    let got = inject(&with_room, &particles);
    let want = mirror(&with_room, &inputs(&particles));
    let base = mirror(&with_room, &inputs(&[]));
    let (mut worst_steps, mut worst_relative, mut dense) = (0.0f32, 0.0f32, 0);
    for ((g, w), b) in got.iter().zip(&want).zip(&base) {
        assert!(g.is_finite(), "{g}");
        for c in 0..4 {
            worst_steps = worst_steps.max((g[c] - w[c]).abs() / half_step(w[c]));
        }
        let scale = w.max_element().max(1e-3);
        worst_relative = worst_relative.max((*g - *w).abs().max_element() / scale);
        if w.w > 2.0 * b.w {
            dense += 1;
        }
    }
    eprintln!(
        "1000 particles vs CPU mirror: worst error {worst_steps} rgba16float steps (bound 2), \
         {worst_relative:e} of the froxel's largest channel; {dense} of {} froxels at least \
         twice as dense as the medium alone",
        got.len()
    );
    assert!(dense > 2000, "the particles shape the fog: {dense} froxels");
    assert!(worst_steps <= 2.0, "{worst_steps}");

    // Room for particles and none: the medium alone, as without the variant.
    let empty = inject(&with_room, &[]);
    let plain = inject(&config(0), &[]);
    let mut base_steps = 0.0f32;
    for (p, b) in plain.iter().zip(&base) {
        for c in 0..4 {
            base_steps = base_steps.max((p[c] - b[c]).abs() / half_step(b[c]));
        }
    }
    eprintln!(
        "the fog without particles vs its mirror: worst error {base_steps} rgba16float steps"
    );
    let mut worst_empty = 0.0f32;
    for (e, p) in empty.iter().zip(&plain) {
        let scale = p.max_element().max(1e-6);
        worst_empty = worst_empty.max((*e - *p).abs().max_element() / scale);
    }
    eprintln!("no particles in the particle variant vs the fog without it: {worst_empty:e}");
    assert!(worst_empty <= 2f32.powi(-11), "{worst_empty}");
}

/// One particle in clear air: the scanned transmittance of each froxel column through
/// it, at the last slice, against exp(-tau) of the particle's closed-form optical depth
/// along the column's centre ray (volfog::cpu::particles::particle_optical_depth).
/// The scan is a midpoint rule over the slices, so the bound is on the optical depth:
/// within 1.5 % of tau plus, where the profile jumps at the radius (falloff below 1, a
/// jump of (1 - falloff) sigma), (1 - falloff) sigma ds for its two edges (each edge
/// falls inside a slice of length ds along the ray: half a slice of error at most);
/// 2e-3 absolute in the columns that miss it.
#[test]
fn scan_through_a_particle_matches_its_closed_form_optical_depth() {
    let gpu = gpu();
    let config = FogConfig {
        volume_size: UVec3::new(32, 18, 128),
        far: 40.0,
        slice_curve: 1.0,
        ..config(4)
    };
    let clear = FogMedium {
        density: 0.0,
        noise_strength: 0.0,
        ..medium()
    };
    for falloff in [0.0, 0.5, 1.0] {
        let particle = FogParticle {
            position: Vec3::new(1.0, 1.5, -20.0),
            radius: 4.0,
            albedo: Vec3::splat(0.8),
            extinction: 0.3,
            emission: Vec3::ZERO,
            falloff,
        };
        let particles = [particle];
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let frame = || FrameInputs {
            medium: clear,
            ..inputs(&particles)
        };
        let mut got = Vec::new();
        run_frames(
            gpu,
            &mut fog,
            1,
            |_| frame(),
            |_, fog| got = read_volume(gpu, fog.integrated_texture()),
        );
        let u = expected_uniforms(&config, &frame(), 0);
        let camera = u.frame.camera_position;
        let size = config.volume_size;
        let (mut crossed, mut worst, mut worst_abs) = (0, 0.0f32, 0.0f32);
        for y in 0..size.y {
            for x in 0..size.x {
                let last = UVec3::new(x, y, size.z - 1);
                let (far_point, _) = froxel_world_position(&u.froxels, &u.frame, last, false);
                let dir = (far_point - camera).normalize();
                let tau = particle_optical_depth(&particle, camera, dir, 1e9);
                let t = got[index(size, x, y, size.z - 1)].w;
                let scanned = -t.max(1e-6).ln();
                // The slice length along this ray at the particle's depth.
                let at = |z: u32| {
                    froxel_world_position(&u.froxels, &u.frame, UVec3::new(x, y, z), false).0
                };
                let ds = at(64).distance(at(65));
                let jump = (1.0 - falloff) * particle.extinction * ds;
                if tau > 0.05 {
                    crossed += 1;
                    let error = (scanned - tau).abs();
                    assert!(
                        error <= 1.5e-2 * tau + jump,
                        "column ({x}, {y}): {scanned} vs {tau}, ds {ds}"
                    );
                    worst = worst.max((error - jump).max(0.0) / tau);
                } else {
                    worst_abs = worst_abs.max((scanned - tau).abs());
                }
            }
        }
        eprintln!(
            "scan through one particle (falloff {falloff}): {crossed} columns with tau > 0.05, \
             worst relative error of tau beyond the edges' allowance {worst:e} (bound 1.5e-2), \
             elsewhere worst absolute {worst_abs:e} (bound 2e-3)"
        );
        assert!(crossed > 15, "{crossed}");
        assert!(worst_abs <= 2e-3, "{worst_abs}");
    }
}

/// Bad particles and too many are typed errors naming the field.
#[test]
fn bad_particles_are_typed_errors_naming_the_field() {
    let config = config(4);
    let good = FogParticle::smoke(Vec3::new(0.0, 2.0, -5.0), 1.0, 0.5, Vec3::splat(0.6));
    let field = |particles: &[FogParticle]| inputs(particles).validate(&config).unwrap_err().field;
    assert!(inputs(&[good]).validate(&config).is_ok());
    let cases = [
        (
            FogParticle {
                position: Vec3::new(f32::NAN, 0.0, 0.0),
                ..good
            },
            "FogParticle.position",
        ),
        (
            FogParticle {
                position: Vec3::splat(f32::INFINITY),
                ..good
            },
            "FogParticle.position",
        ),
        (
            FogParticle {
                radius: 0.0,
                ..good
            },
            "FogParticle.radius",
        ),
        (
            FogParticle {
                radius: -1.0,
                ..good
            },
            "FogParticle.radius",
        ),
        (
            FogParticle {
                radius: f32::NAN,
                ..good
            },
            "FogParticle.radius",
        ),
        (
            FogParticle {
                extinction: -0.1,
                ..good
            },
            "FogParticle.extinction",
        ),
        (
            FogParticle {
                extinction: f32::INFINITY,
                ..good
            },
            "FogParticle.extinction",
        ),
        (
            FogParticle {
                albedo: Vec3::new(0.5, 1.5, 0.5),
                ..good
            },
            "FogParticle.albedo",
        ),
        (
            FogParticle {
                emission: Vec3::new(-1.0, 0.0, 0.0),
                ..good
            },
            "FogParticle.emission",
        ),
        (
            FogParticle {
                falloff: 1.5,
                ..good
            },
            "FogParticle.falloff",
        ),
    ];
    for (bad, name) in cases {
        let err = inputs(&[good, bad]).validate(&config).unwrap_err();
        assert_eq!(err.field, name, "{bad:?}");
        assert!(!err.expected.is_empty());
    }
    assert_eq!(field(&[good; 5]), "FrameInputs.particles");
    let too_many = FogConfig {
        max_particles: volfog::limits::MAX_PARTICLES + 1,
        ..config.clone()
    };
    let Err(err) = VolumetricFog::new(&gpu().device, &too_many) else {
        panic!("FogConfig.max_particles above the limit is accepted");
    };
    assert!(err.to_string().contains("FogConfig.max_particles"), "{err}");
    // A rejected frame is an error from prepare, never a panic.
    let mut fog = VolumetricFog::new(&gpu().device, &config).unwrap();
    assert!(
        fog.prepare(
            &gpu().queue,
            &inputs(&[FogParticle {
                radius: 0.0,
                ..good
            }])
        )
        .is_err()
    );
}
