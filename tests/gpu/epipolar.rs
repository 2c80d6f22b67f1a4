//! Epipolar sun shafts (Yusov 2012): the coordinate texture against the CPU mirror for
//! epipoles inside, on the edge of and outside the screen; refinement never
//! interpolating across a depth break; the min/max tree march against the march over
//! every section; the final image against the per-pixel brute-force reference; and the
//! far field of `VolumetricFog` against the analytic tail.

use crate::common;

use common::gpu;
use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};
use volfog::cpu::epipolar as cpu;
use volfog::pipeline::cascade_projection;
use volfog::pipeline::epipolar::{EpipolarError, EpipolarMode, EpipolarShafts};
use volfog::uniforms::{EpipolarFrame, EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::depth_texture;

/// An axis-aligned box (min, max), m.
type Aabb = (Vec3, Vec3);

/// The test scene: a ground plane, three pillars and a bar across them, a low sun ahead
/// of the camera; depth buffer and shadow map ray traced from the same boxes.
struct Scene {
    width: u32,
    height: u32,
    view_from_world: Mat4,
    clip_from_view: Mat4,
    sun: Vec3,
    light_from_world: Mat4,
    shadow_size: u32,
    shadow: Vec<f32>,
    depth: Vec<f32>,
}

const FAR: f32 = 400.0;
const MAX_DEPTH: f32 = 150.0;

fn occluders() -> Vec<Aabb> {
    // Four pillars and a lintel high over the two middle ones.
    let mut boxes = vec![(Vec3::new(-4.0, 16.0, -32.0), Vec3::new(4.0, 17.0, -30.0))];
    for x in [-9.0f32, -3.0, 3.0, 9.0] {
        let top = if x.abs() < 5.0 { 16.0 } else { 12.0 };
        boxes.push((
            Vec3::new(x - 0.8, 0.0, -32.0),
            Vec3::new(x + 0.8, top, -30.0),
        ));
    }
    boxes
}

/// Nearest hit t > 0 of origin + t dir with the boxes and the ground (y = 0).
fn trace(origin: Vec3, dir: Vec3, boxes: &[Aabb]) -> Option<f32> {
    let mut best = f32::INFINITY;
    if dir.y < 0.0 && origin.y > 0.0 {
        best = -origin.y / dir.y;
    }
    for (lo, hi) in boxes {
        let inv = dir.recip();
        let a = (*lo - origin) * inv;
        let b = (*hi - origin) * inv;
        let near = a.min(b).max_element();
        let far = a.max(b).min_element();
        if near <= far && far > 0.0 && near > 0.0 && near < best {
            best = near;
        }
    }
    best.is_finite().then_some(best)
}

fn sun_direction() -> Vec3 {
    Vec3::new(0.15, 0.22, -1.0).normalize()
}

impl Scene {
    fn new(width: u32, height: u32, shadow_size: u32, boxes: &[Aabb], sun: Vec3) -> Self {
        let eye = Vec3::new(0.0, 2.0, 6.0);
        let view_from_world =
            glam::camera::rh::view::look_at_mat4(eye, Vec3::new(0.0, 5.0, -30.0), Vec3::Y);
        let clip_from_view = glam::camera::rh::proj::directx::perspective(
            1.0,
            width as f32 / height as f32,
            0.1,
            FAR,
        );
        let light_from_world = cascade_projection(sun, Vec3::new(0.0, 0.0, -40.0), 70.0, 200.0);
        let light_inv = light_from_world.inverse();
        let shadow = (0..shadow_size * shadow_size)
            .map(|t| {
                let (x, y) = (t % shadow_size, t / shadow_size);
                let u = (x as f32 + 0.5) / shadow_size as f32;
                let v = (y as f32 + 0.5) / shadow_size as f32;
                let start = light_inv.project_point3(Vec3::new(2.0 * u - 1.0, 1.0 - 2.0 * v, 0.0));
                match trace(start, -sun, boxes) {
                    Some(t) => light_from_world
                        .project_point3(start - sun * t)
                        .z
                        .clamp(0.0, 1.0),
                    None => 1.0,
                }
            })
            .collect();
        let world_from_view = view_from_world.inverse();
        let view_from_clip = clip_from_view.inverse();
        let depth = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let ndc = Vec2::new(
                    (x as f32 + 0.5) / width as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / height as f32 * 2.0,
                );
                let p = view_from_clip.project_point3(ndc.extend(0.5));
                let dir = world_from_view.transform_vector3(p).normalize();
                match trace(eye, dir, boxes) {
                    Some(t) => {
                        let view = view_from_world.transform_point3(eye + dir * t);
                        clip_from_view.project_point3(view).z.min(1.0)
                    }
                    None => 1.0,
                }
            })
            .collect();
        Self {
            width,
            height,
            view_from_world,
            clip_from_view,
            sun,
            light_from_world,
            shadow_size,
            shadow,
            depth,
        }
    }

    fn medium(&self) -> HeightFog {
        HeightFog::new(Vec3::new(0.02, 0.025, 0.03), 0.02, Vec3::Y, 0.04, 0.0)
            .unwrap()
            .with_sun(self.sun, Vec3::new(3.0, 2.8, 2.5), 0.5)
            .unwrap()
    }

    fn view(&self, start_depth: f32) -> EpipolarView {
        EpipolarView {
            view_from_world: self.view_from_world,
            clip_from_view: self.clip_from_view,
            light_from_world: self.light_from_world,
            cascade: 0,
            rayleigh: Vec3::new(0.05, 0.1, 0.2),
            phase: EpipolarPhase::HenyeyGreenstein,
            start_depth,
            max_depth: MAX_DEPTH,
            depth_bias: 0.001,
        }
    }

    /// The view depth (m) the coordinate pass reads at a screen point (nearest pixel).
    fn view_depth_at(&self, ndc: Vec2) -> f32 {
        let uv = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
        let x = ((uv.x * self.width as f32).floor() as i64).clamp(0, self.width as i64 - 1);
        let y = ((uv.y * self.height as f32).floor() as i64).clamp(0, self.height as i64 - 1);
        let d = self.depth[(y * self.width as i64 + x) as usize];
        let v = volfog::cpu::froxel::view_from_ndc(ndc.extend(d), self.clip_from_view.inverse());
        v.z.abs().min(MAX_DEPTH)
    }

    fn sampling(&self) -> EpipolarSampling {
        EpipolarSampling {
            slices: 256,
            samples: 256,
            reference_steps: 1024,
            ..EpipolarSampling::new(self.width, self.height, self.shadow_size)
        }
    }

    fn textures(&self, gpu: &Gpu) -> (wgpu::Texture, wgpu::Texture) {
        let depth = depth_texture(gpu, self.width, self.height, &self.depth).unwrap();
        let shadow = depth_texture(gpu, self.shadow_size, self.shadow_size, &self.shadow).unwrap();
        (depth, shadow)
    }
}

/// Runs the shafts once and returns the object (for its textures) and the frame.
fn run(
    gpu: &Gpu,
    scene: &Scene,
    sampling: EpipolarSampling,
    mode: EpipolarMode,
    frame: Option<EpipolarFrame>,
) -> (EpipolarShafts, EpipolarFrame) {
    let mut shafts = EpipolarShafts::new(&gpu.device, sampling).unwrap();
    let (depth, shadow) = scene.textures(gpu);
    shafts.set_inputs(&gpu.device, &depth, &shadow).unwrap();
    let medium = scene.medium();
    let frame = match frame {
        Some(f) => {
            shafts
                .prepare_frame(
                    &gpu.queue,
                    &f,
                    &EpipolarFrame::medium(&medium, scene.view_from_world),
                )
                .unwrap();
            f
        }
        None => shafts
            .prepare(&gpu.queue, &scene.view(0.0), &medium)
            .unwrap(),
    };
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    shafts.encode(&mut encoder, mode).unwrap();
    gpu.queue.submit([encoder.finish()]);
    (shafts, frame)
}

fn read_vec4(gpu: &Gpu, t: &wgpu::Texture) -> Vec<Vec4> {
    let raw = gpu.read_texture_raw(t, 16).unwrap();
    bytemuck::cast_slice::<u8, f32>(&raw)
        .chunks_exact(4)
        .map(Vec4::from_slice)
        .collect()
}

/// The rgb of an rgba32float texture (the marched lit fractions).
fn read_rgb(gpu: &Gpu, t: &wgpu::Texture) -> Vec<Vec3> {
    read_vec4(gpu, t).into_iter().map(Vec4::truncate).collect()
}

fn read_uvec2(gpu: &Gpu, t: &wgpu::Texture) -> Vec<UVec2> {
    bytemuck::cast_slice::<u8, u32>(&gpu.read_texture_raw(t, 4).unwrap())
        .iter()
        .map(|&p| UVec2::new(p & 0xffff, p >> 16))
        .collect()
}

#[test]
fn coordinates_match_the_cpu_for_epipoles_inside_on_the_edge_and_outside() {
    let gpu = gpu();
    let scene = Scene::new(160, 90, 256, &occluders(), sun_direction());
    let sampling = scene.sampling();
    let base = EpipolarFrame::new(&sampling, &scene.view(0.0), scene.sun).unwrap();
    let cases = [
        ("inside", base.light_screen),
        ("on the right edge", Vec2::new(1.0, 0.3)),
        ("on a corner", Vec2::new(-1.0, 1.0)),
        ("outside", Vec2::new(1.8, 1.4)),
        ("far outside", Vec2::new(-40.0, 3.0)),
        ("behind (1e6)", Vec2::new(1e6, -2e5)),
    ];
    for (name, light) in cases {
        let frame = EpipolarFrame {
            light_screen: light,
            ..base
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, Some(frame));
        let got = read_vec4(gpu, shafts.coordinate_texture());
        let want = cpu::coordinates(&frame, |ndc| scene.view_depth_at(ndc));
        let (mut worst_xy, mut worst_z, mut valid, mut flags_differ) = (0.0f32, 0.0f32, 0, 0);
        let mut dead_slices = 0;
        for j in 0..frame.slices as usize {
            let row = j * frame.samples as usize..(j + 1) * frame.samples as usize;
            if want[row.clone()].iter().all(|c| c.w == 0.0) {
                dead_slices += 1;
            }
            for i in row {
                let (g, w) = (got[i], want[i]);
                if (g.w > 0.5) != (w.w > 0.5) {
                    // A sample on the border can fall either side of the tolerance.
                    if (w.x.abs().max(w.y.abs()) - 1.0).abs() > 1e-3 {
                        flags_differ += 1;
                    }
                    continue;
                }
                if w.w > 0.5 {
                    valid += 1;
                    worst_xy = worst_xy.max(
                        (g.truncate().truncate() - w.truncate().truncate())
                            .abs()
                            .max_element(),
                    );
                    worst_z = worst_z.max((g.z - w.z).abs() / w.z.max(1.0));
                }
            }
        }
        eprintln!(
            "epipole {name} {light}: {valid} valid samples, {dead_slices} of {} slices off the screen; worst |xy| {worst_xy:.2e} (bound 1e-4), view depth {worst_z:.2e} (bound 1e-3), validity differs off the border: {flags_differ}",
            frame.slices
        );
        assert_eq!(flags_differ, 0, "{name}");
        assert!(valid > 1000, "{name}: {valid}");
        assert!(worst_xy <= 1e-4, "{name}: {worst_xy}");
        assert!(worst_z <= 1e-3, "{name}: {worst_z}");
        if name.starts_with("outside") || name.starts_with("far") || name.starts_with("behind") {
            assert!(dead_slices > 0, "{name}: some slices miss the screen");
        }
        if name == "inside" {
            assert_eq!(dead_slices, 0);
        }
    }
}

#[test]
fn refinement_never_interpolates_across_a_depth_break() {
    let gpu = gpu();
    let scene = Scene::new(160, 90, 256, &occluders(), sun_direction());
    for step in [8u32, 16, 32, 64] {
        let sampling = EpipolarSampling {
            initial_step: step,
            ..scene.sampling()
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, None);
        let coords = read_vec4(gpu, shafts.coordinate_texture());
        let sources = read_uvec2(gpu, shafts.source_texture());
        let n = frame.samples as usize;
        let (mut marched, mut straddles, mut cpu_differs, mut breaks) = (0, 0, 0, 0);
        for j in 0..frame.slices as usize {
            let depths: Vec<f32> = coords[j * n..(j + 1) * n].iter().map(|c| c.z).collect();
            let want = cpu::refine_slice(&frame, &depths);
            for k in 0..n {
                let s = sources[j * n + k];
                if s != want[k] {
                    cpu_differs += 1;
                }
                if coords[j * n + k].w < 0.5 {
                    continue;
                }
                if s.x == s.y {
                    marched += 1;
                    assert_eq!(s.x as usize, k);
                    continue;
                }
                assert!(s.x as usize <= k && k <= s.y as usize);
                for m in s.x as usize..s.y as usize {
                    if !cpu::continuous(depths[m], depths[m + 1], frame.depth_threshold) {
                        straddles += 1;
                    }
                }
            }
            breaks += (0..n - 1)
                .filter(|&m| {
                    coords[j * n + m].w > 0.5
                        && coords[j * n + m + 1].w > 0.5
                        && !cpu::continuous(depths[m], depths[m + 1], frame.depth_threshold)
                })
                .count();
        }
        eprintln!(
            "initial step {step}: {marched} ray-marching samples, {breaks} depth breaks between valid samples, {straddles} interpolations across a break (bound 0), {cpu_differs} sources differ from the CPU mirror (bound 0)"
        );
        assert!(breaks > 100, "the scene has depth breaks");
        assert_eq!(straddles, 0);
        assert_eq!(cpu_differs, 0);
    }
}

#[test]
fn tree_march_equals_the_march_over_every_section() {
    let gpu = gpu();
    let scene = Scene::new(160, 90, 512, &occluders(), sun_direction());
    let sampling = scene.sampling();
    let (tree, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, None);
    let (steps, _) = run(gpu, &scene, sampling, EpipolarMode::Steps, None);
    let coords = read_vec4(gpu, tree.coordinate_texture());
    let sources = read_uvec2(gpu, tree.source_texture());
    let a: Vec<f32> = read_rgb(gpu, tree.marched_texture())
        .iter()
        .map(|v| v.x)
        .collect();
    let b: Vec<f32> = read_rgb(gpu, steps.marched_texture())
        .iter()
        .map(|v| v.x)
        .collect();
    let layer = cpu::ShadowLayer {
        size: scene.shadow_size,
        depths: &scene.shadow,
    };
    let cpu_tree = cpu::MinMaxTree::build(&frame, &layer);
    let medium = EpipolarFrame::medium(&scene.medium(), scene.view_from_world);
    let (mut count, mut partial, mut worst, mut worst_cpu) = (0, 0, 0.0f32, 0.0f32);
    for i in 0..a.len() {
        if coords[i].w < 0.5 || sources[i].x != sources[i].y {
            continue;
        }
        count += 1;
        let rel = (a[i] - b[i]).abs() / b[i].abs().max(1e-6);
        worst = worst.max(rel);
        let slice = (i / frame.samples as usize) as u32;
        let map = cpu::slice_map(&frame, slice);
        let ray = cpu::ray(
            &frame,
            map,
            coords[i].truncate().truncate(),
            0.0,
            coords[i].z,
        );
        if b[i] > 0.02 && b[i] < 0.98 {
            partial += 1;
        }
        let want = cpu::lit_fraction(
            &medium,
            &ray,
            cpu::march_tree(&cpu_tree, slice, &medium, &ray, None),
        )
        .x;
        worst_cpu = worst_cpu.max((a[i] - want).abs() / want.abs().max(1e-6));
    }
    eprintln!(
        "{count} ray-marching samples, {partial} partly shadowed: lit fraction of the tree march vs every section worst {worst:.2e} relative (bound 1e-4); tree GPU vs CPU worst {worst_cpu:.2e} (bound 1e-4)"
    );
    assert!(count > 2000 && partial > 200, "{count} {partial}");
    assert!(worst <= 1e-4, "{worst}");
    assert!(worst_cpu <= 1e-4, "{worst_cpu}");
}

/// Mean of S over pixels selected by `keep`.
fn mean_where(s: &[Vec4], keep: impl Fn(usize) -> bool) -> (f32, usize) {
    let (sum, n) = s
        .iter()
        .enumerate()
        .filter(|(i, _)| keep(*i))
        .fold((0.0f64, 0), |(a, n), (_, v)| (a + f64::from(v.x), n + 1));
    ((sum / n.max(1) as f64) as f32, n)
}

#[test]
fn final_image_matches_the_per_pixel_reference() {
    let gpu = gpu();
    let scene = Scene::new(192, 108, 512, &occluders(), sun_direction());
    let open = Scene::new(192, 108, 512, &[], sun_direction());
    let sampling = scene.sampling();
    let read = |s: &EpipolarShafts| gpu.read_texture_rgba16f(s.shaft_texture()).unwrap();
    let (reference, _) = run(gpu, &scene, sampling, EpipolarMode::Reference, None);
    let reference = read(&reference);
    let (open_reference, _) = run(gpu, &open, sampling, EpipolarMode::Reference, None);
    let open_reference = read(&open_reference);
    for downscale in [1u32, 2] {
        let sampling = EpipolarSampling {
            downscale,
            ..sampling
        };
        let (shafts, frame) = run(gpu, &scene, sampling, EpipolarMode::Tree, None);
        let image = read(&shafts);
        let (fixed_resolve, fixed_upscale) = shafts.read_corrected(&gpu.device).unwrap();
        assert!(image.iter().all(|p| p.is_finite()), "no NaN");
        let medium = EpipolarFrame::medium(&scene.medium(), scene.view_from_world);
        let (mut err, mut err_light, mut worst) = (0.0f64, 0.0f64, 0.0f32);
        let mut light_scale = 0.0f64;
        for (i, (got, want)) in image.iter().zip(&reference).enumerate() {
            let e = (got.x - want.x).abs();
            err += f64::from(e);
            worst = worst.max(e);
            let (x, y) = (i as u32 % scene.width, i as u32 / scene.width);
            let ndc = Vec2::new(
                (x as f32 + 0.5) / scene.width as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / scene.height as f32 * 2.0,
            );
            let ray = cpu::view_ray(frame.view_from_clip, ndc);
            let p = cpu::phase(&frame, &medium, ray.normalize());
            let lit = cpu::fog(&frame, &medium, ray * want.w, want.truncate());
            let got_lit = cpu::fog(&frame, &medium, ray * want.w, got.truncate());
            err_light += f64::from((got_lit - lit).abs().max_element());
            light_scale += f64::from((p * want.x * (1.0 - lit.w)).max_element());
        }
        let n = image.len() as f64;
        // The occluders' shafts: pixels whose reference S drops by more than 20 % when
        // the occluders are present, against pixels where it does not change, both
        // among sky pixels (same march length).
        let sky = |i: usize| scene.depth[i] >= 1.0;
        let shadowed = |i: usize| sky(i) && reference[i].x < 0.8 * open_reference[i].x;
        let lit = |i: usize| sky(i) && reference[i].x > 0.98 * open_reference[i].x;
        let (ref_shadowed, n_shadowed) = mean_where(&reference, shadowed);
        let (ref_lit, n_lit) = mean_where(&reference, lit);
        let (got_shadowed, _) = mean_where(&image, shadowed);
        let (got_lit, _) = mean_where(&image, lit);
        let (ratio_ref, ratio_got) = (ref_lit / ref_shadowed, got_lit / got_shadowed);
        eprintln!(
            "downscale {downscale}: lit fraction mean abs error {:.2e} (bound 1e-2), worst {worst:.3}; in-scattered light mean abs error {:.2e} = {:.2} % of the sun's mean (bound 1 %); corrected pixels {fixed_resolve} (resolve) + {fixed_upscale} (upscale); shaft ratio lit/shadowed (sky, {n_lit} / {n_shadowed} px) reference {ratio_ref:.2}, epipolar {ratio_got:.2}",
            err / n,
            err_light / n,
            100.0 * err_light / light_scale,
        );
        // F spans [0, 1]; its error sits on shaft edges, where linear interpolation
        // along a slice and between slices blurs an edge over a few pixels, and in the
        // reference's own steps (1024 per ray).
        assert!(err / n <= 1e-2, "{}", err / n);
        assert!(
            err_light / light_scale <= 0.01,
            "{}",
            err_light / light_scale
        );
        assert!(n_shadowed > 50 && n_lit > 50);
        assert!(
            ratio_ref > 1.2,
            "the occluders cast visible shafts: {ratio_ref}"
        );
        assert!(
            (ratio_got / ratio_ref - 1.0).abs() <= 0.1,
            "{ratio_got} vs {ratio_ref}"
        );
    }
}

#[test]
fn bad_sampling_and_inputs_are_typed_errors() {
    let gpu = gpu();
    let scene = Scene::new(64, 36, 128, &occluders(), sun_direction());
    for (bad, field) in [
        (
            EpipolarSampling {
                samples: 200,
                ..scene.sampling()
            },
            "samples",
        ),
        (
            EpipolarSampling {
                initial_step: 4,
                ..scene.sampling()
            },
            "initial_step",
        ),
        (
            EpipolarSampling {
                downscale: 3,
                ..scene.sampling()
            },
            "downscale",
        ),
        (
            EpipolarSampling {
                shadow_size: 1000,
                ..scene.sampling()
            },
            "shadow_size",
        ),
        (
            EpipolarSampling {
                depth_threshold: f32::NAN,
                ..scene.sampling()
            },
            "depth_threshold",
        ),
        (
            EpipolarSampling {
                width: 0,
                ..scene.sampling()
            },
            "width",
        ),
    ] {
        match EpipolarShafts::new(&gpu.device, bad) {
            Err(EpipolarError::Invalid(e)) => assert!(e.field.ends_with(field), "{e}"),
            other => panic!("{field}: {other:?}"),
        }
    }
    let mut shafts = EpipolarShafts::new(&gpu.device, scene.sampling()).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(matches!(
        shafts.encode(&mut encoder, EpipolarMode::Tree),
        Err(EpipolarError::NotReady("set_inputs"))
    ));
    let (depth, shadow) = scene.textures(gpu);
    match shafts.set_inputs(&gpu.device, &shadow, &shadow) {
        Err(EpipolarError::Texture {
            property: "size", ..
        }) => {}
        other => panic!("a depth buffer of the wrong size: {other:?}"),
    }
    shafts.set_inputs(&gpu.device, &depth, &shadow).unwrap();
    assert!(matches!(
        shafts.encode(&mut encoder, EpipolarMode::Tree),
        Err(EpipolarError::NotReady("prepare"))
    ));
    let bad_view = EpipolarView {
        max_depth: -1.0,
        ..scene.view(0.0)
    };
    match shafts.prepare(&gpu.queue, &bad_view, &scene.medium()) {
        Err(EpipolarError::Invalid(e)) => assert_eq!(e.field, "EpipolarView.max_depth"),
        other => panic!("{other:?}"),
    }
    let perspective_light = EpipolarView {
        light_from_world: scene.clip_from_view,
        ..scene.view(0.0)
    };
    match shafts.prepare(&gpu.queue, &perspective_light, &scene.medium()) {
        Err(EpipolarError::Invalid(e)) => assert_eq!(e.field, "EpipolarView.light_from_world"),
        other => panic!("{other:?}"),
    }
    assert!(shafts.memory_bytes() > 0);
}

/// Applies `fog` (the plain apply, or the far field with `shafts`) over the depth buffer
/// `depth` onto a black and a white target: (in-scatter, transmittance) per pixel.
pub(crate) fn apply_over_depth(
    gpu: &Gpu,
    fog: &volfog::pipeline::VolumetricFog,
    depth: &wgpu::Texture,
    shafts: Option<&EpipolarShafts>,
    (w, h): (u32, u32),
) -> Vec<Vec4> {
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let format = wgpu::TextureFormat::Rgba16Float;
    let (apply, group) = match shafts {
        Some(s) => {
            let apply = fog.create_apply_far_field(&gpu.device, format).unwrap();
            let group = apply.far_field_bind_group(&gpu.device, &depth_view, &s.shaft_view());
            (apply, group)
        }
        None => {
            let apply = fog.create_apply(&gpu.device, format).unwrap();
            let group = apply.depth_bind_group(&gpu.device, &depth_view);
            (apply, group)
        }
    };
    let mut images = Vec::new();
    for base in [0.0f32, 1.0] {
        let color =
            gpu.texture_2d_rgba16f("colour", [w, h], &vec![Vec4::splat(base); (w * h) as usize]);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.record_apply(
            &mut encoder,
            &apply,
            &color.create_view(&Default::default()),
            &group,
        )
        .unwrap();
        gpu.queue.submit([encoder.finish()]);
        images.push(gpu.read_texture_rgba16f(&color).unwrap());
    }
    images[0]
        .iter()
        .zip(&images[1])
        .map(|(black, white)| black.truncate().extend(white.x - black.x))
        .collect()
}

#[test]
fn far_field_continues_the_tail_and_shadows_it() {
    use volfog::cpu::ambient::AmbientSh;
    use volfog::pipeline::{FrameInputs, VolumetricFog};
    use volfog::uniforms::{FogMedium, ShadowCascades};
    use volfog_testkit::scene::{projection, small_config, view};

    let gpu = gpu();
    let (w, h) = (64u32, 36u32);
    let config = small_config();
    let far = config.far;
    let sun = Vec3::new(0.2, 0.3, -1.0).normalize();
    let medium = FogMedium {
        density: 0.02,
        height_falloff: 0.04,
        base_height: 0.0,
        noise_strength: 0.0,
        ..FogMedium::default()
    };
    let tail = HeightFog::from_medium(&medium, Vec3::splat(0.05))
        .with_sun(sun, Vec3::new(2.0, 1.8, 1.5), 0.6)
        .unwrap();
    let camera = view(4.0, 0.1);
    let inputs = FrameInputs {
        medium,
        ambient: AmbientSh::constant(Vec3::splat(0.05)),
        cascades: ShadowCascades::default(),
        tail,
        ..FrameInputs::new(camera, projection(), 0.0)
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);

    let shadow_size = 256;
    let light_from_world = cascade_projection(sun, Vec3::new(0.0, 0.0, -150.0), 400.0, 900.0);
    let epipolar_view = EpipolarView {
        view_from_world: camera,
        clip_from_view: projection(),
        light_from_world,
        cascade: 0,
        rayleigh: Vec3::ZERO,
        phase: EpipolarPhase::HenyeyGreenstein,
        start_depth: far,
        max_depth: 500.0,
        depth_bias: 0.0,
    };
    let sampling = EpipolarSampling {
        slices: 128,
        samples: 128,
        downscale: 1,
        ..EpipolarSampling::new(w, h, shadow_size)
    };
    let froxels = volfog_testkit::scene::expected_uniforms(&config, &inputs, 0).froxels;
    let tail_view = tail.to_view_space(camera);
    let view_from_clip = projection().inverse();
    // Shadow maps: nothing casts a shadow (depth 1), or everything above the far
    // plane's depth range is in shadow (depth 0).
    for (name, shadow_depth) in [("open", 1.0f32), ("shadowed", 0.0)] {
        let shadow = depth_texture(
            gpu,
            shadow_size,
            shadow_size,
            &vec![shadow_depth; (shadow_size * shadow_size) as usize],
        )
        .unwrap();
        let mut results = Vec::new();
        for d in [far - 0.01, far + 0.01, far + 150.0] {
            let clip = projection() * Vec4::new(0.0, 0.0, -d, 1.0);
            let depth = depth_texture(gpu, w, h, &vec![clip.z / clip.w; (w * h) as usize]).unwrap();
            let mut shafts = EpipolarShafts::new(&gpu.device, sampling).unwrap();
            shafts.set_inputs(&gpu.device, &depth, &shadow).unwrap();
            shafts.prepare(&gpu.queue, &epipolar_view, &tail).unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            shafts.encode(&mut encoder, EpipolarMode::Tree).unwrap();
            gpu.queue.submit([encoder.finish()]);
            let s = gpu.read_texture_rgba16f(shafts.shaft_texture()).unwrap();
            let plain = apply_over_depth(gpu, &fog, &depth, None, (w, h));
            let field = apply_over_depth(gpu, &fog, &depth, Some(&shafts), (w, h));
            results.push((d, s, plain, field));
        }
        // Continuity across the far plane.
        let (_, _, _, before) = &results[0];
        let (_, _, _, after) = &results[1];
        let step = before
            .iter()
            .zip(after)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        // Beyond it: the far field against the plain tail and the CPU mirror, with
        // the volume's transmittance at the far plane read from the plain apply.
        let (d, s, plain, field) = &results[2];
        let (mut worst_tail, mut worst_cpu, mut worst_s, mut darkening) =
            (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        for i in 0..(w * h) as usize {
            assert!(field[i].is_finite() && s[i].is_finite());
            let (x, y) = (i as u32 % w, i as u32 / w);
            let ndc = Vec2::new(
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            );
            let view_pos = cpu::view_ray(view_from_clip, ndc) * *d;
            let want_s = if shadow_depth > 0.5 { 1.0 } else { 0.0 };
            worst_s = worst_s.max((s[i].x - want_s).abs());
            let t_volume = after[i].w;
            let want_tail = volfog::cpu::apply::fog_tail_shafts(
                &froxels,
                &tail_view,
                view_pos,
                Vec3::splat(want_s),
            );
            let plain_tail = volfog::cpu::apply::fog_tail(&froxels, &tail_view, view_pos);
            // field - plain = T_volume * (tail with shafts - plain tail)
            let want =
                plain[i].truncate() + t_volume * (want_tail.truncate() - plain_tail.truncate());
            worst_cpu = worst_cpu.max(
                (field[i].truncate() - want).abs().max_element() / want.max_element().max(0.05),
            );
            worst_tail = worst_tail.max((field[i] - plain[i]).abs().max_element());
            darkening = darkening.max((plain[i] - field[i]).max_element());
        }
        eprintln!(
            "{name}: far field step across the far plane {step:.2e} (bound 1e-3); at far + 150 m: lit fraction vs 1 (open) or 0 (shadowed) {worst_s:.2e} (bound 2e-3), far field vs CPU mirror {worst_cpu:.2e} relative (bound 5e-3), |far field - plain tail| {worst_tail:.2e}, largest darkening {darkening:.3}"
        );
        assert!(step <= 1e-3, "{name}: {step}");
        assert!(worst_s <= 2e-3, "{name}: {worst_s}");
        assert!(worst_cpu <= 5e-3, "{name}: {worst_cpu}");
        if shadow_depth > 0.5 {
            assert!(
                worst_tail <= 1e-3,
                "unshadowed, the far field is the tail: {worst_tail}"
            );
        } else {
            assert!(
                darkening > 0.02,
                "shadowed, the far field loses the sun's light: {darkening}"
            );
        }
    }
}

/// The functions the passes use per pixel, on the GPU against the CPU mirror for random
/// inputs: the slice of a screen point, its position on that slice's line, the
/// standalone fog with a lit fraction and the far-field tail of the forward snippet
/// (`volfog::apply::fog_tail_shafts`).
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
        .unwrap();
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

/// The main job's self-check of the shafts holds its bounds.
#[test]
fn self_check_of_the_shafts_holds() {
    let check = volfog_testkit::selfcheck::epipolar_check(gpu()).unwrap();
    eprintln!("{check:?}");
    assert!(check.unshadowed <= 1e-3, "{check:?}");
    assert!(check.tree_vs_steps <= 1e-5, "{check:?}");
    assert!(check.partly_shadowed > 100, "{check:?}");
}

/// Coloured shafts (`VOLFOG_EPIPOLAR_COLORED`): a light-space colour texture (a warm
/// band and a blue band of stained glass over the pillars) weights every lit section.
/// The tree march still equals the march over every section and the CPU mirror; the
/// image matches the coloured per-pixel reference; a uniform colour scales the white
/// image channel by channel.
#[test]
fn coloured_shafts_match_every_section_the_cpu_and_the_reference() {
    let gpu = gpu();
    let scene = Scene::new(192, 108, 512, &occluders(), sun_direction());
    let size = scene.shadow_size;
    // Values exact in f16, so the CPU reads what the GPU reads.
    let band = |t: u32| {
        let x = t % size;
        if (size / 4..size / 2).contains(&x) {
            Vec3::new(1.0, 0.5, 0.25)
        } else if (size / 2..size / 2 + size / 8).contains(&x) {
            Vec3::new(0.25, 0.5, 1.0)
        } else {
            Vec3::ONE
        }
    };
    let run_colored = |colors: &[Vec3], mode: EpipolarMode| {
        let sampling = EpipolarSampling {
            colored: true,
            ..scene.sampling()
        };
        let mut shafts = EpipolarShafts::new(&gpu.device, sampling).unwrap();
        let (depth, shadow) = scene.textures(gpu);
        let texels: Vec<Vec4> = colors.iter().map(|c| c.extend(1.0)).collect();
        let color_texture = gpu.texture_2d_rgba16f("light colours", [size, size], &texels);
        assert!(matches!(
            shafts.set_inputs(&gpu.device, &depth, &shadow),
            Err(EpipolarError::Texture {
                property: "presence",
                ..
            })
        ));
        shafts
            .set_inputs_colored(&gpu.device, &depth, &shadow, &color_texture)
            .unwrap();
        let frame = shafts
            .prepare(&gpu.queue, &scene.view(0.0), &scene.medium())
            .unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        shafts.encode(&mut encoder, mode).unwrap();
        gpu.queue.submit([encoder.finish()]);
        (shafts, frame)
    };
    let colors: Vec<Vec3> = (0..size * size).map(band).collect();
    let (tree, frame) = run_colored(&colors, EpipolarMode::Tree);
    let (steps, _) = run_colored(&colors, EpipolarMode::Steps);
    let coords = read_vec4(gpu, tree.coordinate_texture());
    let sources = read_uvec2(gpu, tree.source_texture());
    let a = read_rgb(gpu, tree.marched_texture());
    let b = read_rgb(gpu, steps.marched_texture());
    let layer = cpu::ShadowLayer {
        size,
        depths: &scene.shadow,
    };
    let color_layer = cpu::ColorLayer {
        size,
        colors: &colors,
    };
    let cpu_tree = cpu::MinMaxTree::build(&frame, &layer);
    let medium = EpipolarFrame::medium(&scene.medium(), scene.view_from_world);
    let (mut count, mut tinted, mut worst, mut worst_cpu) = (0, 0, 0.0f32, 0.0f32);
    let mut flips = 0;
    for i in 0..a.len() {
        if coords[i].w < 0.5 || sources[i].x != sources[i].y {
            continue;
        }
        count += 1;
        let rel = |g: Vec3, w: Vec3| ((g - w).abs() / w.abs().max(Vec3::splat(1e-6))).max_element();
        worst = worst.max(rel(a[i], b[i]));
        if (b[i].x - b[i].z).abs() > 0.05 {
            tinted += 1;
        }
        let slice = (i / frame.samples as usize) as u32;
        let map = cpu::slice_map(&frame, slice);
        let ray = cpu::ray(
            &frame,
            map,
            coords[i].truncate().truncate(),
            0.0,
            coords[i].z,
        );
        let s = cpu::march_tree(&cpu_tree, slice, &medium, &ray, Some((map, &color_layer)));
        let e = rel(a[i], cpu::lit_fraction(&medium, &ray, s));
        if e > 1e-4 {
            flips += 1;
        }
        worst_cpu = worst_cpu.max(e);
    }
    // The image against the coloured per-pixel reference, and a uniform colour against
    // the white image.
    let (reference, _) = run_colored(&colors, EpipolarMode::Reference);
    let image = gpu.read_texture_rgba16f(tree.shaft_texture()).unwrap();
    let reference = gpu.read_texture_rgba16f(reference.shaft_texture()).unwrap();
    let n = image.len() as f32;
    let err = image.iter().zip(&reference).fold(Vec3::ZERO, |e, (g, w)| {
        e + (g.truncate() - w.truncate()).abs()
    }) / n;
    let tint = Vec3::new(0.75, 0.5, 0.125);
    let (uniform, _) = run_colored(&vec![tint; (size * size) as usize], EpipolarMode::Tree);
    let (white, _) = run(gpu, &scene, scene.sampling(), EpipolarMode::Tree, None);
    let tinted_image = gpu.read_texture_rgba16f(uniform.shaft_texture()).unwrap();
    let white_image = gpu.read_texture_rgba16f(white.shaft_texture()).unwrap();
    // Beyond the shadow map the light is white: compare pixels whose rays stay on it
    // (view depth <= 60 m; the map reaches 70 m around (0, 0, -40)).
    let scale = tinted_image
        .iter()
        .zip(&white_image)
        .filter(|(_, w)| w.w <= 60.0)
        .map(|(t, w)| (t.truncate() - tint * w.x).abs().max_element())
        .fold(0.0f32, f32::max);
    eprintln!(
        "coloured: {count} ray-marching samples, {tinted} tinted: tree vs every section {worst:.2e} relative (bound 1e-4), GPU vs CPU {worst_cpu:.2e} (bound 1e-2; {flips} samples above 1e-4, bound 1 %); image vs coloured reference mean abs error per channel {:.2e} / {:.2e} / {:.2e} (bound 1e-2); uniform tint vs tint x white image {scale:.2e} (bound 2e-3)",
        err.x, err.y, err.z
    );
    assert!(count > 2000 && tinted > 200, "{count} {tinted}");
    // A section whose texel position lies within f32 rounding of a texel edge can read
    // the neighbouring colour on one side and not the other: one section of about 180
    // changes the sum by up to half its share.
    assert!(worst <= 1e-4 && worst_cpu <= 1e-2, "{worst} {worst_cpu}");
    assert!(flips * 100 <= count, "{flips} of {count}");
    assert!(err.max_element() <= 1e-2, "{err}");
    assert!(scale <= 2e-3, "{scale}");
    assert!(image.iter().all(|p| p.is_finite()));
}
