//! The fullscreen apply pass against the CPU answer `color * T + L` on a synthetic
//! case (volume, depths from the near plane to beyond far, analytic tail).

use glam::{Vec2, Vec3, Vec4};

use volfog::cpu;
use volfog::cpu::apply::Volume;
use volfog::options::Filtering;
use volfog::pipeline::apply::{
    ApplyPipeline, FogResources, fog_bind_group, fog_layout_entries, fog_sampler,
};
use volfog::uniforms::Froxels;

use super::depth::depth_texture;
use super::{round_f16, test_froxels, uniform_buffer};
use crate::gpu::{Gpu, GpuError};

/// Inputs of an apply run: a colour image, a depth image and an integrated volume.
#[derive(Debug, Clone)]
pub struct ApplyCase {
    /// Froxel placement.
    pub froxels: Froxels,
    /// Image size in pixels.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Lit colour per pixel (rgb, a ignored), row-major from the top.
    pub color: Vec<Vec4>,
    /// Depth-buffer value per pixel (standard depth, [0, 1]).
    pub depth: Vec<f32>,
    /// The integrated volume (x fastest).
    pub volume: Vec<Vec4>,
    /// The analytic tail beyond the far plane, in view space.
    pub tail: volfog::uniforms::HeightFog,
}

impl ApplyCase {
    /// A deterministic case: a smooth volume whose in-scatter and transmittance
    /// vary along every axis, depths spanning the near plane to beyond far, and a
    /// colour gradient.
    pub fn synthetic(width: u32, height: u32) -> Self {
        let froxels = test_froxels([20, 12], 32);
        let [sx, sy, sz] = froxels.size.to_array();
        let mut volume = Vec::with_capacity((sx * sy * sz) as usize);
        for z in 0..sz {
            for y in 0..sy {
                for x in 0..sx {
                    let (fx, fy, fz) = (
                        x as f32 / sx as f32,
                        y as f32 / sy as f32,
                        (z + 1) as f32 / sz as f32,
                    );
                    let t = (-2.5 * fz * (1.0 + 0.3 * fx)).exp();
                    let l = Vec3::new(0.8 + 0.2 * fy, 0.6 + 0.3 * fx, 0.5) * (1.0 - t);
                    volume.push(l.extend(t));
                }
            }
        }
        let proj = froxels.clip_from_view;
        let mut color = Vec::new();
        let mut depth = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let v = (y as f32 + 0.5) / height as f32;
                color.push(Vec4::new(u, v, 1.0 - u, 1.0));
                // View depth from 0.2 m (in front of near) to 400 m (beyond far).
                let view_depth = 0.2 * (2000.0f32).powf((u + v * 0.37).fract());
                let clip = proj * Vec4::new(0.0, 0.0, -view_depth, 1.0);
                depth.push(clip.z / clip.w);
            }
        }
        Self {
            froxels,
            width,
            height,
            color,
            depth,
            volume,
            tail: volfog::uniforms::HeightFog::new(
                Vec3::new(0.5, 0.6, 0.7),
                0.01,
                Vec3::Y,
                0.05,
                -2.0,
            )
            .and_then(|f| {
                f.with_sun(
                    Vec3::new(0.3, 0.5, -0.8).normalize(),
                    Vec3::new(0.4, 0.3, 0.2),
                    0.6,
                )
            })
            .expect("valid tail"),
        }
    }

    /// The CPU answer: `color * T + L` with the fog at each pixel's centre.
    pub fn expected(&self) -> Vec<Vec4> {
        let volume = Volume {
            size: self.froxels.size.to_array(),
            texels: self.volume.iter().map(|t| round_f16(*t)).collect(),
        };
        let mut out = Vec::with_capacity(self.color.len());
        for y in 0..self.height {
            for x in 0..self.width {
                let i = (y * self.width + x) as usize;
                let uv = Vec2::new(
                    (x as f32 + 0.5) / self.width as f32,
                    (y as f32 + 0.5) / self.height as f32,
                );
                let ndc = cpu::froxel::ndc_from_uv(uv).extend(self.depth[i]);
                let view = cpu::froxel::view_from_ndc(ndc, self.froxels.view_from_clip);
                let fog = volume.fog(cpu::apply::fog_coord(uv, view.z.abs(), &self.froxels));
                let fog = cpu::apply::fog_with_tail(
                    fog,
                    cpu::apply::fog_tail(&self.froxels, &self.tail, view),
                );
                let color = round_f16(self.color[i]);
                out.push(cpu::apply::apply_fog(color.truncate(), fog).extend(color.w));
            }
        }
        out
    }
}

/// Runs the fullscreen apply pass on an `ApplyCase` into an rgba16float target
/// (blending onto the case's colour) and returns the fogged image.
pub fn run_apply(gpu: &Gpu, filtering: Filtering, case: &ApplyCase) -> Result<Vec<Vec4>, GpuError> {
    let format = wgpu::TextureFormat::Rgba16Float;
    let fog_layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fog group"),
            entries: &fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT),
        });
    let pass = gpu
        .checked(|| ApplyPipeline::new(&gpu.device, &fog_layout, filtering, format))?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let froxel_buffer = uniform_buffer(gpu, "froxels", &case.froxels.to_bytes());
    let tail_buffer = uniform_buffer(gpu, "tail", &case.tail.to_bytes());
    let view_buffer = uniform_buffer(
        gpu,
        "view",
        &volfog::uniforms::to_uniform_bytes(&volfog::uniforms::FogView::default()),
    );
    let volume = gpu.texture_3d_rgba16f("integrated", case.froxels.size.to_array(), &case.volume);
    let depth = depth_texture(gpu, case.width, case.height, &case.depth)?;
    let color = gpu.texture_2d_rgba16f("scene colour", [case.width, case.height], &case.color);
    let (fog_group, depth_group) = gpu.checked(|| {
        (
            fog_bind_group(
                &gpu.device,
                &fog_layout,
                filtering,
                &FogResources {
                    froxels: &froxel_buffer,
                    integrated: &volume.create_view(&Default::default()),
                    tail: &tail_buffer,
                    view: &view_buffer,
                    sampler: &fog_sampler(&gpu.device),
                },
            ),
            pass.depth_bind_group(
                &gpu.device,
                &depth.create_view(&wgpu::TextureViewDescriptor {
                    aspect: wgpu::TextureAspect::DepthOnly,
                    ..Default::default()
                }),
            ),
        )
    })?;
    let color_view = color.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &color_view, &fog_group, &depth_group, None);
    gpu.queue.submit([encoder.finish()]);
    gpu.read_texture_rgba16f(&color)
}

/// Largest absolute difference between two images.
pub fn max_abs_diff(a: &[Vec4], b: &[Vec4]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f32::max)
}
