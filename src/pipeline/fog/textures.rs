//! The volumes and textures [`VolumetricFog`] owns: the history ping-pong, the ESM
//! array, the density, cloud and noise textures with their placeholders, the
//! live-slice textures; their accessors and the memory they take.

use super::{FogConfig, VolumetricFog, esm_texture, texture_bytes};
use crate::pipeline::cull::{FroxelCullPass, LiveBlocks};
use crate::pipeline::noise::NoiseBake;
use crate::pipeline::temporal::TemporalPass;
use crate::pipeline::timestamps::TimestampPairs;

/// Temporal reprojection: the two history volumes with their views and states, and
/// the separate pass with its bind groups of both parities (`None` when inject does
/// the blend, `FogConfig::fused_temporal`).
#[derive(Debug)]
pub(super) struct Temporal {
    pub(super) volumes: [wgpu::Texture; 2],
    pub(super) views: [wgpu::TextureView; 2],
    pub(super) states: [wgpu::Buffer; 2],
    pub(super) pass: Option<(TemporalPass, [wgpu::BindGroup; 2])>,
}

/// The density multiplier texture of the density-texture variant.
#[derive(Debug)]
pub(super) struct Density {
    /// The user's texture, or a 1x1x1 unit texture until one is set.
    pub(super) texture: wgpu::Texture,
    pub(super) user: bool,
    pub(super) unit_written: bool,
    pub(super) sampler: wgpu::Sampler,
}

/// The cloud shadow of the cloud-shadow variant: the layer's uniform and its density
/// map (the user's, or an empty 1x1 map until one is set).
#[derive(Debug)]
pub(super) struct CloudShadow {
    pub(super) layer: wgpu::Buffer,
    pub(super) map: wgpu::Texture,
    pub(super) user: bool,
    pub(super) empty_written: bool,
    pub(super) sampler: wgpu::Sampler,
}

/// Depth culling: the cull pass, the live-slice textures of both parities (the one of
/// parity p is written with the history volume p), and the cull bind groups of the
/// scene depth when one is set.
#[derive(Debug)]
pub(super) struct Culling {
    pub(super) pass: FroxelCullPass,
    pub(super) live: [wgpu::Texture; 2],
    pub(super) views: [wgpu::TextureView; 2],
    /// The live blocks and the indirect dispatch arguments of this frame.
    pub(super) blocks: LiveBlocks,
    /// The scene depth, its mip level and the cull groups of both parities.
    pub(super) depth: Option<(wgpu::Texture, u32, [wgpu::BindGroup; 2])>,
    /// Whether both textures hold "every slice live" (written by `prepare` while no
    /// scene depth is set).
    pub(super) all_live: bool,
}

/// The baked noise texture of the noise-texture variant: baked by the first `prepare`
/// (one submission of its own), then only read.
#[derive(Debug)]
pub(super) struct Noise {
    pub(super) device: wgpu::Device,
    pub(super) pass: NoiseBake,
    pub(super) texture: wgpu::Texture,
    pub(super) sampler: wgpu::Sampler,
    pub(super) baked: bool,
}

/// The shadow map and the downsample bind group reading it.
#[derive(Debug)]
pub(super) struct ShadowMap {
    pub(super) texture: wgpu::Texture,
    pub(super) group: wgpu::BindGroup,
}
impl VolumetricFog {
    /// The integrated volume (rgb in-scatter, a transmittance) after `encode`.
    pub fn integrated_texture(&self) -> &wgpu::Texture {
        self.integrated.as_ref().unwrap_or(&self.scattering)
    }

    /// The live-slice texture of the prepared frame (R32Uint, one value per froxel
    /// column: how many leading slices inject, temporal and scan process), with
    /// `FogConfig::depth_cull`; `None` without culling or before the first `prepare`.
    pub fn live_slices_texture(&self) -> Option<&wgpu::Texture> {
        let parity = (self.frame_index()? % 2) as usize;
        self.culling.as_ref().map(|c| &c.live[parity])
    }

    /// The scattering volume written by inject (before temporal and scan; with
    /// temporal reprojection the scan overwrites it with the integrated volume). With
    /// the temporal blend fused into inject ([`FogConfig::fused_temporal`]) inject
    /// writes the stabilised volume instead, and this holds only the integrated one.
    pub fn scattering_texture(&self) -> &wgpu::Texture {
        &self.scattering
    }

    /// The lit volume of the prepared frame (after `encode`): per froxel rgb
    /// `sigma_s L_in`, a `sigma_t`, the volume the scan integrates (the stabilised
    /// volume with temporal reprojection, else the scattering volume). Forward shaders
    /// read the fog's light at a point from it (`volfog::fog_lit`).
    pub fn lit_texture(&self) -> &wgpu::Texture {
        self.stabilised_texture()
            .unwrap_or_else(|| self.scattering_texture())
    }

    /// The medium-shadow volume (`FogConfig::medium_shadows`): after `encode`, the
    /// prepared frame's (rgba16float, r the optical depth, g the excess extinction; see
    /// `volfog::medium_shadow`).
    pub fn medium_shadow_texture(&self) -> Option<&wgpu::Texture> {
        self.medium_shadows.as_ref().map(|m| &m.volume)
    }

    /// The stabilised volume of the prepared frame (after `encode`), when temporal
    /// reprojection is on.
    pub fn stabilised_texture(&self) -> Option<&wgpu::Texture> {
        let parity = (self.frame_index()? % 2) as usize;
        self.temporal.as_ref().map(|t| &t.volumes[parity])
    }

    /// The `HistoryState` buffer beside [`VolumetricFog::stabilised_texture`].
    pub fn stabilised_state(&self) -> Option<&wgpu::Buffer> {
        let parity = (self.frame_index()? % 2) as usize;
        self.temporal.as_ref().map(|t| &t.states[parity])
    }

    /// The filtered ESM array (one layer per cascade; 1 x 1 texels with the compare
    /// filter, which reads the shadow map itself).
    pub fn esm_texture(&self) -> &wgpu::Texture {
        &self.esm_texture
    }

    /// GPU memory of every texture and buffer this object owns (the user's shadow map
    /// and density texture excluded), in bytes.
    pub fn memory_bytes(&self) -> u64 {
        let mut textures = vec![&self.scattering, &self.esm_texture, &self.esm_scratch];
        textures.extend(&self.integrated);
        if let Some(t) = &self.temporal {
            textures.extend(&t.volumes);
        }
        if let Some(d) = self.density.as_ref().filter(|d| !d.user) {
            textures.push(&d.texture);
        }
        if let Some(c) = &self.culling {
            textures.extend(&c.live);
        }
        if let Some(n) = &self.noise {
            textures.push(&n.texture);
        }
        if let Some(c) = self.clouds.as_ref().filter(|c| !c.user) {
            textures.push(&c.map);
        }
        if let Some(l) = &self.local_shadows {
            textures.extend(l.textures());
        }
        if let Some(m) = &self.medium_shadows {
            textures.push(&m.volume);
        }
        let mut buffers: Vec<&wgpu::Buffer> = self.buffers.all().to_vec();
        if let Some(m) = &self.medium_shadows {
            buffers.push(&m.params);
        }
        if let Some(c) = &self.culling {
            buffers.extend([&c.blocks.blocks, &c.blocks.dispatch]);
        }
        if let Some(t) = &self.temporal {
            buffers.extend(&t.states);
        }
        if let Some(l) = &self.local_shadows {
            buffers.extend(l.buffers());
        }
        textures.into_iter().map(texture_bytes).sum::<u64>()
            + buffers.iter().map(|b| b.size()).sum::<u64>()
            + self
                .timestamps
                .as_ref()
                .map(TimestampPairs::buffer_bytes)
                .unwrap_or(0)
    }
}

pub(super) fn esm_texture_scratch(device: &wgpu::Device, config: &FogConfig) -> wgpu::Texture {
    esm_texture(
        device,
        "volfog esm scratch",
        esm_side(config),
        config.cascades,
    )
}

/// Texels per side of the fog's ESM arrays: the ESM resolution, or 1 with the compare
/// filter, which reads no ESM (the array is then what inject binds while no shadow map
/// is set).
pub(super) fn esm_side(config: &FogConfig) -> u32 {
    if config.shadow_filter.compares() {
        1
    } else {
        config.esm_resolution
    }
}

pub(super) fn unit_density_texture(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("volfog unit density"),
        size: wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: wgpu::TextureFormat::R8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

pub(super) fn empty_cloud_map(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("volfog empty cloud map"),
        size: wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// Writes the one texel of a 1x1 R8Unorm texture.
pub(super) fn write_texel(queue: &wgpu::Queue, texture: &wgpu::Texture, value: u8) {
    queue.write_texture(
        texture.as_image_copy(),
        &[value],
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: None,
            rows_per_image: None,
        },
        texture.size(),
    );
}

pub(super) fn write_unit_density(queue: &wgpu::Queue, texture: &wgpu::Texture) {
    queue.write_texture(
        texture.as_image_copy(),
        &[255],
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: None,
            rows_per_image: None,
        },
        texture.size(),
    );
}

pub(super) fn density_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog density"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}
