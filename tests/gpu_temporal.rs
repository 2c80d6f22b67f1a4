//! Temporal reprojection: the pass against the CPU mirror under camera motion, the
//! flicker reduction of jittered sampling, and the documented convergence after a
//! lighting change.

mod common;

use common::gpu;
use common::scene::*;
use glam::{Mat4, UVec3, Vec3, Vec4};
use volfog::cpu::apply::Volume;
use volfog::cpu::inject::temporal_blend;
use volfog::pipeline::temporal::TemporalPass;
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::selfcheck::{depth_array_texture, round_f16, test_froxels};
use volfog::uniforms::{self, AmbientSh, DirectionalLight, FogFrame, FogLight, FogMedium};
use wgpu::util::DeviceExt;

#[test]
fn temporal_pass_matches_cpu_under_camera_motion() {
    let gpu = gpu();
    let froxels = test_froxels([24, 14], 32);
    let size = froxels.size;
    let count = (size.x * size.y * size.z) as usize;
    let smooth = |i: usize, phase: f32| {
        let (x, y, z) = (
            i % size.x as usize,
            (i / size.x as usize) % size.y as usize,
            i / (size.x * size.y) as usize,
        );
        let f = Vec3::new(
            x as f32 / size.x as f32,
            y as f32 / size.y as f32,
            z as f32 / size.z as f32,
        );
        Vec4::new(
            0.5 + 0.3 * (3.0 * f.x + phase).sin(),
            0.4 + 0.2 * f.y,
            0.3 + 0.2 * (2.0 * f.z).cos(),
            0.1 + 0.05 * f.x,
        )
    };
    let now: Vec<Vec4> = (0..count).map(|i| smooth(i, 0.0)).collect();
    let history: Vec<Vec4> = (0..count).map(|i| smooth(i, 1.3)).collect();
    for moved in [true, false] {
        let world_from_view = Mat4::from_rotation_translation(
            glam::Quat::from_rotation_y(0.05),
            Vec3::new(0.3, 1.0, 0.0),
        );
        let prev_world_from_view = if moved {
            Mat4::from_translation(Vec3::new(0.0, 1.0, 0.5))
        } else {
            world_from_view
        };
        let frame = FogFrame {
            world_from_view,
            prev_clip_from_world: froxels.clip_from_view * prev_world_from_view.inverse(),
            camera_position: world_from_view.w_axis.truncate(),
            time: 0.0,
            jitter: volfog::cpu::froxel::froxel_jitter(5),
            history_weight: 0.9,
            history_valid: 1,
        };
        let pass = TemporalPass::new(&gpu.device);
        let uniform = |bytes: Vec<u8>| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: None,
                    contents: &bytes,
                    usage: wgpu::BufferUsages::UNIFORM,
                })
        };
        let (fb, fr) = (
            uniform(froxels.to_bytes()),
            uniform(uniforms::to_uniform_bytes(&frame)),
        );
        let cur = gpu.texture_3d_rgba16f("now", size.to_array(), &now);
        let hist = gpu.texture_3d_rgba16f("history", size.to_array(), &history);
        let out = gpu.texture_3d_rgba16f("out", size.to_array(), &[]);
        let v = |t: &wgpu::Texture| t.create_view(&Default::default());
        let group = pass.bind_group(&gpu.device, &fb, &fr, &v(&cur), &v(&hist), &v(&out));
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut c = encoder.begin_compute_pass(&Default::default());
            pass.encode(&mut c, &group, size.to_array());
        }
        gpu.queue.submit([encoder.finish()]);
        let got = gpu.read_texture_rgba16f(&out).unwrap();
        let hist_cpu = Volume {
            size: size.to_array(),
            texels: history.iter().map(|t| round_f16(*t)).collect(),
        };
        let (mut worst, mut reprojected) = (0.0f32, 0);
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    let i = index(size, x, y, z);
                    let want = temporal_blend(
                        &froxels,
                        &frame,
                        UVec3::new(x, y, z),
                        round_f16(now[i]),
                        &hist_cpu,
                    );
                    if (want - round_f16(now[i])).abs().max_element() > 1e-6 {
                        reprojected += 1;
                    }
                    worst = worst.max((got[i] - want).abs().max_element());
                }
            }
        }
        eprintln!("temporal moved={moved}: {reprojected}/{count} froxels use history, max abs difference vs CPU {worst:e} (bound 2e-3)");
        assert!(
            reprojected > count / 2,
            "most froxels reproject into the previous volume"
        );
        if moved {
            assert!(
                reprojected < count,
                "some froxels leave the previous frustum"
            );
        }
        assert!(worst <= 2e-3, "{worst}");
    }
}

fn scene_inputs<'a>(
    lights: &'a [FogLight],
    cascades: uniforms::ShadowCascades,
    time: f32,
) -> FrameInputs<'a> {
    FrameInputs {
        medium: FogMedium {
            density: 0.04,
            height_falloff: 0.05,
            noise_strength: 0.9,
            noise_scale: 0.8,
            ..FogMedium::default()
        },
        sun: DirectionalLight {
            direction: Vec3::Y,
            color: Vec3::splat(3.0),
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::constant(Vec3::new(0.05, 0.06, 0.08)),
        lights,
        cascades,
        ..FrameInputs::new(view(3.0, -0.05), projection(), time)
    }
}

fn rms(a: &[Vec4], b: &[Vec4]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).truncate().length_squared() as f64)
        .sum();
    (sum / a.len() as f64).sqrt()
}

/// Jittered sampling of a static scene with sharp detail (noise, a shadow edge, a
/// small light) flickers frame to frame; reprojection must cut the frame-to-frame RMS
/// change of the integrated volume at least 4x once 16 frames have accumulated.
#[test]
fn reprojection_reduces_jitter_flicker() {
    let gpu = gpu();
    let slab = Slab {
        x: (-20.0, 4.0),
        z: (-60.0, -10.0),
        top: 6.0,
    };
    let lights = [FogLight::point(
        Vec3::new(1.0, 2.0, -9.0),
        Vec3::new(20.0, 12.0, 6.0),
        4.0,
    )];
    let mut measured = Vec::new();
    for temporal in [false, true] {
        let config = FogConfig {
            jitter: true,
            temporal,
            ..small_config()
        };
        let (cascades, layers) = overhead_sun(&config, Some(slab));
        let slices: Vec<&[f32]> = layers.iter().map(|l| l.texels.as_slice()).collect();
        let shadow = depth_array_texture(&gpu, layers[0].width, layers[0].width, &slices).unwrap();
        let shadow = shadow_view(&shadow);
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let mut frames: Vec<Vec<Vec4>> = Vec::new();
        run_frames(
            &gpu,
            &mut fog,
            Some(&shadow),
            24,
            |_| scene_inputs(&lights, cascades, 2.0),
            |f, fog| {
                if f >= 16 {
                    frames.push(read_volume(&gpu, fog.integrated_texture()));
                }
            },
        );
        let change: f64 =
            frames.windows(2).map(|w| rms(&w[1], &w[0])).sum::<f64>() / (frames.len() - 1) as f64;
        measured.push(change);
    }
    let ratio = measured[0] / measured[1];
    eprintln!(
        "frame-to-frame RMS change with jitter, frames 16..24: no reprojection {:.3e}, reprojection {:.3e}: {ratio:.1}x lower (bound 4x)",
        measured[0], measured[1]
    );
    assert!(measured[0] > 0.0 && ratio >= 4.0, "{ratio}");
}

/// After a light moves, the stabilised volume approaches the new steady state as
/// 0.9^n: the documented bound is an error below 5 % after 29 frames.
#[test]
fn lighting_change_converges_within_documented_frames() {
    let gpu = gpu();
    let config = FogConfig {
        jitter: false,
        temporal: true,
        ..small_config()
    };
    let before = [FogLight::point(
        Vec3::new(-3.0, 2.0, -10.0),
        Vec3::new(40.0, 20.0, 10.0),
        15.0,
    )];
    let after = [FogLight::point(
        Vec3::new(4.0, 3.0, -18.0),
        Vec3::new(10.0, 30.0, 40.0),
        15.0,
    )];
    let none = uniforms::ShadowCascades::default();
    // The steady state after the change: one frame without reprojection.
    let mut reference_fog = VolumetricFog::new(
        &gpu.device,
        &FogConfig {
            temporal: false,
            ..config.clone()
        },
    )
    .unwrap();
    let mut steady = Vec::new();
    run_frames(
        &gpu,
        &mut reference_fog,
        None,
        1,
        |_| scene_inputs(&after, none, 1.0),
        |_, fog| steady = read_volume(&gpu, fog.integrated_texture()),
    );

    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let mut start = Vec::new();
    let mut errors = Vec::new();
    run_frames(
        &gpu,
        &mut fog,
        None,
        40 + 60,
        |f| scene_inputs(if f < 40 { &before } else { &after }, none, 1.0),
        |f, fog| {
            if f == 39 {
                start = read_volume(&gpu, fog.integrated_texture());
            } else if f >= 40 {
                errors.push(rms(&read_volume(&gpu, fog.integrated_texture()), &steady));
            }
        },
    );
    let initial = rms(&start, &steady);
    let relative: Vec<f64> = errors.iter().map(|e| e / initial).collect();
    let frames_to_5 = relative.iter().position(|r| *r <= 0.05).map(|n| n + 1);
    eprintln!(
        "light moved: relative error after 1, 10, 29, 44 frames: {:.3} {:.3} {:.4} {:.4}; below 5 % after {frames_to_5:?} frames (documented 29)",
        relative[0], relative[9], relative[28], relative[43]
    );
    assert!(initial > 0.0);
    assert!(frames_to_5.is_some_and(|n| n <= 29), "{frames_to_5:?}");
    assert!(relative[59] <= 0.01, "settles below 1 %: {}", relative[59]);
}
