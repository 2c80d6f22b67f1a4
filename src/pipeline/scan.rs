//! The scan pass: integrates the scattering volume front to back into the
//! integrated volume (`shaders/passes/scan.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, shader_module, storage_entry, texture_entry,
    uint_texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
use crate::options::{ScanStep, cull_defines};
use crate::shaders::CodegenError;

/// Workgroup size of the scan (x, y).
pub const WORKGROUP: u32 = 8;

/// The compiled scan pass.
#[derive(Debug)]
pub struct ScanPass {
    cull: bool,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ScanPass {
    /// The bind group layout: 0 `Froxels` uniform, 1 scattering volume (3D float,
    /// read with textureLoad), 2 integrated volume (3D rgba16float, write-only storage),
    /// and with depth culling 3 the live-slice texture (2D uint).
    pub fn layout_entries(cull: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, c),
            texture_entry(1, c, wgpu::TextureViewDimension::D3, false),
            storage_entry(
                2,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
        ];
        if cull {
            entries.push(uint_texture_entry(3));
        }
        entries
    }

    /// Compiles the pass (`cull`: the depth-culling variant, `VOLFOG_FROXEL_CULL`).
    pub fn new(device: &wgpu::Device, step: ScanStep, cull: bool) -> Result<Self, CodegenError> {
        let mut defines = step.defines();
        defines.extend(cull_defines(cull));
        let module = shader_module(device, "scan", &defines)?;
        let layout = bind_group_layout(device, "volfog scan", &Self::layout_entries(cull));
        let pipeline = compute_pipeline(device, "volfog scan", &module, "scan", &layout);
        Ok(Self {
            cull,
            layout,
            pipeline,
        })
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group for the given resources; `live_slices` is required by the culling
    /// variant (ignored by the other).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        scattering: &wgpu::TextureView,
        integrated: &wgpu::TextureView,
        live_slices: Option<&wgpu::TextureView>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        let mut resources = vec![
            (0, froxels.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(scattering)),
            (2, wgpu::BindingResource::TextureView(integrated)),
        ];
        if self.cull {
            let Some(live) = live_slices else {
                return Err(InvalidValue {
                    field: "ScanPass::bind_group live_slices",
                    value: "None".to_string(),
                    expected: "the live-slice texture for the depth-culling variant".into(),
                });
            };
            resources.push((3, wgpu::BindingResource::TextureView(live)));
        }
        Ok(bind_group(device, "volfog scan", &self.layout, &resources))
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
