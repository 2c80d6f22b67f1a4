//! Fog over a multisampled scene (Wenzel 2007, "Scene depth based rendering and MSAA"):
//! a near triangle in front of a far wall, rendered with 4x MSAA.
//!
//! - The truth is per-sample fog: the forward shader fogs every sample and the resolve
//!   averages the fogged colours.
//! - The naive path fogs the resolved colour with the fog at the resolved (averaged)
//!   view depth: the standard apply pass over that depth.
//! - The seed's path writes `fog_layout` (view depth, fog amount) per sample into an
//!   rg16float target, resolves it, and runs `apply@APPLY_RESOLVED` over it.
//! - The non-MSAA reference is the same forward render with one sample per pixel.
//!
//! Measured: error against the truth on silhouette pixels, the outline (silhouette
//! pixels off the truth by more than 0.01, a visible line), and how far a pixel leaves
//! the range its 3x3 neighbourhood spans in the non-MSAA reference (a correct
//! anti-aliased edge is a blend of both sides, so it stays inside). The shore
//! fade of `volfog::water` is measured on the same resolved depth, with and without the
//! maximum over the direct neighbours.

use crate::common;

use common::{compose, gpu};
use glam::{Vec2, Vec3, Vec4};
use volfog::cpu;
use volfog::cpu::apply::Volume;
use volfog::options::{ApplyInput, FOG_LAYOUT_FORMAT, Filtering};
use volfog::pipeline::apply::{
    ApplyPipeline, FogResources, fog_bind_group, fog_layout_entries, fog_sampler,
};
use volfog_testkit::selfcheck::{ApplyCase, depth_texture, round_f16};
use wgpu::util::DeviceExt;

const W: u32 = 96;
const H: u32 = 54;
const SAMPLES: u32 = 4;
/// View depths (m) of the wall and of the water surface of the shore test.
const WALL: f32 = 90.0;
const SURFACE: f32 = 40.0;

const SHADER: &str = r#"
#import volfog::bindings
#import volfog::apply::{fog_coord_from_view, fog_sample, fog_tail, fog_with_tail, fog_layout, apply_fog}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view: vec3<f32>,
    @location(1) color: vec3<f32>,
}

@vertex
fn vs(@location(0) view: vec3<f32>, @location(1) color: vec3<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = bindings::fog_froxels.clip_from_view * vec4<f32>(view, 1.0);
    out.view = view;
    out.color = color;
    return out;
}

fn fog_at(view: vec3<f32>) -> vec4<f32> {
    let froxels = bindings::fog_froxels;
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler, fog_coord_from_view(view, froxels));
    return fog_with_tail(fog, fog_tail(froxels, bindings::fog_far_tail, view));
}

struct Layout {
    @location(0) color: vec4<f32>,
    @location(1) samples: vec2<f32>,
}

// The depth pre-pass of the MSAA path: the lit colour and each sample's fog layout.
@fragment
fn fs_layout(in: VertexOut) -> Layout {
    var out: Layout;
    out.color = vec4<f32>(in.color, 1.0);
    out.samples = fog_layout(fog_at(in.view), abs(in.view.z));
    return out;
}

// Forward fog per sample: the truth (with MSAA) and the non-MSAA reference.
@fragment
fn fs_forward(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(apply_fog(in.color, fog_at(in.view)), 1.0);
}
"#;

const SHORE_KERNEL: &str = r#"
#import volfog::water::{water_scene_depth, water_shore_fade}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<vec2<f32>>;
@group(0) @binding(2) var resolved: texture_2d<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(resolved);
    let i = id.x;
    if i >= size.x * size.y { return; }
    let pixel = vec2<i32>(i32(i % size.x), i32(i / size.x));
    let surface = input[0].x;
    let fade = input[0].y;
    let own = textureLoad(resolved, pixel, 0).r;
    output[i] = vec2<f32>(
        water_shore_fade(surface, own, fade),
        water_shore_fade(surface, water_scene_depth(resolved, pixel), fade),
    );
}
"#;

/// The scene in view space: (position, colour) per vertex, triangle list.
fn scene(near: Vec3, far: Vec3) -> Vec<[f32; 6]> {
    let v = |p: Vec3, c: Vec3| [p.x, p.y, p.z, c.x, c.y, c.z];
    let s = 2.0 * WALL;
    vec![
        v(Vec3::new(-s, -s, -WALL), far),
        v(Vec3::new(s, -s, -WALL), far),
        v(Vec3::new(s, s, -WALL), far),
        v(Vec3::new(-s, -s, -WALL), far),
        v(Vec3::new(s, s, -WALL), far),
        v(Vec3::new(-s, s, -WALL), far),
        // A tilted triangle 3-6 m away with edges at several slopes.
        v(Vec3::new(-1.3, -0.9, -3.0), near),
        v(Vec3::new(1.6, -0.4, -4.5), near),
        v(Vec3::new(-0.2, 1.3, -6.0), near),
    ]
}

struct Images {
    /// Resolved forward image with MSAA (per-sample fog): the truth.
    truth: Vec<Vec4>,
    /// Forward image with one sample per pixel.
    single: Vec<Vec4>,
    /// Resolved colour and resolved layout (view depth, amount) of the MSAA pre-pass.
    colour: Vec<Vec4>,
    layout: Vec<Vec2>,
    /// The single-sample layout (its view depths mark the silhouette).
    layout_single: Vec<Vec2>,
    /// The seed's path: apply@APPLY_RESOLVED over the resolved layout.
    resolved: Vec<Vec4>,
    /// The naive path: the standard apply at the resolved view depth.
    naive: Vec<Vec4>,
    /// The resolved layout texture, for the shore kernel.
    layout_texture: wgpu::Texture,
}

fn render(case: &ApplyCase, near: Vec3, far: Vec3) -> Images {
    let gpu = gpu();
    let device = &gpu.device;
    let buffer = |label: &str, bytes: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
    };
    let froxel_buffer = buffer(
        "froxels",
        &case.froxels.to_bytes(),
        wgpu::BufferUsages::UNIFORM,
    );
    let tail_buffer = buffer("tail", &case.tail.to_bytes(), wgpu::BufferUsages::UNIFORM);
    let view_buffer = buffer(
        "view",
        &volfog::uniforms::to_uniform_bytes(&volfog::uniforms::FogView::default()),
        wgpu::BufferUsages::UNIFORM,
    );
    let volume = gpu.texture_3d_rgba16f("integrated", case.froxels.size.to_array(), &case.volume);
    let volume_view = volume.create_view(&Default::default());
    let sampler = fog_sampler(device);
    let fog_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("fog"),
        entries: &fog_layout_entries(
            Filtering::Sampler,
            wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        ),
    });
    let fog_group = fog_bind_group(
        device,
        &fog_layout,
        Filtering::Sampler,
        &FogResources {
            froxels: &froxel_buffer,
            integrated: &volume_view,
            tail: &tail_buffer,
            view: &view_buffer,
            sampler: &sampler,
        },
    );
    let vertices = scene(near, far);
    let vertex_buffer = buffer(
        "scene",
        bytemuck::cast_slice(&vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let module = gpu.shader_from_naga("msaa scene", compose(SHADER, &[]));
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&fog_layout)],
        immediate_size: 0,
    });
    let colour_format = wgpu::TextureFormat::Rgba16Float;
    let target = |label: &str, format, samples: u32| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: W,
                height: H,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | if samples == 1 {
                    wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC
                } else {
                    wgpu::TextureUsages::empty()
                },
            view_formats: &[],
        })
    };
    // One draw of the scene: returns the resolved (or single-sample) colour and, for
    // the pre-pass, the layout.
    let draw = |entry: &str, samples: u32| -> (wgpu::Texture, Option<wgpu::Texture>) {
        let with_layout = entry == "fs_layout";
        let mut targets = vec![Some(wgpu::ColorTargetState::from(colour_format))];
        if with_layout {
            targets.push(Some(FOG_LAYOUT_FORMAT.into()));
        }
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(entry),
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
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        let colour = target("colour", colour_format, 1);
        let layout_out = target("layout", FOG_LAYOUT_FORMAT, 1);
        let colour_ms = target("colour ms", colour_format, samples);
        let layout_ms = target("layout ms", FOG_LAYOUT_FORMAT, samples);
        let depth = target("depth", wgpu::TextureFormat::Depth32Float, samples);
        let views = [&colour, &layout_out, &colour_ms, &layout_ms, &depth]
            .map(|t| t.create_view(&Default::default()));
        let attachment = |view, resolve| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut attachments = if samples == 1 {
            vec![attachment(&views[0], None)]
        } else {
            vec![attachment(&views[2], Some(&views[0]))]
        };
        if with_layout {
            attachments.push(if samples == 1 {
                attachment(&views[1], None)
            } else {
                attachment(&views[3], Some(&views[1]))
            });
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(entry),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &views[4],
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &fog_group, &[]);
            pass.set_vertex_buffer(0, vertex_buffer.slice(..));
            pass.draw(0..vertices.len() as u32, 0..1);
        }
        gpu.queue.submit([encoder.finish()]);
        (colour, with_layout.then_some(layout_out))
    };
    let read_rg = |t: &wgpu::Texture| -> Vec<Vec2> {
        let raw = gpu.read_texture_raw(t, 4).unwrap();
        let halfs: &[half::f16] = bytemuck::cast_slice(&raw);
        halfs
            .chunks_exact(2)
            .map(|c| Vec2::new(c[0].to_f32(), c[1].to_f32()))
            .collect()
    };
    let (truth, _) = draw("fs_forward", SAMPLES);
    let (single, _) = draw("fs_forward", 1);
    let (colour, layout_ms) = draw("fs_layout", SAMPLES);
    let (_, layout_1) = draw("fs_layout", 1);
    let layout_texture = layout_ms.expect("layout");
    let layout_values = read_rg(&layout_texture);
    let colour_values = gpu.read_texture_rgba16f(&colour).unwrap();

    // The seed's path over a copy of the resolved colour.
    let apply = |input: ApplyInput, group_view: &wgpu::TextureView| {
        // The scene's fog group (visible to both stages) serves the apply pass too.
        let pass = ApplyPipeline::with_input(
            device,
            &fog_layout,
            Filtering::Sampler,
            colour_format,
            input,
        )
        .unwrap();
        let group = &fog_group;
        let target = gpu.texture_2d_rgba16f("applied", [W, H], &colour_values);
        let second = pass.depth_bind_group(device, group_view);
        let mut encoder = device.create_command_encoder(&Default::default());
        pass.record(
            &mut encoder,
            &target.create_view(&Default::default()),
            group,
            &second,
            None,
        );
        gpu.queue.submit([encoder.finish()]);
        gpu.read_texture_rgba16f(&target).unwrap()
    };
    let resolved = apply(
        ApplyInput::ResolvedLayout,
        &layout_texture.create_view(&Default::default()),
    );
    // The naive path: the averaged view depth written back as a depth buffer.
    let proj = case.froxels.clip_from_view;
    let depths: Vec<f32> = layout_values
        .iter()
        .map(|l| {
            let clip = proj * Vec4::new(0.0, 0.0, -l.x.max(0.2), 1.0);
            clip.z / clip.w
        })
        .collect();
    let depth = depth_texture(gpu, W, H, &depths).unwrap();
    let naive = apply(
        ApplyInput::Depth,
        &depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        }),
    );
    Images {
        truth: gpu.read_texture_rgba16f(&truth).unwrap(),
        single: gpu.read_texture_rgba16f(&single).unwrap(),
        colour: colour_values,
        layout: layout_values,
        layout_single: read_rg(&layout_1.expect("layout")),
        resolved,
        naive,
        layout_texture,
    }
}

/// Pixels whose 3x3 neighbourhood in the single-sample render holds both objects.
fn silhouette(images: &Images) -> Vec<bool> {
    let at = |x: i32, y: i32| {
        let x = x.clamp(0, W as i32 - 1) as usize;
        let y = y.clamp(0, H as i32 - 1) as usize;
        images.layout_single[y * W as usize + x].x
    };
    (0..(W * H) as i32)
        .map(|i| {
            let (x, y) = (i % W as i32, i / W as i32);
            let mut near = false;
            let mut far = false;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let d = at(x + dx, y + dy);
                    near |= d < 20.0;
                    far |= d > 20.0;
                }
            }
            near && far
        })
        .collect()
}

/// How far `v` leaves the per-channel range of the single-sample render's 3x3
/// neighbourhood of pixel i.
fn outline(images: &Images, i: usize, v: Vec4) -> f32 {
    let (x, y) = ((i % W as usize) as i32, (i / W as usize) as i32);
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let xx = (x + dx).clamp(0, W as i32 - 1) as usize;
            let yy = (y + dy).clamp(0, H as i32 - 1) as usize;
            let s = images.single[yy * W as usize + xx].truncate();
            lo = lo.min(s);
            hi = hi.max(s);
        }
    }
    let c = v.truncate();
    (c - hi).max(lo - c).max(Vec3::ZERO).max_element()
}

struct Figures {
    max_naive: f32,
    max_resolved: f32,
    mean_naive: f32,
    mean_resolved: f32,
    outline_naive: f32,
    outline_resolved: f32,
    outlined_naive: usize,
    outlined_resolved: usize,
    edges: usize,
}

fn measure(images: &Images) -> Figures {
    let edge = silhouette(images);
    let mut f = Figures {
        max_naive: 0.0,
        max_resolved: 0.0,
        mean_naive: 0.0,
        mean_resolved: 0.0,
        outline_naive: 0.0,
        outline_resolved: 0.0,
        outlined_naive: 0,
        outlined_resolved: 0,
        edges: 0,
    };
    for (i, _) in edge.iter().enumerate().filter(|(_, e)| **e) {
        f.edges += 1;
        let t = images.truth[i];
        let en = (images.naive[i] - t).truncate().abs().max_element();
        let er = (images.resolved[i] - t).truncate().abs().max_element();
        f.max_naive = f.max_naive.max(en);
        f.max_resolved = f.max_resolved.max(er);
        f.mean_naive += en;
        f.mean_resolved += er;
        let on = outline(images, i, images.naive[i]);
        let or = outline(images, i, images.resolved[i]);
        f.outline_naive = f.outline_naive.max(on);
        f.outline_resolved = f.outline_resolved.max(or);
        f.outlined_naive += (en > 0.01) as usize;
        f.outlined_resolved += (er > 0.01) as usize;
    }
    f.mean_naive /= f.edges as f32;
    f.mean_resolved /= f.edges as f32;
    f
}

/// The seed's path against its CPU mirror on every pixel, and equal to the truth away
/// from silhouettes.
fn check_mirror(case: &ApplyCase, images: &Images) {
    let volume = Volume {
        size: case.froxels.size.to_array(),
        texels: case.volume.iter().map(|t| round_f16(*t)).collect(),
    };
    let edge = silhouette(images);
    let (mut worst_cpu, mut worst_interior) = (0.0f32, 0.0f32);
    for (i, on_edge) in edge.iter().enumerate() {
        let uv = Vec2::new(
            ((i % W as usize) as f32 + 0.5) / W as f32,
            ((i / W as usize) as f32 + 0.5) / H as f32,
        );
        let l = images.layout[i];
        let view = cpu::apply::fog_view_from_depth(uv, l.x, case.froxels.view_from_clip);
        let fog = cpu::apply::fog_with_tail(
            volume.fog(cpu::apply::fog_coord(uv, view.z.abs(), &case.froxels)),
            cpu::apply::fog_tail(&case.froxels, &case.tail, view),
        );
        let want = cpu::apply::apply_fog(
            images.colour[i].truncate(),
            cpu::apply::fog_resolved(fog, l.y),
        );
        let got = images.resolved[i].truncate();
        let e = (got - want).abs().max_element();
        worst_cpu = worst_cpu.max(e);
        assert!(e <= 4e-3, "pixel {i}: gpu {got} cpu {want}");
        if !on_edge {
            let e = (images.resolved[i] - images.truth[i])
                .truncate()
                .abs()
                .max_element();
            worst_interior = worst_interior.max(e);
            assert!(
                e <= 4e-3,
                "interior pixel {i}: {} vs truth {}",
                images.resolved[i],
                images.truth[i]
            );
        }
        assert!(images.resolved[i].is_finite());
    }
    eprintln!(
        "apply@APPLY_RESOLVED vs CPU mirror: worst {worst_cpu:e} (bound 4e-3, rgba16float \
         targets and sampler weights); away from silhouettes vs per-sample truth {worst_interior:e}"
    );
}

#[test]
fn msaa_fog_layout_removes_the_silhouette_outline() {
    let case = ApplyCase::synthetic(W, H);
    // Same lit colour on both sides (rock against rock): only the fog differs.
    let grey = render(&case, Vec3::splat(0.5), Vec3::splat(0.5));
    check_mirror(&case, &grey);
    let a = measure(&grey);
    // Different colours on both sides.
    let coloured = render(&case, Vec3::new(0.9, 0.2, 0.0), Vec3::new(0.0, 0.3, 0.9));
    check_mirror(&case, &coloured);
    let b = measure(&coloured);
    for (name, f) in [("same colour", &a), ("different colours", &b)] {
        eprintln!(
            "{name}: {} silhouette pixels; error vs per-sample fog max/mean naive {:.4}/{:.4} \
             ({} px > 0.01), resolved layout {:.4}/{:.4} ({} px > 0.01); beyond the non-MSAA \
             3x3 range: naive {:.4}, resolved layout {:.4}",
            f.edges,
            f.max_naive,
            f.mean_naive,
            f.outlined_naive,
            f.max_resolved,
            f.mean_resolved,
            f.outlined_resolved,
            f.outline_naive,
            f.outline_resolved,
        );
    }
    assert!(
        a.edges > 50,
        "the triangle crosses enough pixels: {}",
        a.edges
    );
    // Same colour: averaging the amount is exact up to rounding; the averaged depth
    // is not (the fog amount is concave in depth).
    assert!(a.max_resolved <= 4e-3, "{}", a.max_resolved);
    assert!(
        a.max_naive >= 10.0 * a.max_resolved.max(1e-3),
        "{}",
        a.max_naive
    );
    assert_eq!(a.outlined_resolved, 0);
    assert!(a.outlined_naive > 0);
    // Different colours: what remains is the covariance of colour and transmittance
    // over the samples, which no fog applied after the resolve can know; it is smaller
    // than the naive error, but it can leave the neighbourhood's range.
    assert!(
        b.mean_resolved < b.mean_naive,
        "{} vs {}",
        b.mean_resolved,
        b.mean_naive
    );
    assert!(
        b.max_resolved < b.max_naive,
        "{} vs {}",
        b.max_resolved,
        b.max_naive
    );
}

/// The shore fade on a resolved MSAA depth: a water surface 40 m away, in front of the
/// wall (50 m behind it) and behind the triangle. Every pixel where the surface is
/// visible should be fully opaque (the scene lies far behind it); the pixel's own
/// resolved depth averages in the triangle and fades silhouette pixels out, the
/// maximum over the direct neighbours does not.
#[test]
fn shore_fade_uses_the_deepest_neighbour_on_resolved_depth() {
    let case = ApplyCase::synthetic(W, H);
    let images = render(&case, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    let fade = 1.0;
    let input = [SURFACE, fade, 0.0, 0.0];
    let module = gpu().shader_from_naga("shore", compose(SHORE_KERNEL, &[]));
    let out = gpu()
        .run_kernel_with(
            &module,
            "main",
            bytemuck::cast_slice(&input),
            (W * H * 8) as u64,
            W * H,
            &[wgpu::BindingResource::TextureView(
                &images.layout_texture.create_view(&Default::default()),
            )],
        )
        .unwrap();
    let out: &[[f32; 2]] = bytemuck::cast_slice(&out);
    let depths: Vec<f32> = images.layout.iter().map(|l| l.x).collect();
    let (mut faded_own, mut faded_fixed, mut visible) = (0, 0, 0);
    for (i, o) in out.iter().enumerate() {
        let pixel = ((i % W as usize) as i32, (i / W as usize) as i32);
        let own = cpu::water::water_shore_fade(SURFACE, depths[i], fade);
        let fixed = cpu::water::water_shore_fade(
            SURFACE,
            cpu::water::water_scene_depth(&depths, W as usize, H as usize, pixel),
            fade,
        );
        assert!(
            (o[0] - own).abs() <= 1e-6 && (o[1] - fixed).abs() <= 1e-6,
            "pixel {i}: {o:?}"
        );
        // The surface is visible where any sample sees the wall (blue in the colour).
        if images.colour[i].z > 0.01 {
            visible += 1;
            faded_own += (o[0] < 0.999) as usize;
            faded_fixed += (o[1] < 0.999) as usize;
        }
    }
    eprintln!(
        "shore fade on resolved 4x MSAA depth: {visible} pixels see the surface; faded wrongly \
         with the pixel's own depth {faded_own}, with the neighbour maximum {faded_fixed}"
    );
    assert!(faded_own > 0, "the artifact appears without the fix");
    assert_eq!(faded_fixed, 0);
}
