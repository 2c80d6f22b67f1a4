//! Depth culling (`froxel_cull`, `VOLFOG_FROXEL_CULL`) and amortised injection through
//! `VolumetricFog`: the live slices against the CPU mirror and against every look-up
//! the apply pass makes (full-resolution depth, reversed depth, a farthest-depth
//! half-resolution level); a culled fog equal to an unculled one wherever anything
//! reads it, in the integrated volume and in the applied image; no stale froxel after
//! a disocclusion; and the froxels a checkerboard frame injects.

use crate::common;

use common::gpu;
use common::scene::*;
use glam::{Mat4, UVec3, Vec2, Vec3, Vec4};
use volfog::cpu::apply::{Volume, fog_coord};
use volfog::cpu::froxel::{froxel_injected, live_slices_from_depth, view_from_ndc};
use volfog::cpu::inject::{InjectInputs, froxel_scattering, injected_source};
use volfog::cpu::temporal::{TemporalInputs, temporal_froxel};
use volfog::pipeline::{FogConfig, FogPass, FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogLight, FogMedium, Froxels, HistoryState};
use volfog_testkit::Gpu;
use volfog_testkit::gpu::texture_2d;

/// Screen of the culling tests: not a multiple of the 32 x 18 froxel grid.
pub(crate) const SCREEN: (u32, u32) = (203, 117);

/// Depth-buffer values of a ground plane (y = 0) with a pillar 6 m ahead and a wall
/// 14 m ahead on the left half, seen by `view` through `projection` (sky: the value
/// of the far plane, 1 for standard depth).
pub(crate) fn scene_depth(view: Mat4, projection: Mat4) -> Vec<f32> {
    let (w, h) = SCREEN;
    let view_from_clip = projection.inverse();
    let world_from_view = view.inverse();
    let eye = world_from_view.transform_point3(Vec3::ZERO);
    let mut out = Vec::with_capacity((w * h) as usize);
    for py in 0..h {
        for px in 0..w {
            let uv = Vec2::new((px as f32 + 0.5) / w as f32, (py as f32 + 0.5) / h as f32);
            let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
            let target = view_from_ndc(ndc.extend(0.5), view_from_clip);
            let dir = (world_from_view.transform_point3(target) - eye).normalize();
            let mut t = f32::INFINITY;
            if dir.y < -1e-4 {
                t = t.min(-eye.y / dir.y);
            }
            // The pillar: |x| < 0.8, -6.8 < z < -5.2, up to 4 m.
            let hit_box = |min: Vec3, max: Vec3| {
                let inv = dir.recip();
                let a = (min - eye) * inv;
                let b = (max - eye) * inv;
                let near = a.min(b).max_element();
                let far = a.max(b).min_element();
                (near <= far && near > 0.0).then_some(near)
            };
            if let Some(s) = hit_box(Vec3::new(-0.8, 0.0, -6.8), Vec3::new(0.8, 4.0, -5.2)) {
                t = t.min(s);
            }
            if let Some(s) = hit_box(Vec3::new(-30.0, 0.0, -14.5), Vec3::new(-1.0, 9.0, -14.0)) {
                t = t.min(s);
            }
            out.push(if t.is_finite() {
                let p = view.transform_point3(eye + dir * t);
                projection.project_point3(p).z
            } else {
                1.0
            });
        }
    }
    out
}

/// Standard depth made reversed: z' = w - z in clip space.
fn reversed(projection: Mat4) -> Mat4 {
    let flip = Mat4::from_cols(
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -1.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0, 1.0),
    );
    flip * projection
}

/// An R32Float texture of `values`.
fn r32_texture(gpu: &Gpu, size: (u32, u32), values: &[f32]) -> wgpu::Texture {
    let texture = texture_2d(
        &gpu.device,
        "hierarchical depth level",
        size,
        wgpu::TextureFormat::R32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(values),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * size.0),
            rows_per_image: Some(size.1),
        },
        texture.size(),
    );
    texture
}

fn read_live(gpu: &Gpu, fog: &VolumetricFog) -> Vec<u32> {
    let raw = gpu
        .read_texture_raw(fog.live_slices_texture().unwrap(), 4)
        .unwrap();
    bytemuck::cast_slice(&raw).to_vec()
}

/// Checks that every integrated texel the apply pass reads for every pixel of the
/// depth buffer lies within the live slices; returns how many pixels were checked.
fn assert_apply_reads_live(froxels: &Froxels, depth: &[f32], live: &[u32], label: &str) -> usize {
    let (w, h) = SCREEN;
    let size = froxels.size;
    for py in 0..h {
        for px in 0..w {
            let uv = Vec2::new((px as f32 + 0.5) / w as f32, (py as f32 + 0.5) / h as f32);
            let d = depth[(py * w + px) as usize];
            let view_depth = view_from_ndc(Vec3::new(0.0, 0.0, d), froxels.view_from_clip)
                .z
                .abs();
            let coord = fog_coord(uv, view_depth, froxels);
            let texel = coord.truncate() * size.as_vec3() - 0.5;
            let lo = texel.floor().max(Vec3::ZERO).as_uvec3().min(size - 1);
            let hi = (lo + 1).min(size - 1);
            for (x, y) in [(lo.x, lo.y), (hi.x, lo.y), (lo.x, hi.y), (hi.x, hi.y)] {
                let l = live[(y * size.x + x) as usize];
                assert!(
                    hi.z < l,
                    "{label}: pixel ({px}, {py}) at depth {view_depth} reads slice {} of column \
                     ({x}, {y}), which has {l} live slices",
                    hi.z
                );
            }
        }
    }
    (w * h) as usize
}

fn culling_config() -> FogConfig {
    FogConfig {
        depth_cull: true,
        ..small_config()
    }
}

#[test]
fn live_slices_match_cpu_and_cover_every_apply_lookup() {
    let gpu = gpu();
    let config = culling_config();
    let view = view(1.6, -0.05);
    let (w, h) = SCREEN;
    for (label, projection) in [
        ("standard depth", projection()),
        ("reversed depth", reversed(projection())),
    ] {
        let depth = scene_depth(view, projection);
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let inputs = FrameInputs::new(view, projection, 0.0);
        let froxels = expected_uniforms(&config, &inputs, 0).froxels;
        let full = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depth).unwrap();
        // A farthest-depth level at half resolution (max for standard depth, min for
        // reversed), as a hierarchical depth buffer keeps it.
        let (hw, hh) = (w.div_ceil(2), h.div_ceil(2));
        let farthest = |a: f32, b: f32| {
            if label.starts_with("standard") {
                a.max(b)
            } else {
                a.min(b)
            }
        };
        let half: Vec<f32> = (0..hw * hh)
            .map(|i| {
                let (x, y) = (i % hw, i / hw);
                let mut v = depth[((2 * y) * w + 2 * x) as usize];
                for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                    let (sx, sy) = ((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1));
                    v = farthest(v, depth[(sy * w + sx) as usize]);
                }
                v
            })
            .collect();
        let half_texture = r32_texture(gpu, (hw, hh), &half);
        for (level, texture, values, size) in [
            ("full resolution", &full, &depth, (w, h)),
            (
                "half-resolution farthest level",
                &half_texture,
                &half,
                (hw, hh),
            ),
        ] {
            fog.set_scene_depth(&gpu.device, texture, 0).unwrap();
            fog.prepare(&gpu.queue, &inputs).unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            fog.encode_pass(&mut encoder, FogPass::Cull).unwrap();
            gpu.queue.submit([encoder.finish()]);
            let got = read_live(gpu, &fog);
            let want = live_slices_from_depth(&froxels, values, size.0, size.1);
            let exact = got.iter().zip(&want).filter(|(a, b)| a == b).count();
            let worst = got
                .iter()
                .zip(&want)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            let live: u32 = got.iter().sum();
            let fraction = live as f64 / (froxels.size.x * froxels.size.y * froxels.size.z) as f64;
            let pixels = assert_apply_reads_live(&froxels, &depth, &got, label);
            eprintln!(
                "{label}, {level}: {exact}/{} columns equal to the CPU mirror (largest \
                 difference {worst} slice), {:.1} % of the froxels live, {pixels} pixels' \
                 look-ups within them",
                got.len(),
                100.0 * fraction
            );
            assert!(worst <= 1, "{label}, {level}: {worst}");
            assert!(exact * 100 >= got.len() * 99, "{label}, {level}: {exact}");
            assert!(
                fraction < 0.8,
                "{label}, {level}: the scene culls ({fraction})"
            );
        }
    }
}

/// The scene of the pipeline comparisons: the test medium, lights and volumes, a low
/// sun shadowed by the slab.
pub(crate) fn pipeline_inputs<'a>(
    view: Mat4,
    lights: &'a [FogLight],
    volumes: &'a [volfog::uniforms::LocalVolume],
    medium: FogMedium,
    cascades: volfog::uniforms::ShadowCascades,
) -> FrameInputs<'a> {
    FrameInputs {
        medium,
        sun: DirectionalLight {
            direction: Vec3::new(0.3, 1.0, 0.2).normalize(),
            ..DirectionalLight::default()
        },
        lights,
        local_volumes: volumes,
        cascades,
        ..FrameInputs::new(view, projection(), 2.0)
    }
}

/// Runs one frame of each fog.
pub(crate) fn frame(gpu: &Gpu, fogs: [&mut VolumetricFog; 2], inputs: &FrameInputs<'_>) {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for fog in fogs {
        fog.prepare(&gpu.queue, inputs).unwrap();
        fog.encode(&mut encoder).unwrap();
    }
    gpu.queue.submit([encoder.finish()]);
}

/// The integrated volume of a fog (temporal or not).
pub(crate) fn integrated(gpu: &Gpu, fog: &VolumetricFog) -> Vec<Vec4> {
    let texture = if fog.config().temporal {
        fog.scattering_texture()
    } else {
        fog.integrated_texture()
    };
    read_volume(gpu, texture)
}

#[test]
fn culled_fog_equals_unculled_fog_wherever_it_is_read() {
    let gpu = gpu();
    let (w, h) = SCREEN;
    for (temporal, amortize) in [(false, false), (true, false), (true, true)] {
        let base = FogConfig {
            temporal,
            jitter: temporal,
            amortize,
            ..small_config()
        };
        let (cascades, layers) = overhead_sun(&base, Some(SLAB));
        let shadow = shadow_map(gpu, &layers);
        let mut fogs = [false, true].map(|depth_cull| {
            let mut fog = VolumetricFog::new(
                &gpu.device,
                &FogConfig {
                    depth_cull,
                    ..base.clone()
                },
            )
            .unwrap();
            fog.set_shadow_map(&gpu.device, &shadow).unwrap();
            fog
        });
        let view = view(1.6, -0.05);
        let depth_values = scene_depth(view, projection());
        let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depth_values).unwrap();
        let (lights, volumes) = (lights(), local_volumes());
        let inputs = pipeline_inputs(view, &lights, &volumes, medium(), cascades);
        // The first frame without culling, so both fogs start from the same volume (a
        // checkerboard's first frame fills the skipped froxels from their neighbours).
        for f in 0..5 {
            if f == 1 {
                fogs[1].set_scene_depth(&gpu.device, &depth, 0).unwrap();
            }
            let [a, b] = &mut fogs;
            frame(gpu, [a, b], &inputs);
        }
        let live = read_live(gpu, &fogs[1]);
        let (full, culled) = (integrated(gpu, &fogs[0]), integrated(gpu, &fogs[1]));
        let size = base.volume_size;
        // The nearest surface (view depth, m) in each froxel column's screen footprint.
        let view_from_clip = projection().inverse();
        let nearest = |x: u32, y: u32| {
            let (x0, x1) = (x * w / size.x, ((x + 1) * w).div_ceil(size.x).min(w));
            let (y0, y1) = (y * h / size.y, ((y + 1) * h).div_ceil(size.y).min(h));
            let mut near = f32::INFINITY;
            for py in y0..y1 {
                for px in x0..x1 {
                    let d = depth_values[(py * w + px) as usize];
                    let ndc = Vec2::new(
                        2.0 * (px as f32 + 0.5) / w as f32 - 1.0,
                        1.0 - 2.0 * (py as f32 + 0.5) / h as f32,
                    );
                    near = near.min(-view_from_ndc(ndc.extend(d), view_from_clip).z);
                }
            }
            near
        };
        let (mut worst, mut compared, mut straddling) = (0.0f32, 0usize, 0usize);
        for y in 0..size.y {
            for x in 0..size.x {
                let surface = nearest(x, y);
                for z in 0..size.z {
                    // The last live slice is the margin no look-up reaches.
                    if z + 1 >= live[(y * size.x + x) as usize] {
                        continue;
                    }
                    // A froxel that reaches past the surface (its far face, the jitter's
                    // half slice beyond) has shadow taps behind it, which the culled fog
                    // leaves out (shadow_filter::taps_below_the_visible_surface_are_left_out):
                    // the applied image below covers those.
                    let far_face = volfog::cpu::froxel::slice_depth(
                        ((z as f32 + 1.5) / size.z as f32).min(1.0),
                        base.near,
                        base.far,
                        base.slice_curve,
                    );
                    if far_face > surface {
                        straddling += 1;
                        continue;
                    }
                    let i = index(size, x, y, z);
                    let scale = full[i].max_element().max(1e-3);
                    worst = worst.max((culled[i] - full[i]).abs().max_element() / scale);
                    compared += 1;
                }
            }
        }

        // The applied image, with the scene depth.
        let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let base_color = Vec4::new(0.6, 0.3, 0.1, 1.0);
        let images = fogs.each_ref().map(|fog| {
            let apply = fog
                .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
                .unwrap();
            let target =
                gpu.texture_2d_rgba16f("applied", [w, h], &vec![base_color; (w * h) as usize]);
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            fog.record_apply(
                &mut encoder,
                &apply,
                &target.create_view(&Default::default()),
                &apply.depth_bind_group(&gpu.device, &depth_view),
            )
            .unwrap();
            gpu.queue.submit([encoder.finish()]);
            gpu.read_texture_rgba16f(&target).unwrap()
        });
        let image_diff = images[0]
            .iter()
            .zip(&images[1])
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        let fogged = images[0]
            .iter()
            .filter(|p| (**p - base_color).abs().max_element() > 0.02)
            .count();
        eprintln!(
            "temporal={temporal} amortize={amortize}: {compared} read texels in front of the \
             surface ({:.1} % of the volume; {straddling} reaching past it left out), largest relative difference {worst:e} (bound 2e-3, two rgba16float \
             steps); applied images differ by at most {image_diff:e} (bound 2e-3), {fogged} of {} pixels fogged",
            100.0 * compared as f64 / (size.x * size.y * size.z) as f64,
            w * h
        );
        assert!(worst <= 2e-3, "{worst}");
        assert!(image_diff <= 2e-3, "{image_diff}");
        assert!(fogged > (w * h / 2) as usize, "the fog is visible");
        assert!(compared > 0);
    }
}

/// A wall close to the camera culls most froxels while the medium changes; then the
/// wall goes and the camera turns. The froxels behind the wall still hold the old
/// medium (stale). After the turn the culled fog's stabilised volume must equal the CPU
/// mirror of the temporal pass, which gives stale texels no weight, and that answer
/// must differ from a reprojection that ignores culling (so stale texels were there to
/// be avoided).
#[test]
fn disoccluded_froxels_never_take_stale_history() {
    let gpu = gpu();
    // The separate temporal pass, whose input (the scattering volume) is read.
    let config = FogConfig {
        temporal: true,
        fuse_temporal: false,
        jitter: false,
        depth_cull: true,
        ..small_config()
    };
    let (cascades, layers) = overhead_sun(&config, None);
    let shadow = shadow_map(gpu, &layers);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow).unwrap();
    let (w, h) = SCREEN;
    let wall_depth = projection().project_point3(Vec3::new(0.0, 0.0, -4.0)).z;
    let constant = |value: f32| {
        volfog_testkit::selfcheck::depth_texture(gpu, w, h, &vec![value; (w * h) as usize]).unwrap()
    };
    let (wall, sky) = (constant(wall_depth), constant(1.0));
    let (lights, volumes) = (lights(), local_volumes());
    let old = FogMedium {
        density: 0.4,
        albedo: Vec3::new(0.9, 0.1, 0.1),
        ..medium()
    };
    let still = view(1.6, 0.0);
    let turned = Mat4::from_rotation_y(-0.1) * still;
    let run = |fog: &mut VolumetricFog, inputs: &FrameInputs<'_>| {
        fog.prepare(&gpu.queue, inputs).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);
    };
    // 1. Every froxel holds the old medium.
    for _ in 0..3 {
        run(
            &mut fog,
            &pipeline_inputs(still, &lights, &volumes, old, cascades),
        );
    }
    // 2. Behind the wall nothing is updated.
    fog.set_scene_depth(&gpu.device, &wall, 0).unwrap();
    for _ in 0..30 {
        run(
            &mut fog,
            &pipeline_inputs(still, &lights, &volumes, medium(), cascades),
        );
    }
    let history = read_volume(gpu, fog.stabilised_texture().unwrap());
    let walled = read_live(gpu, &fog);
    // 3. The wall goes and the camera turns.
    fog.set_scene_depth(&gpu.device, &sky, 0).unwrap();
    let inputs = pipeline_inputs(turned, &lights, &volumes, medium(), cascades);
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let record = |passes: &[FogPass]| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        for pass in passes {
            fog.encode_pass(&mut encoder, *pass).unwrap();
        }
        gpu.queue.submit([encoder.finish()]);
    };
    let temporal = FogPass::ALL
        .iter()
        .position(|p| *p == FogPass::Temporal)
        .unwrap();
    record(&FogPass::ALL[..temporal]);
    // This frame's injection, before the scan reuses the texture.
    let now = read_volume(gpu, fog.scattering_texture());
    record(&FogPass::ALL[temporal..]);
    let got = read_volume(gpu, fog.stabilised_texture().unwrap());

    let size = config.volume_size;
    let u = expected_uniforms(&config, &inputs, 33);
    let previous = HistoryState {
        clip_from_world: projection() * still,
        valid: 1,
    };
    let all_live = vec![size.z; (size.x * size.y) as usize];
    let volume = |texels: Vec<Vec4>| Volume {
        size: size.to_array(),
        texels,
    };
    let (current, history) = (volume(now), volume(history));
    let mirror = |live: Option<(&[u32], &[u32])>, id: UVec3| {
        temporal_froxel(
            &TemporalInputs {
                froxels: &u.froxels,
                frame: &u.frame,
                previous: &previous,
                current: &current,
                history: &history,
                live_slices: live,
            },
            id,
        )
        .unwrap()
    };
    let (mut worst, mut avoided) = (0.0f32, 0);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = UVec3::new(x, y, z);
                let want = mirror(Some((&all_live, &walled)), id);
                let naive = mirror(None, id);
                let i = index(size, x, y, z);
                let scale = want.max_element().max(1e-3);
                worst = worst.max((got[i] - want).abs().max_element() / scale);
                if (naive - want).abs().max_element() > 0.1 * scale {
                    avoided += 1;
                }
            }
        }
    }
    let total = (size.x * size.y * size.z) as usize;
    let walled_live: u32 = walled.iter().sum();
    eprintln!(
        "behind a wall {:.1} % of the froxels were live; after it goes the stabilised \
         volume matches the CPU mirror within {worst:e} relative (bound 2e-3); in {avoided} \
         of {total} froxels a reprojection ignoring culling would have blended stale texels",
        100.0 * walled_live as f64 / total as f64
    );
    assert!((walled_live as f64) < 0.3 * total as f64);
    assert!(worst <= 2e-3, "{worst}");
    assert!(
        avoided > total / 10,
        "stale texels were in reach: {avoided}"
    );
}

/// One checkerboard frame with culling and the baked noise texture (the fast path):
/// inject computes one froxel of each pair of slices whose first slice is live (the
/// colour of this frame), equal to the CPU mirror (which samples the CPU bake), writes
/// it to both froxels of the pair, and leaves every other texel as it was.
#[test]
fn checkerboard_inject_writes_this_frames_live_froxels_only() {
    let gpu = gpu();
    // The separate temporal pass: inject writes the scattering volume read here.
    let config = FogConfig {
        temporal: true,
        fuse_temporal: false,
        amortize: true,
        depth_cull: true,
        noise_texture: true,
        ..small_config()
    };
    let (cascades, layers) = overhead_sun(&config, Some(SLAB));
    let shadow = shadow_map(gpu, &layers);
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow).unwrap();
    let view = view(1.6, -0.05);
    let (w, h) = SCREEN;
    let depth_values = scene_depth(view, projection());
    let depth = volfog_testkit::selfcheck::depth_texture(gpu, w, h, &depth_values).unwrap();
    let (lights, volumes) = (lights(), local_volumes());
    let inputs = pipeline_inputs(view, &lights, &volumes, medium(), cascades);
    // Frame 0 without culling: every texel of the scattering texture is written (by
    // the scan, which reuses it with temporal reprojection).
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let before = read_volume(gpu, fog.scattering_texture());
    // Frame 1: cull, ESM and inject only.
    fog.set_scene_depth(&gpu.device, &depth, 0).unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for pass in [
        FogPass::Cull,
        FogPass::EsmDownsample,
        FogPass::EsmBlur,
        FogPass::Inject,
    ] {
        fog.encode_pass(&mut encoder, pass).unwrap();
    }
    gpu.queue.submit([encoder.finish()]);
    let after = read_volume(gpu, fog.scattering_texture());
    let live = read_live(gpu, &fog);
    // The compare filter (the default) reads the shadow map itself.
    let esm = if config.shadow_filter.compares() {
        layers.clone()
    } else {
        read_esm(gpu, &fog)
    };
    let mut u = expected_uniforms(&config, &inputs, 1);
    // The scene depth is set: taps behind its surface are left out.
    u.shadow_taps.use_scene_depth = 1;
    let depth_layer = volfog::cpu::esm::Layer {
        width: w,
        height: h,
        texels: depth_values.clone(),
    };
    assert_eq!(u.frame.checkerboard, 1);
    let noise = volfog::cpu::noise::bake_noise_texture();
    let cpu = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &esm,
        shadow_taps: &u.shadow_taps,
        lights: &lights,
        local_volumes: &volumes,
        options: config.inject_options(),
        density_texture: None,
        noise_texture: Some(&noise),
        clouds: None,
        local_shadows: None,
        scene_depth: Some(&depth_layer),
        medium_shadow: None,
    };
    let size = config.volume_size;
    let (mut written, mut kept, mut worst) = (0, 0, 0.0f32);
    let mut sources = std::collections::HashSet::new();
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let id = UVec3::new(x, y, z);
                let i = index(size, x, y, z);
                // A pair of slices is injected when its first slice is live.
                if (z & !1) < live[(y * size.x + x) as usize] {
                    let source = injected_source(id, &u.frame, size.z);
                    assert!(froxel_injected(source, 1, 1) || source.z + 1 == size.z);
                    sources.insert(source);
                    let want = froxel_scattering(&cpu, source);
                    let scale = want.max_element().max(1e-4);
                    worst = worst.max((after[i] - want).abs().max_element() / scale);
                    written += 1;
                } else {
                    assert_eq!(after[i], before[i], "froxel {id} was written");
                    kept += 1;
                }
            }
        }
    }
    eprintln!(
        "checkerboard + culling + noise texture: {} froxels injected, {written} written \
         (worst relative error vs CPU {worst:e}, bound 4e-3), {kept} left untouched",
        sources.len()
    );
    assert!(worst <= 4e-3, "{worst}");
    assert!(written > 0 && kept > 0, "{written} {kept}");
    assert_eq!(2 * sources.len(), written, "one injection per pair");
}
