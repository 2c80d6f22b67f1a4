//! Epipolar sun shafts: unshadowed against the closed-form height fog, half
//! shadowed the tree march against the march over every section.

use glam::{Vec2, Vec3, Vec4};

use super::depth::depth_texture;
use super::test_projection;
use crate::gpu::{Gpu, GpuError};

/// Epipolar sun shafts on a 160x90 screen (ground plane at 1-80 m, 256² shadow map):
/// unshadowed, the lit fraction is 1 everywhere (the fog is then the closed-form
/// height fog); with a half-plane of the shadow map in shadow, the tree march gives
/// the march over every section.
#[derive(Debug, Clone, Copy)]
pub struct EpipolarCheck {
    /// Unshadowed: max |F - 1| over the screen (rgba16float: 1e-3 is its rounding).
    pub unshadowed: f32,
    /// Half shadowed: max |F(tree) - F(every section)| over the ray-marching samples.
    pub tree_vs_steps: f32,
    /// Half shadowed: ray-marching samples neither fully lit nor fully shadowed.
    pub partly_shadowed: usize,
}

/// Runs [`EpipolarCheck`].
pub fn epipolar_check(gpu: &Gpu) -> Result<EpipolarCheck, GpuError> {
    use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
    use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
    let fail = |e: &dyn std::fmt::Display| GpuError::Operation(e.to_string());
    let (w, h, size) = (160u32, 90u32, 256u32);
    let projection = test_projection();
    let view_from_world = glam::camera::rh::view::look_to_mat4(
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(0.0, -0.05, -1.0),
        Vec3::Y,
    );
    let sun = Vec3::new(0.3, 0.4, -1.0).normalize();
    // Depth: the ground seen by each pixel, clamped to 1..80 m of view depth.
    let view_from_clip = projection.inverse();
    let world_from_view = view_from_world.inverse();
    let depths: Vec<f32> = (0..w * h)
        .map(|i| {
            let ndc = Vec2::new(
                ((i % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - ((i / w) as f32 + 0.5) / h as f32 * 2.0,
            );
            let ray = view_from_clip.project_point3(ndc.extend(0.5));
            let dir = world_from_view.transform_vector3(ray / ray.z.abs());
            let z = if dir.y < -1e-4 {
                (3.0 / -dir.y).clamp(1.0, 80.0)
            } else {
                80.0
            };
            let clip = projection * Vec4::new(0.0, 0.0, -z, 1.0);
            clip.z / clip.w
        })
        .collect();
    let depth = depth_texture(gpu, w, h, &depths)?;
    let light_from_world =
        volfog::pipeline::cascade_projection(sun, Vec3::new(0.0, 0.0, -40.0), 60.0, 200.0);
    let medium = HeightFog::new(Vec3::splat(0.02), 0.03, Vec3::Y, 0.05, 0.0)
        .and_then(|f| f.with_sun(sun, Vec3::splat(2.0), 0.5))
        .map_err(|e| fail(&e))?;
    let view = EpipolarView {
        view_from_world,
        clip_from_view: projection,
        light_from_world,
        cascade: 0,
        rayleigh: Vec3::ZERO,
        phase: EpipolarPhase::HenyeyGreenstein,
        start_depth: 0.0,
        max_depth: 80.0,
        depth_bias: 0.0,
    };
    let sampling = EpipolarSampling {
        slices: 128,
        samples: 128,
        downscale: 1,
        ..EpipolarSampling::new(w, h, size)
    };
    // (shaft texture, marched lit fractions, packed interpolation sources)
    type Run = (Vec<Vec4>, Vec<f32>, Vec<u32>);
    let run = |shadow: &[f32], mode| -> Result<Run, GpuError> {
        let shadow = depth_texture(gpu, size, size, shadow)?;
        let mut shafts = EpipolarShafts::new(&gpu.device, sampling).map_err(|e| fail(&e))?;
        shafts
            .set_inputs(&gpu.device, &depth, &shadow)
            .map_err(|e| fail(&e))?;
        shafts
            .prepare(&gpu.queue, &view, &medium)
            .map_err(|e| fail(&e))?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        shafts.encode(&mut encoder, mode).map_err(|e| fail(&e))?;
        gpu.queue.submit([encoder.finish()]);
        let image = gpu.read_texture_rgba16f(shafts.shaft_texture())?;
        // The marched lit fraction is rgba32float: keep its first channel.
        let marched = gpu.read_texture_raw(shafts.marched_texture(), 16)?;
        let sources = gpu.read_texture_raw(shafts.source_texture(), 4)?;
        Ok((
            image,
            bytemuck::cast_slice::<u8, f32>(&marched)
                .iter()
                .step_by(4)
                .copied()
                .collect(),
            bytemuck::cast_slice(&sources).to_vec(),
        ))
    };
    let open = vec![1.0f32; (size * size) as usize];
    let (image, _, _) = run(&open, EpipolarMode::Tree)?;
    let unshadowed = image
        .iter()
        .map(|p| (p.x - 1.0).abs())
        .fold(0.0f32, f32::max);
    let half: Vec<f32> = (0..size * size)
        .map(|t| if (t % size) < size / 2 { 0.0 } else { 1.0 })
        .collect();
    let (_, tree, sources) = run(&half, EpipolarMode::Tree)?;
    let (_, steps, _) = run(&half, EpipolarMode::Steps)?;
    let marching = |i: &usize| sources[*i] & 0xffff == sources[*i] >> 16;
    let tree_vs_steps = (0..tree.len())
        .filter(marching)
        .map(|i| (tree[i] - steps[i]).abs())
        .fold(0.0f32, f32::max);
    let partly_shadowed = (0..tree.len())
        .filter(marching)
        .filter(|&i| steps[i] > 0.01 && steps[i] < 0.99)
        .count();
    Ok(EpipolarCheck {
        unshadowed,
        tree_vs_steps,
        partly_shadowed,
    })
}
