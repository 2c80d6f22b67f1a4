//! The ESM passes: shadow map -> exponential shadow map (4x smaller), then the
//! separable box blur (`shaders/passes/esm_downsample.wgsl`, `esm_blur.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module, storage_entry,
    texture_entry, uniform_entry,
};
use crate::options::EsmOptions;
use crate::shaders::CodegenError;

/// Workgroup size of the downsample (x, y; one cascade per z).
pub const DOWNSAMPLE_WORKGROUP: u32 = 8;
/// Texels one blur workgroup filters along its line (WGSL `GROUP`).
pub const BLUR_GROUP: u32 = 64;

/// The ESM texel format.
pub const ESM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Compiled ESM passes for one define set.
#[derive(Debug)]
pub struct EsmPasses {
    downsample_layout: wgpu::BindGroupLayout,
    downsample: wgpu::ComputePipeline,
    blur_layout: wgpu::BindGroupLayout,
    blur_x: wgpu::ComputePipeline,
    blur_y: wgpu::ComputePipeline,
    gather_sampler: wgpu::Sampler,
}

impl EsmPasses {
    /// Layout of the downsample pass: 0 `ShadowCascades`, 1 shadow map (2D array,
    /// unfilterable float), 2 non-filtering sampler, 3 ESM (R32Float storage array).
    pub fn downsample_entries() -> [wgpu::BindGroupLayoutEntry; 4] {
        [
            uniform_entry(0, wgpu::ShaderStages::COMPUTE),
            texture_entry(
                1,
                wgpu::ShaderStages::COMPUTE,
                wgpu::TextureViewDimension::D2Array,
                false,
            ),
            sampler_entry(2, wgpu::ShaderStages::COMPUTE, false),
            storage_entry(3, wgpu::TextureViewDimension::D2Array, ESM_FORMAT),
        ]
    }

    /// Layout of the blur passes: 0 source (2D array, unfilterable float), 1 target.
    pub fn blur_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            texture_entry(
                0,
                wgpu::ShaderStages::COMPUTE,
                wgpu::TextureViewDimension::D2Array,
                false,
            ),
            storage_entry(1, wgpu::TextureViewDimension::D2Array, ESM_FORMAT),
        ]
    }

    /// Compiles the passes for the options.
    pub fn new(device: &wgpu::Device, options: &EsmOptions) -> Result<Self, CodegenError> {
        let downsample_module =
            shader_module(device, "esm_downsample", &options.downsample_defines())?;
        let blur_module = shader_module(device, "esm_blur", &options.blur_defines())?;
        let downsample_layout =
            bind_group_layout(device, "volfog esm_downsample", &Self::downsample_entries());
        let blur_layout = bind_group_layout(device, "volfog esm_blur", &Self::blur_entries());
        let downsample = compute_pipeline(
            device,
            "volfog esm_downsample",
            &downsample_module,
            "esm_downsample",
            &downsample_layout,
        );
        let blur_x = compute_pipeline(
            device,
            "volfog esm_blur_x",
            &blur_module,
            "esm_blur_x",
            &blur_layout,
        );
        let blur_y = compute_pipeline(
            device,
            "volfog esm_blur_y",
            &blur_module,
            "esm_blur_y",
            &blur_layout,
        );
        let gather_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("volfog esm gather"),
            ..Default::default()
        });
        Ok(Self {
            downsample_layout,
            downsample,
            blur_layout,
            blur_x,
            blur_y,
            gather_sampler,
        })
    }

    /// Bind group of the downsample pass.
    pub fn downsample_bind_group(
        &self,
        device: &wgpu::Device,
        cascades: &wgpu::Buffer,
        shadow_map: &wgpu::TextureView,
        esm: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog esm_downsample",
            &self.downsample_layout,
            &[
                (0, cascades.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(shadow_map)),
                (2, wgpu::BindingResource::Sampler(&self.gather_sampler)),
                (3, wgpu::BindingResource::TextureView(esm)),
            ],
        )
    }

    /// Bind group of a blur pass from `source` into `target`.
    pub fn blur_bind_group(
        &self,
        device: &wgpu::Device,
        source: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog esm_blur",
            &self.blur_layout,
            &[
                (0, wgpu::BindingResource::TextureView(source)),
                (1, wgpu::BindingResource::TextureView(target)),
            ],
        )
    }

    /// Records the downsample of `layers` cascades into an ESM of `size` texels.
    pub fn encode_downsample(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: u32,
        layers: u32,
    ) {
        pass.set_pipeline(&self.downsample);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(
            size.div_ceil(DOWNSAMPLE_WORKGROUP),
            size.div_ceil(DOWNSAMPLE_WORKGROUP),
            layers,
        );
    }

    /// Records one blur pass (`axis` 0: x, 1: y) over an ESM of `size` x `size`.
    pub fn encode_blur(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        axis: u32,
        size: u32,
        layers: u32,
    ) {
        pass.set_pipeline(if axis == 0 {
            &self.blur_x
        } else {
            &self.blur_y
        });
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(size.div_ceil(BLUR_GROUP), size, layers);
    }
}
