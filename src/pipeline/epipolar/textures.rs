//! The epipolar textures (coordinates, sources, the trees, marched and interpolated
//! lit fractions, the resolved and shaft textures) and their accessors.

use super::{COORD_FORMAT, EpipolarShafts, SHAFT_FORMAT, SOURCE_FORMAT, TERM_FORMAT, TREE_FORMAT};
use crate::uniforms::EpipolarSampling;

#[derive(Debug)]
pub(super) struct Textures {
    pub(super) coords: wgpu::Texture,
    pub(super) sources: wgpu::Texture,
    /// Every level of every slice's tree, two nodes per texel.
    pub(super) tree: wgpu::Texture,
    /// One level while it is built (copied into `tree`).
    pub(super) scratch: wgpu::Texture,
    pub(super) marched: wgpu::Texture,
    pub(super) interpolated: wgpu::Texture,
    pub(super) low: Option<wgpu::Texture>,
    pub(super) shafts: wgpu::Texture,
}

impl Textures {
    /// Allocates every texture of `s`.
    pub(super) fn new(device: &wgpu::Device, s: &EpipolarSampling) -> Self {
        let epi = (s.samples, s.slices);
        Textures {
            coords: storage_texture(device, "volfog epipolar coordinates", epi, COORD_FORMAT),
            sources: storage_texture(device, "volfog epipolar sources", epi, SOURCE_FORMAT),
            tree: storage_texture(
                device,
                "volfog epipolar tree",
                (s.shadow_size, s.slices),
                TREE_FORMAT,
            ),
            scratch: storage_texture(
                device,
                "volfog epipolar tree scratch",
                (s.shadow_size / 4, s.slices),
                TREE_FORMAT,
            ),
            marched: storage_texture(device, "volfog epipolar marched", epi, TERM_FORMAT),
            interpolated: storage_texture(device, "volfog epipolar interpolated", epi, TERM_FORMAT),
            low: (s.downscale > 1).then(|| {
                storage_texture(
                    device,
                    "volfog epipolar resolved",
                    s.resolved_size(),
                    SHAFT_FORMAT,
                )
            }),
            shafts: storage_texture(
                device,
                "volfog epipolar shafts",
                (s.width, s.height),
                SHAFT_FORMAT,
            ),
        }
    }
}

fn storage_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

pub(super) fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

impl EpipolarShafts {
    /// The shaft texture ([`SHAFT_FORMAT`], `width` x `height`): r the lit fraction F.
    pub fn shaft_texture(&self) -> &wgpu::Texture {
        &self.textures.shafts
    }

    /// A view of the shaft texture (bind it as unfilterable float).
    pub fn shaft_view(&self) -> wgpu::TextureView {
        view(&self.textures.shafts)
    }

    /// The coordinate texture (rgba32float, samples x slices), for inspection.
    pub fn coordinate_texture(&self) -> &wgpu::Texture {
        &self.textures.coords
    }

    /// The interpolation sources (r32uint, two u16 sample indices, samples x slices),
    /// for inspection.
    pub fn source_texture(&self) -> &wgpu::Texture {
        &self.textures.sources
    }

    /// The marched lit fractions (r32float, samples x slices; 1 at samples that are not
    /// marched), for inspection.
    pub fn marched_texture(&self) -> &wgpu::Texture {
        &self.textures.marched
    }
}
