//! The inject pass: density and in-scattered light per froxel
//! (`shaders/passes/inject.wgsl`).

use super::{
    bind_group, compute_pipeline, sampler_entry, storage_buffer_entry, storage_entry,
    texture_entry, uniform_entry, variant_wgsl,
};
use crate::codegen::CodegenError;

/// Options of the inject pass that select its variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InjectOptions {
    /// Jittered sample positions (`VOLFOG_INJECT_JITTER`).
    pub jitter: bool,
    /// AC4 two-colour sun phase (`VOLFOG_INJECT_TWO_COLOR_PHASE`).
    pub two_color_phase: bool,
    /// Density texture (`VOLFOG_INJECT_DENSITY_TEXTURE`).
    pub density_texture: bool,
    /// Log-space ESM (`VOLFOG_ESM_LOG_SPACE`).
    pub esm_log_space: bool,
    /// fbm octaves, 1..=8 (`VOLFOG_INJECT_NOISE_OCTAVES`).
    pub noise_octaves: u32,
}

impl InjectOptions {
    /// The define set of these options.
    pub fn defines(&self) -> Vec<String> {
        let mut d = Vec::new();
        if self.esm_log_space {
            d.push("VOLFOG_ESM_LOG_SPACE".to_string());
        }
        if self.jitter {
            d.push("VOLFOG_INJECT_JITTER".to_string());
        }
        if self.two_color_phase {
            d.push("VOLFOG_INJECT_TWO_COLOR_PHASE".to_string());
        }
        if self.density_texture {
            d.push("VOLFOG_INJECT_DENSITY_TEXTURE".to_string());
        }
        if self.noise_octaves != 1 {
            d.push(format!(
                "VOLFOG_INJECT_NOISE_OCTAVES={}",
                self.noise_octaves
            ));
        }
        d
    }
}

/// Resources of one inject dispatch.
#[derive(Debug)]
pub struct InjectResources<'a> {
    /// `Froxels` uniform.
    pub froxels: &'a wgpu::Buffer,
    /// `FogFrame` uniform.
    pub frame: &'a wgpu::Buffer,
    /// `FogMedium` uniform.
    pub medium: &'a wgpu::Buffer,
    /// `FogLighting` uniform.
    pub lighting: &'a wgpu::Buffer,
    /// `ShadowCascades` uniform.
    pub cascades: &'a wgpu::Buffer,
    /// Filtered ESM array.
    pub esm: &'a wgpu::TextureView,
    /// `array<FogLight>` storage buffer.
    pub lights: &'a wgpu::Buffer,
    /// `array<LocalVolume>` storage buffer.
    pub local_volumes: &'a wgpu::Buffer,
    /// Output scattering volume.
    pub scattering: &'a wgpu::TextureView,
    /// Density texture and its sampler (density-texture variant only).
    pub density_texture: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
}

/// The compiled inject pass.
#[derive(Debug)]
pub struct InjectPass {
    options: InjectOptions,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl InjectPass {
    /// The bind group layout of a variant (see the pass header for the bindings).
    pub fn layout_entries(options: &InjectOptions) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, c),
            uniform_entry(1, c),
            uniform_entry(2, c),
            uniform_entry(3, c),
            uniform_entry(4, c),
            texture_entry(5, c, wgpu::TextureViewDimension::D2Array, false),
            storage_buffer_entry(6, c),
            storage_buffer_entry(7, c),
            storage_entry(
                8,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
        ];
        if options.density_texture {
            entries.push(texture_entry(9, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(10, c, true));
        }
        entries
    }

    /// Compiles the variant for `options`.
    pub fn new(device: &wgpu::Device, options: InjectOptions) -> Result<Self, CodegenError> {
        let wgsl = variant_wgsl("inject", &options.defines(), "inject")?;
        let (layout, pipeline) = compute_pipeline(
            device,
            "volfog inject",
            &wgsl,
            "inject",
            &Self::layout_entries(&options),
        );
        Ok(Self {
            options,
            layout,
            pipeline,
        })
    }

    /// A bind group for the resources.
    pub fn bind_group(&self, device: &wgpu::Device, r: &InjectResources<'_>) -> wgpu::BindGroup {
        let mut resources = vec![
            (0, r.froxels.as_entire_binding()),
            (1, r.frame.as_entire_binding()),
            (2, r.medium.as_entire_binding()),
            (3, r.lighting.as_entire_binding()),
            (4, r.cascades.as_entire_binding()),
            (5, wgpu::BindingResource::TextureView(r.esm)),
            (6, r.lights.as_entire_binding()),
            (7, r.local_volumes.as_entire_binding()),
            (8, wgpu::BindingResource::TextureView(r.scattering)),
        ];
        if self.options.density_texture {
            let (view, sampler) = r
                .density_texture
                .expect("the density-texture variant needs a texture");
            resources.push((9, wgpu::BindingResource::TextureView(view)));
            resources.push((10, wgpu::BindingResource::Sampler(sampler)));
        }
        bind_group(device, "volfog inject", &self.layout, &resources)
    }

    /// Records the injection into a volume of `size` froxels.
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
