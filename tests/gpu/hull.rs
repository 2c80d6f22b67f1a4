//! Fog hulls (Boyd 2001) on the GPU: the `hull_thickness` pass against the exact chord
//! length of the same shapes along every pixel's view ray (a convex box, a concave U,
//! opaque objects inside the hull, the camera inside the hull closer to a wall than the
//! near plane), its inside/outside counts against the geometry, and `hull_composite`
//! against the CPU formula. Pixels within 1 px of a silhouette (where the hull or an
//! occluder starts or stops covering the pixel) are left out of the comparisons.

use crate::common;

use common::gpu;
use glam::{Mat4, Vec2, Vec3, Vec4};
use volfog::cpu::hull::{
    HULL_MIN_W, HullMesh, box_interval, boxes_chord, hull_fog, hull_thickness,
};
use volfog::options::ApplyInput;
use volfog::pipeline::hull::{
    HullCompositePass, HullSumFormat, HullThicknessPass, hull_sum_texture,
};
use volfog::uniforms::FogHull;
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::{depth_texture, max_abs_diff, round_f16};
use wgpu::util::DeviceExt;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 72;
const FOV_Y: f32 = std::f32::consts::FRAC_PI_3; // 60 degrees
const FAR: f32 = 100.0;
const DENSITY: f32 = 0.6;
const FOG_COLOR: Vec3 = Vec3::new(0.7, 0.75, 0.8);

/// A camera looking from `eye` at `target` with the given near plane.
struct Camera {
    eye: Vec3,
    near: f32,
    view: Mat4,
    proj: Mat4,
}

impl Camera {
    fn new(eye: Vec3, target: Vec3, near: f32) -> Self {
        Self {
            eye,
            near,
            view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
            proj: glam::camera::rh::proj::directx::perspective(
                FOV_Y,
                WIDTH as f32 / HEIGHT as f32,
                near,
                FAR,
            ),
        }
    }

    /// Unit world direction of the view ray through the centre of pixel (x, y), from
    /// the field of view alone (not from the matrices the GPU uses).
    fn ray(&self, x: u32, y: u32) -> Vec3 {
        let tan = (FOV_Y * 0.5).tan();
        let ndc = Vec2::new(
            (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
            1.0 - (y as f32 + 0.5) / HEIGHT as f32 * 2.0,
        );
        let view_dir = Vec3::new(
            ndc.x * tan * WIDTH as f32 / HEIGHT as f32,
            ndc.y * tan,
            -1.0,
        );
        self.view.inverse().transform_vector3(view_dir).normalize()
    }

    /// Depth-buffer value of a world point.
    fn depth(&self, world: Vec3) -> f32 {
        let clip = self.proj * self.view * world.extend(1.0);
        clip.z / clip.w
    }
}

/// A test scene: a hull (mesh and the boxes it is made of), opaque boxes, a camera.
struct Case {
    name: &'static str,
    camera: Camera,
    mesh: HullMesh,
    boxes: Vec<(Vec3, Vec3)>,
    occluders: Vec<(Vec3, Vec3)>,
    /// Least number of compared pixels that must show each feature: two hull parts
    /// on one ray, the scene point in fog, a crossing closer than the near plane.
    min_concave: usize,
    min_scene_in_fog: usize,
    min_before_near: usize,
}

/// What the geometry says about one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Exact {
    /// Chord length in front of the scene (m).
    chord: f32,
    /// Distance of the opaque surface (infinite for the background).
    scene: f32,
    /// Depth-buffer value.
    depth: f32,
    /// The camera lies inside the hull.
    camera_inside: bool,
    /// The scene point lies inside the hull.
    scene_inside: bool,
    /// A hull crossing in front of the scene lies closer than the near plane.
    before_near: bool,
    /// Fog intervals (merged over the boxes) starting in front of the scene, and
    /// whether an occluder is hit: pixels whose neighbours differ are on a silhouette.
    signature: (usize, bool),
}

impl Case {
    fn exact(&self, x: u32, y: u32) -> Exact {
        let (eye, dir) = (self.camera.eye, self.camera.ray(x, y));
        let hit = self
            .occluders
            .iter()
            .filter_map(|(min, max)| box_interval(eye, dir, *min, *max).map(|(t, _)| t))
            .fold(f32::INFINITY, f32::min);
        let (scene, depth) = if hit.is_finite() {
            (hit, self.camera.depth(eye + dir * hit))
        } else {
            (f32::INFINITY, 1.0)
        };
        let mut intervals: Vec<(f32, f32)> = self
            .boxes
            .iter()
            .filter_map(|(min, max)| box_interval(eye, dir, *min, *max))
            .collect();
        intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut merged: Vec<(f32, f32)> = Vec::new();
        for (enter, exit) in intervals {
            match merged.last_mut() {
                Some(last) if enter <= last.1 + 1e-5 => last.1 = last.1.max(exit),
                _ => merged.push((enter, exit)),
            }
        }
        let inside = |p: Vec3| {
            self.boxes
                .iter()
                .any(|(min, max)| p.cmpgt(*min).all() && p.cmplt(*max).all())
        };
        Exact {
            chord: boxes_chord(eye, dir, &self.boxes, scene),
            scene,
            depth,
            camera_inside: inside(eye),
            scene_inside: hit.is_finite() && inside(eye + dir * hit),
            before_near: merged.iter().any(|&(enter, exit)| {
                (enter > 0.0 && enter < self.camera.near.min(scene))
                    || exit < self.camera.near.min(scene)
            }),
            signature: (
                merged.iter().filter(|(enter, _)| *enter < scene).count(),
                hit.is_finite(),
            ),
        }
    }

    /// Every pixel's exact values and whether it is at least 1 px from a silhouette.
    fn exact_image(&self) -> (Vec<Exact>, Vec<bool>) {
        let exact: Vec<Exact> = (0..HEIGHT)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .map(|(x, y)| self.exact(x, y))
            .collect();
        let at = |x: i32, y: i32| {
            let (x, y) = (x.clamp(0, WIDTH as i32 - 1), y.clamp(0, HEIGHT as i32 - 1));
            exact[(y as u32 * WIDTH + x as u32) as usize].signature
        };
        let interior = (0..HEIGHT as i32)
            .flat_map(|y| (0..WIDTH as i32).map(move |x| (x, y)))
            .map(|(x, y)| (-1..=1).all(|dy| (-1..=1).all(|dx| at(x + dx, y + dy) == at(x, y))))
            .collect();
        (exact, interior)
    }

    fn hull(&self, format: HullSumFormat) -> FogHull {
        let hull = FogHull::new(self.camera.proj, self.camera.view, FOG_COLOR, DENSITY).unwrap();
        match format {
            HullSumFormat::Full => hull,
            HullSumFormat::Half => {
                // The U's rays cross its surface up to 4 times.
                let (reference, quantum) = self.mesh.depth_range(self.camera.eye, 4);
                hull.with_depth_range(reference, quantum).unwrap()
            }
        }
    }
}

/// A colour per pixel for the composite: a smooth gradient.
fn lit_color(i: usize) -> Vec4 {
    let (x, y) = ((i as u32 % WIDTH) as f32, (i as u32 / WIDTH) as f32);
    Vec4::new(x / WIDTH as f32, y / HEIGHT as f32, 0.3, 1.0)
}

fn texture_2d(gpu: &Gpu, format: wgpu::TextureFormat, bytes: &[u8]) -> wgpu::Texture {
    let size = wgpu::Extent3d {
        width: WIDTH,
        height: HEIGHT,
        depth_or_array_layers: 1,
    };
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("lit colour"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytes,
    )
}

fn attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    }
}

/// Runs hull_thickness then hull_composite (onto `lit_color`); returns the hull sum
/// and the composited colour.
fn render(
    gpu: &Gpu,
    case: &Case,
    exact: &[Exact],
    format: HullSumFormat,
    input: ApplyInput,
) -> (Vec<Vec4>, Vec<Vec4>) {
    let device = &gpu.device;
    let thickness = gpu
        .checked(|| HullThicknessPass::with_input(device, format, input))
        .unwrap()
        .unwrap();
    let composite = gpu
        .checked(|| HullCompositePass::new(device, wgpu::TextureFormat::Rgba16Float))
        .unwrap()
        .unwrap();
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fog hull"),
        contents: &case.hull(format).to_bytes(),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hull vertices"),
        contents: bytemuck::cast_slice(&case.mesh.positions),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hull indices"),
        contents: bytemuck::cast_slice(&case.mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    let depths: Vec<f32> = exact.iter().map(|e| e.depth).collect();
    let depth_view = match input {
        ApplyInput::Depth | ApplyInput::FarField => depth_texture(gpu, WIDTH, HEIGHT, &depths)
            .unwrap()
            .create_view(&wgpu::TextureViewDescriptor {
                aspect: wgpu::TextureAspect::DepthOnly,
                ..Default::default()
            }),
        ApplyInput::ResolvedLayout => {
            // The resolved MSAA fog layout: view depth (m) in r, fog amount 0 in g.
            let view_from_clip = case.camera.proj.inverse();
            let layout: Vec<half::f16> = depths
                .iter()
                .flat_map(|d| {
                    let p = view_from_clip * Vec4::new(0.0, 0.0, *d, 1.0);
                    let z = if p.w.abs() < 1e-30 {
                        65504.0
                    } else {
                        (-p.z / p.w).min(65504.0)
                    };
                    [half::f16::from_f32(z), half::f16::ZERO]
                })
                .collect();
            device
                .create_texture_with_data(
                    &gpu.queue,
                    &wgpu::TextureDescriptor {
                        label: Some("resolved layout"),
                        size: wgpu::Extent3d {
                            width: WIDTH,
                            height: HEIGHT,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: volfog::options::FOG_LAYOUT_FORMAT,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    bytemuck::cast_slice(&layout),
                )
                .create_view(&Default::default())
        }
    };
    let sum = hull_sum_texture(device, [WIDTH, HEIGHT], format);
    let sum_view = sum.create_view(&Default::default());
    let colors: Vec<half::f16> = (0..exact.len())
        .flat_map(|i| lit_color(i).to_array().map(half::f16::from_f32))
        .collect();
    let color = texture_2d(
        gpu,
        wgpu::TextureFormat::Rgba16Float,
        bytemuck::cast_slice(&colors),
    );
    let color_view = color.create_view(&Default::default());
    let (thickness_group, composite_group) = gpu
        .checked(|| {
            (
                thickness.bind_group(device, &uniform, &depth_view),
                composite.bind_group(device, &uniform, &sum_view),
            )
        })
        .unwrap();
    gpu.checked(|| {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hull_thickness"),
                color_attachments: &[Some(attachment(
                    &sum_view,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                ))],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            thickness.encode(
                &mut pass,
                &thickness_group,
                &vertices,
                &indices,
                case.mesh.indices.len() as u32,
            );
        }
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hull_composite"),
                color_attachments: &[Some(attachment(&color_view, wgpu::LoadOp::Load))],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            composite.encode(&mut pass, &composite_group);
        }
        gpu.queue.submit([encoder.finish()]);
    })
    .unwrap();
    let sums = match format {
        HullSumFormat::Half => gpu.read_texture_rgba16f(&sum).unwrap(),
        HullSumFormat::Full => {
            let raw = gpu.read_texture_raw(&sum, 16).unwrap();
            bytemuck::cast_slice::<u8, f32>(&raw)
                .chunks_exact(4)
                .map(Vec4::from_slice)
                .collect()
        }
    };
    (sums, gpu.read_texture_rgba16f(&color).unwrap())
}

/// Measured errors of one case in one format.
#[derive(Debug, Default)]
struct Errors {
    /// Pixels compared (at least 1 px from a silhouette) and those with fog.
    compared: usize,
    fogged: usize,
    /// Largest |GPU - exact| / exact over pixels whose chord is at least `floor`.
    relative: f32,
    /// Largest |GPU - exact| (m) over all compared pixels.
    absolute: f32,
    /// Largest |GPU - exact| / max(exact, floor) over all compared pixels.
    floored: f32,
    /// Compared pixels whose counts disagree with the geometry.
    count_mismatches: usize,
    /// Compared pixels whose ray crosses two separate parts of the hull in front of
    /// the scene, whose scene point lies in the hull, whose ray starts in the hull.
    concave: usize,
    scene_in_fog: usize,
    camera_in_fog: usize,
    before_near: usize,
    /// Composite vs the CPU formula on the GPU thickness (abs, fp16 target).
    composite_vs_cpu: f32,
    /// Composite vs the CPU formula on the exact chord (abs).
    composite_vs_exact: f32,
}

fn measure(gpu: &Gpu, case: &Case, format: HullSumFormat, floor: f32, input: ApplyInput) -> Errors {
    let (exact, interior) = case.exact_image();
    let (sums, composited) = render(gpu, case, &exact, format, input);
    assert!(
        sums.iter().chain(&composited).all(|v| v.is_finite()),
        "{}: non-finite GPU output",
        case.name
    );
    let mut e = Errors::default();
    let mut from_gpu = Vec::new();
    let mut got_c = Vec::new();
    let mut from_exact = Vec::new();
    for (i, ((ex, sum), inner)) in exact.iter().zip(&sums).zip(&interior).enumerate() {
        let lit = round_f16(lit_color(i)).truncate();
        let fog = hull_fog(hull_thickness(*sum), DENSITY, FOG_COLOR);
        from_gpu.push((lit * fog.w + fog.truncate()).extend(1.0));
        if !inner {
            continue;
        }
        got_c.push(composited[i]);
        let fog_exact = hull_fog(ex.chord, DENSITY, FOG_COLOR);
        from_exact.push((lit * fog_exact.w + fog_exact.truncate()).extend(1.0));
        e.compared += 1;
        e.concave += usize::from(ex.signature.0 >= 2);
        e.scene_in_fog += usize::from(ex.scene_inside);
        e.camera_in_fog += usize::from(ex.camera_inside);
        e.before_near += usize::from(ex.before_near);
        let err = (hull_thickness(*sum) - ex.chord).abs();
        e.absolute = e.absolute.max(err);
        e.floored = e.floored.max(err / ex.chord.max(floor));
        if ex.chord >= floor {
            e.fogged += 1;
            e.relative = e.relative.max(err / ex.chord);
        }
        let integral = (sum.y - sum.y.round()).abs() < 1e-3 && (sum.z - sum.z.round()).abs() < 1e-3;
        let counts = (sum.y.round() as i32, sum.z.round() as i32);
        let want = (ex.camera_inside as i32, ex.scene_inside as i32);
        if counts != want || !integral {
            e.count_mismatches += 1;
        }
    }
    e.composite_vs_cpu = max_abs_diff(&composited, &from_gpu);
    e.composite_vs_exact = max_abs_diff(&got_c, &from_exact);
    assert!(
        e.concave >= case.min_concave
            && e.scene_in_fog >= case.min_scene_in_fog
            && e.before_near >= case.min_before_near,
        "{}: the view misses a feature the case is for: {e:?}",
        case.name
    );
    eprintln!(
        "{:<28} {format:?}: {} px compared, {} with chord >= {floor} m: max rel {:.3e}, \
         max abs {:.3e} m, max err / max(chord, {floor}) {:.3e}; count mismatches {} (two hull parts {}, \
         scene in fog {}, camera in fog {}, crossing before near {}); composite vs CPU {:.2e}, vs exact {:.2e}",
        case.name,
        e.compared,
        e.fogged,
        e.relative,
        e.absolute,
        e.floored,
        e.count_mismatches,
        e.concave,
        e.scene_in_fog,
        e.camera_in_fog,
        e.before_near,
        e.composite_vs_cpu,
        e.composite_vs_exact
    );
    e
}

/// The U of the concave cases: outline in xy (pillars x in [-1.5, -0.5] and
/// [0.5, 1.5] for y in [-0.5, 1.5], bar y in [-1.5, -0.5]), z in [-0.75, 0.75].
fn u_shape() -> (HullMesh, Vec<(Vec3, Vec3)>) {
    let outline = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 3.0),
        (2.0, 3.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 3.0),
        (0.0, 3.0),
    ]
    .map(|(x, y)| Vec2::new(x - 1.5, y - 1.5));
    let z = 0.75;
    let boxes = vec![
        (Vec3::new(-1.5, -1.5, -z), Vec3::new(1.5, -0.5, z)),
        (Vec3::new(-1.5, -0.5, -z), Vec3::new(-0.5, 1.5, z)),
        (Vec3::new(0.5, -0.5, -z), Vec3::new(1.5, 1.5, z)),
    ];
    (HullMesh::prism(&outline, -z, z), boxes)
}

fn cases() -> Vec<Case> {
    let (u_mesh, u_boxes) = u_shape();
    let (box_min, box_max) = (Vec3::new(-1.0, -0.75, -1.0), Vec3::new(1.0, 0.75, 1.0));
    let (room_min, room_max) = (Vec3::new(-2.0, -1.0, -2.0), Vec3::new(2.0, 1.0, 2.0));
    vec![
        Case {
            name: "(a) convex box",
            camera: Camera::new(Vec3::new(2.0, 1.5, 3.0), Vec3::ZERO, 0.1),
            mesh: HullMesh::cuboid(box_min, box_max),
            boxes: vec![(box_min, box_max)],
            occluders: vec![],
            min_concave: 0,
            min_scene_in_fog: 0,
            min_before_near: 0,
        },
        Case {
            name: "(b) concave U",
            camera: Camera::new(Vec3::new(5.0, 1.0, 1.5), Vec3::new(0.0, 0.3, 0.0), 0.1),
            mesh: u_mesh.clone(),
            boxes: u_boxes.clone(),
            occluders: vec![],
            min_concave: 200,
            min_scene_in_fog: 0,
            min_before_near: 0,
        },
        Case {
            name: "(c) objects inside the U",
            camera: Camera::new(Vec3::new(4.0, 2.0, 1.5), Vec3::new(0.0, -0.2, 0.0), 0.1),
            mesh: u_mesh.clone(),
            boxes: u_boxes.clone(),
            occluders: vec![
                // Straddles the left pillar's inner wall (x = -0.5).
                (Vec3::new(-1.0, -0.2, -0.4), Vec3::new(0.0, 0.6, 0.4)),
                // Wholly inside the right pillar and the bar.
                (Vec3::new(0.6, -1.4, -0.6), Vec3::new(1.4, 0.2, 0.6)),
            ],
            min_concave: 20,
            min_scene_in_fog: 100,
            min_before_near: 0,
        },
        Case {
            name: "(d) camera inside a box",
            camera: Camera::new(Vec3::new(1.9, 0.2, 0.5), Vec3::new(1.0, -0.2, -3.0), 0.5),
            mesh: HullMesh::cuboid(room_min, room_max),
            boxes: vec![(room_min, room_max)],
            occluders: vec![(Vec3::new(1.2, -0.6, -1.4), Vec3::new(1.8, 0.1, -0.9))],
            min_concave: 0,
            min_scene_in_fog: 200,
            min_before_near: 200,
        },
        Case {
            name: "(d) camera inside the U",
            camera: Camera::new(Vec3::new(-0.7, 0.5, 0.0), Vec3::new(1.0, 0.3, 0.2), 0.5),
            mesh: u_mesh,
            boxes: u_boxes,
            occluders: vec![],
            min_concave: 1000,
            min_scene_in_fog: 0,
            min_before_near: 1000,
        },
    ]
}

#[test]
fn float32_blendable_is_reported() {
    let gpu = gpu();
    let features = gpu.adapter.features();
    eprintln!(
        "FLOAT32_BLENDABLE: {}; hull sum format: {:?}",
        features.contains(wgpu::Features::FLOAT32_BLENDABLE),
        HullSumFormat::best(features)
    );
    let device_features = gpu.device.features();
    assert_eq!(
        HullThicknessPass::new(&gpu.device, HullSumFormat::Full).is_ok(),
        device_features.contains(wgpu::Features::FLOAT32_BLENDABLE)
    );
    // A device opened without the feature refuses the rgba32float sum with a typed error.
    let (plain, _) = pollster::block_on(gpu.adapter.request_device(&Default::default())).unwrap();
    assert!(matches!(
        HullThicknessPass::new(&plain, HullSumFormat::Full),
        Err(volfog::pipeline::hull::HullError::Float32BlendableMissing)
    ));
}

#[test]
fn thickness_matches_exact_chords_rgba16float() {
    let gpu = gpu();
    for case in cases() {
        // fp16 terms relative to the reference, split at the quantum (2^-8 m or less
        // here): 1 % of the chord per pixel, down to 1 mm chords.
        let e = measure(gpu, &case, HullSumFormat::Half, 1e-3, ApplyInput::Depth);
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_cpu <= 2e-3, "{}: {e:?}", case.name);
        // 1 % of the thickness moves T by at most density * 0.01 * chord * T <= 0.0023.
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}

#[test]
fn thickness_matches_exact_chords_rgba32float() {
    let gpu = gpu();
    gpu.require(wgpu::Features::FLOAT32_BLENDABLE);
    for case in cases() {
        // 1 % of the chord per pixel, down to 1 mm chords.
        let e = measure(gpu, &case, HullSumFormat::Full, 1e-3, ApplyInput::Depth);
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_cpu <= 2e-3, "{}: {e:?}", case.name);
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}

/// A multisampled scene: the thickness pass reads the scene's view depth from the
/// resolved MSAA fog layout (`VOLFOG_HULL_RESOLVED`, rg16float). Against the same
/// exact chords; rg16float keeps 11 bits of the view depth (0.05 %, a few millimetres
/// at these distances), so the bound is 1 % of the chord down to 0.5 m chords.
#[test]
fn thickness_from_the_resolved_msaa_layout_matches_exact_chords() {
    let gpu = gpu();
    for case in cases() {
        let e = measure(
            gpu,
            &case,
            HullSumFormat::Half,
            0.5,
            ApplyInput::ResolvedLayout,
        );
        assert!(
            e.compared > 500 && e.fogged > 100,
            "{}: too few pixels",
            case.name
        );
        assert!(e.floored <= 0.01, "{}: {e:?}", case.name);
        assert_eq!(e.count_mismatches, 0, "{}", case.name);
        assert!(e.composite_vs_exact <= 5e-3, "{}: {e:?}", case.name);
    }
}

/// The scene distance from a view depth (the resolved layout's path) equals the one
/// from the depth-buffer value of the same point, on the CPU, for standard and
/// reversed projections.
#[test]
fn scene_distance_from_view_depth_equals_the_depth_buffer_path() {
    use volfog::cpu::hull::{hull_scene_distance, hull_scene_distance_from_view_depth};
    for proj in [
        glam::camera::rh::proj::directx::perspective(1.0, 1.6, 0.1, 300.0),
        glam::camera::rh::proj::directx::perspective(1.0, 1.6, 300.0, 0.1),
    ] {
        let view_from_clip = proj.inverse();
        for (u, v, z) in [
            (0.5, 0.5, 2.0f32),
            (0.05, 0.9, 40.0),
            (0.97, 0.1, 250.0),
            (0.3, 0.7, 0.3),
        ] {
            let uv = glam::Vec2::new(u, v);
            let ndc = volfog::cpu::froxel::ndc_from_uv(uv);
            let p = view_from_clip.project_point3(ndc.extend(0.5));
            let view = p * (z / p.z.abs());
            let clip = proj * view.extend(1.0);
            let from_depth = hull_scene_distance(ndc.extend(clip.z / clip.w), view_from_clip);
            let from_view = hull_scene_distance_from_view_depth(uv, z, view_from_clip);
            assert!(
                (from_view - view.length()).abs() <= 1e-5 * view.length(),
                "{from_view} vs {}",
                view.length()
            );
            assert!(
                (from_view - from_depth).abs() <= 1e-4 * view.length(),
                "{from_view} vs {from_depth}"
            );
        }
    }
}

#[test]
fn near_clamp_keeps_faces_in_front_of_the_near_plane() {
    // The clip depth w - HULL_MIN_W lies in [0, w] for every w >= HULL_MIN_W: a face at
    // 0.2 m with a 0.5 m near plane is not clipped, one behind the camera is.
    let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.5, 100.0);
    for (view_z, kept) in [(-0.2, true), (-50.0, true), (-500.0, true), (0.5, false)] {
        let clip = volfog::cpu::hull::hull_clip_position(proj * Vec4::new(0.1, 0.0, view_z, 1.0));
        let inside = clip.z >= 0.0 && clip.z <= clip.w;
        assert_eq!(inside, kept, "view z {view_z}");
    }
    // Only hull surfaces within HULL_MIN_W of the camera plane are lost.
    let clip =
        volfog::cpu::hull::hull_clip_position(proj * Vec4::new(0.0, 0.0, -HULL_MIN_W * 2.0, 1.0));
    assert!(clip.z >= 0.0 && clip.z <= clip.w);
}
