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
    use common::scene::{projection, small_config, view};
    use glam::Vec4;
    use volfog::pipeline::{FrameInputs, VolumetricFog};

    let gpu = gpu();
    let (w, h) = (48, 27);
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
