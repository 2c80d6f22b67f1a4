//! Stereo fog (`StereoFog`): each eye's scan against the CPU mirror of the resampling
//! scan, each eye against the mono fog rendered from that eye's camera within a bound
//! derived from what the shared volume cannot hold, the shadow boundary at one world
//! position in both eyes, and the typed errors.

mod disparity;
mod equality;
mod errors;
mod multiview;

use crate::common::gpu;
use crate::common::scene::{SLAB, medium, overhead_sun, shadow_map, small_config};
use glam::{Mat4, Vec3, Vec4};
use volfog::cpu::stereo::{StereoEye, off_centre_projection};
use volfog::pipeline::{FogConfig, FrameInputs, StereoFog, VolumetricFog};
use volfog::uniforms::FogMedium;
use volfog_testkit::Gpu;

/// Image size of the applied fog (pixels).
const IMAGE: [u32; 2] = [64, 36];

/// Two eyes `ipd` metres apart at `world_from_head`, looking down its -Z, with
/// mirrored off-centre frusta as a headset gives them (the inner half-angle narrower).
fn eyes(world_from_head: Mat4, ipd: f32) -> [StereoEye; 2] {
    let left = off_centre_projection([-1.05, 0.9, -0.62, 0.55], 0.1, 500.0);
    let right = off_centre_projection([-0.9, 1.05, -0.62, 0.55], 0.1, 500.0);
    [(-0.5, left), (0.5, right)].map(|(side, clip_from_view)| StereoEye {
        view_from_world: (world_from_head
            * Mat4::from_translation(Vec3::new(side * ipd, 0.0, 0.0)))
        .inverse(),
        clip_from_view,
    })
}

/// The head 2 m up, turned a little to the left and down.
fn head() -> Mat4 {
    Mat4::from_rotation_translation(
        glam::Quat::from_rotation_y(0.15) * glam::Quat::from_rotation_x(0.6),
        Vec3::new(0.5, 2.0, 0.0),
    )
}

/// The small scene's configuration without depth culling (stereo fog has none).
fn config() -> FogConfig {
    FogConfig {
        depth_cull: false,
        ..small_config()
    }
}

/// The scene's inputs (medium, lights, the sun shadowed by the slab) for `eye`'s
/// camera (stereo fog reads everything but the camera).
fn inputs<'a>(
    eye: &StereoEye,
    lights: &'a [volfog::uniforms::FogLight],
    cascades: volfog::uniforms::ShadowCascades,
) -> FrameInputs<'a> {
    FrameInputs {
        // Without the noise, whose 3 m features the small grid (froxels 2.4 m wide at
        // 30 m) cannot resolve in either fog: the bound of the comparison is about what
        // sharing the volume changes, not about aliasing both fogs share.
        medium: FogMedium {
            noise_strength: 0.0,
            ..medium()
        },
        lights,
        cascades,
        ..FrameInputs::new(eye.view_from_world, eye.clip_from_view, 0.0)
    }
}

/// A Depth32Float texture of `layers` layers at depth 1 (nothing opaque: every pixel
/// sees the whole volume).
fn far_depth(gpu: &Gpu, layers: u32) -> wgpu::Texture {
    let values = vec![1.0f32; (IMAGE[0] * IMAGE[1]) as usize];
    let slices: Vec<&[f32]> = (0..layers).map(|_| values.as_slice()).collect();
    volfog_testkit::selfcheck::depth_array_texture(gpu, IMAGE[0], IMAGE[1], &slices)
        .expect("depth written")
}

fn depth_layer(depth: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    depth.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        aspect: wgpu::TextureAspect::DepthOnly,
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

/// A black rgba16float render target of `layers` layers.
fn target(gpu: &Gpu, layers: u32) -> wgpu::Texture {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("stereo target"),
        size: wgpu::Extent3d {
            width: IMAGE[0],
            height: IMAGE[1],
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let zeros = vec![0u8; (IMAGE[0] * IMAGE[1] * 8 * layers) as usize];
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &zeros,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(IMAGE[0] * 8),
            rows_per_image: Some(IMAGE[1]),
        },
        texture.size(),
    );
    texture
}

/// One frame of stereo fog over the scene, applied into a two-layer image: the fog,
/// and the image (layer 0 the left eye, then the right; rows of `IMAGE[0]` pixels).
fn stereo_frame(
    gpu: &Gpu,
    config: &FogConfig,
    eyes: &[StereoEye; 2],
    inputs: &FrameInputs<'_>,
    shadow: &wgpu::Texture,
) -> (StereoFog, Vec<Vec4>) {
    let mut fog = StereoFog::new(&gpu.device, config).unwrap();
    fog.shared_mut()
        .set_shadow_map(&gpu.device, shadow)
        .unwrap();
    fog.prepare(&gpu.queue, eyes, inputs).unwrap();
    let apply = fog
        .shared()
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let depth = far_depth(gpu, 2);
    let groups = [0, 1].map(|i| apply.depth_bind_group(&gpu.device, &depth_layer(&depth, i)));
    let image = target(gpu, 2);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    fog.record_apply(&mut encoder, &apply, &image, [&groups[0], &groups[1]])
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let pixels = gpu.read_texture_rgba16f(&image).unwrap();
    (fog, pixels)
}

/// One frame of the mono fog from `inputs`' camera, applied: the fog and its image.
fn mono_frame(
    gpu: &Gpu,
    config: &FogConfig,
    inputs: &FrameInputs<'_>,
    shadow: &wgpu::Texture,
) -> (VolumetricFog, Vec<Vec4>) {
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    fog.set_shadow_map(&gpu.device, shadow).unwrap();
    fog.prepare(&gpu.queue, inputs).unwrap();
    let apply = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let depth = far_depth(gpu, 1);
    let group = apply.depth_bind_group(&gpu.device, &depth_layer(&depth, 0));
    let image = target(gpu, 1);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    fog.record_apply(
        &mut encoder,
        &apply,
        &image.create_view(&Default::default()),
        &group,
    )
    .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let pixels = gpu.read_texture_rgba16f(&image).unwrap();
    (fog, pixels)
}

/// The scene's shadow map and cascades (the sun overhead, the slab in its way).
fn sun(gpu: &Gpu, config: &FogConfig) -> (volfog::uniforms::ShadowCascades, wgpu::Texture) {
    let (cascades, layers) = overhead_sun(config, Some(SLAB));
    (cascades, shadow_map(gpu, &layers))
}
