//! The wgpu runtime: each pass with its bind group layout spelled out (and compared
//! with the shader's reflection by the tests), compiled from the naga module of its
//! variant, and [`VolumetricFog`], which owns the whole froxel pipeline.
//!
//! Passes: [`esm`] (shadow map -> filtered ESM), [`inject`] (density and lighting),
//! [`temporal`] (reprojection), [`scan`] (front-to-back integration), [`apply`] (the
//! fog group, and the fullscreen apply), [`hull`] (Boyd's fog hulls), [`sky`] (the sky
//! light) and [`clouds`] (cloud shadows, distance clouds, the lit cloud layer).

pub mod apply;
pub mod clouds;
pub mod cull;
pub mod epipolar;
pub mod esm;
mod fog;
pub mod hull;
pub mod inject;
pub mod local_shadow;
pub mod medium_shadow;
pub mod noise;
pub mod scan;
pub mod sky;
pub mod temporal;
mod timestamps;

use std::borrow::Cow;

pub use fog::{
    FogConfig, FogError, FogPass, FrameInputs, FrameUniforms, LocalShadowConfig, LocalShadowStats,
    PassTimings, SCENE_DEPTH_FORMATS, SHADOW_MAP_FORMATS, ShadowedLight, SharedFog, StereoFog,
    VOLUME_FORMAT, VolumetricFog, cascade_projection, cascade_splits, check_device,
};
pub use timestamps::{TimestampError, TimestampPairs};

use crate::shaders::CodegenError;

/// A uniform-buffer layout entry.
pub(crate) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, visibility, wgpu::BufferBindingType::Uniform)
}

/// A storage-buffer layout entry.
pub(crate) fn storage_buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(
        binding,
        visibility,
        wgpu::BufferBindingType::Storage { read_only },
    )
}

fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A sampled-texture layout entry.
pub(crate) fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    dimension: wgpu::TextureViewDimension,
    filterable: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A 2D unsigned-integer texture layout entry (the live-slice texture of depth
/// culling, read with textureLoad).
pub(crate) fn uint_texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A write-only storage-texture layout entry.
pub(crate) fn storage_entry(
    binding: u32,
    dimension: wgpu::TextureViewDimension,
    format: wgpu::TextureFormat,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: dimension,
        },
        count: None,
    }
}

/// A sampler layout entry.
pub(crate) fn sampler_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    filtering: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Sampler(if filtering {
            wgpu::SamplerBindingType::Filtering
        } else {
            wgpu::SamplerBindingType::NonFiltering
        }),
        count: None,
    }
}

/// The shader module of a pass under a define set, composed and validated by naga and
/// handed to wgpu as a naga module.
pub(crate) fn shader_module(
    device: &wgpu::Device,
    pass: &str,
    defines: &[String],
) -> Result<wgpu::ShaderModule, CodegenError> {
    shader_module_with(device, pass, defines, None)
}

/// [`shader_module`] with the user's custom density module (inject's
/// `VOLFOG_INJECT_CUSTOM_DENSITY`).
pub(crate) fn shader_module_with(
    device: &wgpu::Device,
    pass: &str,
    defines: &[String],
    custom_density: Option<&crate::shaders::CustomModule>,
) -> Result<wgpu::ShaderModule, CodegenError> {
    let module = match custom_density {
        Some(_) => crate::shaders::compose_with_custom(pass, defines, custom_density)?,
        None => crate::shaders::compose(pass, defines)?,
    };
    Ok(device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&format!("volfog {pass}")),
        source: wgpu::ShaderSource::Naga(Cow::Owned(module)),
    }))
}

/// A bind group layout from its entries.
pub(crate) fn bind_group_layout(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

/// A compute pipeline for `entry` of `module` with group 0 laid out by `layout`.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A render pipeline drawing into one colour target without depth.
pub(crate) struct RenderPipelineDesc<'a> {
    pub label: &'a str,
    /// Vertex module and entry point.
    pub vertex: (&'a wgpu::ShaderModule, &'a str),
    /// Fragment module and entry point.
    pub fragment: (&'a wgpu::ShaderModule, &'a str),
    pub bind_group_layouts: &'a [Option<&'a wgpu::BindGroupLayout>],
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub primitive: wgpu::PrimitiveState,
    pub target: wgpu::ColorTargetState,
    /// Samples per pixel of the colour target (1 unless multisampled).
    pub samples: u32,
}

pub(crate) fn render_pipeline(
    device: &wgpu::Device,
    desc: RenderPipelineDesc<'_>,
) -> wgpu::RenderPipeline {
    render_pipeline_multiview(device, desc, None)
}

/// [`render_pipeline`] for a multiview render pass of view mask `multiview_mask`
/// (`None`: not multiview).
pub(crate) fn render_pipeline_multiview(
    device: &wgpu::Device,
    desc: RenderPipelineDesc<'_>,
    multiview_mask: Option<std::num::NonZeroU32>,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(desc.label),
        bind_group_layouts: desc.bind_group_layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(desc.label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: desc.vertex.0,
            entry_point: Some(desc.vertex.1),
            compilation_options: Default::default(),
            buffers: desc.buffers,
        },
        primitive: desc.primitive,
        depth_stencil: None,
        multisample: wgpu::MultisampleState {
            count: desc.samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: desc.fragment.0,
            entry_point: Some(desc.fragment.1),
            compilation_options: Default::default(),
            targets: &[Some(desc.target)],
        }),
        multiview_mask,
        cache: None,
    })
}

/// A bind group from (binding, resource) pairs.
pub(crate) fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[(u32, wgpu::BindingResource<'_>)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: resource.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}
