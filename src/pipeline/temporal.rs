//! The temporal pass: blends the injected volume with the reprojected history
//! (`shaders/passes/temporal.wgsl`).

use super::{
    bind_group, compute_pipeline, prebuilt_wgsl, sampler_entry, storage_entry, texture_entry,
    uniform_entry,
};

/// The compiled temporal pass.
#[derive(Debug)]
pub struct TemporalPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    sampler: wgpu::Sampler,
}

impl TemporalPass {
    /// Layout: 0 `Froxels`, 1 `FogFrame`, 2 current volume (unfilterable read),
    /// 3 history (filterable), 4 linear sampler, 5 stabilised output.
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 6] {
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
        ]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device) -> Self {
        let (layout, pipeline) = compute_pipeline(
            device,
            "volfog temporal",
            prebuilt_wgsl("temporal@default", "temporal"),
            "temporal",
            &Self::layout_entries(),
        );
        Self {
            layout,
            pipeline,
            sampler: super::apply::fog_sampler(device),
        }
    }

    /// A bind group.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        frame: &wgpu::Buffer,
        current: &wgpu::TextureView,
        history: &wgpu::TextureView,
        stabilised: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog temporal",
            &self.layout,
            &[
                (0, froxels.as_entire_binding()),
                (1, frame.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(current)),
                (3, wgpu::BindingResource::TextureView(history)),
                (4, wgpu::BindingResource::Sampler(&self.sampler)),
                (5, wgpu::BindingResource::TextureView(stabilised)),
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
            size[0].div_ceil(4),
            size[1].div_ceil(4),
            size[2].div_ceil(4),
        );
    }
}
