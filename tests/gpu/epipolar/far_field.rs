//! The far field: `VolumetricFog`'s apply continued beyond the froxel volume's far
//! plane by the shadowed analytic tail, against the plain tail and the CPU mirror,
//! without and with the sun's transmittance through the medium; and the shafts' own
//! composite (`volfog::epipolar::epipolar_fog`) from the far plane against the tail.

use crate::common::gpu;
use glam::{Vec2, Vec3, Vec4};
use volfog::cpu::epipolar as cpu;
use volfog::pipeline::cascade_projection;
use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::depth_texture;

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

/// The shafts' own composite (`EpipolarShafts::record_apply`) over a black and a white
/// target: (in-scatter, transmittance) per pixel.
fn composite(gpu: &Gpu, shafts: &EpipolarShafts, (w, h): (u32, u32)) -> Vec<Vec4> {
    let apply = shafts
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let mut images = Vec::new();
    for base in [0.0f32, 1.0] {
        let color =
            gpu.texture_2d_rgba16f("colour", [w, h], &vec![Vec4::splat(base); (w * h) as usize]);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        shafts.record_apply(
            &mut encoder,
            &apply,
            &color.create_view(&Default::default()),
        );
        gpu.queue.submit([encoder.finish()]);
        images.push(gpu.read_texture_rgba16f(&color).unwrap());
    }
    images[0]
        .iter()
        .zip(&images[1])
        .map(|(black, white)| black.truncate().extend(white.x - black.x))
        .collect()
}

/// The far field with `FogConfig::light_transmittance` off and on: the runtime's tail
/// then attenuates its sun lobe (or not), and the shafts are marched in the same medium
/// (`HeightFog::sun_transmittance` as the config), so their lit fraction is the share of
/// the attenuated light that is not shadowed: 1 where nothing shadows, and the far
/// field equals the plain tail.
#[test]
fn far_field_continues_the_tail_and_shadows_it() {
    for transmittance in [false, true] {
        far_field_case(transmittance);
    }
}

fn far_field_case(transmittance: bool) {
    use volfog::cpu::ambient::AmbientSh;
    use volfog::pipeline::{FrameInputs, VolumetricFog};
    use volfog::uniforms::{FogMedium, ShadowCascades};
    use volfog_testkit::scene::{projection, small_config, view};

    let gpu = gpu();
    let (w, h) = (64u32, 36u32);
    let config = volfog::pipeline::FogConfig {
        light_transmittance: transmittance,
        ..small_config()
    };
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
    // The medium of the shafts: the tail as the runtime applies it.
    let shafts_medium = tail.with_sun_transmittance(transmittance);
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
    let tail_view = shafts_medium.to_view_space(camera);
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
            shafts
                .prepare(&gpu.queue, &epipolar_view, &shafts_medium)
                .unwrap();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            shafts.encode(&mut encoder, EpipolarMode::Tree).unwrap();
            gpu.queue.submit([encoder.finish()]);
            let s = gpu.read_texture_rgba16f(shafts.shaft_texture()).unwrap();
            let plain = apply_over_depth(gpu, &fog, &depth, None, (w, h));
            let field = apply_over_depth(gpu, &fog, &depth, Some(&shafts), (w, h));
            let alone = composite(gpu, &shafts, (w, h));
            results.push((d, s, plain, field, alone));
        }
        // Continuity across the far plane.
        let (_, _, _, before, _) = &results[0];
        let (_, _, _, after, _) = &results[1];
        let step = before
            .iter()
            .zip(after)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        // Beyond it: the far field against the plain tail and the CPU mirror, with
        // the volume's transmittance at the far plane read from the plain apply.
        let (d, s, plain, field, alone) = &results[2];
        let (mut worst_tail, mut worst_cpu, mut worst_s, mut darkening) =
            (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        let mut worst_alone = 0.0f32;
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
            // The shafts composed alone from the far plane (epipolar_fog, HG phase, no
            // Rayleigh term): the tail with its sun lobe scaled by F.
            worst_alone = worst_alone.max(
                (alone[i] - want_tail).abs().max_element() / want_tail.max_element().max(0.05),
            );
        }
        eprintln!(
            "sun transmittance {transmittance}, {name}: far field step across the far plane {step:.2e} (bound 1e-3); at far + 150 m: lit fraction vs 1 (open) or 0 (shadowed) {worst_s:.2e} (bound 2e-3), far field vs CPU mirror {worst_cpu:.2e} relative (bound 5e-3), shafts composed alone vs the CPU tail {worst_alone:.2e} relative (bound 5e-3), |far field - plain tail| {worst_tail:.2e}, largest darkening {darkening:.3}"
        );
        assert!(step <= 1e-3, "{name}: {step}");
        assert!(worst_s <= 2e-3, "{name}: {worst_s}");
        assert!(worst_cpu <= 5e-3, "{name}: {worst_cpu}");
        assert!(worst_alone <= 5e-3, "{name}: {worst_alone}");
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
