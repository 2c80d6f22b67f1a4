//! Mirror of `volfog::lights`: light reaching the medium and in-scattering.
//!
//! ```
//! use volfog::cpu::lights::light_attenuation;
//! // Inverse square inside the range, bounded by the source radius at the light.
//! assert!((light_attenuation(2.0, 1.0e6, 0.05) - 0.25).abs() < 1e-6);
//! assert!(light_attenuation(0.0, 10.0, 0.05).is_finite());
//! assert_eq!(light_attenuation(10.0, 10.0, 0.05), 0.0);
//! ```

use glam::{Vec3, Vec4};

use super::phase::{phase_hg, phase_hg_sh_l1, phase_sh_l1_radiance, phase_two_color};
use crate::uniforms::{DirectionalLight, FogLight};

/// Inverse square with a smooth range window, bounded by the source radius.
pub fn light_attenuation(distance: f32, range: f32, radius: f32) -> f32 {
    let x = distance / range.max(1e-6);
    let x2 = x * x;
    let window = (1.0 - x2 * x2).clamp(0.0, 1.0);
    let r = radius.max(1e-4);
    window * window / (distance * distance).max(r * r)
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Spot cone falloff (1 for point lights, `cos_outer <= -1`).
pub fn spot_factor(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_outer <= -1.0 {
        return 1.0;
    }
    smoothstep(cos_outer, cos_inner.max(cos_outer + 1e-4), cos_angle)
}

/// Whether a light's range sphere touches a sphere.
pub fn light_touches_sphere(light: &FogLight, center: Vec3, radius: f32) -> bool {
    let d = light.position - center;
    let r = light.range + radius;
    d.dot(d) <= r * r
}

/// In-scattering per unit sigma_s of a point or spot light.
pub fn fog_light_inscatter(light: &FogLight, world: Vec3, view_dir: Vec3, g: f32) -> Vec3 {
    let offset = light.position - world;
    let distance = offset.length();
    let to_light = if distance > 1e-6 {
        offset / distance
    } else {
        view_dir
    };
    let attenuation = light_attenuation(distance, light.range, light.radius);
    let spot = spot_factor(
        (-to_light).dot(light.direction),
        light.cos_outer,
        light.cos_inner,
    );
    let phase = phase_hg(view_dir.dot(to_light), g);
    light.color * (light.fog_intensity * attenuation * spot * phase)
}

/// In-scattering per unit sigma_s of the directional light, HG phase.
pub fn sun_inscatter(sun: &DirectionalLight, shadow: f32, view_dir: Vec3, g: f32) -> Vec3 {
    sun.color * (sun.fog_intensity * shadow * phase_hg(view_dir.dot(sun.direction), g))
}

/// In-scattering per unit sigma_s of the directional light, two-colour phase.
pub fn sun_inscatter_two_color(sun: &DirectionalLight, shadow: f32, view_dir: Vec3) -> Vec3 {
    let tint = phase_two_color(view_dir.dot(sun.direction), sun.toward_tint, sun.away_tint);
    sun.color * tint * (sun.fog_intensity * shadow)
}

/// In-scattering per unit sigma_s of L1 SH ambient radiance.
pub fn ambient_inscatter(sh_r: Vec4, sh_g: Vec4, sh_b: Vec4, view_dir: Vec3, g: f32) -> Vec3 {
    phase_sh_l1_radiance(phase_hg_sh_l1(view_dir, g), sh_r, sh_g, sh_b).max(Vec3::ZERO)
}
