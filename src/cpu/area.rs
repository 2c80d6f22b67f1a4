//! Mirror of `volfog::area_lights` and of the area-light term of inject
//! (`VOLFOG_INJECT_AREA_LIGHTS`): rectangle and disk emitters whose in-scattering is
//! integrated over their area.
//!
//! At a point `x` seen along `view_dir`, a one-sided Lambertian emitter of radiance
//! `L_e` scatters `L_e * integral phase(view_dir, w) T(x, y(w)) dw` per unit sigma_s,
//! over the solid angle the emitter covers from `x` (nothing behind its plane). The
//! emitter is cut into planar cells, a rectangle into [`AREA_LIGHT_GRID`]^2
//! rectangles, a disk into [`AREA_LIGHT_SECTORS`] sectors of two rings of equal area
//! (a 16-gon of the disk's area); each cell's solid angle is exact (Van Oosterom and
//! Strackee's triangle formula), its phase and transmittance are taken at its centre.
//!
//! ```
//! use volfog::cpu::area::area_light_inscatter;
//! use volfog::glam::Vec3;
//! use volfog::uniforms::{AreaLight, FogMedium};
//!
//! // A disk of radius 1 m facing down from 2 m above the point, radiance 1, isotropic
//! // phase, clear air: L_e * solid angle / (4 pi), the solid angle
//! // 2 pi (1 - z / sqrt(z^2 + r^2)).
//! let disk = AreaLight::disk(Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y, 1.0, Vec3::ONE, 100.0);
//! let medium = FogMedium::default();
//! let got = area_light_inscatter(&disk, &medium, false, Vec3::ZERO, Vec3::X, 0.0).x;
//! let omega = std::f32::consts::TAU * (1.0 - 2.0 / 5.0_f32.sqrt());
//! // Within the 16-gon's share of the near field (range window 1 - 1.6e-7).
//! assert!((got / (omega / (4.0 * std::f32::consts::PI)) - 1.0).abs() < 5e-3);
//! ```

use glam::{UVec3, Vec3, Vec4};

use super::density::medium_segment_transmittance;
use super::inject::{HALF_MAX, froxel_world_position, injected_source};
use super::phase::phase_hg;
use crate::uniforms::{AREA_LIGHT_DISK, AreaLight, FogFrame, FogMedium, Froxels};

/// Cells per side of a rectangle (WGSL `AREA_LIGHT_GRID`).
pub const AREA_LIGHT_GRID: u32 = 4;
/// Sectors of a disk, each an inner triangle and an outer quadrilateral (WGSL
/// `AREA_LIGHT_SECTORS`).
pub const AREA_LIGHT_SECTORS: u32 = 16;
/// Radius of a disk's inner ring over its outer one: rings of equal area.
pub const AREA_LIGHT_INNER: f32 = std::f32::consts::FRAC_1_SQRT_2;
/// A disk's polygon radius over its radius: the 16-gon of the disk's area,
/// `sqrt(2 pi / (16 sin(2 pi / 16)))`.
pub const AREA_LIGHT_DISK_SCALE: f32 = 1.013_002_9;

/// Solid angle (sr, in `[0, 2 pi)`) of the triangle `a, b, c` given relative to the
/// point that sees it (Van Oosterom and Strackee).
pub fn triangle_solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    // From the edges (see the WGSL): no cancellation for a small or distant cell.
    let numerator = a.dot((b - a).cross(c - a)).abs();
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// Solid angle (sr) of the quadrilateral `a, b, c, d`, cut along `a-c`.
pub fn quad_solid_angle(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> f32 {
    triangle_solid_angle(a, b, c) + triangle_solid_angle(a, c, d)
}

/// One cell's weight per unit radiance: `omega` times the HG phase towards its centre
/// `mid` (relative to `world`), times the medium's transmittance to it when `through`.
#[allow(clippy::too_many_arguments)]
pub fn area_cell(
    medium: &FogMedium,
    through: bool,
    world: Vec3,
    view_dir: Vec3,
    g: f32,
    omega: f32,
    mid: Vec3,
) -> f32 {
    let length_mid = mid.length();
    let to_cell = if length_mid > 1e-6 {
        mid / length_mid
    } else {
        view_dir
    };
    let mut weight = omega * phase_hg(view_dir.dot(to_cell), g);
    if through {
        weight *= medium_segment_transmittance(medium, world, world + mid);
    }
    weight
}

/// Whether an area light's range sphere touches a sphere (a block of froxels); an
/// unused slot (`range <= 0`) touches nothing.
pub fn area_light_touches_sphere(light: &AreaLight, center: Vec3, radius: f32) -> bool {
    let d = light.center - center;
    let r = light.range + radius;
    light.range > 0.0 && d.dot(d) <= r * r
}

/// In-scattering per unit sigma_s of an area light at `world` seen along the unit
/// `view_dir`, HG mean cosine `g`; `through` attenuates each cell by the medium's
/// height profile (WGSL `area_light_inscatter`).
pub fn area_light_inscatter(
    light: &AreaLight,
    medium: &FogMedium,
    through: bool,
    world: Vec3,
    view_dir: Vec3,
    g: f32,
) -> Vec3 {
    let normal = light.axis_x.cross(light.axis_y);
    let offset = light.center - world;
    let distance = offset.length();
    if offset.dot(normal) >= 0.0 || light.range <= 0.0 {
        return Vec3::ZERO;
    }
    let x = distance / light.range;
    let x2 = x * x;
    let window = (1.0 - x2 * x2).clamp(0.0, 1.0);
    let ex = light.axis_x * light.half_x;
    let ey = light.axis_y * light.half_y;
    let cell = |omega: f32, mid: Vec3| area_cell(medium, through, world, view_dir, g, omega, mid);
    let mut sum = 0.0;
    if light.shape == AREA_LIGHT_DISK {
        let step = std::f32::consts::TAU / AREA_LIGHT_SECTORS as f32;
        for k in 0..AREA_LIGHT_SECTORS {
            let (a0, a1) = (step * k as f32, step * (k + 1) as f32);
            let p = AREA_LIGHT_DISK_SCALE * (ex * a0.cos() + ey * a0.sin());
            let q = AREA_LIGHT_DISK_SCALE * (ex * a1.cos() + ey * a1.sin());
            let (pi, qi) = (AREA_LIGHT_INNER * p, AREA_LIGHT_INNER * q);
            let inner = triangle_solid_angle(offset, offset + pi, offset + qi);
            sum += cell(inner, offset + (pi + qi) / 3.0);
            let outer = quad_solid_angle(offset + pi, offset + p, offset + q, offset + qi);
            sum += cell(outer, offset + 0.25 * (pi + p + q + qi));
        }
    } else {
        let n = AREA_LIGHT_GRID as f32;
        for j in 0..AREA_LIGHT_GRID {
            let (v0, v1) = (2.0 * j as f32 / n - 1.0, 2.0 * (j + 1) as f32 / n - 1.0);
            for i in 0..AREA_LIGHT_GRID {
                let (u0, u1) = (2.0 * i as f32 / n - 1.0, 2.0 * (i + 1) as f32 / n - 1.0);
                let corner = offset + ex * u0 + ey * v0;
                let du = ex * (u1 - u0);
                let dv = ey * (v1 - v0);
                let omega = quad_solid_angle(corner, corner + du, corner + du + dv, corner + dv);
                sum += cell(omega, corner + 0.5 * (du + dv));
            }
        }
    }
    light.radiance * (light.fog_intensity * window * window * sum)
}

/// The in-scattering per unit sigma_s of every area light at `world` (the sum of
/// [`area_light_inscatter`]).
pub fn area_lights_inscatter(
    lights: &[AreaLight],
    medium: &FogMedium,
    through: bool,
    world: Vec3,
    view_dir: Vec3,
) -> Vec3 {
    lights
        .iter()
        .map(|l| area_light_inscatter(l, medium, through, world, view_dir, medium.phase_g))
        .sum()
}

/// Adds the area lights' term of `inject@...INJECT_AREA_LIGHTS` to a volume the inject
/// mirror computed without them (x fastest, then y, then z; without temporal
/// reprojection): each froxel's `rgb += albedo * sigma_t * L_area` at its sample
/// (jittered when `jitter`), clamped to the largest rgba16float value as the pass
/// clamps. Exact where the medium's albedo is `FogMedium::albedo` (no custom density)
/// and the sum stays below that clamp.
pub fn add_area_lights(
    froxels: &Froxels,
    frame: &FogFrame,
    medium: &FogMedium,
    through: bool,
    jitter: bool,
    lights: &[AreaLight],
    volume: &mut [Vec4],
) {
    let size = froxels.size;
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let at = (x + size.x * (y + size.y * z)) as usize;
                let source = injected_source(UVec3::new(x, y, z), frame, size.z);
                let (world, _) = froxel_world_position(froxels, frame, source, jitter);
                let view_dir = (world - frame.camera_position).normalize();
                let texel = volume[at];
                let sigma_s = medium.albedo * texel.w.max(0.0);
                if texel.w <= 0.0 {
                    continue;
                }
                let light = area_lights_inscatter(lights, medium, through, world, view_dir);
                let rgb = (texel.truncate() + sigma_s * light).min(Vec3::splat(HALF_MAX));
                volume[at] = rgb.extend(texel.w);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! The integral against answers that do not use its cells: solid angles in closed
    //! form, a point light of the same intensity, and a fine quadrature of
    //! `L cos(theta_e) dA / r^2 phase T` over the emitter.

    use super::*;
    use crate::cpu::lights::fog_light_inscatter;
    use crate::uniforms::{AREA_LIGHT_RECT, FogLight};
    use std::f64::consts::PI;

    /// Clear air (no density) and a homogeneous medium of `sigma` per metre.
    fn medium(sigma: f32) -> FogMedium {
        FogMedium {
            density: sigma,
            height_falloff: 0.0,
            ..FogMedium::default()
        }
    }

    /// Isotropic phase, clear air: on the disk's axis at height z the result is
    /// L Omega / (4 pi), Omega = 2 pi (1 - z / sqrt(z^2 + r^2)).
    #[test]
    fn a_disk_on_its_axis_subtends_its_closed_form_solid_angle() {
        let r = 1.0f32;
        let disk = AreaLight::disk(Vec3::ZERO, Vec3::Y, r, Vec3::ONE, 1.0e4);
        let mut worst = 0.0f64;
        for z in [0.02f32, 0.1, 0.3, 1.0, 3.0, 10.0] {
            let got = area_light_inscatter(&disk, &medium(0.0), false, Vec3::Y * z, Vec3::X, 0.0);
            let (z, r) = (z as f64, r as f64);
            let omega = 2.0 * PI * (1.0 - z / (z * z + r * r).sqrt());
            let want = omega / (4.0 * PI);
            worst = worst.max((got.x as f64 / want - 1.0).abs());
        }
        eprintln!("disk on its axis vs 2 pi (1 - z / sqrt(z^2 + r^2)): worst {worst:e}");
        assert!(worst < 1e-3, "{worst}");
    }

    /// Isotropic phase, clear air: on a 2a x 2b rectangle's axis at distance d,
    /// Omega = 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))), exact at every distance.
    #[test]
    fn a_rectangle_on_its_axis_subtends_its_closed_form_solid_angle() {
        let (a, b) = (1.5f32, 0.4f32);
        let rect = AreaLight::rect(Vec3::ZERO, Vec3::X, Vec3::NEG_Z, a, b, Vec3::ONE, 1.0e4);
        let mut worst = 0.0f64;
        for d in [0.01f32, 0.2, 1.0, 4.0, 20.0] {
            let got = area_light_inscatter(&rect, &medium(0.0), false, Vec3::Y * d, Vec3::X, 0.0);
            let (a, b, d) = (a as f64, b as f64, d as f64);
            let omega = 4.0 * (a * b / ((a * a + d * d) * (b * b + d * d)).sqrt()).asin();
            worst = worst.max((got.x as f64 * 4.0 * PI / omega - 1.0).abs());
        }
        eprintln!("rectangle on its axis vs 4 asin(ab / ...): worst {worst:e}");
        assert!(worst < 1e-4, "{worst}");
    }

    /// A 2 cm emitter seen from metres away is a point light of intensity
    /// L A cos(theta_e) (the same range window, phase and transmittance).
    #[test]
    fn a_tiny_emitter_is_a_point_light_of_its_intensity() {
        let m = medium(0.05);
        let normal = Vec3::new(0.2, -1.0, 0.3).normalize();
        let centre = Vec3::new(0.5, 4.0, -2.0);
        let radiance = Vec3::new(3.0e3, 2.0e3, 1.0e3);
        for shape in [AREA_LIGHT_RECT, AREA_LIGHT_DISK] {
            let light = AreaLight {
                shape,
                ..AreaLight::disk(centre, normal, 0.01, radiance, 30.0)
            };
            for world in [
                Vec3::ZERO,
                Vec3::new(-3.0, 0.5, -6.0),
                Vec3::new(4.0, 1.0, 3.0),
            ] {
                let view_dir = (world - Vec3::new(0.0, 1.0, 8.0)).normalize();
                let cos_e = (world - centre).normalize().dot(normal);
                let point = FogLight {
                    radius: 1e-4,
                    ..FogLight::point(centre, radiance * light.area() * cos_e, 30.0)
                };
                let want = fog_light_inscatter(&point, world, view_dir, 0.6)
                    * medium_segment_transmittance(&m, world, centre);
                let got = area_light_inscatter(&light, &m, true, world, view_dir, 0.6);
                let err = ((got - want).abs() / want.max_element()).max_element();
                assert!(err < 1e-3, "shape {shape} at {world}: {got} vs {want}");
            }
        }
    }

    /// The integrand L cos(theta_e) / r^2 phase_hg exp(-sigma r) summed by the midpoint
    /// rule over an n x n grid of the emitter's parameter square (f64).
    fn quadrature(light: &AreaLight, sigma: f64, world: Vec3, view_dir: Vec3, g: f64) -> f64 {
        let n = 600;
        let normal = light.normal().as_dvec3();
        let (ex, ey) = (light.axis_x.as_dvec3(), light.axis_y.as_dvec3());
        let (hx, hy) = (light.half_x as f64, light.half_y as f64);
        let c = light.center.as_dvec3() - world.as_dvec3();
        let mut sum = 0.0;
        for j in 0..n {
            for i in 0..n {
                let u = -1.0 + (2 * i + 1) as f64 / n as f64;
                let v = -1.0 + (2 * j + 1) as f64 / n as f64;
                if light.shape == AREA_LIGHT_DISK && u * u + v * v > 1.0 {
                    continue;
                }
                let y = c + ex * (hx * u) + ey * (hy * v);
                let r = y.length();
                let cos_e = (-y / r).dot(normal);
                let mu = view_dir.as_dvec3().dot(y / r);
                let phase = (1.0 - g * g) / (4.0 * PI * (1.0 + g * g - 2.0 * g * mu).powf(1.5));
                sum += cos_e / (r * r) * phase * (-sigma * r).exp();
            }
        }
        sum * (4.0 * hx * hy) / (n * n) as f64
    }

    /// Forward-scattering fog (g = 0.6, 0.1/m) round a 2 m x 1 m panel and a disk of
    /// radius 0.8 m: the cells' centre phase and transmittance against a fine
    /// quadrature, from half a metre to 12 m, in front, beside and below.
    #[test]
    fn the_cells_follow_a_fine_quadrature_in_forward_scattering_fog() {
        let sigma = 0.1;
        let m = medium(sigma);
        let down = Vec3::new(0.1, -1.0, 0.05).normalize();
        let (ax, ay) = down.any_orthonormal_pair();
        let lights = [
            AreaLight::rect(Vec3::new(0.0, 5.0, 0.0), ax, ay, 1.0, 0.5, Vec3::ONE, 100.0),
            AreaLight::disk(Vec3::new(0.0, 5.0, 0.0), down, 0.8, Vec3::ONE, 100.0),
        ];
        let eye = Vec3::new(-6.0, 1.5, 9.0);
        let mut errors = Vec::new();
        for light in &lights {
            for world in [
                Vec3::new(0.0, 4.5, 0.0),
                Vec3::new(0.3, 4.0, -0.2),
                Vec3::new(1.5, 4.2, 0.5),
                Vec3::new(0.0, 2.0, 0.0),
                Vec3::new(-3.0, 1.0, 2.0),
                Vec3::new(8.0, 0.0, -9.0),
            ] {
                let view_dir = (world - eye).normalize();
                let want = quadrature(light, sigma as f64, world, view_dir, 0.6);
                let got = area_light_inscatter(light, &m, true, world, view_dir, 0.6).x as f64;
                errors.push((got / want - 1.0).abs());
            }
        }
        let worst = errors.iter().cloned().fold(0.0, f64::max);
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        eprintln!("cells vs quadrature (g 0.6, 0.1/m): mean {mean:e}, worst {worst:e}");
        assert!(worst < 0.03, "{errors:?}");
    }

    /// Nothing behind the emitter's plane, nothing beyond its range, nothing from an
    /// unused slot; the block test keeps every block the light reaches.
    #[test]
    fn the_emitter_is_one_sided_and_bounded_by_its_range() {
        let panel = AreaLight::rect(Vec3::Y * 3.0, Vec3::X, Vec3::Z, 1.0, 1.0, Vec3::ONE, 10.0);
        let m = medium(0.0);
        assert!(area_light_inscatter(&panel, &m, false, Vec3::ZERO, Vec3::X, 0.3).x > 0.0);
        assert_eq!(
            area_light_inscatter(&panel, &m, false, Vec3::Y * 4.0, Vec3::X, 0.3),
            Vec3::ZERO
        );
        assert_eq!(
            area_light_inscatter(&panel, &m, false, Vec3::new(0.0, -8.0, 0.0), Vec3::X, 0.3),
            Vec3::ZERO
        );
        let unused = AreaLight::default();
        assert_eq!(
            area_light_inscatter(&unused, &m, false, Vec3::ZERO, Vec3::X, 0.3),
            Vec3::ZERO
        );
        assert!(!area_light_touches_sphere(&unused, Vec3::ZERO, 1.0e3));
        assert!(area_light_touches_sphere(
            &panel,
            Vec3::new(0.0, -8.0, 0.0),
            1.5
        ));
        assert!(!area_light_touches_sphere(
            &panel,
            Vec3::new(0.0, -8.0, 0.0),
            0.5
        ));
    }
}
