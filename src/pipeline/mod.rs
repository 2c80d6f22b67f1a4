//! The wgpu runtime: each pass with its bind group layout spelled out (and checked
//! against the shader's reflection by the tests), created from the flattened WGSL of
//! its variant (prebuilt, or composed at run time for non-default values), and
//! [`VolumetricFog`], which owns the whole froxel pipeline.

pub mod apply;
pub mod esm;
pub mod fog;
pub mod hull;
pub mod inject;
pub mod scan;
pub mod temporal;

use std::borrow::Cow;

pub use fog::{
    FogConfig, FogError, FogPass, FrameInputs, PassTimings, ShadowInputs, UploadedUniforms,
    VolumetricFog,
};

/// A uniform-buffer layout entry.
pub(crate) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A read-only storage-buffer layout entry.
pub(crate) fn storage_buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
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

/// The WGSL of a prebuilt variant's entry point.
pub(crate) fn prebuilt_wgsl(variant: &str, entry: &str) -> &'static str {
    crate::shaders::variant(variant)
        .and_then(|v| v.entry(entry))
        .map(|e| e.wgsl)
        .unwrap_or_else(|| panic!("variant {variant} entry {entry} is prebuilt by build.rs"))
}

/// The WGSL of a pass entry point under a define set (`NAME` / `NAME=VALUE`): the
/// prebuilt variant when one matches, otherwise a composition at run time.
pub(crate) fn variant_wgsl(
    pass: &str,
    defines: &[String],
    entry: &str,
) -> Result<Cow<'static, str>, crate::codegen::CodegenError> {
    let source = crate::manifest::pass(pass).expect("pass listed in the manifest");
    let parsed = crate::codegen::compose::Defines::parse(source, defines)?;
    let name = parsed.variant_name(pass);
    if let Some(e) = crate::shaders::variant(&name).and_then(|v| v.entry(entry)) {
        return Ok(Cow::Borrowed(e.wgsl));
    }
    let composed = crate::shaders::compose_variant(pass, defines)?;
    let text = composed
        .entries
        .into_iter()
        .find(|e| e.entry == entry)
        .map(|e| e.wgsl)
        .expect("the pass has this entry point");
    Ok(Cow::Owned(text))
}

/// A compute pipeline with an explicit bind group layout (group 0).
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    wgsl: &str,
    entry: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(Cow::Owned(wgsl.to_string())),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    (layout, pipeline)
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
