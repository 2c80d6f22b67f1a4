//! Stereo fog, as the wgpu guide's "Stereo fog (VR)" section shows it: the eyes of a
//! head 2 m up, 64 mm apart with mirrored off-centre frusta as a headset gives them,
//! one `StereoFog` for both, applied to a two-layer swapchain image; written as one
//! side-by-side image (left eye on the left), tone-mapped, as a binary PPM.
//!
//! Where the adapter offers `wgpu::Features::MULTIVIEW`, the same frame is applied
//! again through the multiview route (both eyes in one multiview render pass) and
//! compared with the first, layer by layer.
//!
//! `cargo run --example stereo_fog [-- out.ppm]` (any Vulkan adapter, Mesa's lavapipe
//! included; `WGPU_ADAPTER_NAME` picks one). The host tests check that the guide's
//! blocks appear here line for line; the GPU tests run it.

use std::error::Error;

use glam::{Mat4, Vec3};
use volfog::cpu::stereo::off_centre_projection;
use volfog_testkit::Gpu;

/// Each eye's view (pixels).
const WIDTH: u32 = 480;
const HEIGHT: u32 = 480;

type Result<T = ()> = std::result::Result<T, Box<dyn Error>>;

/// One eye's camera as an XR runtime reports it (OpenXR's `xrLocateViews`).
struct XrView {
    view_from_world: Mat4,
    clip_from_view: Mat4,
}

fn main() -> Result {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "stereo_fog.ppm".into());
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.describe());
    let layers = gpu.checked(|| stereo(&gpu))??;
    let (left, right) = layers.split_at((WIDTH * HEIGHT) as usize);
    write_side_by_side(&out, left, right)?;
    // The fog is where each eye puts it: the halves differ, their mean brightness
    // hardly (the same fog seen 64 mm apart).
    let mean = |v: &[glam::Vec4]| v.iter().map(|p| p.x + p.y + p.z).sum::<f32>() / v.len() as f32;
    let differ = left
        .iter()
        .zip(right)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-3)
        .count();
    println!(
        "wrote {out}: {}x{} side by side; mean {:.4} left, {:.4} right; {differ} pixels differ",
        2 * WIDTH,
        HEIGHT,
        mean(left),
        mean(right)
    );
    assert!(differ > 0, "the eyes see the fog from different places");
    assert!((mean(left) / mean(right) - 1.0).abs() < 0.05);

    let multiview = wgpu::Features::MULTIVIEW;
    if gpu.adapter.features().contains(multiview) {
        let gpu = Gpu::with_features(multiview)?;
        let both = gpu.checked(|| stereo_multiview(&gpu))??;
        let pixels = (WIDTH * HEIGHT) as usize;
        // Layer 1 still holds the clear colour where no view was drawn into it.
        let cleared = Vec3::new(0.05, 0.05, 0.06);
        let second_drawn = both[pixels..]
            .iter()
            .any(|p| (p.truncate() - cleared).abs().max_element() > 1e-3);
        if second_drawn {
            for (eye, (got, want)) in both.chunks(pixels).zip(layers.chunks(pixels)).enumerate() {
                let largest = got
                    .iter()
                    .zip(want)
                    .map(|(a, b)| (*a - *b).abs().max_element())
                    .fold(0.0f32, f32::max);
                println!(
                    "multiview apply, layer {eye}: largest difference {largest:e} from the apply per layer"
                );
                // One rgba16float step at the image's values (below 2).
                assert!(largest <= 1.0 / 1024.0, "the multiview apply matches");
            }
        } else {
            println!(
                "multiview apply: the driver drew no view into layer 1 (Mesa 22.3's lavapipe \
                 draws both views of a multiview pass into layer 0); not compared"
            );
        }
    } else {
        println!("multiview apply: the adapter lacks wgpu::Features::MULTIVIEW; not run");
    }
    Ok(())
}

/// The guide's stereo frame; returns the swapchain image's two layers.
#[rustfmt::skip]
fn stereo(gpu: &Gpu) -> Result<Vec<glam::Vec4>> {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let time = 1.5;
    let head = Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0));
    let eye = |side: f32, tangents: [f32; 4]| XrView {
        view_from_world: (head * Mat4::from_translation(Vec3::new(side * 0.032, 0.0, 0.0))).inverse(),
        clip_from_view: off_centre_projection(tangents, 0.1, 500.0),
    };
    let (left, right) = (eye(-1.0, [-1.05, 0.9, -1.0, 0.95]), eye(1.0, [-0.9, 1.05, -1.0, 0.95]));
    let config = volfog::pipeline::FogConfig::default();
    let (side, _) = config.shadow_map_size();
    let shadow_map = texture(&device, (side, side, config.cascades), wgpu::TextureFormat::Depth32Float);
    let depth_texture = texture(&device, (WIDTH, HEIGHT, 2), wgpu::TextureFormat::Depth32Float);
    let swapchain_image = texture(&device, (WIDTH, HEIGHT, 2), wgpu::TextureFormat::Rgba16Float);
    let [left_depth, right_depth] = [0, 1].map(|layer| depth_texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect: wgpu::TextureAspect::DepthOnly,
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    }));
    clear(&device, &queue, &swapchain_image, &[&left_depth, &right_depth]);

    use volfog::cpu::stereo::StereoEye;
    use volfog::pipeline::{FogConfig, FrameInputs, StereoFog};

    let mut fog = StereoFog::new(&device, &FogConfig::default())?;
    fog.shared_mut().set_shadow_map(&device, &shadow_map)?; // the shared fog takes the textures
    let apply = fog.shared().create_apply(&device, wgpu::TextureFormat::Rgba16Float)?;
    let depth = [left_depth, right_depth].map(|d| apply.depth_bind_group(&device, &d));
    // every frame, the eyes' cameras as the XR runtime gives them (OpenXR's
    // xrLocateViews: each eye's pose and its off-centre field of view)
    let eyes = [left, right].map(|v| StereoEye {
        view_from_world: v.view_from_world,
        clip_from_view: v.clip_from_view,
    });
    // everything but the camera of `inputs` is read: medium, sun, lights, shadows, tail
    fog.prepare(&queue, &eyes, &FrameInputs::new(eyes[0].view_from_world, eyes[0].clip_from_view, time))?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    // the swapchain image: a two-layer array texture, layer 0 the left eye
    fog.record_apply(&mut encoder, &apply, &swapchain_image, [&depth[0], &depth[1]])?;
    queue.submit([encoder.finish()]);

    Ok(gpu.read_texture_rgba16f(&swapchain_image)?)
}

/// The guide's multiview route: the frame of [`stereo`], applied to both eyes in one
/// multiview render pass; returns the swapchain image's two layers.
#[rustfmt::skip]
fn stereo_multiview(gpu: &Gpu) -> Result<Vec<glam::Vec4>> {
    let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
    let time = 1.5;
    let head = Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0));
    let eye = |side: f32, tangents: [f32; 4]| volfog::cpu::stereo::StereoEye {
        view_from_world: (head * Mat4::from_translation(Vec3::new(side * 0.032, 0.0, 0.0))).inverse(),
        clip_from_view: off_centre_projection(tangents, 0.1, 500.0),
    };
    let eyes = [eye(-1.0, [-1.05, 0.9, -1.0, 0.95]), eye(1.0, [-0.9, 1.05, -1.0, 0.95])];
    let config = volfog::pipeline::FogConfig::default();
    let (side, _) = config.shadow_map_size();
    let shadow_map = texture(&device, (side, side, config.cascades), wgpu::TextureFormat::Depth32Float);
    let depth_texture = texture(&device, (WIDTH, HEIGHT, 2), wgpu::TextureFormat::Depth32Float);
    let swapchain_image = texture(&device, (WIDTH, HEIGHT, 2), wgpu::TextureFormat::Rgba16Float);
    let depth_views = [0, 1].map(|layer| depth_texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect: wgpu::TextureAspect::DepthOnly,
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    }));
    clear(&device, &queue, &swapchain_image, &[&depth_views[0], &depth_views[1]]);
    let mut fog = volfog::pipeline::StereoFog::new(&device, &config)?;
    fog.shared_mut().set_shadow_map(&device, &shadow_map)?;
    let inputs = volfog::pipeline::FrameInputs::new(eyes[0].view_from_world, eyes[0].clip_from_view, time);

    // the device was created with wgpu::Features::MULTIVIEW and a
    // Limits::max_multiview_view_count of 2 or more
    let apply = fog.create_apply_multiview(&device, wgpu::TextureFormat::Rgba16Float)?;
    // both eyes' depths in one texture, layer 0 the left eye
    let depth = fog.multiview_depth_bind_group(&device, &apply, &depth_texture)?;
    // every frame: one draw for both layers
    fog.prepare(&queue, &eyes, &inputs)?;
    let mut encoder = device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder)?;
    fog.record_apply_multiview(&mut encoder, &apply, &swapchain_image, &depth)?;
    queue.submit([encoder.finish()]);

    Ok(gpu.read_texture_rgba16f(&swapchain_image)?)
}

/// A 2D texture (array) that passes render to, shaders read and copies read back.
fn texture(
    device: &wgpu::Device,
    (width, height, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Clears each layer of the colour image to a dark grey and the eyes' depths to 1
/// (nothing drawn: each eye sees the whole fog and its tail).
fn clear(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    color: &wgpu::Texture,
    depths: &[&wgpu::TextureView; 2],
) {
    let mut encoder = device.create_command_encoder(&Default::default());
    for (layer, depth) in depths.iter().enumerate() {
        let view = color.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer as u32,
            array_layer_count: Some(1),
            ..Default::default()
        });
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: 0.05,
                        g: 0.05,
                        b: 0.06,
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
    }
    queue.submit([encoder.finish()]);
}

/// Writes the two eyes side by side as a binary PPM, Reinhard tone-mapped and
/// gamma-encoded (2.2).
fn write_side_by_side(path: &str, left: &[glam::Vec4], right: &[glam::Vec4]) -> Result {
    let mut bytes = format!("P6\n{} {}\n255\n", 2 * WIDTH, HEIGHT).into_bytes();
    let tone = |v: f32| ((v / (1.0 + v)).max(0.0).powf(1.0 / 2.2) * 255.0 + 0.5) as u8;
    for y in 0..HEIGHT {
        for eye in [left, right] {
            for x in 0..WIDTH {
                let p = eye[(y * WIDTH + x) as usize];
                bytes.extend([tone(p.x), tone(p.y), tone(p.z)]);
            }
        }
    }
    std::fs::write(path, bytes)?;
    Ok(())
}
