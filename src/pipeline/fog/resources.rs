//! The textures and buffers of a [`VolumetricFog`](super::VolumetricFog), the check
//! that a device can hold them, and the checks of the textures a user hands over.

use glam::UVec3;

use super::config::FogConfig;
use super::error::FogError;
use crate::pipeline::esm::ESM_FORMAT;

/// The volume texel format.
pub const VOLUME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Shadow map formats the ESM downsample reads (as unfilterable float).
pub const SHADOW_MAP_FORMATS: [wgpu::TextureFormat; 3] = [
    wgpu::TextureFormat::Depth32Float,
    wgpu::TextureFormat::Depth16Unorm,
    wgpu::TextureFormat::R32Float,
];

pub(crate) fn volume_texture(device: &wgpu::Device, label: &str, size: UVec3) -> wgpu::Texture {
    volume_texture_for(
        device,
        label,
        size,
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    )
}

/// An rgba16float 3D texture of `size` texels with `usage`.
pub(crate) fn volume_texture_for(
    device: &wgpu::Device,
    label: &str,
    size: UVec3,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.x,
            height: size.y,
            depth_or_array_layers: size.z,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: VOLUME_FORMAT,
        usage,
        view_formats: &[],
    })
}

pub(crate) fn esm_texture(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: ESM_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A `D2Array` view of a 2D texture (the depth aspect of a depth format).
pub(crate) fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: if texture.format().has_depth_aspect() {
            wgpu::TextureAspect::DepthOnly
        } else {
            wgpu::TextureAspect::All
        },
        ..Default::default()
    })
}

pub(crate) fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        // COPY_SRC: VolumetricFog::encode_share copies the fog group's uniforms.
        usage: wgpu::BufferUsages::UNIFORM
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

pub(crate) fn storage_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Bytes of a texture's texels (one mip level).
pub(crate) fn texture_bytes(t: &wgpu::Texture) -> u64 {
    let s = t.size();
    let texel = u64::from(t.format().block_copy_size(None).unwrap_or(4));
    u64::from(s.width) * u64::from(s.height) * u64::from(s.depth_or_array_layers) * texel
}

pub(super) fn mismatch(
    texture: &'static str,
    property: &'static str,
    found: impl std::fmt::Debug,
    expected: String,
) -> FogError {
    FogError::Texture {
        texture,
        property,
        found: format!("{found:?}"),
        expected,
    }
}

/// Checks a cascaded shadow map against the configuration: a 2D texture of
/// `4 * esm_resolution` texels per side with a layer per cascade, single-sampled, in a
/// format the downsample reads, usable as a texture binding.
pub(crate) fn check_shadow_map(
    texture: &wgpu::Texture,
    config: &FogConfig,
) -> Result<(), FogError> {
    const WHAT: &str = "the shadow map";
    let (side, layers) = config.shadow_map_size();
    let size = texture.size();
    if texture.dimension() != wgpu::TextureDimension::D2 {
        return Err(mismatch(
            WHAT,
            "dimension",
            texture.dimension(),
            "D2 (with array layers)".into(),
        ));
    }
    if config.shadow_filter.compares() {
        if size.width != size.height {
            return Err(mismatch(
                WHAT,
                "size",
                (size.width, size.height),
                "square (the compare filter reads any size)".into(),
            ));
        }
    } else if size.width != side || size.height != side {
        return Err(mismatch(
            WHAT,
            "size",
            (size.width, size.height),
            format!("{side} x {side} texels (4 x FogConfig.esm_resolution)"),
        ));
    }
    if size.depth_or_array_layers < layers {
        return Err(mismatch(
            WHAT,
            "layer count",
            size.depth_or_array_layers,
            format!("at least FogConfig.cascades = {layers}"),
        ));
    }
    if !SHADOW_MAP_FORMATS.contains(&texture.format()) {
        return Err(mismatch(
            WHAT,
            "format",
            texture.format(),
            format!("one of {SHADOW_MAP_FORMATS:?}"),
        ));
    }
    if texture.sample_count() != 1 {
        return Err(mismatch(
            WHAT,
            "sample count",
            texture.sample_count(),
            "1".into(),
        ));
    }
    check_texture_binding(WHAT, texture)
}

/// Checks that a texture the fog samples was created with `TEXTURE_BINDING`.
pub(super) fn check_texture_binding(
    what: &'static str,
    texture: &wgpu::Texture,
) -> Result<(), FogError> {
    if texture
        .usage()
        .contains(wgpu::TextureUsages::TEXTURE_BINDING)
    {
        Ok(())
    } else {
        Err(mismatch(
            what,
            "usage",
            texture.usage(),
            "TEXTURE_BINDING".into(),
        ))
    }
}

/// Checks a density texture: 3D, filterable on this device, usable as a texture
/// binding (its r channel multiplies the density).
pub(crate) fn check_density_texture(
    texture: &wgpu::Texture,
    device: &wgpu::Device,
) -> Result<(), FogError> {
    check_filterable(
        texture,
        device,
        "the density texture",
        wgpu::TextureDimension::D3,
    )
}

/// Checks a cloud density map: 2D, filterable on this device, usable as a texture
/// binding (its r channel is the cloud density).
pub(crate) fn check_cloud_map(
    texture: &wgpu::Texture,
    device: &wgpu::Device,
) -> Result<(), FogError> {
    check_filterable(texture, device, "the cloud map", wgpu::TextureDimension::D2)
}

pub(super) fn check_filterable(
    texture: &wgpu::Texture,
    device: &wgpu::Device,
    what: &'static str,
    dimension: wgpu::TextureDimension,
) -> Result<(), FogError> {
    if texture.dimension() != dimension {
        return Err(mismatch(
            what,
            "dimension",
            texture.dimension(),
            format!("{dimension:?}"),
        ));
    }
    let filterable = texture
        .format()
        .guaranteed_format_features(device.features())
        .flags
        .contains(wgpu::TextureFormatFeatureFlags::FILTERABLE)
        && matches!(
            texture.format().sample_type(None, Some(device.features())),
            Some(wgpu::TextureSampleType::Float { filterable: true })
        );
    if !filterable {
        return Err(mismatch(
            what,
            "format",
            texture.format(),
            "a filterable float format (e.g. R8Unorm, R16Float)".into(),
        ));
    }
    check_texture_binding(what, texture)
}

/// Formats of the scene depth the cull pass reads (as unfilterable float).
pub const SCENE_DEPTH_FORMATS: [wgpu::TextureFormat; 5] = [
    wgpu::TextureFormat::Depth32Float,
    wgpu::TextureFormat::Depth32FloatStencil8,
    wgpu::TextureFormat::Depth24Plus,
    wgpu::TextureFormat::Depth16Unorm,
    wgpu::TextureFormat::R32Float,
];

/// Checks a scene depth for the cull pass: a single-sampled 2D texture in one of
/// [`SCENE_DEPTH_FORMATS`] with the mip level, usable as a texture binding.
pub(crate) fn check_scene_depth(texture: &wgpu::Texture, mip_level: u32) -> Result<(), FogError> {
    const WHAT: &str = "the scene depth";
    if texture.dimension() != wgpu::TextureDimension::D2 {
        return Err(mismatch(
            WHAT,
            "dimension",
            texture.dimension(),
            "D2".into(),
        ));
    }
    if !SCENE_DEPTH_FORMATS.contains(&texture.format()) {
        return Err(mismatch(
            WHAT,
            "format",
            texture.format(),
            format!("one of {SCENE_DEPTH_FORMATS:?}"),
        ));
    }
    if texture.sample_count() != 1 {
        return Err(mismatch(
            WHAT,
            "sample count",
            texture.sample_count(),
            "1 (resolve a multisampled depth buffer first)".into(),
        ));
    }
    if mip_level >= texture.mip_level_count() {
        return Err(mismatch(
            WHAT,
            "mip level count",
            texture.mip_level_count(),
            format!("more than the mip level {mip_level} read"),
        ));
    }
    check_texture_binding(WHAT, texture)
}

/// Checks that a device can run a configuration.
pub fn check_device(device: &wgpu::Device, config: &FogConfig) -> Result<(), FogError> {
    let limits = device.limits();
    let s = config.volume_size;
    if s.max_element() > limits.max_texture_dimension_3d {
        return Err(FogError::MissingCapability {
            what: "3D textures of the volume size",
            detail: format!(
                "volume {s} needs max_texture_dimension_3d >= {}, the device allows {}",
                s.max_element(),
                limits.max_texture_dimension_3d
            ),
        });
    }
    let shadow = config.esm_resolution * 4;
    if shadow > limits.max_texture_dimension_2d || config.cascades > limits.max_texture_array_layers
    {
        return Err(FogError::MissingCapability {
            what: "2D array textures of the shadow map size",
            detail: format!(
                "{shadow} x {shadow} x {} needs max_texture_dimension_2d >= {shadow} and max_texture_array_layers >= {}, the device allows {} and {}",
                config.cascades,
                config.cascades,
                limits.max_texture_dimension_2d,
                limits.max_texture_array_layers
            ),
        });
    }
    if limits.max_storage_buffers_per_shader_stage < 2
        || limits.max_storage_textures_per_shader_stage < 1
    {
        return Err(FogError::MissingCapability {
            what: "storage buffers and textures in compute shaders",
            detail: format!(
                "2 storage buffers and 1 storage texture per stage are needed, the device allows {} and {}",
                limits.max_storage_buffers_per_shader_stage,
                limits.max_storage_textures_per_shader_stage
            ),
        });
    }
    if config.timestamps && cfg!(target_arch = "wasm32") {
        return Err(FogError::MissingCapability {
            what: "blocking GPU readback",
            detail: "FogConfig.timestamps reads its queries back by waiting for the GPU, which \
                     a browser's WebGPU cannot do; on the web, time the passes with timestamp \
                     queries read back asynchronously, or with performance.now()"
                .to_string(),
        });
    }
    if config.timestamps && !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        return Err(FogError::MissingCapability {
            what: "timestamp queries",
            detail: "FogConfig.timestamps needs Features::TIMESTAMP_QUERY enabled on the device"
                .to_string(),
        });
    }
    Ok(())
}
