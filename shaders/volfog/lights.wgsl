// volfog::lights — light reaching a point of the medium, and in-scattering towards the
// eye.
//
// Use:      #import volfog::lights::{light_attenuation, fog_light_spot, fog_light_inscatter,
//           fog_light_transmittance, ...}
// Defines:  none
// Units:    positions in metres; a light's colour is its intensity (illuminance at 1 m),
//           the sun's colour its illuminance; results are radiance scattered per unit
//           sigma_s (multiply by sigma_s to get W / (sr m^3)).
// Reference: Wronski 2014, "Density estimation and volume lighting" (main light with ESM
//           shadow, ambient, loop over point lights marked as affecting the atmosphere),
//           "Ambient / GI support" (SH product with the HG zonal expansion),
//           "Deferred-like light injection" (bounds test per light).
#define_import_path volfog::lights

#import volfog::types::{DirectionalLight, FogLight, FogMedium}
#import volfog::density::{medium_light_transmittance, medium_segment_transmittance}
#import volfog::phase::{phase_hg, phase_hg_sh_l1, phase_sh_l1_radiance, phase_two_color}

// Inverse-square falloff with a smooth range window:
// saturate(1 - (d / range)^4)^2 / max(d^2, radius^2). Finite for every d >= 0,
// including d = 0 (the source radius bounds it), and 0 at and beyond the range.
fn light_attenuation(distance: f32, range: f32, radius: f32) -> f32 {
    let x = distance / max(range, 1e-6);
    let x2 = x * x;
    let window = clamp(1.0 - x2 * x2, 0.0, 1.0);
    let r = max(radius, 1e-4);
    return window * window / max(distance * distance, r * r);
}

// FogLight.flags: the light is directional (at infinity). Its `direction` is the way
// its light travels and its `color` its illuminance; it lights every point of the
// medium without falloff, and its position, range, radius and cone are ignored.
const FOG_LIGHT_DIRECTIONAL: u32 = 1u;
// FogLight.flags: the spot cone falls off as saturate(t)^2 with
// t = (cos_angle - cos_outer) / max(cos_inner - cos_outer, 1e-4) (Filament's punctual
// light, as Bevy's and other engines' surfaces light) instead of the smoothstep.
const FOG_LIGHT_SPOT_SQUARED: u32 = 2u;

// Spot cone falloff: smoothstep between the outer and inner cone cosines of the angle
// between the spot axis and the direction from the light to the point. A light with
// cos_outer <= -1 is a point light (factor 1).
fn spot_factor(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_outer <= -1.0 {
        return 1.0;
    }
    return smoothstep(cos_outer, max(cos_inner, cos_outer + 1e-4), cos_angle);
}

// Spot cone falloff of FOG_LIGHT_SPOT_SQUARED: saturate(t)^2, t as above; 1 for a
// point light (cos_outer <= -1).
fn spot_factor_squared(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_outer <= -1.0 {
        return 1.0;
    }
    let t = clamp((cos_angle - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0.0, 1.0);
    return t * t;
}

// A light's cone falloff at cos_angle (between its axis and the direction from the
// light to the point), by its flags.
fn fog_light_spot(light: FogLight, cos_angle: f32) -> f32 {
    if (light.flags & FOG_LIGHT_SPOT_SQUARED) != 0u {
        return spot_factor_squared(cos_angle, light.cos_outer, light.cos_inner);
    }
    return spot_factor(cos_angle, light.cos_outer, light.cos_inner);
}

// Whether a light's range sphere touches a sphere of the given centre and radius
// (a block of froxels): lights that fail this test cost nothing. A directional light
// touches every sphere.
fn light_touches_sphere(light: FogLight, center: vec3<f32>, radius: f32) -> bool {
    if (light.flags & FOG_LIGHT_DIRECTIONAL) != 0u {
        return true;
    }
    let d = light.position - center;
    let r = light.range + radius;
    return dot(d, d) <= r * r;
}

// Radiance scattered towards the eye per unit sigma_s by a point, spot or directional
// light at a world position; view_dir is the unit direction from the eye to the point,
// g the HG mean cosine.
fn fog_light_inscatter(light: FogLight, world: vec3<f32>, view_dir: vec3<f32>, g: f32) -> vec3<f32> {
    if (light.flags & FOG_LIGHT_DIRECTIONAL) != 0u {
        let phase = phase_hg(dot(view_dir, -light.direction), g);
        return light.color * (light.fog_intensity * phase);
    }
    let offset = light.position - world;
    let distance = length(offset);
    // At the light's own position the direction is undefined; any unit vector will do
    // because the phase is then multiplied by the bounded attenuation.
    let to_light = select(view_dir, offset / distance, distance > 1e-6);
    let attenuation = light_attenuation(distance, light.range, light.radius);
    let spot = fog_light_spot(light, dot(-to_light, light.direction));
    let phase = phase_hg(dot(view_dir, to_light), g);
    return light.color * (light.fog_intensity * attenuation * spot * phase);
}

// The medium's transmittance between a point of the medium and a light, by its height
// profile (FogLighting.transmittance): along the segment to a point or spot light, up
// to the medium's top towards a directional one.
fn fog_light_transmittance(medium: FogMedium, light: FogLight, world: vec3<f32>) -> f32 {
    if (light.flags & FOG_LIGHT_DIRECTIONAL) != 0u {
        return medium_light_transmittance(medium, world, -light.direction);
    }
    return medium_segment_transmittance(medium, world, light.position);
}

// Radiance scattered towards the eye per unit sigma_s by the directional light with
// visibility `shadow` in [0, 1], HG phase.
fn sun_inscatter(sun: DirectionalLight, shadow: f32, view_dir: vec3<f32>, g: f32) -> vec3<f32> {
    return sun.color * (sun.fog_intensity * shadow * phase_hg(dot(view_dir, sun.direction), g));
}

// As sun_inscatter with AC4's art-driven two-colour phase instead of HG.
fn sun_inscatter_two_color(sun: DirectionalLight, shadow: f32, view_dir: vec3<f32>) -> vec3<f32> {
    let tint = phase_two_color(dot(view_dir, sun.direction), sun.toward_tint, sun.away_tint);
    return sun.color * tint * (sun.fog_intensity * shadow);
}

// Radiance scattered towards the eye per unit sigma_s by ambient light given as L1 SH
// of its incoming radiance, with the HG phase rotated to the view direction: one dot
// product per channel (Wronski 2014, bonus slide).
fn ambient_inscatter(sh_r: vec4<f32>, sh_g: vec4<f32>, sh_b: vec4<f32>, view_dir: vec3<f32>, g: f32) -> vec3<f32> {
    return max(phase_sh_l1_radiance(phase_hg_sh_l1(view_dir, g), sh_r, sh_g, sh_b), vec3<f32>(0.0));
}
