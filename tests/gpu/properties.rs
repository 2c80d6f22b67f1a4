//! Property tests: for random valid media (scattering and emitting) the scan never
//! produces NaN or Inf,
//! transmittance stays in [0, 1] and never increases with depth, in-scattering never
//! decreases; phase functions stay finite and positive. The CPU mirror is checked per
//! case; the GPU scan is checked on a volume built from many random columns.

use crate::common;

use glam::{Vec3, Vec4};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use volfog::cpu::phase;
use volfog::cpu::scan::{SCAN_START, scan_step};
use volfog::options::ScanStep;
use volfog_testkit::selfcheck::{run_scan, test_froxels};

fn medium() -> impl Strategy<Value = Vec4> {
    // sigma_t in [0, 2] 1/m (clear air to dense smoke), albedo in [0, 1], light in [0, 100],
    // emission in [0, 10] per metre (glowing fog, with or without extinction).
    (
        (0.0f32..2.0, 0.0f32..=1.0),
        (0.0f32..100.0, 0.0f32..100.0, 0.0f32..100.0),
        (0.0f32..10.0, 0.0f32..10.0, 0.0f32..10.0),
    )
        .prop_map(|((sigma_t, albedo), (r, g, b), (er, eg, eb))| {
            (Vec3::new(r, g, b) * albedo * sigma_t + Vec3::new(er, eg, eb)).extend(sigma_t)
        })
}

fn check_column(column: &[Vec4], label: &str) -> Result<(), TestCaseError> {
    let mut prev = SCAN_START;
    for (k, acc) in column.iter().enumerate() {
        prop_assert!(acc.is_finite(), "{label} slice {k}: {acc}");
        prop_assert!(
            (0.0..=1.0).contains(&acc.w),
            "{label} slice {k}: T = {}",
            acc.w
        );
        prop_assert!(
            acc.w <= prev.w,
            "{label} slice {k}: T rises {} -> {}",
            prev.w,
            acc.w
        );
        for c in 0..3 {
            prop_assert!(
                acc[c] >= prev[c],
                "{label} slice {k}: L falls {} -> {}",
                prev[c],
                acc[c]
            );
        }
        prev = *acc;
    }
    Ok(())
}

proptest! {
    #[test]
    fn cpu_scan_is_finite_and_monotonic(
        media in proptest::collection::vec(medium(), 1..64),
        ds in proptest::collection::vec(0.0f32..20.0, 64),
    ) {
        for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
            let mut acc = SCAN_START;
            let column: Vec<Vec4> = media
                .iter()
                .zip(&ds)
                .map(|(m, d)| {
                    acc = scan_step(acc, *m, *d, step);
                    acc
                })
                .collect();
            check_column(&column, &format!("{step:?}"))?;
        }
    }

    #[test]
    fn phase_functions_are_finite_and_positive(c in -1.0f32..=1.0, g in -0.99f32..=0.99) {
        let values = [
            phase::phase_hg(c, g),
            phase::phase_schlick(c, phase::schlick_k(g)),
            phase::phase_cornette_shanks(c, g),
            phase::phase_rayleigh(c),
            phase::phase_hg_two_lobe(c, g, -g, 0.5),
        ];
        for v in values {
            prop_assert!(v.is_finite() && v > 0.0, "c={c} g={g}: {v}");
        }
    }
}

#[test]
fn gpu_scan_of_random_media_is_finite_and_monotonic() {
    let gpu = common::gpu();
    let froxels = test_froxels([16, 16], 64);
    let count = (16 * 16 * 64) as usize;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let media: Vec<Vec4> = (0..count)
        .map(|_| medium().new_tree(&mut runner).unwrap().current())
        .collect();
    for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
        let out = run_scan(gpu, step, &froxels, &media).unwrap();
        for y in 0..16 {
            for x in 0..16 {
                let column: Vec<Vec4> = (0..64).map(|z| out[(z * 16 + y) * 16 + x]).collect();
                // fp16 rounding can repeat a value, never reverse a trend.
                check_column(&column, &format!("{step:?} column ({x}, {y})")).unwrap();
            }
        }
    }
}

/// Random valid media and lights through the whole froxel pipeline (inject, temporal,
/// scan): no NaN or Inf anywhere, transmittance in [0, 1] and non-increasing along
/// every column, in-scattering non-decreasing.
#[test]
fn pipeline_with_random_media_and_lights_is_finite_and_monotonic() {
    use common::scene::{index, projection, read_volume, small_config, view};
    use glam::{Mat4, UVec3};
    use volfog::cpu::ambient::AmbientSh;
    use volfog::pipeline::{FrameInputs, VolumetricFog};
    use volfog::uniforms::{DirectionalLight, FogLight, FogMedium, LocalVolume, VolumeShape};

    let gpu = common::gpu();
    let config = volfog::pipeline::FogConfig {
        volume_size: UVec3::new(16, 9, 32),
        jitter: true,
        temporal: true,
        ..small_config()
    };
    let fog = std::cell::RefCell::new(VolumetricFog::new(&gpu.device, &config).unwrap());
    let unit =
        || (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    let light = (
        unit(),
        unit(),
        0.1f32..50.0,
        0.0f32..500.0,
        any::<bool>(),
        1e-3f32..1.0,
    )
        .prop_map(|(p, d, range, power, spot, radius)| {
            let position = Vec3::new(p.x * 20.0, 1.0 + p.y * 5.0, -20.0 + p.z * 20.0);
            let mut l = if spot {
                FogLight::spot(
                    position,
                    d.normalize_or(Vec3::NEG_Y),
                    Vec3::splat(power),
                    range,
                    0.2,
                    0.6,
                )
            } else {
                FogLight::point(position, Vec3::splat(power), range)
            };
            l.radius = radius;
            l
        });
    let medium = (
        0.0f32..0.5,
        0.0f32..1.0,
        0.0f32..=1.0,
        0.01f32..2.0,
        -0.95f32..0.95,
        unit(),
        0.0f32..=1.0,
    )
        .prop_map(
            |(density, falloff, strength, scale, g, wind, albedo)| FogMedium {
                density,
                height_falloff: falloff,
                noise_strength: strength,
                noise_scale: scale,
                phase_g: g,
                wind: wind * 5.0,
                albedo: Vec3::splat(albedo),
                ..FogMedium::default()
            },
        );
    let volume = (
        unit(),
        0.5f32..10.0,
        -1.0f32..1.0,
        0.01f32..=1.0,
        any::<bool>(),
    )
        .prop_map(|(c, s, density, edge, ellipsoid)| {
            let m = Mat4::from_scale_rotation_translation(
                Vec3::splat(s),
                glam::Quat::IDENTITY,
                Vec3::new(c.x * 10.0, c.y * 3.0, -15.0 + c.z * 10.0),
            );
            LocalVolume::new(
                m,
                if ellipsoid {
                    VolumeShape::Ellipsoid
                } else {
                    VolumeShape::Box
                },
                density,
                edge,
            )
            .unwrap()
        });
    let case = (
        medium,
        proptest::collection::vec(light, 0..8),
        proptest::collection::vec(volume, 0..4),
        unit(),
        0.0f32..100.0,
    );
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
        cases: 12,
        ..ProptestConfig::default()
    });
    runner
        .run(&case, |(medium, lights, volumes, sun_dir, time)| {
            let inputs = FrameInputs {
                medium,
                sun: DirectionalLight {
                    direction: sun_dir.normalize_or(Vec3::Y),
                    ..DirectionalLight::default()
                },
                ambient: AmbientSh::sky_ground(
                    Vec3::new(0.3, 0.4, 0.6),
                    Vec3::splat(0.05),
                    Vec3::Y,
                ),
                lights: &lights,
                local_volumes: &volumes,
                ..FrameInputs::new(view(2.0, -0.1), projection(), time)
            };
            let mut volume = Vec::new();
            let mut fog = fog.borrow_mut();
            for _ in 0..2 {
                fog.prepare(&gpu.queue, &inputs).expect("valid inputs");
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                fog.encode(&mut encoder).unwrap();
                gpu.queue.submit([encoder.finish()]);
            }
            volume.extend(read_volume(gpu, fog.integrated_texture()));
            let size = config.volume_size;
            for y in 0..size.y {
                for x in 0..size.x {
                    let column: Vec<Vec4> =
                        (0..size.z).map(|z| volume[index(size, x, y, z)]).collect();
                    check_column(&column, &format!("column ({x}, {y})"))?;
                }
            }
            Ok(())
        })
        .unwrap();
}
