//! The scan pass against the closed form of a homogeneous medium and against the
//! CPU mirror, with and without depth culling (live slices per column).

use glam::{Vec2, Vec3, Vec4};

use volfog::cpu;
use volfog::cpu::scan::SCAN_START;
use volfog::options::ScanStep;
use volfog::pipeline::scan::ScanPass;
use volfog::uniforms::Froxels;

use super::{round_f16, test_froxels, uniform_buffer};
use crate::gpu::{Gpu, GpuError};

/// Runs the scan pass over a scattering volume (rgb = sigma_s L_in, a = sigma_t; x
/// fastest) and returns the integrated volume.
pub fn run_scan(
    gpu: &Gpu,
    step: ScanStep,
    froxels: &Froxels,
    medium: &[Vec4],
) -> Result<Vec<Vec4>, GpuError> {
    run_scan_culled(gpu, step, froxels, medium, None)
}

/// A live-slice texture of `columns` holding `values` (x fastest).
pub fn live_slices_texture(gpu: &Gpu, columns: [u32; 2], values: &[u32]) -> wgpu::Texture {
    let texture = volfog::pipeline::cull::live_slices_texture(&gpu.device, "live", columns);
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * columns[0]),
            rows_per_image: Some(columns[1]),
        },
        texture.size(),
    );
    texture
}

/// [`run_scan`] of the depth-culling variant when `live` holds the live slices per
/// column (x fastest; `size.x * size.y` values).
pub fn run_scan_culled(
    gpu: &Gpu,
    step: ScanStep,
    froxels: &Froxels,
    medium: &[Vec4],
    live: Option<&[u32]>,
) -> Result<Vec<Vec4>, GpuError> {
    let size = froxels.size.to_array();
    let pass = gpu
        .checked(|| ScanPass::new(&gpu.device, step, live.is_some()))?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let froxel_buffer = uniform_buffer(gpu, "froxels", &froxels.to_bytes());
    let scattering = gpu.texture_3d_rgba16f("scattering", size, medium);
    let integrated = gpu.texture_3d_rgba16f("integrated", size, &[]);
    let live_texture = live.map(|values| {
        live_slices_texture(gpu, [size[0], size[1]], values).create_view(&Default::default())
    });
    let bind_group = gpu
        .checked(|| {
            pass.bind_group(
                &gpu.device,
                &froxel_buffer,
                &scattering.create_view(&Default::default()),
                &integrated.create_view(&Default::default()),
                live_texture.as_ref(),
            )
        })?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut compute = encoder.begin_compute_pass(&Default::default());
        pass.encode(&mut compute, &bind_group, [size[0], size[1]]);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.read_texture_rgba16f(&integrated)
}

/// A homogeneous medium of extinction `sigma_t`, albedo `albedo` and in-scattered
/// radiance `light` filling every froxel.
pub fn homogeneous(froxels: &Froxels, sigma_t: f32, albedo: f32, light: Vec3) -> Vec<Vec4> {
    let count = (froxels.size.x * froxels.size.y * froxels.size.z) as usize;
    vec![(light * albedo * sigma_t).extend(sigma_t); count]
}

/// Closed form for a homogeneous medium after path length `d` (m):
/// `L = (sigma_s / sigma_t) L_in (1 - exp(-sigma_t d))`, `T = exp(-sigma_t d)`.
pub fn homogeneous_closed_form(sigma_t: f32, albedo: f32, light: Vec3, d: f32) -> Vec4 {
    let t = (-(sigma_t as f64) * d as f64).exp();
    (light * albedo * (1.0 - t) as f32).extend(t as f32)
}

/// Largest relative errors of a scan against the closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanError {
    /// Slices in the volume.
    pub slices: u32,
    /// Step used.
    pub step: ScanStep,
    /// Largest relative error of the in-scattered radiance (any channel, any froxel).
    pub inscatter: f32,
    /// Largest relative error of the transmittance.
    pub transmittance: f32,
}

/// Scans a homogeneous medium on the GPU and compares every froxel with the closed
/// form at the back of its slice, along the column's own ray (relative errors with a
/// denominator floor of 1e-3 of the medium's final value).
pub fn scan_vs_closed_form(
    gpu: &Gpu,
    step: ScanStep,
    slices: u32,
    sigma_t: f32,
) -> Result<ScanError, GpuError> {
    let froxels = test_froxels([16, 9], slices);
    let (albedo, light) = (0.7, Vec3::new(2.0, 1.6, 1.0));
    let out = run_scan(
        gpu,
        step,
        &froxels,
        &homogeneous(&froxels, sigma_t, albedo, light),
    )?;
    let mut err = ScanError {
        slices,
        step,
        inscatter: 0.0,
        transmittance: 0.0,
    };
    let [sx, sy, sz] = froxels.size.to_array();
    for z in 0..sz {
        let back = cpu::froxel::slice_depth(
            (z + 1) as f32 / sz as f32,
            froxels.near,
            froxels.far,
            froxels.curve,
        );
        for y in 0..sy {
            for x in 0..sx {
                let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(sx as f32, sy as f32);
                let d = (back - froxels.near) * cpu::froxel::ray_scale(uv, froxels.view_from_clip);
                let want = homogeneous_closed_form(sigma_t, albedo, light, d);
                let got = out[((z * sy + y) * sx + x) as usize];
                for c in 0..3 {
                    let e = (got[c] - want[c]).abs() / want[c].max(1e-3 * light[c] * albedo);
                    err.inscatter = err.inscatter.max(e);
                }
                let e = (got.w - want.w).abs() / want.w.max(1e-3);
                err.transmittance = err.transmittance.max(e);
            }
        }
    }
    Ok(err)
}

/// The CPU mirror of the scan pass over the same (fp16-rounded) input.
pub fn cpu_scan(step: ScanStep, froxels: &Froxels, medium: &[Vec4]) -> Vec<Vec4> {
    let [sx, sy, sz] = froxels.size.to_array();
    let mut out = vec![Vec4::ZERO; medium.len()];
    for y in 0..sy {
        for x in 0..sx {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(sx as f32, sy as f32);
            let scale = cpu::froxel::ray_scale(uv, froxels.view_from_clip);
            let mut acc = SCAN_START;
            // The slice depths beyond near, walked as the pass walks them.
            let (a, b) = cpu::froxel::slice_walk(sz, froxels.near, froxels.far, froxels.curve);
            let mut front = 0.0;
            for z in 0..sz {
                let back = front * a + b;
                let i = ((z * sy + y) * sx + x) as usize;
                acc = cpu::scan::scan_step(acc, round_f16(medium[i]), (back - front) * scale, step);
                out[i] = acc.min(Vec4::splat(volfog::cpu::inject::HALF_MAX));
                front = back;
            }
        }
    }
    out
}
