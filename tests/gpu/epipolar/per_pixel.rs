//! The per-pixel WGSL functions of the passes on the GPU against the CPU mirror.

use super::{Scene, sun_direction};
use crate::common::{self, gpu};
use glam::{Vec2, Vec3, Vec4};
use volfog::cpu::epipolar as cpu;
use volfog::uniforms::{EpipolarFrame, HeightFog};

/// The functions the passes use per pixel, on the GPU against the CPU mirror for random
/// inputs: the slice of a screen point, its position on that slice's line, the
/// standalone fog with a lit fraction and the far-field tail of the forward snippet
/// (`volfog::apply::fog_tail_shafts`), half of them with the sun's transmittance
/// through the medium (and a top).
#[test]
fn per_pixel_functions_match_the_cpu() {
    use volfog::uniforms::Froxels;
    const KERNEL: &str = r#"
#import volfog::types::{EpipolarFrame, Froxels, HeightFog}
#import volfog::epipolar::{epipolar_pixel_slice, epipolar_line, epipolar_line_position, epipolar_fog, epipolar_pixel_ndc, epipolar_view_depth}
#import volfog::apply::fog_tail_shafts

struct Case { frame: EpipolarFrame, froxels: Froxels, fog: HeightFog, point: vec4<f32>, view_pos: vec4<f32> }
@group(0) @binding(0) var<storage, read> input: array<Case>;
@group(0) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&input) { return; }
    let c = input[id.x];
    let s = epipolar_pixel_slice(c.frame, c.point.xy);
    let slice = min(u32(s), c.frame.slices - 1u);
    let k = epipolar_line_position(epipolar_line(c.frame, slice), c.frame.samples, c.point.xy);
    let position = (c.point.xy * vec2<f32>(0.5, -0.5) + 0.5) * c.frame.screen_size;
    let depth = epipolar_view_depth(c.frame, c.point.xy, 0.3 + 0.69 * c.point.z);
    output[3u * id.x] = vec4<f32>(s, k, depth, epipolar_pixel_ndc(c.frame, position).y);
    let fraction = vec3<f32>(c.point.z, c.point.w, 0.5 * (c.point.z + c.point.w));
    output[3u * id.x + 1u] = epipolar_fog(c.frame, c.fog, c.view_pos.xyz, fraction);
    output[3u * id.x + 2u] = fog_tail_shafts(c.froxels, c.fog, c.view_pos.xyz, fraction);
}
"#;
    let gpu = gpu();
    let mut rng = common::Rng(11);
    let scene = Scene::new(160, 90, 256, &[], sun_direction());
    let base = EpipolarFrame::new(&scene.sampling(), &scene.view(0.0), scene.sun).unwrap();
    let froxels = Froxels::new(
        scene.clip_from_view,
        glam::UVec3::new(32, 18, 48),
        0.5,
        64.0,
        3.0,
    )
    .unwrap();
    let count = 600;
    let (mut bytes, mut want) = (Vec::new(), Vec::new());
    for i in 0..count {
        // Epipoles inside, on the edge and far outside the screen; the far plane of a
        // froxel volume as the start of the march for a third of the cases.
        let light = match i % 3 {
            0 => Vec2::new(rng.range(-0.9, 0.9), rng.range(-0.9, 0.9)),
            1 => Vec2::new(1.0, rng.range(-1.0, 1.0)),
            _ => Vec2::new(rng.range(-50.0, 50.0), rng.range(2.0, 30.0)),
        };
        let frame = EpipolarFrame {
            light_screen: light,
            start_depth: if i % 3 == 2 { 64.0 } else { 0.0 },
            phase_model: (i % 2) as u32,
            ..base
        };
        let fog = HeightFog::new(
            Vec3::new(
                rng.range(0.0, 0.1),
                rng.range(0.0, 0.1),
                rng.range(0.0, 0.1),
            ),
            rng.log(1e-4, 0.1),
            rng.unit(),
            rng.range(-0.1, 0.2),
            rng.range(-20.0, 20.0),
        )
        .unwrap()
        .with_sun(
            rng.unit(),
            Vec3::splat(rng.range(0.0, 4.0)),
            rng.range(-0.9, 0.9),
        )
        .unwrap()
        // Half the cases with the sun's transmittance, half of those under a top.
        .with_sun_transmittance(i % 4 < 2);
        let fog = if i % 4 == 0 {
            fog.with_top(rng.range(-10.0, 40.0)).unwrap()
        } else {
            fog
        };
        let point = Vec2::new(rng.range(-0.999, 0.999), rng.range(-0.999, 0.999));
        let (f0, f1) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        let fraction = Vec3::new(f0, f1, 0.5 * (f0 + f1));
        let view_pos = cpu::view_ray(frame.view_from_clip, point) * rng.log(0.5, 400.0);
        bytes.extend(volfog::uniforms::to_uniform_bytes(&frame));
        bytes.extend(volfog::uniforms::to_uniform_bytes(&froxels));
        bytes.extend(fog.to_bytes());
        bytes.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&[point.x, point.y, f0, f1]));
        bytes.extend_from_slice(bytemuck::cast_slice::<f32, u8>(
            &view_pos.extend(0.0).to_array(),
        ));
        let s = cpu::pixel_slice(&frame, point);
        let slice = (s as u32).min(frame.slices - 1);
        let k = cpu::line_position(cpu::line(&frame, slice), frame.samples, point);
        let position = (point * Vec2::new(0.5, -0.5) + Vec2::splat(0.5)) * frame.screen_size;
        let depth = cpu::view_depth(&frame, point, 0.3 + 0.69 * f0);
        want.push([
            Vec4::new(s, k, depth, cpu::pixel_ndc(&frame, position).y),
            cpu::fog(&frame, &fog, view_pos, fraction),
            volfog::cpu::apply::fog_tail_shafts(&froxels, &fog, view_pos, fraction),
        ]);
    }
    let module = gpu.shader_from_naga("epipolar per pixel", common::compose(KERNEL, &[]));
    let out = gpu
        .run_kernel(&module, "main", &bytes, (count * 48) as u64, count as u32)
        .unwrap();
    let got: &[Vec4] = bytemuck::cast_slice(&out);
    let (mut slice_err, mut pos_err, mut fog_err, mut tail_err) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let (mut depth_err, mut ndc_err) = (0.0f32, 0.0f32);
    for (i, w) in want.iter().enumerate() {
        let g = &got[3 * i..3 * i + 3];
        let mut ds = (g[0].x - w[0].x).abs();
        ds = ds.min(base.slices as f32 - ds); // the slice coordinate wraps
        slice_err = slice_err.max(ds);
        pos_err = pos_err.max((g[0].y - w[0].y).abs());
        depth_err = depth_err.max((g[0].z - w[0].z).abs() / w[0].z);
        ndc_err = ndc_err.max((g[0].w - w[0].w).abs());
        let rel = |a: Vec4, b: Vec4| ((a - b).abs() / b.abs().max(Vec4::splat(1e-3))).max_element();
        fog_err = fog_err.max(rel(g[1], w[1]));
        tail_err = tail_err.max(rel(g[2], w[2]));
    }
    eprintln!(
        "{count} cases: pixel slice {slice_err:.2e} slices (bound 1e-3), line position {pos_err:.2e} samples (bound 1e-2), epipolar_fog {fog_err:.2e} relative (bound 1e-4), fog_tail_shafts {tail_err:.2e} (bound 1e-4), view depth {depth_err:.2e} relative (bound 1e-5), pixel ndc {ndc_err:.2e} (bound 1e-6)"
    );
    assert!(
        depth_err <= 1e-5 && ndc_err <= 1e-6,
        "{depth_err} {ndc_err}"
    );
    assert!(
        slice_err <= 1e-3 && pos_err <= 1e-2,
        "{slice_err} {pos_err}"
    );
    assert!(fog_err <= 1e-4 && tail_err <= 1e-4, "{fog_err} {tail_err}");
}
