//! Each eye's volume and image: against the CPU mirror of the resampling scan, and
//! against the mono fog rendered from that eye's camera.
//!
//! The bound of the mono comparison comes from what the shared volume cannot hold.
//! An eye's froxel reads the shared volume trilinearly at its centre, where the mono
//! fog injects that centre exactly: (1) the interpolation error, per axis at most half
//! the largest second difference f(i - 1) - 2 f(i) + f(i + 1) of the shared texels the
//! look-up weighs (linear interpolation is off by h^2 |f''| / 8 in a smooth field, which
//! the second difference measures as h^2 |f''|, and by half the step at a step, which
//! the second difference on either side of it measures as the step); (2) the phase function's view direction, the
//! centre eye's, off by dtheta <= asin(e / r) at distance r from the eye (e the eye's
//! distance from the centre apex), which changes a Henyey-Greenstein phase by a factor
//! within exp(+-kappa dtheta), kappa = 3|g| / (1 - g^2) the largest |d ln p / d theta|
//! (the scene's ambient is constant, so only the lights' and the sun's terms, all
//! HG-phased, depend on the direction); (3) the rounding of both scattering volumes to
//! rgba16float (2^-11 relative each). The scan then carries an error e of a slice's
//! (sigma_s L, sigma_t) into the integrated radiance L_k by at most
//! sum_j [T'_j e_rgb,j ds_j + min(c_j (exp(tau_j) - 1), c_j + T'_j S_j ds_j)] and into
//! the transmittance by T_k (exp(tau_k) - 1), with tau_j = sum_(i<=j) e_a,i ds_i the
//! optical depth's error so far, T'_j = min(1, T_(j-1) exp(tau_(j-1))) the largest
//! transmittance in front of slice j, c_j = |L_j - L_(j-1)| its contribution, S_j the
//! largest scattering its look-up reads and ds_j its path length,
//! and the integrated volumes and images round to rgba16float once more each.

use super::*;
use crate::common::scene::{index, lights, read_volume};
use glam::Vec2;
use volfog::cpu::apply::Volume;
use volfog::cpu::froxel::{ndc_from_uv, ray_scale, slice_depth, slice_walk};
use volfog::cpu::shadow::shadow_tap_rays;
use volfog::cpu::stereo::{
    CentreEye, centre_eye, resample_scan_volume, stereo_resample_column, stereo_resample_uvw,
};
use volfog::uniforms::{Froxels, TransientLighting};

/// rgba16float's relative rounding (half an ulp).
const HALF: f32 = 1.0 / 2048.0;

/// An eye's froxel placement and column rays, from its camera.
fn eye_grid(config: &FogConfig, eye: &StereoEye) -> (Froxels, TransientLighting) {
    let froxels = Froxels::new(
        eye.clip_from_view,
        config.volume_size,
        config.near,
        config.far,
        config.slice_curve,
    )
    .unwrap();
    let world_from_view = eye.view_from_world.inverse();
    let r = shadow_tap_rays(froxels.view_from_clip, world_from_view);
    let rays = TransientLighting {
        camera_position: world_from_view.w_axis.truncate(),
        ray_origin: r[0],
        ray_x: r[1],
        ray_y: r[2],
        ..TransientLighting::default()
    };
    (froxels, rays)
}

/// The shared volume's placement: the centre eye's frustum, the eyes' slices moved
/// back by the apex offset.
fn shared_grid(config: &FogConfig, centre: &CentreEye) -> Froxels {
    Froxels::new(
        centre.clip_from_view,
        config.volume_size,
        config.near + centre.apex_offset,
        config.far + centre.apex_offset,
        config.slice_curve,
    )
    .unwrap()
}

/// What one shared look-up reads: the spread (max - min per channel) of the eight
/// texels the trilinear look-up at uvw weighs, the sum over the three axes of the
/// largest second difference f(i - 1) - 2 f(i) + f(i + 1) at those texels, and their
/// largest magnitude.
fn footprint(shared: &Volume, uvw: Vec3) -> (Vec4, Vec4, Vec4) {
    let size = Vec3::new(
        shared.size[0] as f32,
        shared.size[1] as f32,
        shared.size[2] as f32,
    );
    let base = (uvw * size - 0.5).floor();
    let (mut lo, mut hi) = (Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY));
    let mut curvature = [Vec4::ZERO; 3];
    for c in 0..8 {
        let (x, y, z) = (
            base.x as i32 + (c & 1),
            base.y as i32 + ((c >> 1) & 1),
            base.z as i32 + ((c >> 2) & 1),
        );
        let t = shared.load(x, y, z);
        lo = lo.min(t);
        hi = hi.max(t);
        let steps = [(1, 0, 0), (0, 1, 0), (0, 0, 1)];
        for (axis, (dx, dy, dz)) in steps.into_iter().enumerate() {
            let d =
                shared.load(x - dx, y - dy, z - dz) - 2.0 * t + shared.load(x + dx, y + dy, z + dz);
            curvature[axis] = curvature[axis].max(d.abs());
        }
    }
    (
        hi - lo,
        curvature[0] + curvature[1] + curvature[2],
        hi.abs().max(lo.abs()),
    )
}

/// Per froxel of an eye's integrated volume, the bound (rgb, a) of its error when
/// every look-up of the shared volume is off by at most `per_sample(spread, magnitude,
/// distance from the eye)`, propagated through the scan as the module documentation
/// states, against the eye volume `integrated` (its T and L).
fn scan_bounds(
    eye: &Froxels,
    rays: &TransientLighting,
    shared: &Volume,
    shared_froxels: &Froxels,
    clip_from_world: Mat4,
    integrated: &[Vec4],
    per_sample: &dyn Fn([Vec4; 3], f32) -> Vec4,
) -> Vec<Vec4> {
    let size = eye.size;
    let mut bounds = vec![Vec4::ZERO; integrated.len()];
    let (a, b) = slice_walk(size.z, eye.near, eye.far, eye.curve);
    for y in 0..size.y {
        for x in 0..size.x {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / size.truncate().as_vec2();
            let scale = ray_scale(uv, eye.view_from_clip);
            let ndc = ndc_from_uv(uv);
            let ray = rays.ray_origin + rays.ray_x * ndc.x + rays.ray_y * ndc.y;
            let column = stereo_resample_column(rays.camera_position, ray, clip_from_world);
            let mut middle =
                slice_depth(0.5 / size.z as f32, eye.near, eye.far, eye.curve) - eye.near;
            let (mut front, mut radiance, mut optical) = (0.0, 0.0, 0.0f32);
            let (mut t_prev, mut l_prev) = (1.0, 0.0f32);
            for k in 0..size.z {
                let back = front * a + b;
                let z = eye.near + middle;
                let uvw = stereo_resample_uvw(column, z, shared_froxels);
                let read = footprint(shared, uvw);
                let magnitude = read.2;
                let e = per_sample([read.0, read.1, read.2], (ray * z).length());
                let ds = (back - front) * scale;
                let i = index(size, x, y, k);
                let got = integrated[i];
                let l = got.truncate().abs().max_element();
                // The perturbed transmittance in front of the slice: at most 1.
                let t_front = (t_prev * optical.exp()).min(1.0);
                radiance += t_front * e.truncate().max_element() * ds;
                optical += e.w * ds;
                let grow = optical.exp() - 1.0;
                // The slice's contribution rescaled by the perturbed transmittance, no
                // more than all of it plus what it can become.
                let c = (l - l_prev).abs();
                radiance += (c * grow).min(c + t_front * magnitude.truncate().max_element() * ds);
                bounds[i] = Vec4::new(
                    radiance + 2.0 * HALF * l,
                    0.0,
                    0.0,
                    got.w * grow + 2.0 * HALF * got.w,
                ) + Vec4::splat(1e-6);
                t_prev = got.w;
                l_prev = l;
                middle = middle * a + b;
                front = back;
            }
        }
    }
    bounds
}

/// Largest excess of |got - want| over the bound (<= 0 passes), the largest
/// difference, and the largest bound (rgb, transmittance).
fn excess(got: &[Vec4], want: &[Vec4], bounds: &[Vec4]) -> (f32, f32, f32) {
    let (mut over, mut diff, mut bound) = (f32::NEG_INFINITY, 0.0f32, 0.0f32);
    for ((g, w), b) in got.iter().zip(want).zip(bounds) {
        let d = (*g - *w).abs();
        let rgb = d.truncate().max_element();
        over = over.max(rgb - b.x).max(d.w - b.w);
        diff = diff.max(rgb);
        bound = bound.max(b.x);
    }
    (over, diff, bound)
}

#[test]
fn each_eye_scan_matches_the_cpu_mirror() {
    let gpu = gpu();
    let config = config();
    let eyes = eyes(head(), 0.064);
    let lights = lights();
    let (cascades, shadow) = sun(gpu, &config);
    let inputs = inputs(&eyes[0], &lights, cascades);
    let (fog, _) = stereo_frame(gpu, &config, &eyes, &inputs, &shadow);
    let centre = centre_eye(&eyes).unwrap();
    assert_eq!(fog.centre_eye(), Some(&centre));
    let shared = Volume {
        size: config.volume_size.to_array(),
        texels: read_volume(gpu, fog.shared().scattering_texture()),
    };
    let shared_froxels = shared_grid(&config, &centre);
    let clip_from_world = centre.clip_from_view * centre.view_from_world;
    for (i, eye) in eyes.iter().enumerate() {
        let (froxels, rays) = eye_grid(&config, eye);
        let want = resample_scan_volume(
            &froxels,
            &rays,
            config.scan_step,
            &shared,
            &shared_froxels,
            clip_from_world,
        );
        let got = read_volume(gpu, fog.eye_integrated_texture(i).unwrap());
        // The sampler's filter weights: at worst 8-bit fixed point, half a step off in
        // each of the three lerps.
        let filter = 3.0 / 512.0;
        let bounds = scan_bounds(
            &froxels,
            &rays,
            &shared,
            &shared_froxels,
            clip_from_world,
            &want,
            &|[spread, _, magnitude], _| filter * spread + 1e-6 * magnitude,
        );
        let (over, diff, bound) = excess(&got, &want, &bounds);
        eprintln!(
            "eye {i}: scan vs mirror, largest difference {diff:.3e}, largest bound {bound:.3e}"
        );
        assert!(
            over <= 0.0,
            "eye {i}: a froxel exceeds its bound by {over:e}"
        );
        let lit = want.iter().map(|v| v.x).fold(0.0f32, f32::max);
        assert!(lit > 1e-3, "the scene lights the fog: {lit}");
    }
}

#[test]
fn each_eye_equals_the_mono_fog_of_its_camera() {
    let gpu = gpu();
    let config = config();
    let eyes = eyes(head(), 0.064);
    let lights = lights();
    let (cascades, shadow) = sun(gpu, &config);
    let (fog, image) = stereo_frame(
        gpu,
        &config,
        &eyes,
        &inputs(&eyes[0], &lights, cascades),
        &shadow,
    );
    let centre = centre_eye(&eyes).unwrap();
    let shared = Volume {
        size: config.volume_size.to_array(),
        texels: read_volume(gpu, fog.shared().scattering_texture()),
    };
    let shared_froxels = shared_grid(&config, &centre);
    let clip_from_world = centre.clip_from_view * centre.view_from_world;
    let g = medium().phase_g.abs();
    let kappa = 3.0 * g / (1.0 - g * g);
    let pixels = (IMAGE[0] * IMAGE[1]) as usize;
    for (i, eye) in eyes.iter().enumerate() {
        let (mono, mono_image) = mono_frame(gpu, &config, &inputs(eye, &lights, cascades), &shadow);
        let want = read_volume(gpu, mono.integrated_texture());
        let got = read_volume(gpu, fog.eye_integrated_texture(i).unwrap());
        let (froxels, rays) = eye_grid(&config, eye);
        let per_sample = |[_, curvature, magnitude]: [Vec4; 3], r: f32| {
            let angle = (centre.eye_distance / r).min(1.0).asin();
            let phase = (kappa * angle).exp() - 1.0;
            0.5 * curvature
                + Vec4::new(phase, phase, phase, 0.0) * magnitude
                + 2.0 * HALF * magnitude
        };
        let bounds = scan_bounds(
            &froxels,
            &rays,
            &shared,
            &shared_froxels,
            clip_from_world,
            &want,
            &per_sample,
        );
        let (over, diff, bound) = excess(&got, &want, &bounds);
        let signal = want.iter().map(|v| v.x).fold(0.0f32, f32::max);
        eprintln!(
            "eye {i}: volume vs mono, largest difference {diff:.3e}, largest bound {bound:.3e}, \
             largest in-scatter {signal:.3e}"
        );
        assert!(
            over <= 0.0,
            "eye {i}: a froxel exceeds its bound by {over:e}"
        );
        // The comparison tells the eyes apart: the other eye's volume breaks the bound.
        let other = read_volume(gpu, fog.eye_integrated_texture(1 - i).unwrap());
        let (swapped, _, _) = excess(&other, &want, &bounds);
        eprintln!("eye {i}: the other eye's volume exceeds the bound by {swapped:.3e}");
        assert!(swapped > 0.0, "eye {i}: the other eye's volume passes too");

        // The image: each pixel reads the last slices of the four columns around it.
        let size = config.volume_size;
        let eye_image = &image[i * pixels..(i + 1) * pixels];
        let (mut worst, mut worst_bound) = (f32::NEG_INFINITY, 0.0f32);
        let (mut sum_d, mut sum_b, mut sum_v) = (0.0, 0.0, 0.0);
        for py in 0..IMAGE[1] {
            for px in 0..IMAGE[0] {
                let uv = (Vec2::new(px as f32, py as f32) + 0.5)
                    / Vec2::new(IMAGE[0] as f32, IMAGE[1] as f32);
                let texel = (uv * size.truncate().as_vec2() - 0.5).floor();
                let mut b = 0.0f32;
                for c in 0..8i32 {
                    let (dx, dy, k) = (c & 1, (c >> 1) & 1, size.z - 1 - (c >> 2) as u32);
                    let cx = (texel.x as i32 + dx).clamp(0, size.x as i32 - 1) as u32;
                    let cy = (texel.y as i32 + dy).clamp(0, size.y as i32 - 1) as u32;
                    b = b.max(bounds[index(size, cx, cy, k)].x);
                }
                let p = (py * IMAGE[0] + px) as usize;
                let (s, m) = (eye_image[p].truncate(), mono_image[p].truncate());
                let d = (s - m).abs().max_element();
                let b = b + 2.0 * HALF * m.abs().max_element();
                worst = worst.max(d - b);
                worst_bound = worst_bound.max(b);
                sum_d += d;
                sum_b += b;
                sum_v += m.max_element();
            }
        }
        eprintln!(
            "eye {i}: image vs mono, mean difference {:.2} % and mean bound {:.2} % of the mean \
             pixel, largest bound {worst_bound:.3e}",
            100.0 * sum_d / sum_v,
            100.0 * sum_b / sum_v
        );
        assert!(
            worst <= 0.0,
            "eye {i}: a pixel exceeds its bound by {worst:e}"
        );
        assert!(sum_v > 0.0);
    }
}

/// With temporal reprojection and jitter (the defaults), over frames of a moving head:
/// each eye scans the shared volume its frame stabilised (the history of that frame's
/// parity), as the mirror does from that volume read back.
#[test]
fn with_temporal_reprojection_each_eye_scans_its_frames_stabilised_volume() {
    let gpu = gpu();
    let config = FogConfig {
        temporal: true,
        jitter: true,
        ..config()
    };
    let lights = lights();
    let (cascades, shadow) = sun(gpu, &config);
    let mut fog = StereoFog::new(&gpu.device, &config).unwrap();
    fog.shared_mut()
        .set_shadow_map(&gpu.device, &shadow)
        .unwrap();
    for frame in 0..3 {
        let moved =
            Mat4::from_translation(Vec3::new(0.05 * frame as f32, 0.0, -0.1 * frame as f32))
                * head();
        let eyes = eyes(moved, 0.064);
        fog.prepare(&gpu.queue, &eyes, &inputs(&eyes[0], &lights, cascades))
            .unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let stabilised = fog.shared().stabilised_texture().expect("temporal is on");
        let shared = Volume {
            size: config.volume_size.to_array(),
            texels: read_volume(gpu, stabilised),
        };
        let centre = centre_eye(&eyes).unwrap();
        let shared_froxels = shared_grid(&config, &centre);
        let clip_from_world = centre.clip_from_view * centre.view_from_world;
        for (i, eye) in eyes.iter().enumerate() {
            let (froxels, rays) = eye_grid(&config, eye);
            let want = resample_scan_volume(
                &froxels,
                &rays,
                config.scan_step,
                &shared,
                &shared_froxels,
                clip_from_world,
            );
            let got = read_volume(gpu, fog.eye_integrated_texture(i).unwrap());
            let bounds = scan_bounds(
                &froxels,
                &rays,
                &shared,
                &shared_froxels,
                clip_from_world,
                &want,
                &|[spread, _, magnitude], _| 3.0 / 512.0 * spread + 1e-6 * magnitude,
            );
            let (over, diff, _) = excess(&got, &want, &bounds);
            eprintln!("frame {frame}, eye {i}: largest difference {diff:.3e}");
            assert!(
                over <= 0.0,
                "frame {frame}, eye {i}: exceeds its bound by {over:e}"
            );
        }
    }
}
