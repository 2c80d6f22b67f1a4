//! The medium-shadow pass: the optical depth towards the sun of the medium beyond its
//! height profile, tabulated in a sun-aligned volume (`shaders/passes/medium_shadow.wgsl`)
//! that `inject@INJECT_MEDIUM_SHADOW` reads (see [`crate::cpu::medium_shadow`], its
//! CPU twin).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module_with,
    storage_buffer_entry, storage_entry, texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
use crate::options::InjectOptions;
use crate::shaders::{CodegenError, CustomModule};
use crate::uniforms::MediumShadowConfig;

/// Workgroup size of the pass: one workgroup per column of the volume, one invocation
/// per slice (64 slices at a time).
pub const WORKGROUP: [u32; 3] = [1, 1, 64];

/// Format of the medium-shadow volume: r the optical depth, g the excess extinction.
pub const MEDIUM_SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Resources of one medium-shadow dispatch (bindings numbered as inject's).
#[derive(Debug)]
pub struct MediumShadowResources<'a> {
    /// `FogFrame` uniform (binding 1).
    pub frame: &'a wgpu::Buffer,
    /// `FogMedium` uniform (binding 2).
    pub medium: &'a wgpu::Buffer,
    /// `array<LocalVolume>` storage buffer (binding 7).
    pub local_volumes: &'a wgpu::Buffer,
    /// Density texture and its linear, repeat sampler (bindings 9, 10; the
    /// density-texture variant).
    pub density_texture: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// The baked noise texture and its linear, repeat sampler (bindings 12, 13; the
    /// noise-texture variant).
    pub noise_texture: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// `FogCustomParams` uniform (binding 31; the custom-density variant).
    pub custom_params: Option<&'a wgpu::Buffer>,
    /// `array<FogParticle>` storage buffer (binding 34; the particle variant).
    pub particles: Option<&'a wgpu::Buffer>,
    /// The volume written (binding 35).
    pub volume: &'a wgpu::TextureView,
    /// `MediumShadow` uniform (binding 37).
    pub params: &'a wgpu::Buffer,
}

/// The compiled medium-shadow pass for the medium defines of an inject variant.
#[derive(Debug)]
pub struct MediumShadowPass {
    options: InjectOptions,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl MediumShadowPass {
    /// The defines of the variant that serves inject `options`: its medium's.
    pub fn defines(options: &InjectOptions) -> Vec<String> {
        const MEDIUM: [&str; 5] = [
            "VOLFOG_INJECT_NOISE_TEXTURE",
            "VOLFOG_INJECT_DENSITY_TEXTURE",
            "VOLFOG_INJECT_CUSTOM_DENSITY",
            "VOLFOG_INJECT_PARTICLES",
            "VOLFOG_INJECT_NOISE_OCTAVES=",
        ];
        options
            .defines()
            .into_iter()
            .filter(|d| {
                MEDIUM
                    .iter()
                    .any(|m| d == m || (m.ends_with('=') && d.starts_with(m)))
            })
            .collect()
    }

    /// The bind group layout of the variant serving inject `options`.
    pub fn layout_entries(options: &InjectOptions) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(1, c),
            uniform_entry(2, c),
            storage_buffer_entry(7, c, true),
            storage_entry(35, wgpu::TextureViewDimension::D3, MEDIUM_SHADOW_FORMAT),
            uniform_entry(37, c),
        ];
        if options.density_texture {
            entries.push(texture_entry(9, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(10, c, true));
        }
        if options.noise_texture {
            entries.push(texture_entry(12, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(13, c, true));
        }
        if options.custom_density {
            entries.push(uniform_entry(31, c));
        }
        if options.particles {
            entries.push(storage_buffer_entry(34, c, true));
        }
        entries
    }

    /// Compiles the variant serving inject `options`, with the user's density module
    /// where `options.custom_density` is set.
    pub fn new(
        device: &wgpu::Device,
        options: InjectOptions,
        custom_density: Option<&CustomModule>,
    ) -> Result<Self, CodegenError> {
        let custom = custom_density.filter(|_| options.custom_density);
        let module = shader_module_with(device, "medium_shadow", &Self::defines(&options), custom)?;
        let layout = bind_group_layout(
            device,
            "volfog medium_shadow",
            &Self::layout_entries(&options),
        );
        let pipeline = compute_pipeline(
            device,
            "volfog medium_shadow",
            &module,
            "medium_shadow_fill",
            &layout,
        );
        Ok(Self {
            options,
            layout,
            pipeline,
        })
    }

    /// A bind group for the resources (an error names a resource the variant needs
    /// and `r` lacks).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        r: &MediumShadowResources<'_>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        let missing = |field: &'static str| InvalidValue {
            field,
            value: "None".to_string(),
            expected: "the resource this variant reads".into(),
        };
        let mut resources = vec![
            (1, r.frame.as_entire_binding()),
            (2, r.medium.as_entire_binding()),
            (7, r.local_volumes.as_entire_binding()),
            (35, wgpu::BindingResource::TextureView(r.volume)),
            (37, r.params.as_entire_binding()),
        ];
        if self.options.density_texture {
            let (view, sampler) = r
                .density_texture
                .ok_or_else(|| missing("MediumShadowResources.density_texture"))?;
            resources.push((9, wgpu::BindingResource::TextureView(view)));
            resources.push((10, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.noise_texture {
            let (view, sampler) = r
                .noise_texture
                .ok_or_else(|| missing("MediumShadowResources.noise_texture"))?;
            resources.push((12, wgpu::BindingResource::TextureView(view)));
            resources.push((13, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.custom_density {
            let params = r
                .custom_params
                .ok_or_else(|| missing("MediumShadowResources.custom_params"))?;
            resources.push((31, params.as_entire_binding()));
        }
        if self.options.particles {
            let particles = r
                .particles
                .ok_or_else(|| missing("MediumShadowResources.particles"))?;
            resources.push((34, particles.as_entire_binding()));
        }
        Ok(bind_group(
            device,
            "volfog medium_shadow",
            &self.layout,
            &resources,
        ))
    }

    /// Records the fill of a volume of `size` texels (one workgroup per column).
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: [u32; 3],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(size[0], size[1], 1);
    }
}

/// Creates the medium-shadow volume for `config`: [`MEDIUM_SHADOW_FORMAT`], usage
/// `STORAGE_BINDING | TEXTURE_BINDING | COPY_SRC`.
pub fn create_volume(device: &wgpu::Device, config: &MediumShadowConfig) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("volfog medium shadow"),
        size: wgpu::Extent3d {
            width: config.size.x,
            height: config.size.y,
            depth_or_array_layers: config.size.z,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format: MEDIUM_SHADOW_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}
