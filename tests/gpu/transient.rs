//! Short-lived lights (`FrameInputs::transient_lights`, the scan's
//! `VOLFOG_SCAN_TRANSIENT_LIGHTS`): the scan pass against the CPU mirror
//! (`volfog::cpu::transient`); a light present for one frame leaves no ghost (the next
//! frames' volumes are bit-identical to a run where it never existed); and in its frame
//! the fog equals the unamortised inject with the light as an ordinary one, rising by
//! the light's whole contribution where an ordinary light shows the history-weighted
//! share.

use crate::common;
use crate::culling::integrated;

use common::gpu;
use common::scene::*;
use glam::{Vec3, Vec4};
use volfog::cpu::transient::{TransientScan, scan_volume};
use volfog::options::ScanStep;
use volfog::pipeline::scan::{ScanPass, TransientScanResources};
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};
use volfog::uniforms::{
    FOG_LIGHT_SPOT_SQUARED, FogLight, FogMedium, TransientLighting, to_storage_bytes,
    to_uniform_bytes,
};
use volfog_testkit::selfcheck::{live_slices_texture, round_f16, test_froxels};
use wgpu::util::DeviceExt;

/// A muzzle flash near the camera, a spot light with Bevy's squared cone and a
/// lightning strike's directional light: one of each kind.
fn flashes() -> [FogLight; 3] {
    let spot = FogLight::spot(
        Vec3::new(4.0, 5.0, -18.0),
        Vec3::new(-0.2, -1.0, -0.1).normalize(),
        Vec3::new(80.0, 120.0, 200.0),
        25.0,
        0.2,
        0.45,
    );
    [
        FogLight::point(
            Vec3::new(-0.8, 1.4, -6.0),
            Vec3::new(400.0, 260.0, 90.0),
            14.0,
        ),
        FogLight {
            flags: FOG_LIGHT_SPOT_SQUARED,
            ..spot
        },
        FogLight::directional(
            Vec3::new(0.3, 1.0, -0.4).normalize(),
            Vec3::new(0.6, 0.7, 1.0),
        ),
    ]
}

/// Runs the transient scan (`live` per column for the culling variant) over `volume`.
fn run_transient_scan(
    froxels: &volfog::uniforms::Froxels,
    volume: &[Vec4],
    live: Option<&[u32]>,
    medium: &FogMedium,
    lighting: &TransientLighting,
    lights: &[FogLight],
) -> Vec<Vec4> {
    let gpu = gpu();
    let size = froxels.size.to_array();
    let pass =
        ScanPass::with_transient_lights(&gpu.device, ScanStep::EnergyConserving, live.is_some())
            .unwrap();
    let buffer = |label, bytes: &[u8], usage| {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage,
            })
    };
    let froxel_buffer = buffer("froxels", &froxels.to_bytes(), wgpu::BufferUsages::UNIFORM);
    let medium_buffer = buffer(
        "medium",
        &to_uniform_bytes(medium),
        wgpu::BufferUsages::UNIFORM,
    );
    let lighting_buffer = buffer(
        "transient",
        &to_uniform_bytes(lighting),
        wgpu::BufferUsages::UNIFORM,
    );
    let light_buffer = buffer(
        "lights",
        &to_storage_bytes(lights),
        wgpu::BufferUsages::STORAGE,
    );
    let scattering = gpu.texture_3d_rgba16f("scattering", size, volume);
    let out = gpu.texture_3d_rgba16f("integrated", size, &[]);
    let live_view = live
        .map(|l| live_slices_texture(gpu, [size[0], size[1]], l).create_view(&Default::default()));
    let group = pass
        .bind_group_with(
            &gpu.device,
            &froxel_buffer,
            &scattering.create_view(&Default::default()),
            &out.create_view(&Default::default()),
            live_view.as_ref(),
            Some(TransientScanResources {
                medium: &medium_buffer,
                lighting: &lighting_buffer,
                lights: &light_buffer,
            }),
        )
        .unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut compute = encoder.begin_compute_pass(&Default::default());
        pass.encode(&mut compute, &group, [size[0], size[1]]);
    }
    gpu.queue.submit([encoder.finish()]);
    read_volume(gpu, &out)
}

/// The transient scan on the GPU against the CPU mirror: a heterogeneous volume, the
/// three kinds of light with and without the medium's transmittance, with and without
/// depth culling. The plain scan of the same volume is the control: the lights change
/// it by far more than the tolerance.
#[test]
fn transient_scan_matches_cpu_mirror() {
    let froxels = test_froxels([24, 14], 48);
    let [sx, sy, sz] = froxels.size.to_array();
    let volume: Vec<Vec4> = (0..sx * sy * sz)
        .map(|i| {
            let h = ((i * 7 + i / 11) % 19) as f32 / 19.0;
            let sigma_t = if i % 13 == 0 { 0.0 } else { 0.004 + 0.04 * h };
            Vec4::new(0.3 * sigma_t, 0.2 * sigma_t * h, 0.1 * sigma_t, sigma_t)
        })
        .map(round_f16)
        .collect();
    let live: Vec<u32> = (0..sx * sy).map(|c| 3 + (c * 17) % (sz - 2)).collect();
    let medium = FogMedium {
        albedo: Vec3::new(0.9, 0.8, 0.7),
        density: 0.03,
        height_falloff: 0.1,
        phase_g: 0.4,
        ..FogMedium::default()
    };
    let camera = glam::Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0));
    let rays = volfog::cpu::shadow::shadow_tap_rays(froxels.view_from_clip, camera);
    let lights = flashes();
    let plain =
        volfog_testkit::selfcheck::run_scan(gpu(), ScanStep::EnergyConserving, &froxels, &volume)
            .unwrap();
    for (transmittance, culled) in [(1, false), (0, false), (1, true)] {
        let lighting = TransientLighting {
            camera_position: Vec3::new(0.0, 1.5, 0.0),
            count: lights.len() as u32,
            ray_origin: rays[0],
            transmittance,
            ray_x: rays[1],
            ray_y: rays[2],
        };
        let live = culled.then_some(live.as_slice());
        let got = run_transient_scan(&froxels, &volume, live, &medium, &lighting, &lights);
        let scan = TransientScan {
            medium: &medium,
            lighting: &lighting,
            lights: &lights,
        };
        let want = scan_volume(
            &froxels,
            ScanStep::EnergyConserving,
            &volume,
            live,
            Some(&scan),
        );
        let (mut worst, mut lit) = (0.0f32, 0.0f32);
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            for k in 0..4 {
                let e = (g[k] - w[k]).abs() / w[k].abs().max(1e-3);
                worst = worst.max(e);
                assert!(e <= 2e-3, "froxel {i}: gpu {g} cpu {w}");
            }
            if !culled {
                let p = plain[i];
                lit = lit
                    .max((w.truncate() - p.truncate()).max_element() / p.max_element().max(1e-3));
            }
        }
        eprintln!(
            "transmittance {transmittance}, culled {culled}: GPU vs CPU mirror worst relative \
             error {worst:e} (bound 2e-3, fp16 output)"
        );
        if !culled {
            eprintln!(
                "  the lights raise the plain scan's in-scatter by up to {lit:.1} times its value"
            );
            assert!(lit > 1.0, "the lights must change the scan: {lit}");
        }
    }
}

/// A fog of the small scene with the scene's lights and volumes.
fn inputs<'a>(
    lights: &'a [FogLight],
    transient: &'a [FogLight],
    volumes: &'a [volfog::uniforms::LocalVolume],
) -> FrameInputs<'a> {
    FrameInputs {
        medium: medium(),
        lights,
        transient_lights: transient,
        local_volumes: volumes,
        ..FrameInputs::new(view(1.6, -0.03), projection(), 2.0)
    }
}

/// The volumes of one frame: the stabilised one (the next frame's history; `None`
/// without temporal reprojection) and the integrated one.
type Volumes = (Option<Vec<Vec4>>, Vec<Vec4>);

/// Runs `frames` frames of a fog of the small scene, with the flashes as transient
/// lights in frame `flash` and as ordinary lights in frame `ordinary`; returns each
/// frame's volumes.
fn run(config: &FogConfig, frames: u32, flash: Option<u32>, ordinary: Option<u32>) -> Vec<Volumes> {
    let gpu = gpu();
    let mut fog = VolumetricFog::new(&gpu.device, config).unwrap();
    let (volumes, flashes) = (local_volumes(), flashes());
    let plain = lights();
    let with_flashes: Vec<FogLight> = plain.iter().chain(&flashes).copied().collect();
    let mut out = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        frames,
        |f| {
            let transient: &[FogLight] = if Some(f) == flash { &flashes } else { &[] };
            let lights: &[FogLight] = if Some(f) == ordinary {
                &with_flashes
            } else {
                &plain
            };
            inputs(lights, transient, &volumes)
        },
        |_, fog| {
            let stabilised = fog.stabilised_texture().map(|t| read_volume(gpu, t));
            out.push((stabilised, integrated(gpu, fog)));
        },
    );
    out
}

/// The cheap path (temporal reprojection, jitter, checkerboard amortisation, the
/// noise texture): a transient light in frame 4 of 7 changes that frame's integrated
/// volume and nothing else. Every stabilised volume (the history) and the integrated
/// volumes of frames 5 and 6 are bit-identical to a run where the light never existed.
#[test]
fn a_transient_light_leaves_no_ghost() {
    let config = FogConfig {
        temporal: true,
        jitter: true,
        amortize: true,
        noise_texture: true,
        ..small_config()
    };
    let (frames, flash) = (7, 4);
    let lit = run(&config, frames, Some(flash), None);
    let never = run(&config, frames, None, None);
    for f in 0..frames as usize {
        let (history, done) = (&lit[f].0, &lit[f].1);
        assert!(history.is_some());
        assert!(
            history == &never[f].0,
            "frame {f}: the history differs from a run without the light"
        );
        let same = done == &never[f].1;
        if f == flash as usize {
            let rise = done
                .iter()
                .zip(&never[f].1)
                .map(|(a, b)| (a.truncate() - b.truncate()).max_element())
                .fold(0.0f32, f32::max);
            eprintln!("frame {f} (the flash): in-scatter up to {rise:.4} above the run without it");
            assert!(
                !same && rise > 0.01,
                "the flash must light its frame: {rise}"
            );
        } else {
            assert!(same, "frame {f}: the integrated volume differs (a ghost)");
        }
    }
    eprintln!(
        "{frames} frames: every history and every integrated volume but the flash's are \
         bit-identical to the run without it"
    );
}

/// Largest difference of two volumes relative to the larger texel, floored at `floor`
/// of the largest value of `b`.
fn worst_relative(a: &[Vec4], b: &[Vec4], floor: f32) -> f32 {
    let top = b.iter().map(|v| v.max_element()).fold(0.0f32, f32::max);
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            let d = (*a - *b).abs().max_element();
            d / a.abs().max(b.abs()).max_element().max(floor * top)
        })
        .fold(0.0, f32::max)
}

/// In a still scene with temporal reprojection (history weight 0.9, no jitter, no
/// checkerboard) settled over 6 frames, frame 6 with the flashes as transient lights
/// equals the unamortised inject with them as ordinary lights (a fog without temporal
/// reprojection, checkerboard or jitter) within 2e-3 of the larger texel (floored at
/// 1e-3 of the volume's largest value): fp16 storage of the stabilised volume, which
/// the transient light is added to, and of the output, one rounding each (about 1e-3). The fog rises by the lights'
/// whole contribution; the same lights as ordinary lights in their first frame raise
/// it by the blend's share, 1 - 0.9 = 10 %.
#[test]
fn a_transient_light_matches_the_unamortised_inject_and_shows_whole() {
    let temporal = FogConfig {
        temporal: true,
        history_weight: 0.9,
        jitter: false,
        amortize: false,
        ..small_config()
    };
    let plain = FogConfig {
        temporal: false,
        ..temporal.clone()
    };
    let frame = 6;
    let transient = &run(&temporal, frame + 1, Some(frame), None)[frame as usize].1;
    let ordinary = &run(&temporal, frame + 1, None, Some(frame))[frame as usize].1;
    let unlit = &run(&temporal, frame + 1, None, None)[frame as usize].1;
    let inject_lit = &run(&plain, 1, None, Some(0))[0].1;
    let inject_unlit = &run(&plain, 1, None, None)[0].1;
    let worst = worst_relative(transient, inject_lit, 1e-3);
    let settled = worst_relative(unlit, inject_unlit, 1e-3);
    eprintln!(
        "frame {frame} with the transient lights vs the unamortised inject with them: worst \
         relative difference {worst:e} (bound 2e-3); without them {settled:e}"
    );
    assert!(worst <= 2e-3, "{worst}");
    // The rise of the in-scattering over the unlit frame, where it is significant.
    let top = inject_lit
        .iter()
        .zip(inject_unlit)
        .map(|(l, u)| (l.truncate() - u.truncate()).max_element())
        .fold(0.0f32, f32::max);
    let (mut whole, mut share) = (Vec::new(), Vec::new());
    for i in 0..unlit.len() {
        let full = inject_lit[i].truncate() - inject_unlit[i].truncate();
        let k = full.max_position();
        if full[k] < 0.05 * top {
            continue;
        }
        whole.push((transient[i][k] - unlit[i][k]) / full[k]);
        share.push((ordinary[i][k] - unlit[i][k]) / full[k]);
    }
    let range = |v: &[f32]| {
        (
            v.iter().copied().fold(f32::MAX, f32::min),
            v.iter().copied().fold(f32::MIN, f32::max),
        )
    };
    let (w, s) = (range(&whole), range(&share));
    eprintln!(
        "over {} froxels lit above 5 % of the brightest rise: transient light rises by \
         {:.4}..{:.4} of the whole contribution, an ordinary light in its first frame by \
         {:.4}..{:.4}",
        whole.len(),
        w.0,
        w.1,
        s.0,
        s.1
    );
    assert!(whole.len() > 100);
    assert!(w.0 >= 0.98 && w.1 <= 1.02, "{w:?}");
    assert!(s.0 >= 0.08 && s.1 <= 0.12, "{s:?}");
}

/// `prepare` refuses more transient lights than their capacity and a light with a NaN,
/// naming the field, and changes nothing: the next valid frame runs.
#[test]
fn bad_transient_lights_are_typed_errors() {
    let gpu = gpu();
    let config = FogConfig {
        max_transient_lights: 2,
        ..small_config()
    };
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    let flashes = flashes();
    let err = fog
        .prepare(&gpu.queue, &inputs(&[], &flashes, &[]))
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("FrameInputs.transient_lights = 3 is invalid: expected at most FogConfig.max_transient_lights = 2"),
        "{err}"
    );
    let nan = [FogLight {
        position: Vec3::new(f32::NAN, 0.0, 0.0),
        ..flashes[0]
    }];
    let err = fog
        .prepare(&gpu.queue, &inputs(&[], &nan, &[]))
        .unwrap_err();
    assert!(err.to_string().starts_with("FogLight.position"), "{err}");
    assert_eq!(fog.frame_index(), None, "a rejected frame prepares nothing");
    let none = FogConfig {
        max_transient_lights: 0,
        ..small_config()
    };
    let mut without = VolumetricFog::new(&gpu.device, &none).unwrap();
    let err = without
        .prepare(&gpu.queue, &inputs(&[], &flashes[..1], &[]))
        .unwrap_err();
    assert!(
        err.to_string().contains("max_transient_lights = 0"),
        "{err}"
    );
    fog.prepare(&gpu.queue, &inputs(&[], &flashes[..2], &[]))
        .unwrap();
    assert_eq!(fog.frame_index(), Some(0));
    let too_many = FogConfig {
        max_transient_lights: volfog::limits::MAX_TRANSIENT_LIGHTS + 1,
        ..small_config()
    };
    let err = VolumetricFog::new(&gpu.device, &too_many).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("FogConfig.max_transient_lights"),
        "{err}"
    );
}
