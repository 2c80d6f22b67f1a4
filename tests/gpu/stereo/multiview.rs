//! The multiview path of stereo fog: the multiview apply (both eyes in one multiview
//! render pass) against the apply drawn once per layer, a multiview forward shader
//! fogging with `volfog::stereo_bindings` against each eye drawn with its own fog group
//! and the mono `volfog::apply` functions, and the typed errors.

use super::*;
use crate::common::scene::lights;
use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use std::collections::HashMap;
use volfog::options::Filtering;
use volfog::pipeline::FogError;

/// One rgba16float step at `v` (the spacing of half floats around it).
fn half_step(v: f32) -> f32 {
    let h = half::f16::from_f32(v.abs());
    (f32::from(half::f16::from_bits(h.to_bits() + 1)) - f32::from(h)).max(f32::MIN_POSITIVE)
}

/// Largest |a - b| over every channel, and the largest in units of the rgba16float step
/// at the larger value.
fn difference(a: &[Vec4], b: &[Vec4]) -> (f32, f32) {
    assert_eq!(a.len(), b.len());
    let (mut abs, mut steps) = (0.0f32, 0.0f32);
    for (x, y) in a.iter().zip(b) {
        for c in 0..4 {
            let d = (x[c] - y[c]).abs();
            abs = abs.max(d);
            steps = steps.max(d / half_step(x[c].abs().max(y[c].abs())));
        }
    }
    (abs, steps)
}

/// Depths of two layers that differ per eye: a ramp from 0.97 (about 3 m with the
/// eyes' projection) to 1.0 (the far plane, where the tail takes over), mirrored in
/// the right eye, so a layer read for the other eye would show.
fn ramp_depth(gpu: &Gpu) -> wgpu::Texture {
    let [w, h] = IMAGE;
    let layer = |mirror: bool| -> Vec<f32> {
        (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let x = if mirror { w - 1 - x } else { x };
                let t = (x + 2 * y) as f32 / (w + 2 * h - 3) as f32;
                (0.97 + 0.031 * t).min(1.0)
            })
            .collect()
    };
    let (left, right) = (layer(false), layer(true));
    volfog_testkit::selfcheck::depth_array_texture(gpu, w, h, &[&left, &right])
        .expect("depth written")
}

/// A prepared and encoded stereo fog over the scene with `filtering`.
fn prepared(gpu: &Gpu, filtering: Filtering) -> (StereoFog, wgpu::CommandEncoder) {
    let config = FogConfig {
        apply_filtering: filtering,
        ..config()
    };
    let eyes = eyes(head(), 0.064);
    let lights = lights();
    let (cascades, shadow) = sun(gpu, &config);
    let inputs = inputs(&eyes[0], &lights, cascades);
    let mut fog = StereoFog::new(&gpu.device, &config).unwrap();
    fog.shared_mut()
        .set_shadow_map(&gpu.device, &shadow)
        .unwrap();
    fog.prepare(&gpu.queue, &eyes, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    (fog, encoder)
}

/// The view masks the tests draw: both eyes, the left alone, the right alone.
const MASKS: [u32; 3] = [0b11, 0b01, 0b10];

/// Whether a two-view pass drew the second view into its own layer. Mesa 22.3's
/// lavapipe does not: it draws both views of a two-view pass into layer 0 (a pass of
/// one view lands in that view's layer, with its view index), so layer 1 stays as it
/// was.
fn routes_views(both: &[Vec4], pixels: usize) -> bool {
    both[pixels..].iter().any(|p| *p != Vec4::ZERO)
}

/// Checks a two-layer image of the multiview pass of `mask` against the per-layer
/// images `one` (each eye in its layer): returns the largest difference in
/// rgba16float steps over the layers the pass drew. A two-view pass on a driver that
/// does not route views to layers (see [`routes_views`]) is reported and not compared:
/// there the passes of one view stand for it.
fn check_views(what: &str, mask: u32, got: &[Vec4], one: &[Vec4]) -> f32 {
    let pixels = (IMAGE[0] * IMAGE[1]) as usize;
    let layer = |image: &[Vec4], l: usize| image[l * pixels..(l + 1) * pixels].to_vec();
    let blank = vec![Vec4::ZERO; pixels];
    let (want, note) = match mask {
        0b11 if routes_views(got, pixels) => {
            ([layer(one, 0), layer(one, 1)], "both eyes in one pass")
        }
        0b11 => {
            assert!(
                got[..pixels].iter().any(|p| *p != Vec4::ZERO),
                "the pass drew"
            );
            eprintln!(
                "{what}, view mask 0b11: THE DRIVER DOES NOT DRAW THE SECOND VIEW INTO LAYER \
                 1 (Mesa 22.3 lavapipe draws both views into layer 0); \
                 the two-view image is not compared, the one-view passes below are"
            );
            return 0.0;
        }
        0b01 => ([layer(one, 0), blank], "the left eye alone"),
        _ => ([blank, layer(one, 1)], "the right eye alone"),
    };
    let mut worst = 0.0f32;
    for (l, want) in want.iter().enumerate() {
        let (abs, steps) = difference(&layer(got, l), want);
        eprintln!(
            "{what}, view mask {mask:#04b} ({note}): layer {l} against the per-layer image: \
             largest difference {abs:e} ({steps} rgba16float steps)"
        );
        worst = worst.max(steps);
    }
    worst
}

#[test]
fn multiview_apply_equals_the_apply_per_layer() {
    let gpu = gpu();
    gpu.require(wgpu::Features::MULTIVIEW | wgpu::Features::SELECTIVE_MULTIVIEW);
    eprintln!("adapter: {}", gpu.describe());
    let pixels = (IMAGE[0] * IMAGE[1]) as usize;
    for filtering in [Filtering::Sampler, Filtering::Manual] {
        let (fog, mut encoder) = prepared(gpu, filtering);
        let format = wgpu::TextureFormat::Rgba16Float;
        let per_layer = fog.shared().create_apply(&gpu.device, format).unwrap();
        let depth = ramp_depth(gpu);
        let groups =
            [0, 1].map(|i| per_layer.depth_bind_group(&gpu.device, &depth_layer(&depth, i)));
        let groups = [&groups[0], &groups[1]];
        let one = target(gpu, 2);
        fog.record_apply(&mut encoder, &per_layer, &one, groups)
            .unwrap();
        let multiview: Vec<wgpu::Texture> = MASKS
            .iter()
            .map(|&mask| {
                let mask = std::num::NonZeroU32::new(mask).unwrap();
                let apply = fog
                    .create_apply_multiview_views(&gpu.device, format, mask)
                    .unwrap();
                let group = fog
                    .multiview_depth_bind_group(&gpu.device, &apply, &depth)
                    .unwrap();
                let image = target(gpu, 2);
                fog.record_apply_multiview(&mut encoder, &apply, &image, &group)
                    .unwrap();
                image
            })
            .collect();
        gpu.queue.submit([encoder.finish()]);
        let read = |t: &wgpu::Texture| gpu.read_texture_rgba16f(t).unwrap();
        let one = read(&one);
        let fog_amount = one
            .iter()
            .map(|p| p.x.max(p.y).max(p.z))
            .fold(0.0f32, f32::max);
        assert!(fog_amount > 0.01, "the image holds fog: {fog_amount}");
        let (eyes_apart, _) = difference(&one[..pixels], &one[pixels..]);
        assert!(eyes_apart > 1e-3, "the eyes differ: {eyes_apart}");
        for (mask, image) in MASKS.iter().zip(&multiview) {
            let what = format!("{filtering:?} multiview apply");
            let steps = check_views(&what, *mask, &read(image), &one);
            assert!(steps <= 1.0, "within one rgba16float step: {steps}");
        }
    }
}

/// A forward shader drawing both eyes in one multiview pass: a floor (one triangle,
/// world-space corners in the uniform) fogged by `stereo_bindings::stereo_fog_at_world` with one import.
const MULTIVIEW_FORWARD: &str = r#"
#import volfog::stereo_bindings
#import volfog::apply::apply_fog

struct Eyes {
    clip_from_world: array<mat4x4<f32>, 2>,
    corners: array<vec4<f32>, 3>,
}
@group(1) @binding(0) var<uniform> eyes: Eyes;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
}

@vertex
fn vs(@builtin(vertex_index) i: u32, @builtin(view_index) view_index: u32) -> VertexOut {
    let world = eyes.corners[i].xyz;
    return VertexOut(eyes.clip_from_world[view_index] * vec4<f32>(world, 1.0), world);
}

@fragment
fn fs(in: VertexOut, @builtin(view_index) view_index: u32) -> @location(0) vec4<f32> {
    let fog = stereo_bindings::stereo_fog_at_world(view_index, in.world);
    return vec4<f32>(apply_fog(vec3<f32>(0.6, 0.5, 0.4), fog), 1.0);
}
"#;

/// The same draw for one eye, with that eye's mono fog group and `volfog::apply`.
const MONO_FORWARD: &str = r#"
#import volfog::bindings
#import volfog::apply::{apply_fog, fog_coord_from_view, fog_sample, fog_tail, fog_view_position, fog_with_tail}

struct Eye {
    clip_from_world: mat4x4<f32>,
    corners: array<vec4<f32>, 3>,
}
@group(1) @binding(0) var<uniform> eye: Eye;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
}

@vertex
fn vs(@builtin(vertex_index) i: u32) -> VertexOut {
    let world = eye.corners[i].xyz;
    return VertexOut(eye.clip_from_world * vec4<f32>(world, 1.0), world);
}

@fragment
fn fs(in: VertexOut) -> @location(0) vec4<f32> {
    let view = fog_view_position(in.world, bindings::fog_view.view_from_world);
    let froxels = bindings::fog_froxels;
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler, fog_coord_from_view(view, froxels));
    let total = fog_with_tail(fog, fog_tail(froxels, bindings::fog_far_tail, view));
    return vec4<f32>(apply_fog(vec3<f32>(0.6, 0.5, 0.4), total), 1.0);
}
"#;

/// A shader composed with volfog's modules, validated with multiview.
fn compose_multiview(source: &str, defs: &[(&str, ShaderDefValue)]) -> naga::Module {
    let mut composer = Composer::default().with_capabilities(
        naga::valid::Capabilities::default() | naga::valid::Capabilities::MULTIVIEW,
    );
    volfog::shaders::add_to_composer(&mut composer).expect("volfog modules compose");
    let shader_defs: HashMap<String, ShaderDefValue> =
        defs.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path: "forward.wgsl",
            shader_defs,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)))
}

fn uniform(gpu: &Gpu, bytes: &[u8]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("forward eyes"),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// A forward pipeline of `module` with `fog_layout` at group 0 and one uniform buffer
/// at group 1; `multiview` the view mask.
fn forward_pipeline(
    gpu: &Gpu,
    module: naga::Module,
    fog_layout: &wgpu::BindGroupLayout,
    multiview: Option<std::num::NonZeroU32>,
) -> (wgpu::RenderPipeline, wgpu::BindGroupLayout) {
    let device = &gpu.device;
    let shader = gpu.shader_from_naga("forward", module);
    let eyes_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("forward eyes"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("forward"),
        bind_group_layouts: &[Some(fog_layout), Some(&eyes_layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("forward"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &shader,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &shader,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::TextureFormat::Rgba16Float.into())],
        }),
        multiview_mask: multiview,
        cache: None,
    });
    (pipeline, eyes_layout)
}

fn draw(
    encoder: &mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    multiview: Option<std::num::NonZeroU32>,
    pipeline: &wgpu::RenderPipeline,
    groups: [&wgpu::BindGroup; 2],
) {
    // The targets start transparent black; the pass loads and stores them.
    let mut pass = volfog::pipeline::apply::composite_pass_multiview(
        encoder, "forward", view, None, multiview,
    );
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, groups[0], &[]);
    pass.set_bind_group(1, groups[1], &[]);
    pass.draw(0..3, 0..1);
}

#[test]
fn multiview_forward_shader_equals_each_eye_with_its_fog_group() {
    let gpu = gpu();
    gpu.require(wgpu::Features::MULTIVIEW | wgpu::Features::SELECTIVE_MULTIVIEW);
    let (fog, mut encoder) = prepared(gpu, Filtering::Sampler);
    let eyes = eyes(head(), 0.064);
    let clip_from_world = eyes.map(|e| e.clip_from_view * e.view_from_world);
    // A floor 1.5 m below the eyes (level with the head), from behind them to 3 km
    // ahead: its near part lies in the volume, its far part in the tail.
    let corners: Vec<f32> = [
        Vec3::new(-3000.0, -1.5, 1000.0),
        Vec3::new(3000.0, -1.5, 1000.0),
        Vec3::new(0.0, -1.5, -3000.0),
    ]
    .iter()
    .flat_map(|c| head().transform_point3(*c).extend(1.0).to_array())
    .collect();
    let device = &gpu.device;
    let uniform_group = |layout: &wgpu::BindGroupLayout, bytes: &[u8]| {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("forward eyes"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform(gpu, bytes).as_entire_binding(),
            }],
        })
    };

    // Each eye alone, into its layer, with its own fog group and the mono functions.
    let module = compose_multiview(MONO_FORWARD, &[]);
    let (mono, eye_layout) =
        forward_pipeline(gpu, module, fog.shared().fog_bind_group_layout(), None);
    let one = target(gpu, 2);
    for (eye, m) in clip_from_world.iter().enumerate() {
        let bytes = [
            bytemuck::bytes_of(&m.to_cols_array()),
            bytemuck::cast_slice(&corners),
        ]
        .concat();
        let group = uniform_group(&eye_layout, &bytes);
        let fog_group = fog.eye_fog_bind_group(eye).unwrap();
        let view = layer_view(&one, eye as u32);
        draw(&mut encoder, &view, None, &mono, [fog_group, &group]);
    }

    // Both eyes in one multiview pass, and each alone, with the stereo group.
    let module = compose_multiview(MULTIVIEW_FORWARD, &[]);
    let mut both_bytes: Vec<u8> = clip_from_world
        .iter()
        .flat_map(|m| bytemuck::bytes_of(&m.to_cols_array()).to_vec())
        .collect();
    both_bytes.extend(bytemuck::cast_slice(&corners));
    let multiview: Vec<wgpu::Texture> = MASKS
        .iter()
        .map(|&mask| {
            let mask = std::num::NonZeroU32::new(mask);
            let (pipeline, eyes_layout) = forward_pipeline(
                gpu,
                module.clone(),
                fog.stereo_fog_bind_group_layout(),
                mask,
            );
            let group = uniform_group(&eyes_layout, &both_bytes);
            let image = target(gpu, 2);
            let view = image.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                array_layer_count: Some(2),
                ..Default::default()
            });
            draw(
                &mut encoder,
                &view,
                mask,
                &pipeline,
                [fog.stereo_fog_bind_group(), &group],
            );
            image
        })
        .collect();
    gpu.queue.submit([encoder.finish()]);
    let read = |t: &wgpu::Texture| gpu.read_texture_rgba16f(t).unwrap();
    let one = read(&one);
    let pixels = (IMAGE[0] * IMAGE[1]) as usize;
    for eye in 0..2 {
        let ground = one[eye * pixels..(eye + 1) * pixels]
            .iter()
            .filter(|p| p.w > 0.5)
            .count();
        assert!(ground > pixels / 4, "the floor covers the image: {ground}");
    }
    let (eyes_apart, _) = difference(&one[..pixels], &one[pixels..]);
    assert!(eyes_apart > 1e-3, "the eyes differ: {eyes_apart}");
    for (mask, image) in MASKS.iter().zip(&multiview) {
        let steps = check_views("multiview forward", *mask, &read(image), &one);
        assert!(steps <= 1.0, "within one rgba16float step: {steps}");
    }
}

/// A colour view of one layer.
fn layer_view(texture: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

#[test]
fn multiview_errors_are_typed() {
    let gpu = gpu();
    gpu.require(wgpu::Features::MULTIVIEW);
    let (fog, mut encoder) = prepared(gpu, Filtering::Sampler);
    let format = wgpu::TextureFormat::Rgba16Float;

    // A device without the feature.
    let plain = volfog_testkit::Gpu::new().unwrap();
    assert!(!plain.device.features().contains(wgpu::Features::MULTIVIEW));
    match fog.create_apply_multiview(&plain.device, format) {
        Err(FogError::MissingCapability { what, .. }) => {
            assert_eq!(what, "wgpu::Features::MULTIVIEW")
        }
        other => panic!("{other:?}"),
    }

    let multiview = fog.create_apply_multiview(&gpu.device, format).unwrap();
    // A view the stereo target lacks.
    let third = std::num::NonZeroU32::new(0b100).unwrap();
    match fog.create_apply_multiview_views(&gpu.device, format, third) {
        Err(FogError::Invalid(e)) => assert_eq!(e.field, "view_mask"),
        other => panic!("{other:?}"),
    }
    let per_layer = fog.shared().create_apply(&gpu.device, format).unwrap();
    let depth = ramp_depth(gpu);
    // A depth array of one layer.
    let single_depth = far_depth(gpu, 1);
    match fog.multiview_depth_bind_group(&gpu.device, &multiview, &single_depth) {
        Err(FogError::Texture {
            texture,
            property,
            found,
            ..
        }) => assert_eq!(
            (texture, property, found.as_str()),
            ("the stereo depth array", "array layers", "1")
        ),
        other => panic!("{other:?}"),
    }
    let group = fog
        .multiview_depth_bind_group(&gpu.device, &multiview, &depth)
        .unwrap();
    // A target of one layer.
    match fog.record_apply_multiview(&mut encoder, &multiview, &target(gpu, 1), &group) {
        Err(FogError::Texture {
            texture,
            property,
            found,
            ..
        }) => assert_eq!(
            (texture, property, found.as_str()),
            ("the stereo target", "array layers", "1")
        ),
        other => panic!("{other:?}"),
    }
    // The per-layer apply where the multiview one is needed.
    match fog.record_apply_multiview(&mut encoder, &per_layer, &target(gpu, 2), &group) {
        Err(FogError::Invalid(e)) => assert_eq!(e.field, "ApplyPipeline multiview mask"),
        other => panic!("{other:?}"),
    }
    // An apply of the other filtering.
    let (manual, _) = prepared(gpu, Filtering::Manual);
    let manual_apply = manual.create_apply_multiview(&gpu.device, format).unwrap();
    assert!(matches!(
        fog.record_apply_multiview(&mut encoder, &manual_apply, &target(gpu, 2), &group),
        Err(FogError::ApplyMismatch { .. })
    ));
    // The frame still records.
    fog.record_apply_multiview(&mut encoder, &multiview, &target(gpu, 2), &group)
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
}
