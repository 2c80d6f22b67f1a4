//! Apply with the froxel volume plus the analytic height-fog tail: transmittance is
//! continuous across the volume's far plane and, beyond it, follows the closed form
//! of the same medium.

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
