//! Depth inputs of the checks: depth values written into Depth32Float textures (2D
//! or one layer per cascade) by a fullscreen draw.

use crate::gpu::{Gpu, GpuError};

/// Writes depth values into a Depth32Float texture (which cannot be a copy
/// destination) by drawing a fullscreen triangle that outputs `frag_depth`.
pub fn depth_texture(
    gpu: &Gpu,
    width: u32,
    height: u32,
    values: &[f32],
) -> Result<wgpu::Texture, GpuError> {
    depth_array_texture(gpu, width, height, &[values])
}

/// Writes one slice of depth values per layer into a Depth32Float 2D array texture
/// (one layer is a plain 2D texture).
pub fn depth_array_texture(
    gpu: &Gpu,
    width: u32,
    height: u32,
    layers: &[&[f32]],
) -> Result<wgpu::Texture, GpuError> {
    const WRITE_DEPTH: &str = r#"
#import volfog::fullscreen::fullscreen_position
@group(0) @binding(0) var values: texture_2d<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(i);
}
@fragment fn fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(values, vec2<i32>(p.xy), 0).r;
}
"#;
    let extent = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: layers.len() as u32,
    };
    let texture = |format, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let source = texture(
        wgpu::TextureFormat::R32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let depth = texture(
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let module = gpu.shader_from_naga("write depth", crate::kernel::compose(WRITE_DEPTH, &[]));
    let pipeline = gpu.checked(|| {
        gpu.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("write depth"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
    })?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for (layer, values) in layers.iter().enumerate() {
        let layer = layer as u32;
        write_f32_layer(gpu, &source, layer, values);
        let layer_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("write depth"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&layer_view(&source)),
            }],
        });
        let view = layer_view(&depth);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("write depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    Ok(depth)
}

/// Writes one layer of a 4-byte-per-texel 2D array texture (e.g. R32Float) with
/// `COPY_DST` usage from its texels in rows; takes effect at the next submit.
pub fn write_f32_layer(gpu: &Gpu, texture: &wgpu::Texture, layer: u32, values: &[f32]) {
    let (width, height) = (texture.width(), texture.height());
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(values),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * 4),
            rows_per_image: Some(height),
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
}
