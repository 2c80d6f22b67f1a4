//! [`SharedFog`]: one fog group for the forward shaders of several cameras, which each
//! camera's [`VolumetricFog`] fills before its forward pass.
//!
//! An engine that binds one material bind group for every view (Bevy's materials, a
//! renderer whose per-material groups are built once) cannot hand each camera's
//! shaders that camera's fog group. With a `SharedFog` the material group holds the
//! shared resources instead, and each camera records
//! [`VolumetricFog::encode_share`] after its fog passes and before the passes that
//! draw its materials: the copy puts that camera's `Froxels`, tail and `FogView`
//! uniforms and its integrated volume into the shared ones, so the materials drawn
//! next read the fog of the camera drawing them. Commands run in the order they are
//! recorded, so a camera's copy cannot overwrite what an earlier camera's passes
//! still read.

use glam::UVec3;

use super::{FogError, VolumetricFog, resources};
use crate::limits::InvalidValue;
use crate::pipeline::apply::FogResources;
use crate::uniforms::{self, FogView, Froxels, HeightFog};

/// The resources of one fog group, filled from a camera's fog by
/// [`VolumetricFog::encode_share`]. Every camera sharing it must have its volume
/// size; it holds no fog (transmittance 1) until the first copy.
///
/// ```no_run
/// # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, fogs: &[volfog::pipeline::VolumetricFog]) -> Result<(), volfog::pipeline::FogError> {
/// use volfog::pipeline::SharedFog;
///
/// // Once: a material group built from the shared resources.
/// let shared = SharedFog::new(device, queue, fogs[0].config().volume_size)?;
/// let resources = shared.resources(); // bind at the bindings of volfog::bindings
/// // Every frame, per camera, after VolumetricFog::prepare:
/// let mut encoder = device.create_command_encoder(&Default::default());
/// for fog in fogs {
///     fog.encode(&mut encoder)?;
///     fog.encode_share(&mut encoder, &shared)?;
///     // ... this camera's passes that draw materials reading the shared group
/// }
/// queue.submit([encoder.finish()]);
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct SharedFog {
    froxels: wgpu::Buffer,
    tail: wgpu::Buffer,
    view: wgpu::Buffer,
    volume: wgpu::Texture,
    volume_view: wgpu::TextureView,
    sampler: wgpu::Sampler,
}

impl SharedFog {
    /// Shared resources for cameras whose fog has `volume_size` froxels (each side
    /// 1..=2048, as `FogConfig::volume_size`; the error names `SharedFog.volume_size`).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        volume_size: UVec3,
    ) -> Result<Self, FogError> {
        // Until a camera's fog arrives: a valid placement over a volume that holds
        // no fog, and no tail.
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
        let empty =
            Froxels::new(projection, volume_size, 0.1, 100.0, 0.0).map_err(|e| InvalidValue {
                field: "SharedFog.volume_size",
                ..e
            })?;
        let buffer = |label, bytes: Vec<u8>| {
            let b = resources::uniform_buffer(device, label, bytes.len());
            queue.write_buffer(&b, 0, &bytes);
            b
        };
        let volume = resources::volume_texture_for(
            device,
            "volfog shared integrated",
            volume_size,
            wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::COPY_SRC,
        );
        let volume_view = volume.create_view(&Default::default());
        let shared = Self {
            froxels: buffer("volfog shared froxels", empty.to_bytes()),
            tail: buffer("volfog shared tail", HeightFog::none().to_bytes()),
            view: buffer(
                "volfog shared view",
                uniforms::to_uniform_bytes(&FogView::default()),
            ),
            volume,
            volume_view,
            sampler: crate::pipeline::apply::fog_sampler(device),
        };
        shared.clear(queue);
        Ok(shared)
    }

    /// Fills the volume with "no fog" (in-scatter 0, transmittance 1).
    fn clear(&self, queue: &wgpu::Queue) {
        let size = self.volume.size();
        let texel: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0]
            .iter()
            .flat_map(|v| half::f16::from_f32(*v).to_le_bytes())
            .collect();
        let row = texel.repeat(size.width as usize);
        let data = row.repeat((size.height * size.depth_or_array_layers) as usize);
        queue.write_texture(
            self.volume.as_image_copy(),
            &data,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row.len() as u32),
                rows_per_image: Some(size.height),
            },
            size,
        );
    }

    /// The froxel count per axis every sharing camera's fog must have.
    pub fn volume_size(&self) -> UVec3 {
        let s = self.volume.size();
        UVec3::new(s.width, s.height, s.depth_or_array_layers)
    }

    /// The resources to bind at the bindings of `volfog::bindings` (a material's
    /// group, or a group of [`crate::pipeline::apply::fog_bind_group`]). They stay
    /// the same for the life of the `SharedFog`.
    pub fn resources(&self) -> FogResources<'_> {
        FogResources {
            froxels: &self.froxels,
            integrated: &self.volume_view,
            tail: &self.tail,
            view: &self.view,
            sampler: &self.sampler,
        }
    }

    /// The shared integrated volume (what the last copy put there).
    pub fn integrated_texture(&self) -> &wgpu::Texture {
        &self.volume
    }
}

impl VolumetricFog {
    /// Records the copy of this camera's fog (its `Froxels`, tail and `FogView`
    /// uniforms of the prepared frame and its integrated volume) into `shared`. Record
    /// it after [`VolumetricFog::encode`] and before the passes whose shaders read
    /// `shared`. A fog whose volume size differs from `shared`'s is an error
    /// ([`FogError::Texture`]) and records nothing.
    pub fn encode_share(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        shared: &SharedFog,
    ) -> Result<(), FogError> {
        self.frame_index().ok_or(FogError::NotPrepared)?;
        let size = self.config.volume_size;
        if size != shared.volume_size() {
            return Err(FogError::Texture {
                texture: "the shared fog's volume",
                property: "size",
                found: format!("{}", shared.volume_size()),
                expected: format!("{size}, this fog's FogConfig.volume_size"),
            });
        }
        let b = &self.buffers;
        for (from, to) in [
            (&b.froxels, &shared.froxels),
            (&b.tail, &shared.tail),
            (&b.view, &shared.view),
        ] {
            encoder.copy_buffer_to_buffer(from, 0, to, 0, from.size());
        }
        encoder.copy_texture_to_texture(
            self.integrated_texture().as_image_copy(),
            shared.volume.as_image_copy(),
            shared.volume.size(),
        );
        Ok(())
    }
}
