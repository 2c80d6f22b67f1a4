//! The noise bake: one period of the tileable Perlin noise written once into a 3D
//! texture (`shaders/passes/noise_bake.wgsl`), for the texture form of the fog's noise
//! (`volfog::noise::noise_fbm_texture`, sampled with [`noise_sampler`]).
//!
//! Texel `i` of the [`NOISE_TEXTURE_SIZE`]^3 `Rgba16Float` texture holds, in its red
//! channel, `perlin_noise_tiled(i / NOISE_TEXTURE_TEXELS_PER_UNIT, NOISE_TEXTURE_PERIOD)`
//! (see [`crate::cpu::noise::bake_noise_texture`], its CPU twin); green and blue are 0
//! and alpha 1.

use super::{bind_group, bind_group_layout, compute_pipeline, shader_module, storage_entry};
pub use crate::cpu::noise::{
    NOISE_TEXTURE_PERIOD, NOISE_TEXTURE_SIZE, NOISE_TEXTURE_TEXELS_PER_UNIT,
};
use crate::shaders::CodegenError;

/// Workgroup size of the bake (each axis).
pub const WORKGROUP: u32 = 4;

/// Format of the noise texture (written as a storage texture, read as a filterable
/// `texture_3d<f32>`).
pub const NOISE_TEXTURE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Memory of the noise texture in bytes: [`NOISE_TEXTURE_SIZE`]^3 texels of 8 bytes
/// (2 MiB).
pub const NOISE_TEXTURE_BYTES: u64 = (NOISE_TEXTURE_SIZE as u64).pow(3) * 8;

/// The compiled noise bake pass.
#[derive(Debug)]
pub struct NoiseBake {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl NoiseBake {
    /// The bind group layout: 0 the noise texture (3D rgba16float, write-only storage).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 1] {
        [storage_entry(
            0,
            wgpu::TextureViewDimension::D3,
            NOISE_TEXTURE_FORMAT,
        )]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device) -> Result<Self, CodegenError> {
        let module = shader_module(device, "noise_bake", &[])?;
        let layout = bind_group_layout(device, "volfog noise_bake", &Self::layout_entries());
        let pipeline =
            compute_pipeline(device, "volfog noise_bake", &module, "noise_bake", &layout);
        Ok(Self { layout, pipeline })
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// Creates an empty noise texture: [`NOISE_TEXTURE_SIZE`]^3, [`NOISE_TEXTURE_FORMAT`],
    /// usage `STORAGE_BINDING | TEXTURE_BINDING | COPY_SRC`.
    pub fn create_texture(device: &wgpu::Device) -> wgpu::Texture {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("volfog noise texture"),
            size: wgpu::Extent3d {
                width: NOISE_TEXTURE_SIZE,
                height: NOISE_TEXTURE_SIZE,
                depth_or_array_layers: NOISE_TEXTURE_SIZE,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: NOISE_TEXTURE_FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }

    /// Records the bake of every texel of `texture` (a 3D texture of
    /// [`NOISE_TEXTURE_FORMAT`] with storage binding usage, normally from
    /// [`NoiseBake::create_texture`]).
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) {
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D3),
            ..Default::default()
        });
        let group = bind_group(
            device,
            "volfog noise_bake",
            &self.layout,
            &[(0, wgpu::BindingResource::TextureView(&view))],
        );
        let size = texture.size();
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("volfog noise_bake"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(
            size.width.div_ceil(WORKGROUP),
            size.height.div_ceil(WORKGROUP),
            size.depth_or_array_layers.div_ceil(WORKGROUP),
        );
    }

    /// Compiles the pass, creates the noise texture, bakes it and submits the work to
    /// `queue`; the texture is ready for any later submission.
    pub fn bake(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<wgpu::Texture, CodegenError> {
        let pass = Self::new(device)?;
        let texture = Self::create_texture(device);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("volfog noise_bake"),
        });
        pass.encode(device, &mut encoder, &texture);
        queue.submit([encoder.finish()]);
        Ok(texture)
    }
}

/// The sampler of the noise texture: linear filtering (mag, min; one mip level) and
/// repeat addressing on u, v and w, as `noise_fbm_texture` expects.
pub fn noise_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog noise sampler"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    })
}
