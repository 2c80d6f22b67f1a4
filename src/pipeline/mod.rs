//! The wgpu runtime: each pass with its bind group layout spelled out (and checked
//! against the shader's reflection by the tests), created from the prebuilt,
//! flattened WGSL of its variant.

pub mod apply;
pub mod scan;

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

/// The WGSL of a prebuilt variant's entry point.
pub(crate) fn prebuilt_wgsl(variant: &str, entry: &str) -> &'static str {
    crate::shaders::variant(variant)
        .and_then(|v| v.entry(entry))
        .map(|e| e.wgsl)
        .unwrap_or_else(|| panic!("variant {variant} entry {entry} is prebuilt by build.rs"))
}
