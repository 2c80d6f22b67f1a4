//! The uniform and storage buffers of [`VolumetricFog`](super::VolumetricFog): what
//! `prepare` writes each frame's uniforms, lights and local volumes into.

use super::{FogConfig, storage_buffer, uniform_buffer};
use crate::uniforms::{
    self, AreaLight, FogCustomParams, FogFrame, FogLight, FogLighting, FogMedium, FogParticle,
    FogView, Froxels, HeightFog, LocalVolume, ShadowCascades, ShadowTaps, TransientLighting,
};

/// The uniform and storage buffers of the fog.
#[derive(Debug)]
pub(super) struct Buffers {
    pub(super) froxels: wgpu::Buffer,
    pub(super) frame: wgpu::Buffer,
    pub(super) medium: wgpu::Buffer,
    pub(super) lighting: wgpu::Buffer,
    pub(super) cascades: wgpu::Buffer,
    pub(super) tail: wgpu::Buffer,
    pub(super) view: wgpu::Buffer,
    pub(super) lights: wgpu::Buffer,
    pub(super) local_volumes: wgpu::Buffer,
    /// `ShadowTaps` (the compare filter).
    pub(super) shadow_taps: wgpu::Buffer,
    /// `TransientLighting` (the transient scan).
    pub(super) transient: wgpu::Buffer,
    /// The transient lights (`FogConfig::max_transient_lights`, at least one element).
    pub(super) transient_lights: wgpu::Buffer,
    /// `FogCustomParams` (the custom density).
    pub(super) custom_params: wgpu::Buffer,
    /// The area lights (`FogConfig::max_area_lights` elements, at least one; unused
    /// slots have range 0).
    pub(super) area_lights: wgpu::Buffer,
    /// The particles (`FogConfig::max_particles` elements, at least one; the first
    /// `FogMedium::particle_count` are read).
    pub(super) particles: wgpu::Buffer,
}

impl Buffers {
    pub(super) fn new(device: &wgpu::Device, config: &FogConfig) -> Self {
        let uniform = |label, bytes: Vec<u8>| uniform_buffer(device, label, bytes.len());
        let lights = uniforms::to_storage_bytes(&vec![
            FogLight::default();
            config.max_lights.max(1) as usize
        ]);
        let transient_lights = uniforms::to_storage_bytes(&vec![
            FogLight::default();
            config.max_transient_lights.max(1)
                as usize
        ]);
        let volumes = uniforms::to_storage_bytes(&vec![
            LocalVolume::default();
            config.max_local_volumes.max(1) as usize
        ]);
        let area_lights = uniforms::to_storage_bytes(&vec![
            AreaLight::default();
            config.max_area_lights.max(1) as usize
        ]);
        let particles = uniforms::to_storage_bytes(&vec![
            FogParticle::default();
            config.max_particles.max(1) as usize
        ]);
        Self {
            particles: storage_buffer(device, "volfog particles", particles.len()),
            area_lights: storage_buffer(device, "volfog area lights", area_lights.len()),
            froxels: uniform("volfog froxels", Froxels::default().to_bytes()),
            frame: uniform(
                "volfog frame",
                uniforms::to_uniform_bytes(&FogFrame::default()),
            ),
            medium: uniform(
                "volfog medium",
                uniforms::to_uniform_bytes(&FogMedium::default()),
            ),
            lighting: uniform(
                "volfog lighting",
                uniforms::to_uniform_bytes(&FogLighting::default()),
            ),
            cascades: uniform(
                "volfog cascades",
                uniforms::to_uniform_bytes(&ShadowCascades::default()),
            ),
            tail: uniform("volfog tail", HeightFog::none().to_bytes()),
            view: uniform(
                "volfog view",
                uniforms::to_uniform_bytes(&FogView::default()),
            ),
            lights: storage_buffer(device, "volfog lights", lights.len()),
            local_volumes: storage_buffer(device, "volfog local volumes", volumes.len()),
            shadow_taps: uniform(
                "volfog shadow taps",
                uniforms::to_uniform_bytes(&ShadowTaps::default()),
            ),
            transient: uniform(
                "volfog transient lighting",
                uniforms::to_uniform_bytes(&TransientLighting::default()),
            ),
            transient_lights: storage_buffer(
                device,
                "volfog transient lights",
                transient_lights.len(),
            ),
            custom_params: uniform(
                "volfog custom density parameters",
                uniforms::to_uniform_bytes(&FogCustomParams::default()),
            ),
        }
    }

    pub(super) fn all(&self) -> [&wgpu::Buffer; 15] {
        [
            &self.froxels,
            &self.frame,
            &self.medium,
            &self.lighting,
            &self.cascades,
            &self.tail,
            &self.view,
            &self.lights,
            &self.local_volumes,
            &self.shadow_taps,
            &self.transient,
            &self.transient_lights,
            &self.custom_params,
            &self.area_lights,
            &self.particles,
        ]
    }
}
