//! Mirror of the scan pass with the frame's transient lights
//! (`VOLFOG_SCAN_TRANSIENT_LIGHTS`): short-lived point, spot and directional lights
//! (a muzzle flash, a lightning strike) added to each live froxel of the stabilised
//! volume as the scan integrates it, so they light this frame only and never reach the
//! history.
//!
//! At the centre of froxel `(x, y, k)`, on its column's ray `r` (per metre of view
//! depth, [`column_ray`]) at view depth `z_k`, the scattering `(rgb, sigma_t)` read
//! from the volume becomes `rgb + albedo sigma_t sum_i L_i`, with `L_i` the light's
//! [`fog_light_inscatter`] along `r / |r|` (times [`fog_light_transmittance`] under
//! `TransientLighting::transmittance`), clamped to the largest rgba16float value, and
//! is then integrated by [`scan_step`]. The slice centres are walked as the
//! boundaries are ([`slice_walk`]), from `slice_depth(0.5 / slices)`.
//!
//! ```
//! use glam::{UVec3, Vec3, Vec4};
//! use volfog::cpu::transient::{TransientScan, scan_volume};
//! use volfog::options::ScanStep;
//! use volfog::uniforms::{FogLight, FogMedium, Froxels, TransientLighting};
//!
//! let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
//! let froxels = Froxels::new(proj, UVec3::new(2, 2, 8), 0.5, 16.0, 2.0).unwrap();
//! // Fog of 0.05/m that nothing lights, and a flash 4 m in front of the camera.
//! let volume = vec![Vec4::new(0.0, 0.0, 0.0, 0.05); 2 * 2 * 8];
//! let flash = [FogLight::point(Vec3::new(0.0, 0.0, -4.0), Vec3::splat(50.0), 10.0)];
//! let rays = volfog::cpu::shadow::shadow_tap_rays(froxels.view_from_clip, glam::Mat4::IDENTITY);
//! let lighting = TransientLighting {
//!     count: 1,
//!     ray_origin: rays[0],
//!     ray_x: rays[1],
//!     ray_y: rays[2],
//!     ..TransientLighting::default()
//! };
//! let medium = FogMedium { density: 0.05, ..FogMedium::default() };
//! let scan = TransientScan { medium: &medium, lighting: &lighting, lights: &flash };
//! let dark = scan_volume(&froxels, ScanStep::EnergyConserving, &volume, None, None);
//! let lit = scan_volume(&froxels, ScanStep::EnergyConserving, &volume, None, Some(&scan));
//! // The flash lights the fog; the transmittance is the medium's either way.
//! assert_eq!(dark[31].x, 0.0);
//! assert!(lit[31].x > 0.0);
//! assert_eq!(lit[31].w, dark[31].w);
//! ```

use glam::{Vec2, Vec3, Vec4};

use super::froxel::{ndc_from_uv, ray_scale, slice_depth, slice_walk};
use super::inject::HALF_MAX;
use super::lights::{fog_light_inscatter, fog_light_transmittance, light_touches_sphere};
use super::scan::{SCAN_START, scan_step};
use crate::options::ScanStep;
use crate::uniforms::{FogLight, FogMedium, Froxels, TransientLighting};

/// What the transient variant of the scan reads besides the volume.
#[derive(Debug, Clone, Copy)]
pub struct TransientScan<'a> {
    /// The medium (its albedo, phase and height profile).
    pub medium: &'a FogMedium,
    /// The camera, its rays, the light count and the transmittance switch.
    pub lighting: &'a TransientLighting,
    /// The transient lights (the first `lighting.count` are used).
    pub lights: &'a [FogLight],
}

/// Radiance scattered towards the eye per unit sigma_s by the transient lights at a
/// world position seen along the unit `view_dir` (a point or spot light beyond its
/// range, where its light is 0, is skipped).
pub fn transient_inscatter(scan: &TransientScan<'_>, world: Vec3, view_dir: Vec3) -> Vec3 {
    let g = scan.medium.phase_g;
    let through = scan.lighting.transmittance != 0;
    scan.lights
        .iter()
        .take(scan.lighting.count as usize)
        .filter(|light| light_touches_sphere(light, world, 0.0))
        .map(|light| {
            let inscatter = fog_light_inscatter(light, world, view_dir, g);
            if through && inscatter.max_element() > 0.0 {
                inscatter * fog_light_transmittance(scan.medium, light, world)
            } else {
                inscatter
            }
        })
        .sum()
}

/// A froxel's scattering (rgb = sigma_s L_in, a = sigma_t) with the in-scattering per
/// unit sigma_s `inscatter` added: `rgb + albedo max(sigma_t, 0) inscatter`, clamped to
/// the largest rgba16float value as inject clamps its output.
pub fn with_inscatter(scattering: Vec4, albedo: Vec3, inscatter: Vec3) -> Vec4 {
    let sigma_s = albedo * scattering.w.max(0.0);
    (scattering.truncate() + sigma_s * inscatter)
        .extend(scattering.w)
        .min(Vec4::splat(HALF_MAX))
}

/// The world-space ray per metre of view depth through the centre of column `(x, y)`.
pub fn column_ray(froxels: &Froxels, lighting: &TransientLighting, x: u32, y: u32) -> Vec3 {
    let uv = (Vec2::new(x as f32, y as f32) + 0.5) / froxels.size.truncate().as_vec2();
    let ndc = ndc_from_uv(uv);
    lighting.ray_origin + lighting.ray_x * ndc.x + lighting.ray_y * ndc.y
}

/// The scan of column `(x, y)` over its first `live` slices (`column` holds the
/// column's scattering, slice 0 first): the integrated values of those slices, with
/// the transient lights added when `transient` is given.
pub fn scan_column(
    froxels: &Froxels,
    step: ScanStep,
    column: &[Vec4],
    (x, y): (u32, u32),
    live: u32,
    transient: Option<&TransientScan<'_>>,
) -> Vec<Vec4> {
    let slices = froxels.size.z;
    let uv = (Vec2::new(x as f32, y as f32) + 0.5) / froxels.size.truncate().as_vec2();
    let scale = ray_scale(uv, froxels.view_from_clip);
    let (a, b) = slice_walk(slices, froxels.near, froxels.far, froxels.curve);
    let (near, far, curve) = (froxels.near, froxels.far, froxels.curve);
    let ray = transient.map(|t| column_ray(froxels, t.lighting, x, y));
    let mut middle = slice_depth(0.5 / slices as f32, near, far, curve) - near;
    let mut front = 0.0;
    let mut acc = SCAN_START;
    let mut out = Vec::with_capacity(live as usize);
    for &read in column.iter().take(live.min(slices) as usize) {
        let back = front * a + b;
        let mut medium = read;
        if let (Some(t), Some(ray)) = (transient, ray) {
            let world = t.lighting.camera_position + ray * (near + middle);
            let inscatter = transient_inscatter(t, world, ray.normalize());
            medium = with_inscatter(medium, t.medium.albedo, inscatter);
            middle = middle * a + b;
        }
        acc = scan_step(acc, medium, (back - front) * scale, step);
        out.push(acc.min(Vec4::splat(HALF_MAX)));
        front = back;
    }
    out
}

/// The scan pass over a whole volume (x fastest, then y, then slices), with the live
/// slices per column of the depth-culling variant (`size.x * size.y` values; the
/// texels behind them hold the value at the last live slice) and the transient lights.
pub fn scan_volume(
    froxels: &Froxels,
    step: ScanStep,
    volume: &[Vec4],
    live: Option<&[u32]>,
    transient: Option<&TransientScan<'_>>,
) -> Vec<Vec4> {
    let [sx, sy, sz] = froxels.size.to_array();
    let mut out = vec![Vec4::ZERO; volume.len()];
    let index = |x: u32, y: u32, z: u32| ((z * sy + y) * sx + x) as usize;
    for y in 0..sy {
        for x in 0..sx {
            let column: Vec<Vec4> = (0..sz).map(|z| volume[index(x, y, z)]).collect();
            let count = live.map_or(sz, |l| l[(y * sx + x) as usize].min(sz));
            let scanned = scan_column(froxels, step, &column, (x, y), count, transient);
            let held = scanned.last().copied().unwrap_or(SCAN_START);
            for z in 0..sz {
                out[index(x, y, z)] = scanned.get(z as usize).copied().unwrap_or(held);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::density::medium_segment_transmittance;
    use crate::cpu::froxel::froxel_view_position;
    use glam::{Mat4, UVec3};

    /// The walked centres and the column rays put each froxel's sample where inject's
    /// `froxel_view_position` (without jitter) puts it, within 3e-5 of its depth.
    #[test]
    fn centres_walked_on_the_column_ray_are_the_froxel_centres() {
        let proj = glam::camera::rh::proj::directx::perspective(1.1, 1.6, 0.1, 300.0);
        let world_from_view = Mat4::from_rotation_translation(
            glam::Quat::from_rotation_y(0.7) * glam::Quat::from_rotation_x(-0.2),
            Vec3::new(3.0, 2.0, -5.0),
        );
        for curve in [0.0, 1.5, (128.0f32 / 0.5).ln()] {
            let froxels = Froxels::new(proj, UVec3::new(7, 5, 64), 0.5, 128.0, curve).unwrap();
            let rays = crate::cpu::shadow::shadow_tap_rays(froxels.view_from_clip, world_from_view);
            let lighting = TransientLighting {
                camera_position: world_from_view.w_axis.truncate(),
                ray_origin: rays[0],
                ray_x: rays[1],
                ray_y: rays[2],
                ..TransientLighting::default()
            };
            let (a, b) = slice_walk(64, 0.5, 128.0, curve);
            for (x, y) in [(0, 0), (3, 2), (6, 4)] {
                let ray = column_ray(&froxels, &lighting, x, y);
                let mut middle = slice_depth(0.5 / 64.0, 0.5, 128.0, curve) - 0.5;
                for k in 0..64 {
                    let walked = lighting.camera_position + ray * (0.5 + middle);
                    let view = froxel_view_position(
                        UVec3::new(x, y, k),
                        Vec3::ZERO,
                        froxels.size,
                        froxels.view_from_clip,
                        0.5,
                        128.0,
                        curve,
                    );
                    let want = world_from_view.transform_point3(view);
                    assert!(
                        walked.distance(want) <= 3e-5 * view.z.abs() + 1e-5,
                        "curve {curve}, column {x},{y}, slice {k}: {walked} vs {want}"
                    );
                    middle = middle * a + b;
                }
            }
        }
    }

    /// Skipping a point or spot light beyond its range changes nothing: its light there
    /// is exactly 0 (the range window), at random points in and out of range.
    #[test]
    fn skipping_lights_beyond_their_range_is_exact() {
        let mut rng = crate::cpu::TestRng(7);
        let medium = FogMedium::default();
        let lights = [
            FogLight::point(Vec3::new(1.0, 2.0, -4.0), Vec3::new(30.0, 20.0, 10.0), 6.0),
            FogLight::spot(
                Vec3::new(-2.0, 5.0, -9.0),
                Vec3::NEG_Y,
                Vec3::splat(80.0),
                9.0,
                0.3,
                0.6,
            ),
        ];
        let lighting = TransientLighting {
            count: 2,
            ..TransientLighting::default()
        };
        let scan = TransientScan {
            medium: &medium,
            lighting: &lighting,
            lights: &lights,
        };
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..2000 {
            let world = Vec3::new(
                rng.range(-15.0, 15.0),
                rng.range(-5.0, 15.0),
                rng.range(-25.0, 5.0),
            );
            let every: Vec3 = lights
                .iter()
                .map(|l| fog_light_inscatter(l, world, Vec3::NEG_Z, medium.phase_g))
                .sum();
            assert_eq!(
                transient_inscatter(&scan, world, Vec3::NEG_Z),
                every,
                "{world}"
            );
            for l in &lights {
                if light_touches_sphere(l, world, 0.0) {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
        }
        assert!(inside > 100 && outside > 100, "{inside} {outside}");
    }

    /// A lone point light in fog whose albedo is 0.5: at a froxel the light's
    /// in-scattering is sigma_s times the inverse-square law times the isotropic phase
    /// times the medium's transmittance along the segment, written out here.
    #[test]
    fn a_point_light_adds_its_inverse_square_inscattering() {
        let medium = FogMedium {
            albedo: Vec3::splat(0.5),
            density: 0.1,
            height_falloff: 0.2,
            phase_g: 0.0,
            ..FogMedium::default()
        };
        let light = FogLight::point(Vec3::new(0.0, 1.0, -5.0), Vec3::new(8.0, 4.0, 2.0), 1.0e4);
        let lighting = TransientLighting {
            count: 1,
            transmittance: 1,
            ..TransientLighting::default()
        };
        let scan = TransientScan {
            medium: &medium,
            lighting: &lighting,
            lights: &[light],
        };
        let world = Vec3::new(0.0, 1.0, -3.0);
        let got = with_inscatter(
            Vec4::new(0.01, 0.02, 0.03, 0.1),
            medium.albedo,
            transient_inscatter(&scan, world, Vec3::NEG_Z),
        );
        // 2 m away: 1 / 4 of the intensity, phase 1 / (4 pi), sigma_s 0.05.
        let through = medium_segment_transmittance(&medium, world, light.position);
        assert!(through > 0.5 && through < 1.0, "{through}");
        let want = Vec3::new(0.01, 0.02, 0.03)
            + 0.05 * light.color * (0.25 / (4.0 * std::f32::consts::PI)) * through;
        assert!(
            (got.truncate() - want).abs().max_element() < 1e-6,
            "{got} {want}"
        );
        assert_eq!(got.w, 0.1);
        // Without extinction nothing scatters; more lights than `count` are ignored.
        assert_eq!(
            with_inscatter(
                Vec4::new(1.0, 2.0, 3.0, 0.0),
                medium.albedo,
                Vec3::splat(9.0)
            ),
            Vec4::new(1.0, 2.0, 3.0, 0.0)
        );
        let none = TransientLighting {
            count: 0,
            ..lighting
        };
        let unlit = TransientScan {
            lighting: &none,
            ..scan
        };
        assert_eq!(transient_inscatter(&unlit, world, Vec3::NEG_Z), Vec3::ZERO);
    }
}
