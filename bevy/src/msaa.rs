//! Multisampled cameras: the fog reads one depth per pixel, so a camera rendering with
//! MSAA (Bevy's default, `Msaa::Sample4`) has its multisampled depth resolved to the
//! farthest of each pixel's samples before the fog runs. The farthest sample is the
//! depth that culls no froxel any sample can see; the apply pass then fogs every
//! sample of the multisampled colour target with the pixel's fog before Bevy resolves
//! it, so the fog survives the passes that follow (Bevy's transparent pass renders
//! into the same multisampled target). Away from silhouettes every sample of a pixel
//! lies at the same depth and the image is the one without MSAA; on a silhouette's
//! pixels the nearer samples take the fog of the farther ones.

/// The resolved depth's format (what volfog's culling and apply read).
const RESOLVED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Bevy's depth is reversed (1 at the near plane, 0 infinitely far): the farthest
/// sample is the smallest value.
const SHADER: &str = r#"
@group(0) @binding(0) var scene_depth: texture_depth_multisampled_2d;

@vertex
fn resolve_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn resolve_fs(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    let pixel = vec2<i32>(frag.xy);
    var farthest = 1.0;
    for (var s = 0u; s < textureNumSamples(scene_depth); s++) {
        farthest = min(farthest, textureLoad(scene_depth, pixel, i32(s)));
    }
    return farthest;
}
"#;

/// The resolve of one multisampled depth texture into a single-sampled one.
pub struct DepthResolve {
    /// The multisampled depth it reads.
    source: wgpu::Texture,
    /// The farthest sample per pixel.
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    group: wgpu::BindGroup,
    pipeline: wgpu::RenderPipeline,
}

impl DepthResolve {
    /// The resolve of `source` (Bevy's multisampled depth, with `TEXTURE_BINDING`).
    pub fn new(device: &wgpu::Device, source: &wgpu::Texture) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("volfog depth resolve"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: true,
                },
                count: None,
            }],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("volfog depth resolve"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("volfog depth resolve"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("volfog depth resolve"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("resolve_vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: RESOLVED_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("resolve_fs"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        let source_view = source.create_view(&wgpu::TextureViewDescriptor {
            label: Some("volfog multisampled depth"),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("volfog depth resolve"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&source_view),
            }],
        });
        let resolved = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("volfog resolved depth"),
            size: source.size(),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: RESOLVED_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let resolved_view = resolved.create_view(&Default::default());
        Self {
            source: source.clone(),
            resolved,
            resolved_view,
            group,
            pipeline,
        }
    }

    /// The multisampled depth it resolves.
    pub fn source(&self) -> &wgpu::Texture {
        &self.source
    }

    /// The single-sampled depth it writes (the fog's scene depth).
    pub fn resolved(&self) -> &wgpu::Texture {
        &self.resolved
    }

    /// Records the resolve.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("volfog depth resolve"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.resolved_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}
