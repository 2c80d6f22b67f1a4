//! The inject pass: density and in-scattered light per froxel
//! (`shaders/passes/inject.wgsl`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module_with,
    storage_buffer_entry, storage_entry, texture_entry, uint_texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
pub use crate::options::InjectOptions;
use crate::shaders::{CodegenError, CustomModule};

/// Workgroup size of the inject pass: one invocation per froxel of a block of
/// [`BLOCK`](super::cull::BLOCK) froxels.
pub const WORKGROUP: [u32; 3] = [4, 4, 8];
/// Workgroup size of the checkerboard variant: one invocation per pair of slices.
pub const WORKGROUP_CHECKERBOARD: [u32; 3] = [4, 4, 4];

/// Resources of one inject dispatch.
#[derive(Debug)]
pub struct InjectResources<'a> {
    /// `Froxels` uniform.
    pub froxels: &'a wgpu::Buffer,
    /// `FogFrame` uniform.
    pub frame: &'a wgpu::Buffer,
    /// `FogMedium` uniform.
    pub medium: &'a wgpu::Buffer,
    /// `FogLighting` uniform.
    pub lighting: &'a wgpu::Buffer,
    /// `ShadowCascades` uniform.
    pub cascades: &'a wgpu::Buffer,
    /// Filtered ESM array, or with the compare filter the sun's cascaded shadow map
    /// (a depth 2D array view).
    pub esm: &'a wgpu::TextureView,
    /// `array<FogLight>` storage buffer.
    pub lights: &'a wgpu::Buffer,
    /// `array<LocalVolume>` storage buffer.
    pub local_volumes: &'a wgpu::Buffer,
    /// Output scattering volume.
    pub scattering: &'a wgpu::TextureView,
    /// Density texture and its sampler (required by the density-texture variant,
    /// ignored by the others).
    pub density_texture: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// The live-slice texture and the live blocks of `froxel_cull` (required by the
    /// depth-culling variant).
    pub culling: Option<(&'a wgpu::TextureView, &'a wgpu::Buffer)>,
    /// The scene depth depth culling reads, or a 1 x 1 float texture while there is
    /// none (required by the variant with depth culling and the compare filter, binding
    /// 32: its shadow taps behind the scene's surface are left out).
    pub scene_depth: Option<&'a wgpu::TextureView>,
    /// The baked noise texture and its linear, repeat sampler (required by the
    /// noise-texture variant).
    pub noise_texture: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// The `CloudLayer` uniform, the cloud density map and its linear, repeat sampler
    /// (required by the cloud-shadow variant).
    pub cloud_shadow: Option<(&'a wgpu::Buffer, &'a wgpu::TextureView, &'a wgpu::Sampler)>,
    /// The local-light ESM atlas, the `LightProjection` buffer, the cookie array and
    /// its linear, clamp-to-edge sampler (required by the local-shadow variant).
    pub local_shadows: Option<LocalShadowResources<'a>>,
    /// The history and the states of the fused-temporal variant (required by it,
    /// ignored by the others); `scattering` is then the stabilised volume.
    pub temporal: Option<InjectTemporalResources<'a>>,
    /// The `ShadowTaps` uniform of the compare-filter variant (required by it, ignored
    /// by the others; the pass brings the maps' non-filtering sampler, binding 28).
    pub shadow_taps: Option<&'a wgpu::Buffer>,
    /// The `FogCustomParams` uniform of the custom-density variant (binding 31;
    /// required by it, ignored by the others).
    pub custom_params: Option<&'a wgpu::Buffer>,
    /// The `array<AreaLight>` storage buffer of the area-light variant (binding 33;
    /// required by it, ignored by the others; every element is read).
    pub area_lights: Option<&'a wgpu::Buffer>,
    /// The `array<FogParticle>` storage buffer of the particle variant (binding 34;
    /// required by it, ignored by the others; its first `FogMedium::particle_count`
    /// elements are read).
    pub particles: Option<&'a wgpu::Buffer>,
    /// The medium-shadow volume, its linear, clamp-to-edge sampler and the
    /// `MediumShadow` uniform of the medium-shadow variant (bindings 35 to 37; required
    /// by it, ignored by the others).
    pub medium_shadow: Option<(&'a wgpu::TextureView, &'a wgpu::Sampler, &'a wgpu::Buffer)>,
}

/// The resources of the fused-temporal variant of the inject pass (bindings 22 to 26;
/// the pass brings the history's linear, clamp-to-edge sampler, binding 23).
#[derive(Debug, Clone, Copy)]
pub struct InjectTemporalResources<'a> {
    /// The history volume (last frame's stabilised volume).
    pub history: &'a wgpu::TextureView,
    /// The history's `HistoryState` (80-byte storage buffer).
    pub history_state: &'a wgpu::Buffer,
    /// The stabilised volume's `HistoryState`, written by the dispatch.
    pub stabilised_state: &'a wgpu::Buffer,
    /// The live slices the history was written with (required with depth culling).
    pub history_live_slices: Option<&'a wgpu::TextureView>,
}

/// The resources of the local-shadow variant of the inject pass (bindings 18 to 21,
/// and 29 and 30 with the compare filter).
#[derive(Debug, Clone, Copy)]
pub struct LocalShadowResources<'a> {
    /// The local-light ESM atlas (R32Float 2D array; the ESM filter).
    pub atlas: &'a wgpu::TextureView,
    /// The spot lights' shadow maps (a depth 2D array view; the compare filter).
    pub spot_maps: &'a wgpu::TextureView,
    /// The point lights' cube maps, six layers a cube (a depth 2D array view; the
    /// compare filter).
    pub point_maps: &'a wgpu::TextureView,
    /// `array<LightProjection>` storage buffer (at least one element).
    pub projections: &'a wgpu::Buffer,
    /// The cookies (a filterable float 2D array).
    pub cookies: &'a wgpu::TextureView,
    /// Linear, clamp-to-edge sampler of the cookies.
    pub cookie_sampler: &'a wgpu::Sampler,
}

/// The compiled inject pass.
#[derive(Debug)]
pub struct InjectPass {
    options: InjectOptions,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    /// The history's sampler of the fused-temporal variant.
    history_sampler: Option<wgpu::Sampler>,
    /// The shadow maps' non-filtering sampler of the compare-filter variant.
    gather_sampler: Option<wgpu::Sampler>,
}

impl InjectPass {
    /// The options the pass was compiled for.
    pub fn options(&self) -> &InjectOptions {
        &self.options
    }

    /// The bind group layout of a variant (see the pass header for the bindings).
    pub fn layout_entries(options: &InjectOptions) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, c),
            uniform_entry(1, c),
            uniform_entry(2, c),
            uniform_entry(3, c),
            uniform_entry(4, c),
            texture_entry(5, c, wgpu::TextureViewDimension::D2Array, false),
            storage_buffer_entry(6, c, true),
            storage_buffer_entry(7, c, true),
            storage_entry(
                8,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
        ];
        if options.density_texture {
            entries.push(texture_entry(9, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(10, c, true));
        }
        if options.depth_cull {
            entries.push(uint_texture_entry(11));
            entries.push(storage_buffer_entry(14, c, true));
            if options.shadow_compare {
                entries.push(texture_entry(32, c, wgpu::TextureViewDimension::D2, false));
            }
        }
        if options.noise_texture {
            entries.push(texture_entry(12, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(13, c, true));
        }
        if options.cloud_shadow {
            entries.push(uniform_entry(15, c));
            entries.push(texture_entry(16, c, wgpu::TextureViewDimension::D2, true));
            entries.push(sampler_entry(17, c, true));
        }
        if options.shadow_compare {
            entries.push(uniform_entry(27, c));
            entries.push(sampler_entry(28, c, false));
        }
        if options.local_shadows {
            let maps: &[u32] = if options.shadow_compare {
                &[29, 30]
            } else {
                &[18]
            };
            for &binding in maps {
                entries.push(texture_entry(
                    binding,
                    c,
                    wgpu::TextureViewDimension::D2Array,
                    false,
                ));
            }
            entries.push(storage_buffer_entry(19, c, true));
            entries.push(texture_entry(
                20,
                c,
                wgpu::TextureViewDimension::D2Array,
                true,
            ));
            entries.push(sampler_entry(21, c, true));
        }
        if options.custom_density {
            entries.push(uniform_entry(31, c));
        }
        if options.area_lights {
            entries.push(storage_buffer_entry(33, c, true));
        }
        if options.particles {
            entries.push(storage_buffer_entry(34, c, true));
        }
        if options.medium_shadow {
            entries.push(texture_entry(35, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(36, c, true));
            entries.push(uniform_entry(37, c));
        }
        if options.temporal {
            entries.push(texture_entry(22, c, wgpu::TextureViewDimension::D3, true));
            entries.push(sampler_entry(23, c, true));
            entries.push(storage_buffer_entry(24, c, true));
            entries.push(storage_buffer_entry(25, c, false));
            if options.depth_cull {
                entries.push(uint_texture_entry(26));
            }
        }
        entries
    }

    /// Compiles the variant for `options` (without a custom density: see
    /// [`InjectPass::with_custom_density`]).
    pub fn new(device: &wgpu::Device, options: InjectOptions) -> Result<Self, CodegenError> {
        Self::with_custom_density(device, options, None)
    }

    /// Compiles the variant for `options` with the user's density module, which the
    /// custom-density variant (`options.custom_density`) needs and the others ignore.
    pub fn with_custom_density(
        device: &wgpu::Device,
        options: InjectOptions,
        custom_density: Option<&CustomModule>,
    ) -> Result<Self, CodegenError> {
        let custom = custom_density.filter(|_| options.custom_density);
        let module = shader_module_with(device, "inject", &options.defines(), custom)?;
        let layout = bind_group_layout(device, "volfog inject", &Self::layout_entries(&options));
        let pipeline = compute_pipeline(device, "volfog inject", &module, "inject", &layout);
        Ok(Self {
            options,
            layout,
            pipeline,
            history_sampler: options.temporal.then(|| super::apply::fog_sampler(device)),
            gather_sampler: options.shadow_compare.then(|| {
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("volfog inject shadow gather"),
                    ..Default::default()
                })
            }),
        })
    }

    /// A bind group for the resources.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        r: &InjectResources<'_>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        let mut resources = vec![
            (0, r.froxels.as_entire_binding()),
            (1, r.frame.as_entire_binding()),
            (2, r.medium.as_entire_binding()),
            (3, r.lighting.as_entire_binding()),
            (4, r.cascades.as_entire_binding()),
            (5, wgpu::BindingResource::TextureView(r.esm)),
            (6, r.lights.as_entire_binding()),
            (7, r.local_volumes.as_entire_binding()),
            (8, wgpu::BindingResource::TextureView(r.scattering)),
        ];
        let missing = |field: &'static str, what: &str| InvalidValue {
            field,
            value: "None".to_string(),
            expected: format!("{what} for this variant").into(),
        };
        if self.options.density_texture {
            let (view, sampler) = r.density_texture.ok_or_else(|| {
                missing("InjectResources.density_texture", "a texture and sampler")
            })?;
            resources.push((9, wgpu::BindingResource::TextureView(view)));
            resources.push((10, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.depth_cull {
            let (view, blocks) = r.culling.ok_or_else(|| {
                missing(
                    "InjectResources.culling",
                    "the live-slice texture and the live blocks",
                )
            })?;
            resources.push((11, wgpu::BindingResource::TextureView(view)));
            resources.push((14, blocks.as_entire_binding()));
            if self.options.shadow_compare {
                let depth = r.scene_depth.ok_or_else(|| {
                    missing(
                        "InjectResources.scene_depth",
                        "the scene depth (or a 1 x 1 texture)",
                    )
                })?;
                resources.push((32, wgpu::BindingResource::TextureView(depth)));
            }
        }
        if self.options.noise_texture {
            let (view, sampler) = r.noise_texture.ok_or_else(|| {
                missing(
                    "InjectResources.noise_texture",
                    "the baked noise texture and its sampler",
                )
            })?;
            resources.push((12, wgpu::BindingResource::TextureView(view)));
            resources.push((13, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.cloud_shadow {
            let (layer, map, sampler) = r.cloud_shadow.ok_or_else(|| {
                missing(
                    "InjectResources.cloud_shadow",
                    "the cloud layer, its map and its sampler",
                )
            })?;
            resources.push((15, layer.as_entire_binding()));
            resources.push((16, wgpu::BindingResource::TextureView(map)));
            resources.push((17, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.local_shadows {
            let l = r.local_shadows.ok_or_else(|| {
                missing(
                    "InjectResources.local_shadows",
                    "the atlas, the projections, the cookies and their sampler",
                )
            })?;
            if self.options.shadow_compare {
                resources.push((29, wgpu::BindingResource::TextureView(l.spot_maps)));
                resources.push((30, wgpu::BindingResource::TextureView(l.point_maps)));
            } else {
                resources.push((18, wgpu::BindingResource::TextureView(l.atlas)));
            }
            resources.push((19, l.projections.as_entire_binding()));
            resources.push((20, wgpu::BindingResource::TextureView(l.cookies)));
            resources.push((21, wgpu::BindingResource::Sampler(l.cookie_sampler)));
        }
        if let Some(sampler) = &self.gather_sampler {
            let taps = r
                .shadow_taps
                .ok_or_else(|| missing("InjectResources.shadow_taps", "the ShadowTaps uniform"))?;
            resources.push((27, taps.as_entire_binding()));
            resources.push((28, wgpu::BindingResource::Sampler(sampler)));
        }
        if self.options.custom_density {
            let params = r.custom_params.ok_or_else(|| {
                missing(
                    "InjectResources.custom_params",
                    "the FogCustomParams uniform",
                )
            })?;
            resources.push((31, params.as_entire_binding()));
        }
        if self.options.area_lights {
            let lights = r
                .area_lights
                .ok_or_else(|| missing("InjectResources.area_lights", "the AreaLight buffer"))?;
            resources.push((33, lights.as_entire_binding()));
        }
        if self.options.particles {
            let particles = r
                .particles
                .ok_or_else(|| missing("InjectResources.particles", "the FogParticle buffer"))?;
            resources.push((34, particles.as_entire_binding()));
        }
        if self.options.medium_shadow {
            let (volume, sampler, params) = r.medium_shadow.ok_or_else(|| {
                missing(
                    "InjectResources.medium_shadow",
                    "the medium-shadow volume, its sampler and the MediumShadow uniform",
                )
            })?;
            resources.push((35, wgpu::BindingResource::TextureView(volume)));
            resources.push((36, wgpu::BindingResource::Sampler(sampler)));
            resources.push((37, params.as_entire_binding()));
        }
        if let Some(sampler) = &self.history_sampler {
            let t = r.temporal.ok_or_else(|| {
                missing(
                    "InjectResources.temporal",
                    "the history, its state and the stabilised volume's state",
                )
            })?;
            resources.push((22, wgpu::BindingResource::TextureView(t.history)));
            resources.push((23, wgpu::BindingResource::Sampler(sampler)));
            resources.push((24, t.history_state.as_entire_binding()));
            resources.push((25, t.stabilised_state.as_entire_binding()));
            if self.options.depth_cull {
                let live = t.history_live_slices.ok_or_else(|| {
                    missing(
                        "InjectTemporalResources.history_live_slices",
                        "the live slices the history was written with",
                    )
                })?;
                resources.push((26, wgpu::BindingResource::TextureView(live)));
            }
        }
        Ok(bind_group(
            device,
            "volfog inject",
            &self.layout,
            &resources,
        ))
    }

    /// Records the injection into a volume of `size` froxels: one workgroup per block
    /// of [`BLOCK`](super::cull::BLOCK) froxels, or, for the depth-culling variant,
    /// `indirect` (the dispatch arguments `froxel_cull` wrote, one workgroup per live
    /// block).
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        size: [u32; 3],
        indirect: Option<&wgpu::Buffer>,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        match indirect {
            Some(args) => pass.dispatch_workgroups_indirect(args, 0),
            None => {
                let [x, y, z] = super::cull::block_grid(size);
                pass.dispatch_workgroups(x, y, z);
            }
        }
    }
}
