//! The forward snippet in an engine's own lit shader: it composes with
//! `volfog::apply` / `volfog::bindings` in the engine's bind group scheme, validates,
//! and on the GPU gives the same fog as the fullscreen apply pass, from view-space
//! positions and from world positions (through the fog group's `FogView`).

use crate::common;

use common::{compose, gpu};
use glam::{Vec3, Vec4};
use naga_oil::compose::ShaderDefValue;
use volfog::options::Filtering;
use volfog::pipeline::apply::{ApplyPipeline, fog_layout_entries, fog_sampler};
use volfog_testkit::selfcheck::{ApplyCase, max_abs_diff};
use wgpu::util::DeviceExt;

/// A forward-lit shader as an engine would write it: its own view and material
/// groups, and the fog bind group at index 2.
const LIT_SHADER: &str = r#"
#import volfog::bindings
#import volfog::apply::{fog_coord_from_view, fog_coord_from_world, fog_view_position, fog_sample, fog_tail, fog_with_tail, apply_fog}

struct View {
    clip_from_view: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
}
struct Material {
    base_color: vec4<f32>,
    light_dir: vec4<f32>,
}
@group(0) @binding(0) var<uniform> view: View;
@group(1) @binding(0) var<uniform> material: Material;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world_pos: vec3<f32>,
}

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VertexOut {
    let view_pos = (view.view_from_world * vec4<f32>(position, 1.0)).xyz;
    var out: VertexOut;
    out.clip = view.clip_from_view * vec4<f32>(view_pos, 1.0);
    out.view_pos = view_pos;
    out.normal = (view.view_from_world * vec4<f32>(normal, 0.0)).xyz;
    out.world_pos = position;
    return out;
}

@fragment
fn fs(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let lit = material.base_color.rgb * (0.2 + 0.8 * max(dot(n, material.light_dir.xyz), 0.0));
#ifdef ENGINE_WITHOUT_FOG
    return vec4<f32>(lit, material.base_color.a);
#else
#ifdef ENGINE_WORLD_POSITIONS
    let view_from_world = bindings::fog_view.view_from_world;
    let coord = fog_coord_from_world(in.world_pos, view_from_world, bindings::fog_froxels);
    let view_pos = fog_view_position(in.world_pos, view_from_world);
#else
    let coord = fog_coord_from_view(in.view_pos, bindings::fog_froxels);
    let view_pos = in.view_pos;
#endif
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler, coord);
    let tail = fog_tail(bindings::fog_froxels, bindings::fog_far_tail, view_pos);
    return vec4<f32>(apply_fog(lit, fog_with_tail(fog, tail)), material.base_color.a);
#endif
}
"#;

/// How the lit shader fogs.
#[derive(Clone, Copy, PartialEq)]
enum Fog {
    None,
    FromView,
    FromWorld,
}

fn defs(fog: Fog) -> Vec<(&'static str, ShaderDefValue)> {
    let mut d = vec![("VOLFOG_FOG_GROUP", ShaderDefValue::UInt(2))];
    match fog {
        Fog::None => d.push(("ENGINE_WITHOUT_FOG", ShaderDefValue::Bool(true))),
        Fog::FromWorld => d.push(("ENGINE_WORLD_POSITIONS", ShaderDefValue::Bool(true))),
        Fog::FromView => {}
    }
    d
}

#[test]
fn lit_shader_composes_with_apply_and_validates() {
    let module = compose(LIT_SHADER, &defs(Fog::FromView));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("composed lit shader validates");
    let _ = info;
    let fog_globals: Vec<(u32, u32)> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.map(|b| (b.group, b.binding)))
        .filter(|(group, _)| *group == 2)
        .collect();
    assert_eq!(
        fog_globals.len(),
        4,
        "froxels, volume, sampler and tail land in group 2"
    );
}

#[test]
fn forward_snippet_agrees_with_fullscreen_pass() {
    let gpu = gpu();
    let device = &gpu.device;
    let (width, height) = (160u32, 90u32);
    let case = ApplyCase::synthetic(width, height);
    let froxels = case.froxels;

    // A floor-like quad receding from 0.3 m (in front of the fog's near plane) to
    // 300 m (beyond its far plane), given in view space and placed in the world by a
    // rigid camera transform.
    let corners = [
        Vec3::new(-0.4, -0.25, -0.3),
        Vec3::new(0.4, -0.25, -0.3),
        Vec3::new(-250.0, 40.0, -300.0),
        Vec3::new(250.0, 40.0, -300.0),
    ];
    let normal = (corners[1] - corners[0])
        .cross(corners[2] - corners[0])
        .normalize();
    let view_from_world = glam::Mat4::from_rotation_translation(
        glam::Quat::from_rotation_y(0.4) * glam::Quat::from_rotation_x(-0.1),
        Vec3::new(3.0, -1.5, 7.0),
    );
    let world_from_view = view_from_world.inverse();
    let vertices: Vec<f32> = [0, 1, 2, 2, 1, 3]
        .iter()
        .flat_map(|&i| {
            let world = world_from_view.transform_point3(corners[i]);
            let normal = world_from_view.transform_vector3(normal);
            [world.to_array(), normal.to_array()].concat()
        })
        .collect();
    let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("quad"),
        contents: bytemuck::cast_slice(&vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let view_uniform: Vec<f32> = [
        froxels.clip_from_view.to_cols_array(),
        view_from_world.to_cols_array(),
    ]
    .concat();
    let material: [f32; 8] = [0.7, 0.5, 0.3, 1.0, 0.0, 0.6, 0.8, 0.0];
    let uniform = |label, data: &[f32]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    };
    let view_buffer = uniform("view", &view_uniform);
    let material_buffer = uniform("material", &material);
    let froxel_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("froxels"),
        contents: &froxels.to_bytes(),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let volume = gpu.texture_3d_rgba16f("integrated", froxels.size.to_array(), &case.volume);
    let tail_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("tail"),
        contents: &volfog::uniforms::to_uniform_bytes(&case.tail),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let volume_view = volume.create_view(&Default::default());
    let fog_view_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fog view"),
        contents: &volfog::uniforms::to_uniform_bytes(&volfog::uniforms::FogView {
            view_from_world,
        }),
        usage: wgpu::BufferUsages::UNIFORM,
    });

    let uniform_layout = |vis| {
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: vis,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        })
    };
    let view_layout = uniform_layout(wgpu::ShaderStages::VERTEX);
    let material_layout = uniform_layout(wgpu::ShaderStages::FRAGMENT);
    let fog_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("fog"),
        entries: &fog_layout_entries(Filtering::Sampler, wgpu::ShaderStages::FRAGMENT),
    });
    let sampler = fog_sampler(device);
    let bind = |layout: &wgpu::BindGroupLayout, entries: &[wgpu::BindGroupEntry]| {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout,
            entries,
        })
    };
    let view_group = bind(
        &view_layout,
        &[wgpu::BindGroupEntry {
            binding: 0,
            resource: view_buffer.as_entire_binding(),
        }],
    );
    let material_group = bind(
        &material_layout,
        &[wgpu::BindGroupEntry {
            binding: 0,
            resource: material_buffer.as_entire_binding(),
        }],
    );
    let fog_group = bind(
        &fog_layout,
        &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: froxel_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&volume_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: tail_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: fog_view_buffer.as_entire_binding(),
            },
        ],
    );

    let format = wgpu::TextureFormat::Rgba16Float;
    let make_pipeline = |fog: Fog| {
        let module = gpu.shader_from_naga("lit", compose(LIT_SHADER, &defs(fog)));
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = if fog != Fog::None {
            vec![
                Some(&view_layout),
                Some(&material_layout),
                Some(&fog_layout),
            ]
        } else {
            vec![Some(&view_layout), Some(&material_layout)]
        };
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lit"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 24,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                })],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let extent = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let target = |format, label| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    // Background black; fog covers only the quad's pixels in both paths.
    let render = |fog: Fog| {
        let color = target(format, "colour");
        let depth = target(wgpu::TextureFormat::Depth32Float, "depth");
        let pipeline = make_pipeline(fog);
        let color_view = color.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
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
            pass.set_bind_group(0, &view_group, &[]);
            pass.set_bind_group(1, &material_group, &[]);
            if fog != Fog::None {
                pass.set_bind_group(2, &fog_group, &[]);
            }
            pass.set_vertex_buffer(0, vertex_buffer.slice(..));
            pass.draw(0..6, 0..1);
        }
        gpu.queue.submit([encoder.finish()]);
        (color, depth)
    };

    let (forward, _) = render(Fog::FromView);
    let (from_world, _) = render(Fog::FromWorld);
    let (plain, depth) = render(Fog::None);
    let unfogged_px = gpu.read_texture_rgba16f(&plain).unwrap();
    let apply = ApplyPipeline::new(device, &fog_layout, Filtering::Sampler, format).unwrap();
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let depth_group = apply.depth_bind_group(device, &depth_view);
    let plain_view = plain.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    apply.record(&mut encoder, &plain_view, &fog_group, &depth_group, None);
    gpu.queue.submit([encoder.finish()]);

    let forward_px = gpu.read_texture_rgba16f(&forward).unwrap();
    let world_px = gpu.read_texture_rgba16f(&from_world).unwrap();
    let world_vs_view = max_abs_diff(&world_px, &forward_px);
    eprintln!(
        "fog from world positions vs from view positions: max abs difference {world_vs_view:e} (bound 2e-3)"
    );
    assert!(world_vs_view <= 2e-3, "{world_vs_view}");
    let fullscreen_px = gpu.read_texture_rgba16f(&plain).unwrap();
    // Compare the quad's pixels (alpha 1 in the forward image).
    let covered: Vec<usize> = (0..forward_px.len())
        .filter(|&i| forward_px[i].w > 0.5)
        .collect();
    assert!(
        covered.len() > 2000,
        "the quad covers {} pixels",
        covered.len()
    );
    let f: Vec<Vec4> = covered.iter().map(|&i| forward_px[i]).collect();
    let s: Vec<Vec4> = covered.iter().map(|&i| fullscreen_px[i]).collect();
    let diff = max_abs_diff(&f, &s);
    let u: Vec<Vec4> = covered.iter().map(|&i| unfogged_px[i]).collect();
    let fog_effect = max_abs_diff(&f, &u);
    eprintln!(
        "forward vs fullscreen over {} pixels: max abs difference {diff:e} (bound 2e-3); fog changes pixels by up to {fog_effect}",
        covered.len()
    );
    assert!(fog_effect > 0.3, "the fog visibly changes the quad");
    assert!(
        diff <= 2e-3,
        "forward snippet and fullscreen pass differ by {diff}"
    );
}
