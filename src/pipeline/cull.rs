//! The froxel_cull pass: how many leading slices of each froxel column can be seen,
//! from the scene depth (`shaders/passes/froxel_cull.wgsl`), and the live-slice
//! textures it writes.

use super::{bind_group, bind_group_layout, compute_pipeline, shader_module, texture_entry};
use super::{storage_entry, uniform_entry};
use crate::shaders::CodegenError;

/// Workgroup size of the cull pass (x, y): one workgroup per froxel column.
pub const WORKGROUP: u32 = 8;

/// Format of the live-slice texture (one value per froxel column).
pub const LIVE_SLICES_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// The compiled cull pass.
#[derive(Debug)]
pub struct FroxelCullPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl FroxelCullPass {
    /// Layout: 0 `Froxels` uniform, 1 scene depth (2D, unfilterable float; a depth
    /// texture's depth aspect or any float texture of depth-buffer values), 2 the
    /// live-slice texture (2D r32uint, write-only storage).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 3] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
            uniform_entry(0, c),
            texture_entry(1, c, wgpu::TextureViewDimension::D2, false),
            storage_entry(2, wgpu::TextureViewDimension::D2, LIVE_SLICES_FORMAT),
        ]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device) -> Result<Self, CodegenError> {
        let module = shader_module(device, "froxel_cull", &[])?;
        let layout = bind_group_layout(device, "volfog froxel_cull", &Self::layout_entries());
        let pipeline = compute_pipeline(
            device,
            "volfog froxel_cull",
            &module,
            "froxel_cull",
            &layout,
        );
        Ok(Self { layout, pipeline })
    }

    /// A bind group: the `Froxels` uniform, the scene depth and the live-slice texture
    /// to write.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        depth: &wgpu::TextureView,
        live_slices: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog froxel_cull",
            &self.layout,
            &[
                (0, froxels.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(depth)),
                (2, wgpu::BindingResource::TextureView(live_slices)),
            ],
        )
    }

    /// Records the pass for a grid of `columns` (size.x, size.y).
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        columns: [u32; 2],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(columns[0], columns[1], 1);
    }
}

/// A live-slice texture for a grid of `columns` (storage binding for the cull pass,
/// texture binding for the passes that read it, copy destination so it can be filled
/// with "every slice live", copy source for inspection).
pub fn live_slices_texture(device: &wgpu::Device, label: &str, columns: [u32; 2]) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: columns[0],
            height: columns[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: LIVE_SLICES_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Fills a live-slice texture with `slices` in every column (no culling).
pub fn write_all_live(queue: &wgpu::Queue, texture: &wgpu::Texture, slices: u32) {
    let size = texture.size();
    let data: Vec<u8> =
        std::iter::repeat_n(slices.to_le_bytes(), (size.width * size.height) as usize)
            .flatten()
            .collect();
    queue.write_texture(
        texture.as_image_copy(),
        &data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * size.width),
            rows_per_image: Some(size.height),
        },
        size,
    );
}
