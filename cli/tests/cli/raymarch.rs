//! The bench's per-pixel raymarch reference integrates the same medium as the froxel
//! pipeline, so the comparison is like for like (its sun's shadow from a filtered ESM of
//! the bench's cascades).

use glam::{Mat4, Vec2, Vec3, Vec4};
use volfog::cpu;
use volfog::cpu::ambient::AmbientSh;
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogMedium};
use volfog_cli::bench::raymarch;
use volfog_testkit::Gpu;
use volfog_testkit::rng::rel_err;
use volfog_testkit::scene::{expected_uniforms, projection, view};

/// Depth-buffer values of a ground plane y = 0 (1 for the sky), row by row from the top.
fn ground_depth(view: Mat4, projection: Mat4, width: u32, height: u32) -> Vec<f32> {
    let world_from_view = view.inverse();
    let view_from_clip = projection.inverse();
    let eye = world_from_view.w_axis.truncate();
    (0..width * height)
        .map(|i| {
            let uv = Vec2::new(
                ((i % width) as f32 + 0.5) / width as f32,
                ((i / width) as f32 + 0.5) / height as f32,
            );
            let ray = cpu::froxel::view_from_ndc(
                cpu::froxel::ndc_from_uv(uv).extend(0.5),
                view_from_clip,
            );
            let dir = world_from_view.transform_vector3(ray);
            if dir.y >= 0.0 {
                return 1.0;
            }
            let hit = eye + dir * (-eye.y / dir.y);
            (projection * view).project_point3(hit).z
        })
        .collect()
}

fn target(gpu: &Gpu, width: u32, height: u32) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("fog target"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Fog (rgb in-scatter, a transmittance) drawn by `draw` with the fog blend, read from
/// a black and a white target: L = black, T = white - black.
fn fog_image(
    gpu: &Gpu,
    width: u32,
    height: u32,
    draw: impl Fn(&mut wgpu::CommandEncoder, &wgpu::TextureView),
) -> Vec<Vec4> {
    let mut images = Vec::new();
    for clear in [0.0, 1.0] {
        let texture = target(gpu, width, height);
        let view = texture.create_view(&Default::default());
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: clear,
                        g: clear,
                        b: clear,
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw(&mut encoder, &view);
        gpu.queue.submit([encoder.finish()]);
        images.push(gpu.read_texture_rgba16f(&texture).unwrap());
    }
    images[0]
        .iter()
        .zip(&images[1])
        .map(|(black, white)| black.truncate().extend(white.x - black.x))
        .collect()
}

/// Homogeneous fog lit by an unshadowed sun and sky/ground ambient, over a ground
/// plane and the sky: the 64-step raymarch must match the closed form per pixel
/// L = albedo L_in(view_dir) (1 - e^(-sigma_t d)), T = e^(-sigma_t d) with d the path
/// from the near plane to the ground or the far plane, and the froxel pipeline
/// (default 160x90x128 grid, no jitter, no temporal blending) must match the raymarch.
#[test]
fn raymarch_reference_matches_the_froxel_pipeline_in_homogeneous_fog() {
    let gpu = Gpu::shared();
    let (width, height) = (320, 180);
    // The raymarch and this closed form light the fog as clear air would (no light
    // transmittance through the medium), and a uniform fog without a top would let no
    // sunlight through.
    let config = FogConfig {
        jitter: false,
        temporal: false,
        light_transmittance: false,
        ..FogConfig::default()
    };
    let sigma_t = 0.04;
    let albedo = Vec3::new(0.9, 0.8, 0.7);
    let medium = FogMedium {
        density: sigma_t,
        height_falloff: 0.0,
        noise_strength: 0.0,
        albedo,
        phase_g: 0.5,
        ..FogMedium::default()
    };
    let sun = DirectionalLight {
        direction: Vec3::new(0.3, 0.25, -0.92).normalize(),
        ..DirectionalLight::default()
    };
    let ambient = AmbientSh::sky_ground(
        Vec3::new(0.2, 0.25, 0.35),
        Vec3::new(0.05, 0.04, 0.03),
        Vec3::Y,
    );
    let camera = view(2.0, -0.08);
    let inputs = FrameInputs {
        medium,
        sun,
        ambient,
        ..FrameInputs::new(camera, projection(), 0.0)
    };
    let depth_values = ground_depth(camera, projection(), width, height);
    let depth =
        volfog_testkit::selfcheck::depth_texture(gpu, width, height, &depth_values).unwrap();
    let depth = depth.create_view(&wgpu::TextureViewDescriptor {
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });

    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let apply = fog
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let depth_group = apply.depth_bind_group(&gpu.device, &depth);
    let froxel = fog_image(gpu, width, height, |encoder, view| {
        fog.record_apply(encoder, &apply, view, &depth_group)
            .unwrap()
    });

    let reference = raymarch::Raymarch::new(
        &gpu.device,
        &raymarch::RaymarchOptions {
            steps: raymarch::RAYMARCH_STEPS,
            noise_octaves: config.noise_octaves,
            color_format: wgpu::TextureFormat::Rgba16Float,
            max_lights: config.max_lights,
            max_local_volumes: config.max_local_volumes,
        },
    )
    .unwrap();
    reference.upload(
        &gpu.queue,
        &expected_uniforms(&config, &inputs, 0),
        &[],
        &[],
    );
    let esm = fog.esm_texture().create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let group = reference.bind_group(&gpu.device, &esm, &depth);
    let marched = fog_image(gpu, width, height, |encoder, view| {
        reference.draw(encoder, view, &group, None)
    });

    // Closed form per pixel.
    let view_from_clip = projection().inverse();
    let world_from_view = camera.inverse();
    let expected: Vec<Vec4> = (0..width * height)
        .map(|i| {
            let uv = Vec2::new(
                ((i % width) as f32 + 0.5) / width as f32,
                ((i / width) as f32 + 0.5) / height as f32,
            );
            let ndc = cpu::froxel::ndc_from_uv(uv);
            let scene =
                cpu::froxel::view_from_ndc(ndc.extend(depth_values[i as usize]), view_from_clip)
                    .z
                    .abs();
            let end = scene.min(config.far);
            let d = (end - config.near).max(0.0) * cpu::froxel::ray_scale(uv, view_from_clip);
            let ray = cpu::froxel::view_from_ndc(ndc.extend(0.5), view_from_clip);
            let dir = world_from_view.transform_vector3(ray).normalize();
            let light = cpu::lights::sun_inscatter(&sun, 1.0, dir, medium.phase_g)
                + cpu::lights::ambient_inscatter(
                    ambient.rgb[0],
                    ambient.rgb[1],
                    ambient.rgb[2],
                    dir,
                    medium.phase_g,
                );
            let t = (-sigma_t * d).exp();
            (albedo * light * (1.0 - t)).extend(t)
        })
        .collect();

    // Relative error of the in-scatter (per channel, against the image's largest
    // in-scatter times 1e-2 as floor) and absolute error of the transmittance.
    let compare = |got: &[Vec4], want: &[Vec4]| {
        let floor = want
            .iter()
            .map(|w| w.truncate().max_element())
            .fold(0.0f32, f32::max)
            * 1e-2;
        let mut worst = (0.0f32, 0.0f32);
        for (g, w) in got.iter().zip(want) {
            assert!(g.is_finite(), "non-finite fog {g}");
            for c in 0..3 {
                worst.0 = worst.0.max(rel_err(g[c], w[c], floor));
            }
            worst.1 = worst.1.max((g.w - w.w).abs());
        }
        worst
    };
    let (l_ref, t_ref) = compare(&marched, &expected);
    let (l_fx, t_fx) = compare(&froxel, &marched);
    eprintln!(
        "raymarch vs closed form: in-scatter {l_ref:e} relative (bound 3e-3), transmittance {t_ref:e} (bound 3e-3)"
    );
    eprintln!(
        "froxel pipeline vs raymarch: in-scatter {l_fx:e} relative (bound 1e-2), transmittance {t_fx:e} (bound 5e-3)"
    );
    assert!(l_ref <= 3e-3 && t_ref <= 3e-3, "{l_ref} {t_ref}");
    assert!(l_fx <= 1e-2 && t_fx <= 5e-3, "{l_fx} {t_fx}");
}
