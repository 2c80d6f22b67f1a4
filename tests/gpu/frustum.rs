//! World positions from depth the seed's cheap way (`volfog::frustum`: corner rays
//! interpolated by the rasterizer, one multiply-add per pixel) against the
//! inverse-projection path (`volfog::froxel::view_from_ndc`, then the camera's
//! transform), rendered on the GPU for standard, reversed and infinite projections,
//! and against the CPU mirror.

use crate::common;

use common::{Rng, compose, gpu};
use glam::{Mat4, Vec2, Vec4};
use volfog::cpu::frustum::{frustum_ray, frustum_view_depth, frustum_world_position};
use volfog::uniforms::FrustumRays;
use volfog_testkit::selfcheck::depth_texture;
use wgpu::util::DeviceExt;

const SHADER: &str = r#"
#import volfog::types::FrustumRays
#import volfog::frustum::{frustum_vertex, frustum_view_depth, frustum_world_position}
#import volfog::froxel::{ndc_from_uv, view_from_ndc}

struct Camera { rays: FrustumRays, world_from_view: mat4x4<f32>, view_from_clip: mat4x4<f32> }
@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var depth_buffer: texture_2d<f32>;

struct Out { @builtin(position) clip: vec4<f32>, @location(0) ray: vec3<f32> }

@vertex
fn vs(@builtin(vertex_index) index: u32) -> Out {
    let v = frustum_vertex(camera.rays, index);
    return Out(v.clip, v.ray);
}

@fragment
fn fs_rays(in: Out) -> @location(0) vec4<f32> {
    let d = textureLoad(depth_buffer, vec2<i32>(in.clip.xy), 0).r;
    return vec4<f32>(frustum_world_position(camera.rays, in.ray, frustum_view_depth(camera.rays, d)), 1.0);
}

@fragment
fn fs_inverse(in: Out) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(depth_buffer));
    let d = textureLoad(depth_buffer, vec2<i32>(in.clip.xy), 0).r;
    let view = view_from_ndc(vec3<f32>(ndc_from_uv(in.clip.xy / size), d), camera.view_from_clip);
    return vec4<f32>((camera.world_from_view * vec4<f32>(view, 1.0)).xyz, 1.0);
}
"#;

const W: u32 = 64;
const H: u32 = 36;

fn render(world_from_view: Mat4, proj: Mat4, depths: &[f32]) -> [Vec<Vec4>; 2] {
    let gpu = gpu();
    let device = &gpu.device;
    let rays = FrustumRays::new(world_from_view, proj).unwrap();
    let mut bytes = rays.to_bytes();
    bytes.extend_from_slice(bytemuck::cast_slice(&world_from_view.to_cols_array()));
    bytes.extend_from_slice(bytemuck::cast_slice(&proj.inverse().to_cols_array()));
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("camera"),
        contents: &bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let depth = depth_texture(gpu, W, H, depths).unwrap();
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let module = gpu.shader_from_naga("frustum", compose(SHADER, &[]));
    ["fs_rays", "fs_inverse"].map(|entry| {
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(entry),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::TextureFormat::Rgba32Float.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&depth_view),
                },
            ],
        });
        let target = volfog_testkit::gpu::texture_2d(
            device,
            "positions",
            (W, H),
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let view = target.create_view(&Default::default());
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.queue.submit([encoder.finish()]);
        let raw = gpu.read_texture_raw(&target, 16).unwrap();
        bytemuck::cast_slice::<u8, f32>(&raw)
            .chunks_exact(4)
            .map(Vec4::from_slice)
            .collect()
    })
}

#[test]
fn corner_rays_equal_the_inverse_projection() {
    let mut rng = Rng(31);
    let aspect = W as f32 / H as f32;
    let near = 0.1;
    let projections = [
        (
            "standard",
            glam::camera::rh::proj::directx::perspective(1.0, aspect, near, 500.0),
        ),
        (
            "reversed",
            glam::camera::rh::proj::directx::perspective(1.0, aspect, 500.0, near),
        ),
        (
            "infinite reversed",
            glam::camera::rh::proj::directx::perspective_infinite_reverse(1.0, aspect, near),
        ),
    ];
    for (name, proj) in projections {
        let world_from_view = Mat4::from_rotation_translation(rng.quat(), rng.vec(100.0));
        let rays = FrustumRays::new(world_from_view, proj).unwrap();
        // View depths from 0.2 m to 400 m, one per pixel.
        let view_depths: Vec<f32> = (0..W * H).map(|_| rng.log(0.2, 400.0)).collect();
        let depths: Vec<f32> = view_depths
            .iter()
            .map(|z| {
                let c = proj * Vec4::new(0.0, 0.0, -z, 1.0);
                c.z / c.w
            })
            .collect();
        let [by_rays, by_inverse] = render(world_from_view, proj, &depths);
        let (mut worst, mut worst_cpu) = (0.0f32, 0.0f32);
        for i in 0..(W * H) as usize {
            let uv = Vec2::new(
                ((i as u32 % W) as f32 + 0.5) / W as f32,
                ((i as u32 / W) as f32 + 0.5) / H as f32,
            );
            let a = by_rays[i].truncate();
            let b = by_inverse[i].truncate();
            // Relative to the view depth, or to the coordinates' magnitude where f32
            // rounding of the world position (camera up to 170 m out) dominates.
            let distance = view_depths[i].max(a.abs().max_element());
            let e = a.distance(b) / distance;
            worst = worst.max(e);
            assert!(e <= 2e-6, "{name} pixel {i}: rays {a} inverse {b}");
            let cpu = frustum_world_position(
                &rays,
                frustum_ray(&rays, uv),
                frustum_view_depth(&rays, depths[i]),
            );
            let e = cpu.distance(a) / distance;
            worst_cpu = worst_cpu.max(e);
            assert!(e <= 2e-6, "{name} pixel {i}: gpu {a} cpu {cpu}");
        }
        eprintln!(
            "{name}: corner rays vs inverse projection worst {worst:.1e} of the distance, \
             vs the CPU mirror {worst_cpu:.1e} (bounds 2e-6)"
        );
    }
}
