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

use super::density::{medium_light_transmittance, medium_segment_transmittance};
use super::phase::{phase_hg, phase_hg_sh_l1, phase_sh_l1_radiance, phase_two_color};
use crate::uniforms::{DirectionalLight, FOG_LIGHT_SPOT_SQUARED, FogLight, FogMedium};

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

/// Spot cone falloff of [`FOG_LIGHT_SPOT_SQUARED`]: `saturate(t)^2` (1 for point
/// lights).
pub fn spot_factor_squared(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_outer <= -1.0 {
        return 1.0;
    }
    let t = ((cos_angle - cos_outer) / (cos_inner - cos_outer).max(1e-4)).clamp(0.0, 1.0);
    t * t
}

/// A light's cone falloff by its flags.
pub fn fog_light_spot(light: &FogLight, cos_angle: f32) -> f32 {
    if light.flags & FOG_LIGHT_SPOT_SQUARED != 0 {
        spot_factor_squared(cos_angle, light.cos_outer, light.cos_inner)
    } else {
        spot_factor(cos_angle, light.cos_outer, light.cos_inner)
    }
}

/// Whether a light's range sphere touches a sphere (a directional light touches
/// every sphere).
pub fn light_touches_sphere(light: &FogLight, center: Vec3, radius: f32) -> bool {
    if light.is_directional() {
        return true;
    }
    let d = light.position - center;
    let r = light.range + radius;
    d.dot(d) <= r * r
}

/// In-scattering per unit sigma_s of a point, spot or directional light.
pub fn fog_light_inscatter(light: &FogLight, world: Vec3, view_dir: Vec3, g: f32) -> Vec3 {
    if light.is_directional() {
        return light.color * (light.fog_intensity * phase_hg(view_dir.dot(-light.direction), g));
    }
    let offset = light.position - world;
    let distance = offset.length();
    let to_light = if distance > 1e-6 {
        offset / distance
    } else {
        view_dir
    };
    let attenuation = light_attenuation(distance, light.range, light.radius);
    let spot = fog_light_spot(light, (-to_light).dot(light.direction));
    let phase = phase_hg(view_dir.dot(to_light), g);
    light.color * (light.fog_intensity * attenuation * spot * phase)
}

/// The medium's transmittance between a point and a light by its height profile:
/// along the segment to a point or spot light, up to the medium's top towards a
/// directional one.
pub fn fog_light_transmittance(medium: &FogMedium, light: &FogLight, world: Vec3) -> f32 {
    if light.is_directional() {
        medium_light_transmittance(medium, world, -light.direction)
    } else {
        medium_segment_transmittance(medium, world, light.position)
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uniforms::{FOG_LIGHT_DIRECTIONAL, LOCAL_SHADOW_NONE};

    /// The squared cone against Filament's form as engines precompute it:
    /// `saturate(cos * scale + offset)^2`, `scale = 1 / max(cos_inner - cos_outer,
    /// 1e-4)`, `offset = -cos_outer * scale`.
    #[test]
    fn squared_cone_is_filaments_punctual_spot() {
        for (inner, outer) in [(0.2f32, 0.7f32), (0.0, 0.5), (0.6, 0.6), (1.0, 1.2)] {
            let (ci, co) = (inner.cos(), outer.cos());
            let scale = 1.0 / (ci - co).max(1e-4);
            let offset = -co * scale;
            for k in 0..=100 {
                let c = -1.0 + 2.0 * k as f32 / 100.0;
                let filament = (c * scale + offset).clamp(0.0, 1.0).powi(2);
                let ours = spot_factor_squared(c, co, ci);
                assert!(
                    (ours - filament).abs() < 1e-5,
                    "{inner} {outer} {c}: {ours} {filament}"
                );
            }
        }
        // Halfway between the cones in cosine: 1/4 squared, 1/2 smoothstep.
        let (co, ci) = (0.5, 0.9);
        assert!((spot_factor_squared(0.7, co, ci) - 0.25).abs() < 1e-6);
        assert!((spot_factor(0.7, co, ci) - 0.5).abs() < 1e-6);
    }

    /// A directional light ignores distance, range and cone, and its flags are checked.
    #[test]
    fn directional_light_has_no_falloff_and_bad_flags_are_refused() {
        let toward = Vec3::new(0.0, 1.0, 0.0);
        let light = FogLight::directional(toward, Vec3::ONE);
        let g = 0.3;
        for world in [Vec3::ZERO, Vec3::new(1e4, -50.0, 3.0)] {
            let l = fog_light_inscatter(&light, world, Vec3::X, g);
            assert!((l - Vec3::splat(phase_hg(0.0, g))).length() < 1e-6);
            assert!(light_touches_sphere(&light, world, 0.0));
        }
        assert_eq!(light.projection, LOCAL_SHADOW_NONE);
        let bad = FogLight {
            flags: FOG_LIGHT_DIRECTIONAL | 8,
            ..light
        };
        assert_eq!(bad.validate().unwrap_err().field, "FogLight.flags");
        let unnormalised = FogLight {
            direction: Vec3::new(0.0, -2.0, 0.0),
            ..light
        };
        assert_eq!(
            unnormalised.validate().unwrap_err().field,
            "FogLight.direction"
        );
    }
}
