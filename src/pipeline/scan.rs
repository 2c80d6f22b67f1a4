//! The scan pass: integrates the scattering volume front to back into the
//! integrated volume (`shaders/passes/scan.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, shader_module, storage_entry, texture_entry,
    uniform_entry,
};
use crate::options::ScanStep;
use crate::shaders::CodegenError;

/// Workgroup size of the scan (x, y).
pub const WORKGROUP: u32 = 8;

/// The compiled scan pass.
#[derive(Debug)]
pub struct ScanPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ScanPass {
    /// The bind group layout: 0 `Froxels` uniform, 1 scattering volume (3D float,
    /// read with textureLoad), 2 integrated volume (3D rgba16float, write-only storage).
    pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 3] {
        let c = wgpu::ShaderStages::COMPUTE;
        [
            uniform_entry(0, c),
            texture_entry(1, c, wgpu::TextureViewDimension::D3, false),
            storage_entry(
                2,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
        ]
    }

    /// Compiles the pass.
    pub fn new(device: &wgpu::Device, step: ScanStep) -> Result<Self, CodegenError> {
        let module = shader_module(device, "scan", &step.defines())?;
        let layout = bind_group_layout(device, "volfog scan", &Self::layout_entries());
        let pipeline = compute_pipeline(device, "volfog scan", &module, "scan", &layout);
        Ok(Self { layout, pipeline })
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group for the given resources.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        scattering: &wgpu::TextureView,
        integrated: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog scan",
            &self.layout,
            &[
                (0, froxels.as_entire_binding()),
                (1, wgpu::BindingResource::TextureView(scattering)),
                (2, wgpu::BindingResource::TextureView(integrated)),
            ],
        )
    }

    /// Records the scan of a volume of `size` froxels (x, y).
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        bind_group: &wgpu::BindGroup,
        size: [u32; 2],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(size[0].div_ceil(WORKGROUP), size[1].div_ceil(WORKGROUP), 1);
    }
}
