//! Apply with the froxel volume plus the analytic height-fog tail: transmittance is
//! continuous across the volume's far plane and, beyond it, follows the closed form
//! of the same medium; with the sun, the in-scattered light per metre of the volume's
//! last slice meets the tail's, with and without the sun's transmittance through the
//! medium.

use crate::common;

use common::gpu;
use common::scene::*;
use glam::{Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::pipeline::{FrameInputs, VolumetricFog};
use volfog::uniforms::{FogMedium, HeightFog, ShadowCascades};
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::depth_texture;

const W: u32 = 64;
const H: u32 = 36;

/// Applies the fog at one view depth everywhere onto a black and a white target and
/// returns (in-scatter, transmittance) per pixel.
fn apply_at_depth(gpu: &Gpu, fog: &VolumetricFog, view_depth: f32) -> Vec<Vec4> {
    let clip = projection() * Vec4::new(0.0, 0.0, -view_depth, 1.0);
    let depth = depth_texture(gpu, W, H, &vec![clip.z / clip.w; (W * H) as usize]).unwrap();
    crate::epipolar::apply_over_depth(gpu, fog, &depth, None, (W, H))
}

#[test]
fn transmittance_is_continuous_across_the_far_plane() {
    let gpu = gpu();
    let config = small_config();
    let medium = FogMedium {
        density: 0.02,
        height_falloff: 0.04,
        base_height: 0.0,
        noise_strength: 0.0,
        ..FogMedium::default()
    };
    for with_tail in [true, false] {
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        let view = view(4.0, 0.1);
        let inputs = FrameInputs {
            medium,
            ambient: AmbientSh::constant(Vec3::splat(0.2)),
            cascades: ShadowCascades::default(),
            tail: if with_tail {
                HeightFog::from_medium(&medium, Vec3::splat(0.2))
            } else {
                HeightFog::none()
            },
            ..FrameInputs::new(view, projection(), 0.0)
        };
        fog.prepare(&gpu.queue, &inputs).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);

        let far = config.far;
        let before = apply_at_depth(gpu, &fog, far - 0.01);
        let after = apply_at_depth(gpu, &fog, far + 0.01);
        let beyond = apply_at_depth(gpu, &fog, far + 150.0);
        let seam = before
            .iter()
            .zip(&after)
            .map(|(a, b)| (a.w - b.w).abs())
            .fold(0.0f32, f32::max);
        // Beyond the far plane: the volume's transmittance at far times the closed form
        // of the medium from the far plane to the point, along each pixel's ray.
        let u = expected_uniforms(&config, &inputs, 0);
        let world_from_view = u.frame.world_from_view;
        let tail_world = HeightFog::from_medium(&medium, Vec3::splat(0.2));
        let mut worst_tail = 0.0f32;
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let uv = glam::Vec2::new((x as f32 + 0.5) / W as f32, (y as f32 + 0.5) / H as f32);
                let n = volfog::cpu::froxel::ndc_from_uv(uv);
                let ray = volfog::cpu::froxel::view_from_ndc(
                    Vec3::new(n.x, n.y, 0.5),
                    u.froxels.view_from_clip,
                );
                let dir = ray / ray.z.abs();
                let start = world_from_view.transform_point3(dir * far);
                let end = world_from_view.transform_point3(dir * (far + 150.0));
                let tail_t = volfog::cpu::height_fog::height_fog(&tail_world, start, end - start).w;
                let want = if with_tail {
                    after[i].w * tail_t
                } else {
                    after[i].w
                };
                worst_tail = worst_tail.max((beyond[i].w - want).abs());
            }
        }
        let t_far = after.iter().map(|p| p.w).fold(1.0f32, f32::min);
        let t_beyond = beyond.iter().map(|p| p.w).fold(1.0f32, f32::min);
        eprintln!(
            "tail={with_tail}: max |T(far + 1 cm) - T(far - 1 cm)| = {seam:.2e} (bound 1e-3); beyond far: T from {t_far:.4} down to {t_beyond:.4}, max deviation from volume x closed form {worst_tail:.2e} (bound 2e-3)"
        );
        assert!(seam <= 1e-3, "seam {seam}");
        assert!(worst_tail <= 2e-3, "{worst_tail}");
        assert!(
            before
                .iter()
                .chain(&after)
                .chain(&beyond)
                .all(|p| p.is_finite())
        );
        if with_tail {
            assert!(
                t_beyond < t_far * 0.9,
                "the tail keeps attenuating beyond the far plane"
            );
        }
    }
}

/// The sun of the in-scatter seam: low ahead of the camera (16.5 degrees up), so the
/// medium between a point and the sun matters.
fn low_sun() -> volfog::uniforms::DirectionalLight {
    volfog::uniforms::DirectionalLight {
        direction: Vec3::new(0.2, 0.3, -1.0).normalize(),
        color: Vec3::new(3.0, 2.8, 2.5),
        fog_intensity: 1.0,
        ..Default::default()
    }
}

/// In-scattered light per metre at the far plane, with the sun, with
/// `FogConfig::light_transmittance` off and on: the froxel volume's last slice (inject
/// output, rgb = sigma_s L_in, the sun lobe attenuated by medium_light_transmittance
/// when on) against the analytic tail the runtime continues it with (`height_fog`, its
/// sun lobe built from the same sun colour, albedo and phase, attenuated by
/// `height_fog_lit_integral` when on), for an exponential medium and a uniform one under
/// a top; and the applied fog beyond the far plane against the volume followed by the
/// CPU tail.
#[test]
fn inscatter_is_continuous_across_the_far_plane_with_the_sun() {
    let exponential = FogMedium {
        density: 0.02,
        height_falloff: 0.04,
        base_height: 0.0,
        noise_strength: 0.0,
        ..FogMedium::default()
    };
    // Uniform fog 20 m deep: the far plane's rays pass above and below its top.
    let capped = FogMedium {
        density: 0.015,
        height_falloff: 0.0,
        top_height: 20.0,
        ..exponential
    };
    for transmittance in [false, true] {
        for (name, medium) in [("exponential", exponential), ("uniform, top 20 m", capped)] {
            inscatter_seam_case(name, medium, transmittance);
        }
    }
}

fn inscatter_seam_case(name: &str, medium: FogMedium, transmittance: bool) {
    use volfog::cpu::height_fog::height_fog;
    use volfog::cpu::inject::froxel_world_position;

    let gpu = gpu();
    let config = volfog::pipeline::FogConfig {
        light_transmittance: transmittance,
        depth_cull: false,
        ..small_config()
    };
    let sun = low_sun();
    let ambient = Vec3::splat(0.05);
    // The tail lit as the froxels are: albedo times the constant ambient radiance, and
    // the sun lobe albedo x sun colour x HG(phase_g) towards the sun.
    let tail = HeightFog::from_medium(&medium, medium.albedo * ambient)
        .with_sun(
            sun.direction,
            medium.albedo * sun.color * sun.fog_intensity,
            medium.phase_g,
        )
        .unwrap();
    let camera = view(4.0, 0.1);
    let inputs = FrameInputs {
        medium,
        sun,
        ambient: AmbientSh::constant(ambient),
        cascades: ShadowCascades::default(),
        tail,
        ..FrameInputs::new(camera, projection(), 0.0)
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.prepare(&gpu.queue, &inputs).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let scattering = gpu.read_texture_rgba16f(fog.scattering_texture()).unwrap();
    let u = expected_uniforms(&config, &inputs, 0);
    let (froxels, frame) = (u.froxels, u.frame);
    let size = froxels.size;
    let camera_pos = frame.world_from_view.transform_point3(Vec3::ZERO);
    // The tail as the runtime applies it (world space here), and with the other switch.
    let as_applied = tail.with_sun_transmittance(transmittance);
    let switched = tail.with_sun_transmittance(!transmittance);
    // In-scattered light per metre (rgb) of a height fog at p along the unit dir: the fog
    // of a 1 mm segment centred on p over its length (self-attenuation 1e-5 relative).
    let rate = |f: &HeightFog, p: Vec3, dir: Vec3| {
        let delta = 1e-3;
        height_fog(f, p - dir * (0.5 * delta), dir * delta).truncate() / delta
    };
    let last = size.z - 1;
    let (mut worst_point, mut worst_step, mut worst_excess, mut step_bound) =
        (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut worst_switched = 0.0f32;
    let mut compared = 0;
    for y in 0..size.y {
        for x in 0..size.x {
            let id = glam::UVec3::new(x, y, last);
            let (world, depth) = froxel_world_position(&froxels, &frame, id, false);
            let volume = scattering[((last * size.y + y) * size.x + x) as usize].truncate();
            let dir = (world - camera_pos).normalize();
            let here = rate(&as_applied, world, dir);
            let scale = here.max_element();
            // Above the capped medium's top both are empty.
            if scale < 1e-6 {
                assert!(
                    volume.max_element() <= 1e-6,
                    "{name}: {volume} above the top"
                );
                continue;
            }
            compared += 1;
            // The same point: the volume's sample against the tail's closed form.
            let e_point = (volume - here).abs().max_element() / scale;
            worst_point = worst_point.max(e_point);
            // Across the far plane: the last slice's sample (at its centre, depth `depth`)
            // against the tail where it starts, on the same ray. The seam may not exceed
            // the medium's own change between the two points plus the bound above.
            let at_far = camera_pos + dir * ((froxels.far / depth) * (world - camera_pos).length());
            let start = rate(&as_applied, at_far, dir);
            let e_step = (volume - start).abs().max_element() / scale;
            let change = (here - start).abs().max_element() / scale;
            worst_step = worst_step.max(e_step);
            step_bound = step_bound.max(change);
            worst_excess = worst_excess.max(e_step - change);
            worst_switched = worst_switched
                .max((volume - rate(&switched, world, dir)).abs().max_element() / scale);
        }
    }
    // The applied fog beyond the far plane: the volume at far followed by the tail.
    let far = config.far;
    let after = apply_at_depth(gpu, &fog, far + 0.01);
    let beyond = apply_at_depth(gpu, &fog, far + 150.0);
    let tail_view = as_applied.to_view_space(camera);
    let mut worst_applied = 0.0f32;
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let uv = glam::Vec2::new((x as f32 + 0.5) / W as f32, (y as f32 + 0.5) / H as f32);
            let p =
                volfog::cpu::apply::fog_view_from_depth(uv, far + 150.0, froxels.view_from_clip);
            let t = volfog::cpu::apply::fog_tail(&froxels, &tail_view, p);
            let want = after[i].truncate() + after[i].w * t.truncate();
            worst_applied = worst_applied.max(
                (beyond[i].truncate() - want).abs().max_element() / want.max_element().max(0.05),
            );
        }
    }
    eprintln!(
        "{name}, sun transmittance {transmittance}: {compared} columns; in-scatter per metre of the last slice vs the tail at its sample {worst_point:.2e} relative (bound 2e-3); vs the tail at the far plane {worst_step:.2e} (the medium's own change over the half slice {step_bound:.2e}; excess {worst_excess:.2e}, bound 2e-3); vs the tail with the sun's transmittance switched {worst_switched:.2e} (must exceed 5e-2); applied fog at far + 150 m vs volume + CPU tail {worst_applied:.2e} (bound 5e-3)"
    );
    assert!(compared >= 200, "{name}: {compared}");
    assert!(worst_point <= 2e-3, "{name}: {worst_point}");
    assert!(worst_excess <= 2e-3, "{name}: {worst_excess}");
    assert!(worst_switched > 5e-2, "{name}: {worst_switched}");
    assert!(worst_applied <= 5e-3, "{name}: {worst_applied}");
}
