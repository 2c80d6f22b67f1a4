//! The fullscreen apply pass (`shaders/passes/apply.wgsl`) and the bind group layout
//! of `volfog::bindings`, which forward shaders that apply fog share.

use super::{prebuilt_wgsl, texture_entry, uniform_entry};

/// How the integrated volume is filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filtering {
    /// A linear, clamp-to-edge sampler (binding 2).
    Sampler,
    /// Eight texel loads filtered in the shader; no sampler binding
    /// (`VOLFOG_BINDINGS_NO_SAMPLER`).
    Manual,
}

/// The layout entries of `volfog::bindings`: 0 `Froxels` uniform, 1 integrated
/// volume (3D, filterable float), 2 linear sampler (absent with manual filtering),
/// 3 `HeightFog` uniform (the analytic tail beyond the far plane, in view space).
pub fn fog_layout_entries(
    filtering: Filtering,
    visibility: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut entries = vec![
        uniform_entry(0, visibility),
        texture_entry(1, visibility, wgpu::TextureViewDimension::D3, true),
    ];
    if filtering == Filtering::Sampler {
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        });
    }
    entries.push(uniform_entry(3, visibility));
    entries
}

/// The sampler `volfog::bindings` expects: linear filtering, clamp to edge.
pub fn fog_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog integrated volume"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    })
}

/// The blend state that turns the pass output (L, T) into `dst * T + L`.
pub const FOG_BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::SrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The compiled fullscreen apply pass.
#[derive(Debug)]
pub struct ApplyPass {
    filtering: Filtering,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
}

impl ApplyPass {
    /// The prebuilt variant for a filtering mode.
    pub fn variant(filtering: Filtering) -> &'static str {
        match filtering {
            Filtering::Sampler => "apply@default",
            Filtering::Manual => "apply@BINDINGS_NO_SAMPLER",
        }
    }

    /// Layout: the `volfog::bindings` entries plus 4, the scene depth (2D,
    /// unfilterable float view of a depth texture).
    pub fn layout_entries(filtering: Filtering) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT);
        entries.push(texture_entry(
            4,
            wgpu::ShaderStages::FRAGMENT,
            wgpu::TextureViewDimension::D2,
            false,
        ));
        entries
    }

    /// Compiles the pass for a colour target format.
    pub fn new(
        device: &wgpu::Device,
        filtering: Filtering,
        color_format: wgpu::TextureFormat,
    ) -> Self {
        let variant = Self::variant(filtering);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volfog apply"),
            entries: &Self::layout_entries(filtering),
        });
        let vs = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("volfog apply_vs"),
            source: wgpu::ShaderSource::Wgsl(prebuilt_wgsl(variant, "apply_vs").into()),
        });
        let fs = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("volfog apply_fs"),
            source: wgpu::ShaderSource::Wgsl(prebuilt_wgsl(variant, "apply_fs").into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("volfog apply"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("volfog apply"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &vs,
                entry_point: Some("apply_vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &fs,
                entry_point: Some("apply_fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: color_format,
                    blend: Some(FOG_BLEND),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self {
            filtering,
            layout,
            pipeline,
            sampler: fog_sampler(device),
        }
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group: froxels uniform, integrated volume view, the view-space
    /// `HeightFog` tail uniform and the scene depth view (a depth-aspect view of the
    /// depth texture).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        integrated: &wgpu::TextureView,
        tail: &wgpu::Buffer,
        depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: froxels.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(integrated),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: tail.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(depth),
            },
        ];
        if self.filtering == Filtering::Sampler {
            entries.push(wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            });
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("volfog apply"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Records the fullscreen draw into a render pass whose colour attachment is the
    /// lit scene (loaded, not cleared).
    pub fn encode(&self, pass: &mut wgpu::RenderPass<'_>, bind_group: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Records a render pass that loads the lit colour target `color` and blends the
    /// fog onto it (the fullscreen draw of [`ApplyPass::encode`]).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        bind_group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("volfog apply"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.encode(&mut pass, bind_group);
    }
}
