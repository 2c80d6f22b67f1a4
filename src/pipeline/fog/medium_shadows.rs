//! The medium's shadows of [`VolumetricFog`] (`FogConfig::medium_shadows`): the
//! `medium_shadow` pass, its volume, sampler, `MediumShadow` uniform and bind group.

use super::buffers::Buffers;
use super::textures::{Density, Noise};
use super::{FogConfig, FogError, FrameUniforms, uniform_buffer, view};
use crate::limits::InvalidValue;
use crate::pipeline::medium_shadow::{MediumShadowPass, MediumShadowResources, create_volume};
use crate::uniforms::{self, MediumShadow, MediumShadowConfig};

/// The pass and the resources of the medium's shadows.
pub(super) struct MediumShadows {
    config: MediumShadowConfig,
    pass: MediumShadowPass,
    pub(super) volume: wgpu::Texture,
    pub(super) view: wgpu::TextureView,
    pub(super) sampler: wgpu::Sampler,
    pub(super) params: wgpu::Buffer,
    group: wgpu::BindGroup,
}

impl MediumShadows {
    /// The pass for `config.medium_shadows` (`None` without it), its group bound to the
    /// fog's buffers and medium textures.
    pub(super) fn new(
        device: &wgpu::Device,
        config: &FogConfig,
        buffers: &Buffers,
        density: Option<&Density>,
        noise: Option<&Noise>,
    ) -> Result<Option<Self>, FogError> {
        let Some(c) = config.medium_shadows.filter(|_| config.light_transmittance) else {
            return Ok(None);
        };
        let pass = MediumShadowPass::new(
            device,
            config.inject_options(),
            config.custom_density.as_ref(),
        )?;
        let volume = create_volume(device, &c);
        let volume_view = view(&volume);
        let params = uniform_buffer(
            device,
            "volfog medium shadow",
            uniforms::to_uniform_bytes(&MediumShadow::default()).len(),
        );
        let group = group(
            device,
            &pass,
            buffers,
            density,
            noise,
            &volume_view,
            &params,
        );
        Ok(Some(Self {
            config: c,
            pass,
            volume,
            view: volume_view,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("volfog medium shadow"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            params,
            group,
        }))
    }

    /// Binds the pass again (after the density texture changed).
    pub(super) fn rebuild_group(
        &mut self,
        device: &wgpu::Device,
        buffers: &Buffers,
        density: Option<&Density>,
        noise: Option<&Noise>,
    ) {
        self.group = group(
            device,
            &self.pass,
            buffers,
            density,
            noise,
            &self.view,
            &self.params,
        );
    }

    /// The placement for a frame's uniforms (the error names what is out of range).
    pub(super) fn placement(&self, u: &FrameUniforms) -> Result<MediumShadow, InvalidValue> {
        MediumShadow::fit(
            &self.config,
            u.frame.world_from_view,
            u.froxels.view_from_clip,
            u.froxels.far,
            u.lighting.sun.direction,
        )
    }

    /// Uploads a frame's placement.
    pub(super) fn write(&self, queue: &wgpu::Queue, placement: &MediumShadow) {
        queue.write_buffer(&self.params, 0, &uniforms::to_uniform_bytes(placement));
    }

    /// Records the fill.
    pub(super) fn encode(&self, pass: &mut wgpu::ComputePass<'_>) {
        self.pass
            .encode(pass, &self.group, self.config.size.to_array());
    }
}

fn group(
    device: &wgpu::Device,
    pass: &MediumShadowPass,
    buffers: &Buffers,
    density: Option<&Density>,
    noise: Option<&Noise>,
    volume: &wgpu::TextureView,
    params: &wgpu::Buffer,
) -> wgpu::BindGroup {
    let density_view = density.map(|d| view(&d.texture));
    let noise_view = noise.map(|n| view(&n.texture));
    pass.bind_group(
        device,
        &MediumShadowResources {
            frame: &buffers.frame,
            medium: &buffers.medium,
            local_volumes: &buffers.local_volumes,
            density_texture: density_view.as_ref().zip(density.map(|d| &d.sampler)),
            noise_texture: noise_view.as_ref().zip(noise.map(|n| &n.sampler)),
            custom_params: Some(&buffers.custom_params),
            particles: Some(&buffers.particles),
            volume,
            params,
        },
    )
    .expect("the fog binds every texture its medium variant reads")
}
