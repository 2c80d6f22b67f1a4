//! Bevy 0.20's volumetric fog (`bevy_pbr/src/volumetric_fog/volumetric_fog.wesl`)
//! evaluated on the CPU for a mapped truth scene, pixel by pixel, with three of its
//! choices as switches ([`ModelOptions`]) so that each one's share of the difference
//! from the path tracer can be measured. What the shader does, per fog volume, for the
//! ray through a pixel's centre:
//!
//! - the ray starts on the near plane, enters and leaves the volume's box, and ends at
//!   the depth buffer's surface; its length is taken as the difference of the view
//!   depths of its ends (`ray_length_view`), and `step_count` steps of that length
//!   are taken from the entry point along the unit ray: off the view's axis the march
//!   stops short of the surface, by the cosine of the ray's angle to the axis;
//! - each step's point `P = entry + i step` (no jitter): its density `density_factor`
//!   times the density texture (0 outside the unit cube), the transmittance so far
//!   multiplied by that step's `exp(-step density extinction)`, then the light it
//!   scatters added, weighted by the transmittance including the step; a ray stops once
//!   the transmittance is below 0.001;
//! - the sun (a directional light with `VolumetricLight`): its colour times illuminance,
//!   Henyey-Greenstein's phase of the view and light directions, the shadow map, and
//!   `exp(-density bounding_radius extinction)` for the light's way through the fog,
//!   `bounding_radius` the half diagonal of the volume's box whatever the light's path;
//! - point and spot lights: lumens over 4 pi, `1 / max(d^2, 1e-4)` times the range
//!   window `(1 - (d / range)^4)^2`, a spot's cone `saturate((cos - cos_outer) /
//!   (cos_inner - cos_outer))^2`, their shadow maps, the same bounding-radius
//!   attenuation, and no phase function (the light is scattered as if the phase were
//!   1 / sr, not `1 / (4 pi)` or Henyey-Greenstein's);
//! - everything times `fog_color light_tint scattering density step light_intensity
//!   exposure`; the volume's colour and `1 - transmittance` are blended over the image
//!   (`src + dst (1 - alpha)`), volume after volume.
//!
//! Shadows here are exact (a ray cast to the light against the scene's boxes) instead
//! of Bevy's shadow maps.

use bevy::prelude::*;
use volfog::glam as vg;
use volfog_testkit::truth::scene::{TruthBox, TruthImage, TruthScene};
use volfog_testkit::truth::volfog::trace;

use crate::mapping::{MappedScene, MappedVolume};

/// Bevy's stop of a ray: transmittance below this.
const DARK: f32 = 0.001;
/// Midpoint samples of a textured volume's optical depth along a light's path.
const PATH_SAMPLES: u32 = 32;

/// How the model departs from Bevy's shader (all `false`: the shader as it is).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ModelOptions {
    /// The light reaching a point is dimmed by the optical depth of every volume along
    /// its path to the light, instead of `exp(-density bounding_radius extinction)`.
    pub path_attenuation: bool,
    /// Point and spot lights are scattered with the volume's Henyey-Greenstein phase
    /// function, as the sun is.
    pub lamp_phase: bool,
    /// The march covers the ray's length to the surface, not the difference of view
    /// depths.
    pub ray_length: bool,
}

impl ModelOptions {
    /// All three departures: single scattering as the path tracer computes it, but
    /// for Bevy's quadrature and its volume after volume blending.
    pub const PHYSICAL: Self = Self {
        path_attenuation: true,
        lamp_phase: true,
        ray_length: true,
    };
}

fn v(a: Vec3) -> vg::Vec3 {
    vg::Vec3::from_array(a.to_array())
}

/// A light as Bevy's fog shader reads it (colours already times the exposure).
enum Light {
    Sun {
        toward: Vec3,
        color: Vec3,
    },
    Lamp {
        position: Vec3,
        color: Vec3,
        inverse_square_range: f32,
        /// (axis, scale, offset) of a spot's cone.
        cone: Option<(Vec3, f32, f32)>,
    },
}

fn lights(mapped: &MappedScene) -> Vec<Light> {
    let e = mapped.exposure().exposure();
    let linear = |c: Color| Vec3::from_array(c.to_linear().to_f32_array_no_alpha());
    let mut out = Vec::new();
    if let Some((sun, transform, _)) = &mapped.sun {
        out.push(Light::Sun {
            toward: -transform.forward().as_vec3(),
            color: linear(sun.color) * sun.illuminance * e,
        });
    }
    let candela = |lumens: f32| lumens / (4.0 * std::f32::consts::PI);
    for (p, t) in &mapped.points {
        out.push(Light::Lamp {
            position: t.translation,
            color: linear(p.color) * candela(p.intensity) * e,
            inverse_square_range: 1.0 / (p.range * p.range),
            cone: None,
        });
    }
    for (s, t) in &mapped.spots {
        let cos_outer = s.outer_angle.cos();
        let scale = 1.0 / (s.inner_angle.cos() - cos_outer).max(1e-4);
        out.push(Light::Lamp {
            position: t.translation,
            color: linear(s.color) * candela(s.intensity) * e,
            inverse_square_range: 1.0 / (s.range * s.range),
            cone: Some((t.forward().as_vec3(), scale, -cos_outer * scale)),
        });
    }
    out
}

/// The entry and exit distances of a ray through an axis-aligned box.
fn slab(origin: Vec3, dir: Vec3, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let inv = dir.recip();
    let (t0, t1) = ((min - origin) * inv, (max - origin) * inv);
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element();
    (near < far).then_some((near, far))
}

fn bounds(volume: &MappedVolume) -> (Vec3, Vec3) {
    let half = volume.transform.scale * 0.5;
    (
        volume.transform.translation - half,
        volume.transform.translation + half,
    )
}

/// `density_factor` times the density texture at `p` (0 outside a textured volume's
/// box).
fn density(volume: &MappedVolume, p: Vec3) -> f32 {
    let f = volume.volume.density_factor;
    match &volume.grid {
        None => f,
        Some(grid) => {
            let (min, max) = bounds(volume);
            let uvw = (p - min) / (max - min);
            if uvw.cmpge(Vec3::ZERO).all() && uvw.cmple(Vec3::ONE).all() {
                f * grid.sample(uvw)
            } else {
                0.0
            }
        }
    }
}

fn extinction(volume: &MappedVolume) -> f32 {
    volume.volume.absorption + volume.volume.scattering
}

/// The optical depth of every volume along `dir` from `p` up to `length` (m).
fn optical_depth(volumes: &[MappedVolume], p: Vec3, dir: Vec3, length: f32) -> f32 {
    let mut tau = 0.0;
    for volume in volumes {
        let (min, max) = bounds(volume);
        let Some((t0, t1)) = slab(p, dir, min, max) else {
            continue;
        };
        let t1 = t1.min(length);
        if t1 <= t0 {
            continue;
        }
        let sum = match volume.grid {
            None => volume.volume.density_factor * (t1 - t0),
            Some(_) => {
                let h = (t1 - t0) / PATH_SAMPLES as f32;
                (0..PATH_SAMPLES)
                    .map(|k| density(volume, p + dir * (t0 + (k as f32 + 0.5) * h)))
                    .sum::<f32>()
                    * h
            }
        };
        tau += sum * extinction(volume);
    }
    tau
}

fn henyey_greenstein(g: f32, cos: f32) -> f32 {
    let denom = 1.0 + g * g - 2.0 * g * cos;
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * denom * denom.sqrt())
}

/// What one pixel's ray gathers in one volume: in-scattered colour and transmittance.
struct Ray<'a> {
    scene: &'a TruthScene,
    mapped: &'a MappedScene,
    lights: &'a [Light],
    options: ModelOptions,
}

impl Ray<'_> {
    /// Whether the straight path from `p` along `dir` meets no occluder within `length`.
    fn visible(&self, boxes: &[TruthBox], p: Vec3, dir: Vec3, length: f32) -> bool {
        trace(v(p), v(dir), boxes).is_none_or(|t| t >= length)
    }

    /// The light a point receives from `light` before the phase and the medium's
    /// coefficients: colour, attenuations, shadow; and the direction towards it.
    fn light_at(&self, light: &Light, volume: &MappedVolume, p: Vec3, rho: f32) -> (Vec3, Vec3) {
        let boxes = &self.scene.occluders;
        let bounding = |rho: f32| {
            let radius = (volume.transform.scale * 0.5).length();
            (-rho * radius * extinction(volume)).exp()
        };
        match *light {
            Light::Sun { toward, color } => {
                if !self.visible(boxes, p, toward, f32::INFINITY) {
                    return (Vec3::ZERO, toward);
                }
                let dim = if self.options.path_attenuation {
                    (-optical_depth(&self.mapped.volumes, p, toward, f32::INFINITY)).exp()
                } else {
                    bounding(rho)
                };
                (color * dim, toward)
            }
            Light::Lamp {
                position,
                color,
                inverse_square_range,
                cone,
            } => {
                let to_light = position - p;
                let d2 = to_light.length_squared();
                let d = d2.sqrt();
                let l = to_light / d;
                let f = d2 * inverse_square_range;
                let window = (1.0 - f * f).clamp(0.0, 1.0).powi(2);
                let mut a = window / d2.max(1e-4);
                if let Some((axis, scale, offset)) = cone {
                    let c = ((-axis).dot(l) * scale + offset).clamp(0.0, 1.0);
                    a *= c * c;
                }
                if a == 0.0 || !self.visible(boxes, p, l, d) {
                    return (Vec3::ZERO, l);
                }
                let dim = if self.options.path_attenuation {
                    (-optical_depth(&self.mapped.volumes, p, l, d)).exp()
                } else {
                    bounding(rho)
                };
                (color * a * dim, l)
            }
        }
    }

    /// Marches one volume along the ray from the near-plane point `start` (view depth
    /// `near`) in the unit direction `dir` (view-axis cosine `cos`) up to the surface
    /// at view depth `surface`: (colour, transmittance).
    fn march(
        &self,
        volume: &MappedVolume,
        start: Vec3,
        dir: Vec3,
        cos: f32,
        surface: f32,
    ) -> (Vec3, f32) {
        let (min, max) = bounds(volume);
        let Some((t_enter, t_exit)) = slab(start, dir, min, max) else {
            return (Vec3::ZERO, 1.0);
        };
        let near = self.mapped.projection.near;
        let start_depth = near + t_enter * cos;
        let end_depth = (near + t_exit * cos).min(surface);
        let span = (end_depth - start_depth).max(0.0);
        if span == 0.0 {
            return (Vec3::ZERO, 1.0);
        }
        let steps = self.mapped.fog.step_count;
        let length = if self.options.ray_length {
            span / cos
        } else {
            span
        };
        let step = length / steps as f32;
        let entry = start + dir * t_enter;
        let fog = &volume.volume;
        let tint = Vec3::from_array(fog.fog_color.to_linear().to_f32_array_no_alpha())
            * Vec3::from_array(fog.light_tint.to_linear().to_f32_array_no_alpha());
        let ext = extinction(volume);
        let factors = |rho: f32| tint * (fog.scattering * rho * step * fog.light_intensity);
        let g = fog.scattering_asymmetry;
        let mut color = Vec3::ZERO;
        // The sun's march, then the lamps' (the transmittance returned is the last's).
        for light in self
            .lights
            .iter()
            .filter(|l| matches!(l, Light::Sun { .. }))
        {
            let mut t = 1.0;
            for i in 0..steps {
                if t < DARK {
                    break;
                }
                let p = entry + dir * (i as f32 * step);
                let rho = density(volume, p);
                t *= (-step * rho * ext).exp();
                let (light, toward) = self.light_at(light, volume, p, rho);
                if light != Vec3::ZERO {
                    let phase = henyey_greenstein(g, toward.dot(dir));
                    color += light * phase * factors(rho) * t;
                }
            }
        }
        let mut t = 1.0;
        for i in 0..steps {
            if t < DARK {
                break;
            }
            let p = entry + dir * (i as f32 * step);
            let rho = density(volume, p);
            let mut sample = Vec3::ZERO;
            for light in self
                .lights
                .iter()
                .filter(|l| matches!(l, Light::Lamp { .. }))
            {
                let (light, toward) = self.light_at(light, volume, p, rho);
                let phase = if self.options.lamp_phase {
                    henyey_greenstein(g, toward.dot(dir))
                } else {
                    1.0
                };
                sample += light * phase * factors(rho);
            }
            t *= (-step * rho * ext).exp();
            color += sample * t;
        }
        (color, t)
    }
}

/// The scene as Bevy's fog shader renders it (with `options`' departures), over black
/// and white occluders: the in-scattered radiance and the transmittance per pixel,
/// row-major from the top, through each pixel's centre.
pub fn render(scene: &TruthScene, mapped: &MappedScene, options: ModelOptions) -> TruthImage {
    let [w, h] = mapped.size;
    let lights = lights(mapped);
    let ray = Ray {
        scene,
        mapped,
        lights: &lights,
        options,
    };
    let projection = &mapped.projection;
    let tan = (projection.fov * 0.5).tan();
    let world_from_view = mapped.camera.to_matrix();
    let eye = mapped.camera.translation;
    let mut radiance = Vec::with_capacity((w * h) as usize);
    let mut transmittance = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let ndc_x = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
            let view = Vec3::new(ndc_x * tan * projection.aspect_ratio, ndc_y * tan, -1.0);
            let cos = 1.0 / view.length();
            let dir = world_from_view.transform_vector3(view).normalize();
            let start = world_from_view.transform_point3(view * projection.near);
            // The depth buffer's surface: the first occluder from the eye.
            let surface =
                trace(v(eye), v(dir), &scene.occluders).map_or(f32::INFINITY, |t| t * cos);
            let (mut black, mut white) = (Vec3::ZERO, Vec3::ONE);
            for volume in &mapped.volumes {
                let (color, t) = ray.march(volume, start, dir, cos, surface);
                black = color + black * t;
                white = color + white * t;
            }
            radiance.push(v(black));
            transmittance.push(v((white - black).max(Vec3::ZERO)));
        }
    }
    TruthImage {
        width: w,
        height: h,
        radiance,
        transmittance,
    }
}
