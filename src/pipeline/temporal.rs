//! The temporal pass: blends the injected volume with the reprojected history
//! (`shaders/passes/temporal.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module,
    storage_buffer_entry, storage_entry, texture_entry, uniform_entry,
};
use crate::shaders::CodegenError;

/// Workgroup size of the temporal pass (each axis).
pub const WORKGROUP: u32 = 4;

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
}

/// The compiled temporal pass.
#[derive(Debug)]
pub struct TemporalPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    sampler: wgpu::Sampler,
}

impl TemporalPass {
    /// Layout: 0 `Froxels`, 1 `FogFrame`, 2 current volume (unfilterable read),
    /// 3 history (filterable), 4 linear sampler, 5 stabilised output, 6 the history's
    /// `HistoryState` (read), 7 the stabilised volume's `HistoryState` (read-write).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 8] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
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
        ]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device) -> Result<Self, CodegenError> {
        let module = shader_module(device, "temporal", &[])?;
        let layout = bind_group_layout(device, "volfog temporal", &Self::layout_entries());
        let pipeline = compute_pipeline(device, "volfog temporal", &module, "temporal", &layout);
        Ok(Self {
            layout,
            pipeline,
            sampler: super::apply::fog_sampler(device),
        })
    }

    /// A bind group.
    pub fn bind_group(&self, device: &wgpu::Device, r: &TemporalResources<'_>) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog temporal",
            &self.layout,
            &[
                (0, r.froxels.as_entire_binding()),
                (1, r.frame.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(r.current)),
                (3, wgpu::BindingResource::TextureView(r.history)),
                (4, wgpu::BindingResource::Sampler(&self.sampler)),
                (5, wgpu::BindingResource::TextureView(r.stabilised)),
                (6, r.history_state.as_entire_binding()),
                (7, r.stabilised_state.as_entire_binding()),
            ],
        )
    }

    /// Records the pass over a volume of `size` froxels.
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: [u32; 3],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(
            size[0].div_ceil(WORKGROUP),
            size[1].div_ceil(WORKGROUP),
            size[2].div_ceil(WORKGROUP),
        );
    }
}
