//! The local-light shadow pass: point and spot lights' shadow depth maps to the
//! local-light ESM atlas (`shaders/passes/local_shadow_downsample.wgsl`), blurred by
//! the ESM blur passes ([`super::esm::EsmPasses`]).

use super::esm::ESM_FORMAT;
use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module,
    storage_buffer_entry, storage_entry, texture_entry,
};
use crate::shaders::CodegenError;

/// Workgroup size of the downsample (x, y; one atlas layer per z).
pub const WORKGROUP: u32 = 8;

/// The compiled `local_shadow_downsample` pass.
#[derive(Debug)]
pub struct LocalShadowPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    gather_sampler: wgpu::Sampler,
}

impl LocalShadowPass {
    /// The defines of the variant: `VOLFOG_ESM_LOG_SPACE` for a log-space atlas.
    pub fn defines(log_space: bool) -> Vec<String> {
        if log_space {
            vec!["VOLFOG_ESM_LOG_SPACE".to_string()]
        } else {
            Vec::new()
        }
    }

    /// Layout: 0 `array<LocalShadowSource>`, 1 the spot shadow maps, 2 the point
    /// shadow maps (2D arrays, unfilterable float), 3 the atlas (R32Float storage
    /// array), 4 the non-filtering sampler of the depth maps' gathers.
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 5] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
            storage_buffer_entry(0, c, true),
            texture_entry(1, c, wgpu::TextureViewDimension::D2Array, false),
            texture_entry(2, c, wgpu::TextureViewDimension::D2Array, false),
            storage_entry(3, wgpu::TextureViewDimension::D2Array, ESM_FORMAT),
            sampler_entry(4, c, false),
        ]
    }

    /// Compiles the pass for a linear or log-space atlas.
    pub fn new(device: &wgpu::Device, log_space: bool) -> Result<Self, CodegenError> {
        let module = shader_module(device, "local_shadow_downsample", &Self::defines(log_space))?;
        let layout = bind_group_layout(
            device,
            "volfog local_shadow_downsample",
            &Self::layout_entries(),
        );
        let pipeline = compute_pipeline(
            device,
            "volfog local_shadow_downsample",
            &module,
            "local_shadow_downsample",
            &layout,
        );
        // Nearest, clamp to edge: the gathers read whole texels.
        let gather_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("volfog local_shadow_downsample gather"),
            ..Default::default()
        });
        Ok(Self {
            layout,
            pipeline,
            gather_sampler,
        })
    }

    /// A bind group: the sources buffer, the two depth arrays (D2Array views), the
    /// atlas (a D2Array view of its storage texture) and the pass's gather sampler.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        sources: &wgpu::Buffer,
        spot_maps: &wgpu::TextureView,
        point_maps: &wgpu::TextureView,
        atlas: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog local_shadow_downsample",
            &self.layout,
            &[
                (0, sources.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(spot_maps)),
                (2, wgpu::BindingResource::TextureView(point_maps)),
                (3, wgpu::BindingResource::TextureView(atlas)),
                (4, wgpu::BindingResource::Sampler(&self.gather_sampler)),
            ],
        )
    }

    /// Records the downsample of `layers` sources into an atlas of `size` texels per
    /// side.
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: u32,
        layers: u32,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        let n = size.div_ceil(WORKGROUP);
        pass.dispatch_workgroups(n, n, layers);
    }
}
