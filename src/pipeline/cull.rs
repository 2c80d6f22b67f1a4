//! The froxel_cull pass: how many leading slices of each froxel column can be seen,
//! from the scene depth, and the list of froxel blocks with live froxels that inject
//! and temporal are dispatched over indirectly (`shaders/passes/froxel_cull.wgsl`).

use super::{bind_group, bind_group_layout, compute_pipeline, shader_module, texture_entry};
use super::{storage_buffer_entry, uniform_entry};
use crate::shaders::CodegenError;

/// Workgroup size (x, y) of `froxel_cull_cells` (one invocation per cell of half a
/// column) and `froxel_cull` (one per column).
pub const WORKGROUP: u32 = 8;
/// Workgroup size of `froxel_cull_compact` (x, y): one invocation per column of blocks.
pub const COMPACT_WORKGROUP: u32 = 8;
/// Froxels per block of inject and temporal (x, y, z): `FROXEL_BLOCK_*` of
/// `volfog::froxel`.
pub const BLOCK: [u32; 3] = [4, 4, 8];

/// Format of the live-slice texture (one value per froxel column).
pub const LIVE_SLICES_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// Blocks of a volume of `size` froxels along each axis.
pub fn block_grid(size: [u32; 3]) -> [u32; 3] {
    [0, 1, 2].map(|i| size[i].div_ceil(BLOCK[i]))
}

/// The list item of block `b` (`froxel_block_pack`).
pub fn pack_block(b: [u32; 3]) -> u32 {
    b[0] | (b[1] << 11) | (b[2] << 22)
}

/// The compiled cull pass (both entry points).
#[derive(Debug)]
pub struct FroxelCullPass {
    layout: wgpu::BindGroupLayout,
    cells: wgpu::ComputePipeline,
    cull: wgpu::ComputePipeline,
    compact: wgpu::ComputePipeline,
}

/// The buffers the cull pass fills: the live blocks and the indirect dispatch
/// arguments of inject and temporal.
#[derive(Debug)]
pub struct LiveBlocks {
    /// `array<u32>`, one item per listed block.
    pub blocks: wgpu::Buffer,
    /// `[x, y, z]` workgroups (`INDIRECT | STORAGE`).
    pub dispatch: wgpu::Buffer,
    /// The farthest view depth per cell of half a column (scratch of the pass).
    pub cells: wgpu::Buffer,
}

impl LiveBlocks {
    /// Buffers for a volume of `size` froxels (room for every block).
    pub fn new(device: &wgpu::Device, size: [u32; 3]) -> Self {
        let [x, y, z] = block_grid(size);
        let buffer = |label: &str, bytes: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        let copy = wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        Self {
            blocks: buffer(
                "volfog live blocks",
                4 * u64::from(x * y * z),
                wgpu::BufferUsages::STORAGE | copy,
            ),
            dispatch: buffer(
                "volfog live block dispatch",
                12,
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | copy,
            ),
            cells: buffer(
                "volfog cull cells",
                16 * u64::from(size[0] * size[1]),
                wgpu::BufferUsages::STORAGE,
            ),
        }
    }

    /// Lists every block of a volume of `size` (no culling).
    pub fn write_all(&self, queue: &wgpu::Queue, size: [u32; 3]) {
        let [gx, gy, gz] = block_grid(size);
        let mut items = Vec::with_capacity((gx * gy * gz) as usize);
        for y in 0..gy {
            for x in 0..gx {
                items.extend((0..gz).map(|z| pack_block([x, y, z])));
            }
        }
        let bytes: Vec<u8> = items.iter().flat_map(|v| v.to_le_bytes()).collect();
        queue.write_buffer(&self.blocks, 0, &bytes);
        let args: Vec<u8> = [items.len() as u32, 1, 1]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        queue.write_buffer(&self.dispatch, 0, &args);
    }

    /// Bytes of the buffers.
    pub fn bytes(&self) -> u64 {
        self.blocks.size() + self.dispatch.size() + self.cells.size()
    }
}

impl FroxelCullPass {
    /// Layout: 0 `Froxels` uniform, 1 scene depth (2D, unfilterable float; a depth
    /// texture's depth aspect or any float texture of depth-buffer values), 2 the
    /// live-slice texture (2D r32uint, read-write storage), 3 the live blocks, 4 the
    /// dispatch arguments and 5 the cell depths (read-write storage buffers).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 6] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
            uniform_entry(0, c),
            texture_entry(1, c, wgpu::TextureViewDimension::D2, false),
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: c,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::ReadWrite,
                    format: LIVE_SLICES_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            storage_buffer_entry(3, c, false),
            storage_buffer_entry(4, c, false),
            storage_buffer_entry(5, c, false),
        ]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device) -> Result<Self, CodegenError> {
        let module = shader_module(device, "froxel_cull", &[])?;
        let layout = bind_group_layout(device, "volfog froxel_cull", &Self::layout_entries());
        let label = "volfog froxel_cull";
        Ok(Self {
            cells: compute_pipeline(device, label, &module, "froxel_cull_cells", &layout),
            cull: compute_pipeline(device, label, &module, "froxel_cull", &layout),
            compact: compute_pipeline(device, label, &module, "froxel_cull_compact", &layout),
            layout,
        })
    }

    /// A bind group: the `Froxels` uniform, the scene depth, the live-slice texture and
    /// the block list to write.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        depth: &wgpu::TextureView,
        live_slices: &wgpu::TextureView,
        blocks: &LiveBlocks,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog froxel_cull",
            &self.layout,
            &[
                (0, froxels.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(depth)),
                (2, wgpu::BindingResource::TextureView(live_slices)),
                (3, blocks.blocks.as_entire_binding()),
                (4, blocks.dispatch.as_entire_binding()),
                (5, blocks.cells.as_entire_binding()),
            ],
        )
    }

    /// Records the three entry points for a volume of `size` froxels.
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: [u32; 3],
    ) {
        pass.set_bind_group(0, group, &[]);
        pass.set_pipeline(&self.cells);
        pass.dispatch_workgroups(
            (2 * size[0]).div_ceil(WORKGROUP),
            (2 * size[1]).div_ceil(WORKGROUP),
            1,
        );
        pass.set_pipeline(&self.cull);
        pass.dispatch_workgroups(size[0].div_ceil(WORKGROUP), size[1].div_ceil(WORKGROUP), 1);
        let [x, y, _] = block_grid(size);
        pass.set_pipeline(&self.compact);
        pass.dispatch_workgroups(
            x.div_ceil(COMPACT_WORKGROUP),
            y.div_ceil(COMPACT_WORKGROUP),
            1,
        );
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
