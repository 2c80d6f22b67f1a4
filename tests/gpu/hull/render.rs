//! One case through the GPU passes (hull_thickness, then hull_composite onto a lit
//! colour) and its errors against the exact chords and the CPU composite.

use super::scene::{Case, Exact};
use super::{DENSITY, FOG_COLOR, HEIGHT, WIDTH};
use glam::Vec4;
use volfog::cpu::hull::{hull_fog, hull_thickness};
use volfog::options::ApplyInput;
use volfog::pipeline::hull::{
    HullCompositePass, HullSumFormat, HullThicknessPass, hull_sum_texture,
};
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::{depth_texture, max_abs_diff, round_f16};
use wgpu::util::DeviceExt;

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
pub(super) struct Errors {
    /// Pixels compared (at least 1 px from a silhouette) and those with fog.
    pub(super) compared: usize,
    pub(super) fogged: usize,
    /// Largest |GPU - exact| / exact over pixels whose chord is at least `floor`.
    pub(super) relative: f32,
    /// Largest |GPU - exact| (m) over all compared pixels.
    pub(super) absolute: f32,
    /// Largest |GPU - exact| / max(exact, floor) over all compared pixels.
    pub(super) floored: f32,
    /// Compared pixels whose counts disagree with the geometry.
    pub(super) count_mismatches: usize,
    /// Compared pixels whose ray crosses two separate parts of the hull in front of
    /// the scene, whose scene point lies in the hull, whose ray starts in the hull.
    pub(super) concave: usize,
    pub(super) scene_in_fog: usize,
    pub(super) camera_in_fog: usize,
    pub(super) before_near: usize,
    /// Composite vs the CPU formula on the GPU thickness (abs, fp16 target).
    pub(super) composite_vs_cpu: f32,
    /// Composite vs the CPU formula on the exact chord (abs).
    pub(super) composite_vs_exact: f32,
}

pub(super) fn measure(
    gpu: &Gpu,
    case: &Case,
    format: HullSumFormat,
    floor: f32,
    input: ApplyInput,
) -> Errors {
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
