//! The bind groups of the fog's passes: inject, temporal and scan by frame parity
//! (they differ in the live-slice texture and the history read), the ESM blur.

use super::buffers::Buffers;
use super::local_shadows::LocalShadows;
use super::medium_shadows::MediumShadows;
use super::textures::{CloudShadow, Culling, Density, Noise, Temporal};
use super::{FogError, VolumetricFog, array_view, view};
use crate::pipeline::esm::EsmPasses;
use crate::pipeline::inject::{InjectPass, InjectResources, InjectTemporalResources};
use crate::pipeline::scan::{ScanPass, TransientScanResources};
use crate::pipeline::temporal::{TemporalPass, TemporalResources};

impl VolumetricFog {
    /// What inject reads at binding 5: the filtered ESM, or with the compare filter the
    /// sun's shadow map (the 1 x 1 placeholder ESM while none is set).
    pub(super) fn inject_sun_view(&self) -> wgpu::TextureView {
        match &self.shadow_map {
            Some(map) if self.config.shadow_filter.compares() => array_view(&map.texture),
            _ => array_view(&self.esm_texture),
        }
    }

    pub(super) fn rebuild_inject_groups(&mut self, device: &wgpu::Device) {
        if let Some(m) = self.medium_shadows.as_mut() {
            m.rebuild_group(
                device,
                &self.buffers,
                self.density.as_ref(),
                self.noise.as_ref(),
            );
        }
        let scattering = view(&self.scattering);
        let fused = self
            .temporal
            .as_ref()
            .filter(|_| self.config.fused_temporal());
        let sun_view = self.inject_sun_view();
        let scene_depth = scene_depth_view(self.culling.as_ref(), &self.esm_texture);
        let groups = |inject: &InjectPass| {
            [0, 1].map(|p| {
                let (output, temporal) =
                    inject_output(&scattering, fused, self.culling.as_ref(), p);
                inject_bind_group(
                    device,
                    inject,
                    &self.buffers,
                    &sun_view,
                    output,
                    InjectTextures {
                        density: self.density.as_ref(),
                        culling: inject_culling(self.culling.as_ref(), p),
                        noise: self.noise.as_ref(),
                        clouds: self.clouds.as_ref(),
                        local_shadows: self.local_shadows.as_ref(),
                        scene_depth: Some(&scene_depth),
                        temporal,
                        medium_shadow: self.medium_shadows.as_ref(),
                    },
                )
            })
        };
        self.inject_groups = groups(&self.inject);
        if let Some((pass, _)) = &self.inject_shadowed {
            let shadowed = groups(pass);
            self.inject_shadowed.as_mut().expect("checked above").1 = shadowed;
        }
    }

    /// Compiles the local-shadow variant of inject (once) and rebuilds the inject
    /// groups: called when shadow maps or cookies are set.
    pub(super) fn enable_shadowed_inject(&mut self, device: &wgpu::Device) -> Result<(), FogError> {
        if self.inject_shadowed.is_none() {
            let pass = InjectPass::with_custom_density(
                device,
                self.config.inject_options(),
                self.config.custom_density.as_ref(),
            )?;
            let placeholder = self.inject_groups.clone();
            self.inject_shadowed = Some((pass, placeholder));
        }
        self.rebuild_inject_groups(device);
        Ok(())
    }
}

/// The live slices and live blocks inject reads at parity `p` with depth culling.
pub(super) fn inject_culling(
    culling: Option<&Culling>,
    p: usize,
) -> Option<(&wgpu::TextureView, &wgpu::Buffer)> {
    culling.map(|c| (&c.views[p], &c.blocks.blocks))
}

/// What inject writes at frame parity `p`: the scattering volume, or, with the
/// temporal blend fused into it (`fused`), stabilised volume p with the history
/// (volume and state 1 - p) it blends.
pub(super) fn inject_output<'a>(
    scattering: &'a wgpu::TextureView,
    fused: Option<&'a Temporal>,
    culling: Option<&'a Culling>,
    p: usize,
) -> (&'a wgpu::TextureView, Option<InjectTemporalResources<'a>>) {
    match fused {
        None => (scattering, None),
        Some(t) => (
            &t.views[p],
            Some(InjectTemporalResources {
                history: &t.views[1 - p],
                history_state: &t.states[1 - p],
                stabilised_state: &t.states[p],
                history_live_slices: culling.map(|c| &c.views[1 - p]),
            }),
        ),
    }
}

/// The temporal bind groups of both parities.
pub(super) fn temporal_groups(
    device: &wgpu::Device,
    pass: &TemporalPass,
    buffers: &Buffers,
    scattering_view: &wgpu::TextureView,
    views: &[wgpu::TextureView; 2],
    states: &[wgpu::Buffer; 2],
    culling: Option<&Culling>,
) -> [wgpu::BindGroup; 2] {
    let live_view = |p: usize| culling.map(|c| &c.views[p]);
    let live_blocks = culling.map(|c| &c.blocks.blocks);
    // Frame parity p reads history 1 - p and writes history p.
    [0, 1].map(|p| {
        pass.bind_group(
            device,
            &TemporalResources {
                froxels: &buffers.froxels,
                frame: &buffers.frame,
                current: scattering_view,
                history: &views[1 - p],
                history_state: &states[1 - p],
                stabilised: &views[p],
                stabilised_state: &states[p],
                culling: live_view(p)
                    .zip(live_view(1 - p))
                    .zip(live_blocks)
                    .map(|((a, b), c)| (a, b, c)),
            },
        )
        .expect("the fog binds live slices whenever it culls")
    })
}

/// The scan bind groups of both parities (with the transient variant's buffers, which
/// the other variants ignore).
pub(super) fn scan_groups(
    device: &wgpu::Device,
    scan: &ScanPass,
    buffers: &Buffers,
    scattering_view: &wgpu::TextureView,
    temporal: Option<&Temporal>,
    integrated: Option<&wgpu::Texture>,
    culling: Option<&Culling>,
) -> [wgpu::BindGroup; 2] {
    let live_view = |p: usize| culling.map(|c| &c.views[p]);
    // Parity p scans stabilised volume p (or the scattering volume) with live
    // slices p.
    [0, 1].map(|p| {
        let (input, output) = match (temporal, integrated) {
            (Some(t), _) => (t.views[p].clone(), scattering_view.clone()),
            (None, Some(out)) => (scattering_view.clone(), view(out)),
            (None, None) => unreachable!("the integrated volume exists without temporal"),
        };
        let transient = TransientScanResources {
            medium: &buffers.medium,
            lighting: &buffers.transient,
            lights: &buffers.transient_lights,
        };
        scan.bind_group_with(
            device,
            &buffers.froxels,
            &input,
            &output,
            live_view(p),
            Some(transient),
        )
        .expect("the fog binds live slices whenever it culls")
    })
}

/// The ESM blur bind groups: the ESM array into the scratch array, and back.
pub(super) fn blur_groups(
    device: &wgpu::Device,
    esm: &EsmPasses,
    esm_view: &wgpu::TextureView,
    scratch_view: &wgpu::TextureView,
) -> [wgpu::BindGroup; 2] {
    [
        esm.blur_bind_group(device, esm_view, scratch_view),
        esm.blur_bind_group(device, scratch_view, esm_view),
    ]
}

/// The optional textures an inject variant reads.
pub(super) struct InjectTextures<'a> {
    pub(super) density: Option<&'a Density>,
    pub(super) culling: Option<(&'a wgpu::TextureView, &'a wgpu::Buffer)>,
    pub(super) noise: Option<&'a Noise>,
    pub(super) clouds: Option<&'a CloudShadow>,
    pub(super) local_shadows: Option<&'a LocalShadows>,
    pub(super) temporal: Option<InjectTemporalResources<'a>>,
    /// The scene depth culling reads, or a 1 x 1 placeholder (binding 32 of the
    /// compare filter's culling variant).
    pub(super) scene_depth: Option<&'a wgpu::TextureView>,
    /// The medium's shadows (bindings 35 to 37 of the medium-shadow variant).
    pub(super) medium_shadow: Option<&'a MediumShadows>,
}

/// The view inject reads the scene depth through: the depth culling's texture at its
/// mip level, or the layer 0 of `placeholder` (an R32Float array) while none is set.
pub(super) fn scene_depth_view(
    culling: Option<&Culling>,
    placeholder: &wgpu::Texture,
) -> wgpu::TextureView {
    match culling.and_then(|c| c.depth.as_ref()) {
        Some((texture, mip_level, _)) => depth_view(texture, *mip_level),
        None => placeholder.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            array_layer_count: Some(1),
            ..Default::default()
        }),
    }
}

/// A `D2` view of one mip level of a scene depth (its depth aspect where it has one).
pub(super) fn depth_view(texture: &wgpu::Texture, mip_level: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect: if texture.format().has_depth_aspect() {
            wgpu::TextureAspect::DepthOnly
        } else {
            wgpu::TextureAspect::All
        },
        base_mip_level: mip_level,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

pub(super) fn inject_bind_group(
    device: &wgpu::Device,
    inject: &InjectPass,
    buffers: &Buffers,
    esm: &wgpu::TextureView,
    scattering: &wgpu::TextureView,
    textures: InjectTextures<'_>,
) -> wgpu::BindGroup {
    let InjectTextures {
        density,
        culling,
        noise,
        clouds,
        local_shadows,
        temporal,
        scene_depth,
        medium_shadow,
    } = textures;
    let local_views = local_shadows.map(LocalShadows::views);
    let density_view = density.map(|d| view(&d.texture));
    let noise_view = noise.map(|n| view(&n.texture));
    let cloud_view = clouds.map(|c| view(&c.map));
    inject
        .bind_group(
            device,
            &InjectResources {
                froxels: &buffers.froxels,
                frame: &buffers.frame,
                medium: &buffers.medium,
                lighting: &buffers.lighting,
                cascades: &buffers.cascades,
                esm,
                lights: &buffers.lights,
                local_volumes: &buffers.local_volumes,
                scattering,
                density_texture: density_view.as_ref().zip(density.map(|d| &d.sampler)),
                culling,
                scene_depth,
                noise_texture: noise_view.as_ref().zip(noise.map(|n| &n.sampler)),
                cloud_shadow: clouds
                    .zip(cloud_view.as_ref())
                    .map(|(c, v)| (&c.layer, v, &c.sampler)),
                local_shadows: local_shadows
                    .zip(local_views.as_ref())
                    .map(|(l, v)| l.resources(v)),
                temporal,
                shadow_taps: Some(&buffers.shadow_taps),
                custom_params: Some(&buffers.custom_params),
                area_lights: Some(&buffers.area_lights),
                particles: Some(&buffers.particles),
                medium_shadow: medium_shadow.map(|m| (&m.view, &m.sampler, &m.params)),
            },
        )
        .expect("the fog binds every texture its inject variant reads")
}
