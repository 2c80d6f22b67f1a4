//! The apply pass on the GPU against the CPU (`color * T + L` of the filtered
//! integrated volume), in both filtering modes.

use crate::common;

use common::gpu;
use volfog::options::Filtering;
use volfog_testkit::selfcheck::{ApplyCase, max_abs_diff, run_apply};

#[test]
fn fullscreen_apply_matches_cpu() {
    let gpu = gpu();
    let case = ApplyCase::synthetic(160, 90);
    let expected = case.expected();
    for filtering in [Filtering::Sampler, Filtering::Manual] {
        let got = run_apply(gpu, filtering, &case).unwrap();
        let diff = max_abs_diff(&got, &expected);
        eprintln!("{filtering:?}: max abs difference vs CPU {diff:e} (bound 2e-3)");
        // fp16 output (2^-11 relative) plus the sampler's fixed-point filter weights.
        assert!(diff <= 2e-3, "{filtering:?}: {diff}");
    }
}

/// `VolumetricFog`'s apply in the caller's own render pass (after a draw of its own)
/// and for several colour formats gives what the pass it records by itself gives.
#[test]
fn apply_draws_into_the_callers_pass_for_several_formats() {
    use glam::Vec4;

    let gpu = gpu();
    let (w, h) = (48, 27);
    let (fog, _depth, depth_view) = encoded_fog(gpu, w, h);
    let base = Vec4::new(0.6, 0.3, 0.1, 1.0);
    // The reference: the pass the fog records itself, onto rgba16float.
    let apply16 = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let reference = gpu.texture_2d_rgba16f("reference", [w, h], &vec![base; (w * h) as usize]);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.record_apply(
        &mut encoder,
        &apply16,
        &reference.create_view(&Default::default()),
        &apply16.depth_bind_group(&gpu.device, &depth_view),
    )
    .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let reference = gpu.read_texture_rgba16f(&reference).unwrap();
    assert!(
        reference
            .iter()
            .any(|p| (*p - base).abs().max_element() > 0.05),
        "fog is visible"
    );

    for (format, bytes, tolerance) in [
        (wgpu::TextureFormat::Rgba16Float, 8, 1e-3),
        // unorm8: the cleared colour and the result are each quantised (1/255).
        (wgpu::TextureFormat::Rgba8Unorm, 4, 2.0 / 255.0),
    ] {
        let apply = fog.create_apply(&gpu.device, format).unwrap();
        let depth_group = apply.depth_bind_group(&gpu.device, &depth_view);
        let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("caller target"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = target.create_view(&Default::default());
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            // The caller's pass: cleared to the lit colour, then the fog drawn in it.
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("caller"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: base.x as f64,
                            g: base.y as f64,
                            b: base.z as f64,
                            a: base.w as f64,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            fog.draw_apply(&mut pass, &apply, &depth_group).unwrap();
        }
        gpu.queue.submit([encoder.finish()]);
        let got: Vec<Vec4> = if bytes == 8 {
            gpu.read_texture_rgba16f(&target).unwrap()
        } else {
            gpu.read_texture_raw(&target, 4)
                .unwrap()
                .chunks_exact(4)
                .map(|c| Vec4::new(c[0] as f32, c[1] as f32, c[2] as f32, c[3] as f32) / 255.0)
                .collect()
        };
        let diff = max_abs_diff(&got, &reference);
        eprintln!(
            "apply in the caller's pass onto {format:?}: max abs difference {diff:e} (bound {tolerance:e})"
        );
        assert!(diff <= tolerance, "{format:?}: {diff}");
    }
}

/// Fog coordinates from world positions (the path of shaders that hold world
/// positions) on the GPU against the CPU mirror, for random cameras and points.
#[test]
fn fog_coordinates_from_world_match_cpu() {
    use glam::{Vec3, Vec4};
    use volfog::cpu::apply::fog_coord_from_world;
    use volfog::uniforms::Froxels;
    const KERNEL: &str = r#"
#import volfog::types::Froxels
#import volfog::apply::fog_coord_from_world

struct Case { froxels: Froxels, view_from_world: mat4x4<f32>, world: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&input) { return; }
    let c = input[id.x];
    output[id.x] = fog_coord_from_world(c.world.xyz, c.view_from_world, c.froxels);
}
"#;
    let gpu = gpu();
    let mut rng = common::Rng(7);
    let mut bytes = Vec::new();
    let mut want = Vec::new();
    let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.6, 0.1, 500.0);
    let froxels =
        Froxels::new(projection, glam::UVec3::new(160, 90, 128), 0.5, 128.0, 4.0).unwrap();
    let count = 256;
    for _ in 0..count {
        let eye = rng.vec(50.0);
        let view = glam::camera::rh::view::look_to_mat4(eye, rng.unit(), Vec3::Y);
        // Points in front of the camera, from the near plane to beyond the far plane.
        let dir = view.inverse().transform_vector3(
            Vec3::new(rng.range(-0.5, 0.5), rng.range(-0.3, 0.3), -1.0).normalize(),
        );
        let world = eye + dir * rng.log(0.3, 300.0);
        bytes.extend(volfog::uniforms::to_uniform_bytes(&froxels));
        bytes.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&view.to_cols_array()));
        bytes.extend_from_slice(bytemuck::cast_slice::<f32, u8>(
            &world.extend(1.0).to_array(),
        ));
        want.push(fog_coord_from_world(world, view, &froxels));
    }
    let module = gpu.shader_from_naga("world coords", common::compose(KERNEL, &[]));
    let out = gpu
        .run_kernel(&module, "main", &bytes, (count * 16) as u64, count as u32)
        .unwrap();
    let got: &[Vec4] = bytemuck::cast_slice(&out);
    let worst = got
        .iter()
        .zip(&want)
        .map(|(g, w)| (*g - *w).abs().max_element())
        .fold(0.0f32, f32::max);
    // f32 rounding of positions up to ~350 m from the origin moves a coordinate by
    // ~1e-5: bound 5e-5, under 1 % of a froxel across 160 froxels.
    eprintln!(
        "fog_coord_from_world: {count} random cameras and points, max abs difference vs CPU {worst:e} (bound 5e-5)"
    );
    assert!(worst <= 5e-5, "{worst}");
}

/// View depths and fog coordinates from depth-buffer values (the apply pass's path:
/// `volfog::froxel::view_from_ndc`, `volfog::apply::fog_coord_from_ndc`) on the GPU
/// against the CPU mirror, and the depths against the inverse projection taken
/// in f64, for a standard, a reversed and an infinite reversed projection with
/// off-centre (jittered) offsets, and depths from the near plane to infinity.
#[test]
fn view_depths_from_the_depth_buffer_match_cpu_and_the_inverse_projection() {
    use glam::{DVec4, Mat4, Vec3, Vec4};
    use volfog::cpu::apply::fog_coord_from_ndc;
    use volfog::cpu::froxel::view_from_ndc;
    use volfog::uniforms::Froxels;
    const KERNEL: &str = r#"
#import volfog::types::Froxels
#import volfog::froxel::view_from_ndc
#import volfog::apply::fog_coord_from_ndc

struct Case { froxels: Froxels, ndc: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&input) { return; }
    let c = input[id.x];
    output[2u * id.x] = vec4<f32>(view_from_ndc(c.ndc.xyz, c.froxels.view_from_clip), 0.0);
    output[2u * id.x + 1u] = fog_coord_from_ndc(c.ndc.xyz, c.froxels);
}
"#;
    use glam::camera::rh::proj::directx as proj;
    let gpu = gpu();
    let mut rng = common::Rng(11);
    let jitter = |mut m: Mat4, x: f32, y: f32| {
        m.z_axis.x = x;
        m.z_axis.y = y;
        m
    };
    // A reversed finite projection swaps near and far.
    let projections = [
        ("standard", proj::perspective(1.0, 1.6, 0.1, 500.0), false),
        (
            "reversed",
            jitter(proj::perspective(0.9, 1.78, 800.0, 0.2), 0.004, -0.003),
            true,
        ),
        (
            "infinite reversed",
            jitter(
                proj::perspective_infinite_reverse(1.2, 1.0, 0.05),
                -0.002,
                0.001,
            ),
            true,
        ),
    ];
    let (mut bytes, mut cases) = (Vec::new(), Vec::new());
    for (name, projection, reversed) in projections {
        let froxels =
            Froxels::new(projection, glam::UVec3::new(160, 90, 128), 0.5, 128.0, 4.0).unwrap();
        for i in 0..128 {
            // Depth-buffer values of view depths from 0.25 m to 1000 m, and the far
            // end of the buffer (infinity for the infinite projection).
            let target = if i == 0 {
                f32::INFINITY
            } else {
                rng.log(0.25, 1000.0)
            };
            let clip = projection * Vec4::new(0.0, 0.0, -target.min(1e30), 1.0);
            let far_value = if reversed { 0.0 } else { 1.0 };
            let d = if i == 0 {
                far_value
            } else {
                (clip.z / clip.w).clamp(0.0, 1.0)
            };
            let ndc = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), d);
            bytes.extend(volfog::uniforms::to_uniform_bytes(&froxels));
            bytes.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&ndc.extend(1.0).to_array()));
            cases.push((name, projection, froxels, ndc));
        }
    }
    let count = cases.len();
    let module = gpu.shader_from_naga("ndc depths", common::compose(KERNEL, &[]));
    let out = gpu
        .run_kernel(&module, "main", &bytes, (count * 32) as u64, count as u32)
        .unwrap();
    let got: &[Vec4] = bytemuck::cast_slice(&out);
    let (mut worst_cpu, mut worst_coord, mut worst_f64) = (0.0f32, 0.0f32, 0.0f64);
    for (i, (name, projection, froxels, ndc)) in cases.iter().enumerate() {
        let depth = got[2 * i].z.abs();
        let want = view_from_ndc(*ndc, froxels.view_from_clip).z.abs();
        let coord = fog_coord_from_ndc(*ndc, froxels);
        assert!(
            depth.is_finite() && depth >= 0.0,
            "{name}: {depth} at {ndc}"
        );
        worst_coord = worst_coord.max((got[2 * i + 1] - coord).abs().max_element());
        let relative = |a: f64, b: f64| (a - b).abs() / b.max(1e-30);
        worst_cpu = worst_cpu.max(relative(depth as f64, want as f64) as f32);
        // The inverse projection in f64.
        let p = projection.as_dmat4().inverse()
            * DVec4::new(ndc.x as f64, ndc.y as f64, ndc.z as f64, 1.0);
        if p.w.abs() < 1e-12 {
            // The far end of the infinite projection (w is 0 in f32, about 1e-17 in
            // f64): a depth beyond any scene.
            assert!(depth >= 1e12, "{name}: {depth} at infinity");
            continue;
        }
        worst_f64 = worst_f64.max(relative(depth as f64, (p.z / p.w).abs()));
    }
    // The CPU mirror evaluates the same f32 expressions: 1e-6 relative. Against f64,
    // f32 rounding of the inverse projection near the far end of a standard depth
    // buffer (where a depth value step is metres) loses digits: 1e-3 relative.
    eprintln!(
        "view_from_ndc: {count} depth values, 3 projections: vs CPU {worst_cpu:e} relative (bound 1e-6), vs f64 inverse projection {worst_f64:e} (bound 1e-3); fog_coord_from_ndc vs CPU {worst_coord:e} (bound 1e-5)"
    );
    assert!(worst_cpu <= 1e-6, "{worst_cpu}");
    assert!(worst_f64 <= 1e-3, "{worst_f64}");
    assert!(worst_coord <= 1e-5, "{worst_coord}");
}

/// A multisampled scene fogged before its resolve: `create_apply_multisampled` draws
/// into a 4x colour target whose samples hold different colours (written per sample),
/// and every sample blends the pixel's fog onto its own colour, so the resolve is the
/// mean colour times T plus L, with (T, L) from the single-sample pass over black and
/// white. A sample count outside 1, 2, 4, 8 is a typed error naming `samples`.
#[test]
fn multisampled_apply_fogs_every_sample_before_the_resolve() {
    use glam::Vec4;
    use volfog::pipeline::FogError;

    const SAMPLES: u32 = 4;
    let gpu = gpu();
    let (w, h) = (48, 27);
    let format = wgpu::TextureFormat::Rgba16Float;
    let (fog, _depth, depth_view) = encoded_fog(gpu, w, h);

    // T and L per pixel: the single-sample pass over black and over white.
    let single = fog.create_apply(&gpu.device, format).unwrap();
    let over = |base: f32| {
        let target =
            gpu.texture_2d_rgba16f("over", [w, h], &vec![Vec4::splat(base); (w * h) as usize]);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.record_apply(
            &mut encoder,
            &single,
            &target.create_view(&Default::default()),
            &single.depth_bind_group(&gpu.device, &depth_view),
        )
        .unwrap();
        gpu.queue.submit([encoder.finish()]);
        gpu.read_texture_rgba16f(&target).unwrap()
    };
    let (black, white) = (over(0.0), over(1.0));

    // The samples' colours, one per sample index (the fill runs per sample).
    const FILL: &str = r#"
@vertex
fn fill_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
@fragment
fn fill_fs(@builtin(sample_index) s: u32) -> @location(0) vec4<f32> {
    let k = f32(s);
    return vec4<f32>(0.2 + 0.2 * k, 0.7 - 0.15 * k, 0.05 + 0.3 * k * k / 9.0, 1.0);
}
"#;
    let colour = |s: u32| {
        let k = s as f32;
        Vec4::new(0.2 + 0.2 * k, 0.7 - 0.15 * k, 0.05 + 0.3 * k * k / 9.0, 1.0)
    };
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("per-sample fill"),
            source: wgpu::ShaderSource::Wgsl(FILL.into()),
        });
    let fill = gpu
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("per-sample fill"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("fill_vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState {
                count: SAMPLES,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fill_fs"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
    let texture = |label, samples, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | usage,
            view_formats: &[],
        })
    };
    let scene = texture("scene 4x", SAMPLES, wgpu::TextureUsages::empty());
    let resolved = texture("resolved", 1, wgpu::TextureUsages::COPY_SRC);
    let (scene_view, resolved_view) = (
        scene.create_view(&Default::default()),
        resolved.create_view(&Default::default()),
    );
    let apply = fog
        .create_apply_multisampled(&gpu.device, format, SAMPLES)
        .unwrap();
    assert_eq!(apply.samples(), SAMPLES);
    let depth_group = apply.depth_bind_group(&gpu.device, &depth_view);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for (load, resolve) in [(true, None), (false, Some(&resolved_view))] {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("multisampled scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &scene_view,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: if load {
                        wgpu::LoadOp::Clear(wgpu::Color::BLACK)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if load {
            pass.set_pipeline(&fill);
            pass.draw(0..3, 0..1);
        } else {
            fog.draw_apply(&mut pass, &apply, &depth_group).unwrap();
        }
    }
    gpu.queue.submit([encoder.finish()]);
    let got = gpu.read_texture_rgba16f(&resolved).unwrap();

    let mean = (0..SAMPLES).map(colour).sum::<Vec4>() / SAMPLES as f32;
    let (mut worst, mut fogged) = (0.0f32, 0usize);
    for i in 0..(w * h) as usize {
        let l = black[i].truncate();
        let t = white[i].truncate() - l;
        let want = mean.truncate() * t + l;
        let e = (got[i].truncate() - want).abs().max_element();
        worst = worst.max(e);
        fogged += usize::from((want - mean.truncate()).abs().max_element() > 0.05);
        assert!(e <= 2e-3, "pixel {i}: {} against {want}", got[i]);
    }
    eprintln!(
        "4x multisampled apply, resolved, against mean colour * T + L: max abs difference \
         {worst:e} (bound 2e-3: rgba16float samples); {fogged} of {} pixels fogged by more \
         than 0.05",
        w * h
    );
    assert!(
        fogged > (w * h / 10) as usize,
        "the fog is visible: {fogged}"
    );

    for samples in [0, 3, 16] {
        match fog.create_apply_multisampled(&gpu.device, format, samples) {
            Err(FogError::Invalid(e)) => assert_eq!(e.field, "samples", "{e}"),
            other => panic!("{samples} samples: {other:?}"),
        }
    }
}

/// The small scene's fog, prepared and encoded once, and a w x h depth buffer (a
/// gradient from 0.9 to 1.0 across each row) with its depth-aspect view.
fn encoded_fog(
    gpu: &volfog_testkit::Gpu,
    w: u32,
    h: u32,
) -> (
    volfog::pipeline::VolumetricFog,
    wgpu::Texture,
    wgpu::TextureView,
) {
    use common::scene::{projection, small_config, view};
    use volfog::pipeline::{FrameInputs, VolumetricFog};
    let mut fog = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    fog.prepare(
        &gpu.queue,
        &FrameInputs::new(view(2.0, 0.0), projection(), 0.0),
    )
    .unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let depths: Vec<f32> = (0..w * h)
        .map(|i| 0.9 + 0.1 * (i % w) as f32 / w as f32)
        .collect();
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depths).unwrap();
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    (fog, depth, depth_view)
}

/// A frame prepared without a tail (`HeightFog::none()`) is applied by the variant
/// without it (`VOLFOG_APPLY_NO_TAIL`): the very image of the variant with the tail,
/// bit for bit. A frame with a tail is applied with it, which changes every pixel
/// beyond the far plane and none in front of it.
#[test]
fn an_empty_tail_is_left_out_and_draws_the_same_image() {
    use common::scene::{projection, view};
    use glam::{Vec3, Vec4};
    use volfog::pipeline::FrameInputs;
    use volfog::pipeline::apply::Tail;
    use volfog::uniforms::HeightFog;

    let gpu = gpu();
    let (w, h) = (48, 27);
    let (mut fog, ..) = encoded_fog(gpu, w, h);
    // Depths from about 50 m to the camera's far plane (500 m): the fog's far plane
    // (64 m) crosses every row.
    let depths: Vec<f32> = (0..w * h)
        .map(|i| 0.998 + 0.002 * (i % w) as f32 / (w - 1) as f32)
        .collect();
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depths).unwrap();
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let apply = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let group = apply.depth_bind_group(&gpu.device, &depth_view);
    let base = Vec4::new(0.6, 0.3, 0.1, 1.0);
    // The fog's own choice (None) or the variant `tail`, onto the lit colour.
    let draw = |fog: &volfog::pipeline::VolumetricFog, tail: Option<Tail>| {
        let target = gpu.texture_2d_rgba16f("tail", [w, h], &vec![base; (w * h) as usize]);
        let view = target.create_view(&Default::default());
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        match tail {
            None => fog
                .record_apply(&mut encoder, &apply, &view, &group)
                .unwrap(),
            Some(tail) => apply.record_tail(
                &mut encoder,
                &view,
                fog.fog_bind_group(),
                &group,
                None,
                tail,
            ),
        }
        gpu.queue.submit([encoder.finish()]);
        gpu.read_texture_rgba16f(&target).unwrap()
    };
    let bits = |image: &[Vec4]| -> Vec<[u32; 4]> {
        image
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };

    assert_eq!(fog.tail(), Tail::Empty);
    let chosen = draw(&fog, None);
    let with_tail = draw(&fog, Some(Tail::Analytic));
    let without = draw(&fog, Some(Tail::Empty));
    assert!(
        chosen
            .iter()
            .any(|p| (*p - base).abs().max_element() > 0.05),
        "fog is visible"
    );
    assert_eq!(
        bits(&chosen),
        bits(&without),
        "no tail: the variant without it"
    );
    assert_eq!(
        bits(&with_tail),
        bits(&without),
        "an empty tail changes no bit of the image"
    );

    // A frame with a tail (view space, 0.02 / m, grey): applied with it.
    fog.prepare(
        &gpu.queue,
        &FrameInputs {
            tail: HeightFog {
                density: 0.02,
                color: Vec3::splat(0.5),
                ..HeightFog::none()
            },
            ..FrameInputs::new(view(2.0, 0.0), projection(), 0.0)
        },
    )
    .unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    assert_eq!(fog.tail(), Tail::Analytic);
    let chosen = draw(&fog, None);
    let with_tail = draw(&fog, Some(Tail::Analytic));
    let without = draw(&fog, Some(Tail::Empty));
    assert_eq!(
        bits(&chosen),
        bits(&with_tail),
        "a tail: the variant with it"
    );
    let view_from_clip = projection().inverse();
    let (mut beyond, mut changed_beyond, mut changed_in_front) = (0, 0, 0);
    for (i, d) in depths.iter().enumerate() {
        let z = -view_from_clip.project_point3(Vec3::new(0.0, 0.0, *d)).z;
        let changed = bits(&with_tail[i..=i]) != bits(&without[i..=i]);
        if z > common::scene::small_config().far * 1.01 {
            beyond += 1;
            changed_beyond += changed as usize;
        } else if z < common::scene::small_config().far * 0.99 {
            changed_in_front += changed as usize;
        }
    }
    eprintln!(
        "tail 0.02 / m: {changed_beyond} of {beyond} pixels beyond the far plane changed by the \
         tail, {changed_in_front} in front of it"
    );
    assert!(
        beyond > 100 && changed_beyond == beyond,
        "{changed_beyond} of {beyond}"
    );
    assert_eq!(changed_in_front, 0);
}
