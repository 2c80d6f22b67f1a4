//! Local volumes scaled by the density texture in their own space
//! (`LocalVolume::with_density_texture`): the GPU against the CPU mirror's trilinear,
//! repeat-addressed sample at `local * 0.5 + 0.5 + offset`, and against the closed
//! form of a constant texture, which scales a textured volume's extinction by its
//! value and leaves an untextured one alone; the global medium reads the texture only
//! when `FogMedium::textured` is 1.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{Mat4, UVec3, Vec3};
use volfog::cpu::inject::{DensityTexture, InjectInputs, froxel_scattering};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{FogMedium, LocalVolume, ShadowCascades, VolumeShape};

const SIZE: [u32; 3] = [16, 8, 12];

/// An R16Float 3D texture of `SIZE` texels from `value(x, y, z)` and the CPU mirror's
/// copy of its rounded values.
fn density_texture(value: impl Fn(u32, u32, u32) -> f32) -> (wgpu::Texture, DensityTexture) {
    super::density_texture(SIZE, value)
}

/// Two boxes in front of the camera, side by side, of extinction 0.2 / m: the left one
/// textured (the texture's offset scrolled by `offset`), the right one not.
fn volumes(offset: Vec3) -> [LocalVolume; 2] {
    let boxed = |x: f32| {
        LocalVolume::new(
            Mat4::from_scale_rotation_translation(
                Vec3::new(3.0, 2.5, 6.0),
                glam::Quat::from_rotation_y(0.3),
                Vec3::new(x, 2.0, -16.0),
            ),
            VolumeShape::Box,
            0.2,
            0.2,
        )
        .unwrap()
    };
    [
        boxed(-3.5).with_density_texture(offset).unwrap(),
        boxed(3.5),
    ]
}

/// The scattering volume of one frame of the two boxes (no global medium) with the
/// density texture `texture`, and the CPU mirror's inputs for it.
fn inject(
    texture: &wgpu::Texture,
    volumes: &[LocalVolume],
) -> (Vec<glam::Vec4>, FogConfig, FrameInputs<'static>) {
    inject_in(
        texture,
        volumes,
        FogMedium {
            density: 0.0,
            noise_strength: 0.0,
            ..FogMedium::default()
        },
    )
}

/// [`inject`] in the global medium `medium`.
fn inject_in(
    texture: &wgpu::Texture,
    volumes: &[LocalVolume],
    medium: FogMedium,
) -> (Vec<glam::Vec4>, FogConfig, FrameInputs<'static>) {
    let gpu = gpu();
    let config = FogConfig {
        density_texture: true,
        ..small_config()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_density_texture(&gpu.device, texture).unwrap();
    let volumes: &'static [LocalVolume] = Box::leak(volumes.to_vec().into_boxed_slice());
    let frame_inputs = FrameInputs {
        medium,
        cascades: ShadowCascades::default(),
        local_volumes: volumes,
        ..FrameInputs::new(view(2.0, 0.0), projection(), 1.5)
    };
    let mut scattering = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        1,
        |_| frame_inputs.clone(),
        |_, fog| scattering = read_volume(gpu, fog.scattering_texture()),
    );
    (scattering, config, frame_inputs)
}

#[test]
fn textured_local_volumes_match_the_cpu_mirror_and_a_constant_texture_scales_them() {
    // A pattern that repeats across the box several times over, scrolled.
    let (texture, reference) = density_texture(|x, y, z| {
        0.5 + 0.5
            * ((x as f32 * 0.9).sin() * (y as f32 * 1.3).cos() + 0.4 * (z as f32 * 0.7).sin())
                .clamp(-1.0, 1.0)
    });
    let volumes = volumes(Vec3::new(0.25, -0.4, 0.6));
    let (scattering, config, frame_inputs) = inject(&texture, &volumes);
    let u = expected_uniforms(&config, &frame_inputs, 0);
    let inputs = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &[],
        local_volumes: &volumes,
        options: config.inject_options(),
        density_texture: Some(&reference),
        noise_texture: None,
        clouds: None,
        local_shadows: None,
        scene_depth: None,
        medium_shadow: None,
    };
    let s = config.volume_size;
    let (mut worst, mut inside, mut lo, mut hi) = (0.0f32, 0usize, f32::MAX, 0.0f32);
    for z in 0..s.z {
        for y in 0..s.y {
            for x in 0..s.x {
                let id = UVec3::new(x, y, z);
                let want = froxel_scattering(&inputs, id).w;
                let got = scattering[index(s, x, y, z)].w;
                // The sampler's fixed-point filter weights (8 bits on lavapipe) and the
                // fp16 output, relative to the volume's extinction.
                worst = worst.max((got - want).abs() / 0.2);
                let textured = volfog::cpu::density::local_volume_density(&volumes[0], {
                    volfog::cpu::inject::froxel_world_position(&u.froxels, &u.frame, id, false).0
                });
                if textured >= 0.2 {
                    inside += 1;
                    lo = lo.min(got);
                    hi = hi.max(got);
                }
            }
        }
    }
    eprintln!(
        "textured local volume: {inside} froxels fully inside, sigma_t from {lo:.4} to {hi:.4} \
         (untextured 0.2); worst difference vs CPU {:.3}% of the volume's extinction (bound 0.5%)",
        worst * 100.0
    );
    assert!(inside >= 50, "the textured box covers froxels: {inside}");
    assert!(
        hi > 2.0 * lo && hi <= 0.2 + 1e-3,
        "the texture modulates the box: {lo} .. {hi}"
    );
    assert!(worst <= 5e-3, "{worst}");

    // Closed form: a texture of constant value c scales the textured box's extinction
    // by c, whatever its offset, and leaves the untextured box and the empty space alone.
    let c = 0.375;
    let (constant, _) = density_texture(|_, _, _| c);
    let (scaled, ..) = inject(&constant, &volumes);
    let untextured: Vec<LocalVolume> = volumes
        .iter()
        .map(|v| LocalVolume { textured: 0, ..*v })
        .collect();
    let (plain, ..) = inject(&constant, &untextured);
    let (mut worst_textured, mut worst_plain, mut counted) = (0.0f32, 0.0f32, 0usize);
    for z in 0..s.z {
        for y in 0..s.y {
            for x in 0..s.x {
                let i = index(s, x, y, z);
                let world = volfog::cpu::inject::froxel_world_position(
                    &u.froxels,
                    &u.frame,
                    UVec3::new(x, y, z),
                    false,
                )
                .0;
                let in_textured =
                    volfog::cpu::density::local_volume_density(&volumes[0], world) > 0.0;
                let expected = if in_textured {
                    c * plain[i].w
                } else {
                    plain[i].w
                };
                let error = (scaled[i].w - expected).abs() / 0.2;
                if in_textured {
                    counted += 1;
                    worst_textured = worst_textured.max(error);
                } else {
                    worst_plain = worst_plain.max(error);
                }
            }
        }
    }
    eprintln!(
        "constant texture {c}: {counted} froxels in the textured box, worst |sigma_t - c sigma_t(untextured)| \
         {:.3}% of the extinction, elsewhere {:.3}% (bounds 0.1%, fp16)",
        worst_textured * 100.0,
        worst_plain * 100.0
    );
    assert!(counted >= 50);
    assert!(worst_textured <= 1e-3 && worst_plain <= 1e-3);
}

#[test]
fn the_global_medium_reads_the_density_texture_only_when_textured() {
    // A uniform medium of extinction 0.05 / m and no local volume: with a texture of
    // constant value c, a textured medium's extinction is c times an untextured one's,
    // and an untextured medium's equals its extinction under a texture of ones.
    let c = 0.375;
    let (constant, _) = density_texture(|_, _, _| c);
    let (ones, _) = density_texture(|_, _, _| 1.0);
    let medium = |textured| FogMedium {
        density: 0.05,
        height_falloff: 0.0,
        noise_strength: 0.0,
        textured,
        ..FogMedium::default()
    };
    let (textured, ..) = inject_in(&constant, &[], medium(1));
    let (untextured, ..) = inject_in(&constant, &[], medium(0));
    let (reference, ..) = inject_in(&ones, &[], medium(0));
    let (mut worst_scaled, mut worst_ignored) = (0.0f32, 0.0f32);
    for ((t, u), r) in textured.iter().zip(&untextured).zip(&reference) {
        worst_scaled = worst_scaled.max((t.w - c * r.w).abs() / 0.05);
        worst_ignored = worst_ignored.max((u.w - r.w).abs() / 0.05);
    }
    eprintln!(
        "global medium under a constant texture {c}: textured, worst |sigma_t - c sigma_t| \
         {:.3}% of the extinction; untextured, worst change {:.3}% (bounds 0.1%, fp16)",
        worst_scaled * 100.0,
        worst_ignored * 100.0
    );
    assert!(reference.iter().all(|r| (r.w - 0.05).abs() <= 1e-4));
    assert!(worst_scaled <= 1e-3 && worst_ignored <= 1e-3);
}
