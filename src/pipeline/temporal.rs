//! The temporal pass: blends the injected volume with the reprojected history
//! (`shaders/passes/temporal.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module,
    storage_buffer_entry, storage_entry, texture_entry, uint_texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
use crate::options::cull_defines;
use crate::shaders::CodegenError;

/// Workgroup size of the temporal pass: one invocation per pair of slices of a block
/// of [`BLOCK`](super::cull::BLOCK) froxels.
pub const WORKGROUP: [u32; 3] = [4, 4, 4];

/// Resources of one temporal dispatch.
#[derive(Debug)]
pub struct TemporalResources<'a> {
    /// `Froxels` uniform.
    pub froxels: &'a wgpu::Buffer,
    /// `FogFrame` uniform.
    pub frame: &'a wgpu::Buffer,
    /// This frame's scattering volume.
    pub current: &'a wgpu::TextureView,
    /// The history volume.
    pub history: &'a wgpu::TextureView,
    /// The history's `HistoryState` (80-byte storage buffer).
    pub history_state: &'a wgpu::Buffer,
    /// The stabilised volume this dispatch writes.
    pub stabilised: &'a wgpu::TextureView,
    /// Its `HistoryState`, written by the dispatch.
    pub stabilised_state: &'a wgpu::Buffer,
    /// Live slices of this frame and of the history, and the live blocks (read by the
    /// culling variant only; `None` for the other).
    pub culling: Option<(
        &'a wgpu::TextureView,
        &'a wgpu::TextureView,
        &'a wgpu::Buffer,
    )>,
}

/// The compiled temporal pass.
#[derive(Debug)]
pub struct TemporalPass {
    cull: bool,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    sampler: wgpu::Sampler,
}

impl TemporalPass {
    /// Layout: 0 `Froxels`, 1 `FogFrame`, 2 current volume (unfilterable read),
    /// 3 history (filterable), 4 linear sampler, 5 stabilised output, 6 the history's
    /// `HistoryState` (read), 7 the stabilised volume's `HistoryState` (read-write);
    /// with depth culling 8 and 9 the live slices of this frame and of the history.
    pub fn layout_entries(cull: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, c),
            uniform_entry(1, c),
            texture_entry(2, c, wgpu::TextureViewDimension::D3, false),
            texture_entry(3, c, wgpu::TextureViewDimension::D3, true),
            sampler_entry(4, c, true),
            storage_entry(
                5,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
            storage_buffer_entry(6, c, true),
            storage_buffer_entry(7, c, false),
        ];
        if cull {
            entries.extend([
                uint_texture_entry(8),
                uint_texture_entry(9),
                storage_buffer_entry(10, c, true),
            ]);
        }
        entries
    }

    /// Compiles the pass (`cull`: the depth-culling variant, `VOLFOG_FROXEL_CULL`).
    pub fn new(device: &wgpu::Device, cull: bool) -> Result<Self, CodegenError> {
        let module = shader_module(device, "temporal", &cull_defines(cull))?;
        let layout = bind_group_layout(device, "volfog temporal", &Self::layout_entries(cull));
        let pipeline = compute_pipeline(device, "volfog temporal", &module, "temporal", &layout);
        Ok(Self {
            cull,
            layout,
            pipeline,
            sampler: super::apply::fog_sampler(device),
        })
    }

    /// A bind group; the culling variant requires `r.live_slices`.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        r: &TemporalResources<'_>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        let mut resources = vec![
            (0, r.froxels.as_entire_binding()),
            (1, r.frame.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(r.current)),
            (3, wgpu::BindingResource::TextureView(r.history)),
            (4, wgpu::BindingResource::Sampler(&self.sampler)),
            (5, wgpu::BindingResource::TextureView(r.stabilised)),
            (6, r.history_state.as_entire_binding()),
            (7, r.stabilised_state.as_entire_binding()),
        ];
        if self.cull {
            let Some((live, history_live, blocks)) = r.culling else {
                return Err(InvalidValue {
                    field: "TemporalResources.culling",
                    value: "None".to_string(),
                    expected: "the live-slice textures and the live blocks for the \
                               depth-culling variant"
                        .into(),
                });
            };
            resources.push((8, wgpu::BindingResource::TextureView(live)));
            resources.push((9, wgpu::BindingResource::TextureView(history_live)));
            resources.push((10, blocks.as_entire_binding()));
        }
        Ok(bind_group(
            device,
            "volfog temporal",
            &self.layout,
            &resources,
        ))
    }

    /// Records the pass over a volume of `size` froxels: one workgroup per block of
    /// [`BLOCK`](super::cull::BLOCK) froxels, or, for the depth-culling variant,
    /// `indirect` (the dispatch arguments `froxel_cull` wrote).
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: [u32; 3],
        indirect: Option<&wgpu::Buffer>,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        match indirect {
            Some(args) => pass.dispatch_workgroups_indirect(args, 0),
            None => {
                let [x, y, z] = super::cull::block_grid(size);
                pass.dispatch_workgroups(x, y, z);
            }
        }
    }
}
