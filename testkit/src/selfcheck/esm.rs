//! The ESM passes (downsample, blur x, blur y) over a cascaded shadow map.

use volfog::options::EsmOptions;

use super::depth::depth_array_texture;
use super::uniform_buffer;
use crate::gpu::{Gpu, GpuError};

/// Runs the ESM passes (downsample, blur x, blur y) over a cascaded shadow map given
/// as depth layers of `4 * size` texels per side (stored as given: reversed depth when
/// `options.reversed_z`), and returns the filtered ESM layers.
pub fn run_esm(
    gpu: &Gpu,
    options: &EsmOptions,
    exponent: f32,
    depth_layers: &[volfog::cpu::esm::Layer],
) -> Result<Vec<volfog::cpu::esm::Layer>, GpuError> {
    use volfog::pipeline::esm::EsmPasses;
    let layers = depth_layers.len() as u32;
    let full = depth_layers[0].width;
    let size = full / 4;
    let passes =
        EsmPasses::new(&gpu.device, options).map_err(|e| GpuError::Operation(e.to_string()))?;
    let slices: Vec<&[f32]> = depth_layers.iter().map(|l| l.texels.as_slice()).collect();
    let shadow = depth_array_texture(gpu, full, full, &slices)?;
    let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let cascades = volfog::uniforms::ShadowCascades {
        exponent,
        count: layers,
        ..Default::default()
    };
    let cascade_buffer = uniform_buffer(
        gpu,
        "cascades",
        &volfog::uniforms::to_uniform_bytes(&cascades),
    );
    let esm_texture = |label| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: volfog::pipeline::esm::ESM_FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let (a, b) = (esm_texture("esm a"), esm_texture("esm b"));
    let array = |t: &wgpu::Texture| {
        t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    };
    let (av, bv) = (array(&a), array(&b));
    let groups = gpu.checked(|| {
        (
            passes.downsample_bind_group(&gpu.device, &cascade_buffer, &shadow_view, &av),
            passes.blur_bind_group(&gpu.device, &av, &bv),
            passes.blur_bind_group(&gpu.device, &bv, &av),
        )
    })?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_downsample(&mut pass, &groups.0, size, layers);
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_blur(&mut pass, &groups.1, 0, size, layers);
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_blur(&mut pass, &groups.2, 1, size, layers);
    }
    gpu.queue.submit([encoder.finish()]);
    let raw = gpu.read_texture_raw(&a, 4)?;
    let values: &[f32] = bytemuck::cast_slice(&raw);
    Ok(values
        .chunks_exact((size * size) as usize)
        .map(|c| volfog::cpu::esm::Layer {
            width: size,
            height: size,
            texels: c.to_vec(),
        })
        .collect())
}
