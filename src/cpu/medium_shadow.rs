//! Mirror of `volfog::medium_shadow` and of the `medium_shadow` pass: the medium's
//! extinction beyond its height profile tabulated in a sun-aligned volume, and the
//! factors by which it dims the sun's and the local lights' paths.

use glam::{UVec3, Vec2, Vec3};

use super::density::{medium_extinction, medium_with_sample};
use super::inject::{CustomMedium, InjectInputs, medium_at};
use super::particles::{particle_density, particle_total};
use crate::uniforms::{FOG_LIGHT_DIRECTIONAL, FogLight, FogParticle, MediumShadow};

/// Points per texel along the sunlight at which the pass evaluates the extinction
/// (WGSL `MEDIUM_SHADOW_SUBSAMPLES`); the texel holds their mean.
pub const MEDIUM_SHADOW_SUBSAMPLES: u32 = 4;

/// Mirror of `volfog::medium_shadow::medium_shadow_texel`: the optical depth at the
/// centre of a slice, `prefix` the column's before it, `excess` the slice's excess
/// extinction (1/m), `step` its length (m).
pub fn medium_shadow_texel(prefix: f32, excess: f32, step: f32) -> f32 {
    prefix + 0.5 * excess * step
}

/// The medium-shadow volume: per texel (x fastest, then y, then z) the optical depth
/// from the sun-side face (x) and the excess extinction (y, 1/m), as the
/// `medium_shadow` pass writes them (before their rounding to rgba16float).
#[derive(Debug, Clone, PartialEq)]
pub struct MediumShadowVolume {
    /// The placement.
    pub params: MediumShadow,
    /// (tau, excess) per texel.
    pub texels: Vec<Vec2>,
}

impl MediumShadowVolume {
    /// The volume the pass fills for `params` from the medium of `inputs` (its
    /// `frame.time`, medium, local volumes, noise and density textures and options),
    /// for the custom-density variant `custom`, and for the particle variant the first
    /// `FogMedium::particle_count` of `particles`.
    pub fn fill(
        inputs: &InjectInputs<'_>,
        custom: Option<CustomMedium<'_>>,
        particles: &[FogParticle],
        params: &MediumShadow,
    ) -> Self {
        let count = particles.len().min(inputs.medium.particle_count as usize);
        let particles = if inputs.options.particles {
            &particles[..count]
        } else {
            &[]
        };
        let size = params.size;
        let mut texels = vec![Vec2::ZERO; size.as_u64vec3().element_product() as usize];
        for y in 0..size.y {
            for x in 0..size.x {
                let column = (Vec2::new(x as f32, y as f32) + 0.5) / size.truncate().as_vec2();
                let top = params
                    .world_from_volume
                    .transform_point3(column.extend(0.0));
                let bottom = params
                    .world_from_volume
                    .transform_point3(column.extend(1.0));
                let mut prefix = 0.0;
                for k in 0..size.z {
                    let n = MEDIUM_SHADOW_SUBSAMPLES;
                    let excess = (0..n)
                        .map(|j| {
                            let w = (k as f32 + (j as f32 + 0.5) / n as f32) / size.z as f32;
                            excess_extinction(inputs, custom, particles, top.lerp(bottom, w))
                        })
                        .sum::<f32>()
                        / n as f32;
                    let tau = medium_shadow_texel(prefix, excess, params.step)
                        .clamp(-MAX_DEPTH, MAX_DEPTH);
                    texels[texel_index(size, UVec3::new(x, y, k))] = Vec2::new(tau, excess);
                    prefix = (prefix + excess * params.step).clamp(-MAX_DEPTH, MAX_DEPTH);
                }
            }
        }
        Self {
            params: *params,
            texels,
        }
    }

    /// Trilinear sample at volume coordinate `uvw` with clamp-to-edge addressing, as
    /// the pass's linear sampler reads it.
    pub fn sample(&self, uvw: Vec3) -> Vec2 {
        let size = self.params.size;
        let t = uvw * size.as_vec3() - 0.5;
        let b = t.floor();
        let f = t - b;
        let at = |dx: i32, dy: i32, dz: i32| {
            let c = (b.as_ivec3() + glam::IVec3::new(dx, dy, dz))
                .clamp(glam::IVec3::ZERO, size.as_ivec3() - 1)
                .as_uvec3();
            self.texels[texel_index(size, c)]
        };
        let plane = |dz: i32| {
            at(0, 0, dz)
                .lerp(at(1, 0, dz), f.x)
                .lerp(at(0, 1, dz).lerp(at(1, 1, dz), f.x), f.y)
        };
        plane(0).lerp(plane(1), f.z)
    }

    /// Mirror of `medium_shadow_sun`: the factor by which the medium beyond its height
    /// profile dims the sunlight at `world` (1 outside the volume across the sunlight).
    pub fn sun(&self, world: Vec3) -> f32 {
        let uvw = self.params.coord(world);
        if uvw.x < 0.0 || uvw.y < 0.0 || uvw.x > 1.0 || uvw.y > 1.0 {
            return 1.0;
        }
        (-self.sample(uvw).x.clamp(-80.0, 80.0)).exp()
    }

    /// Mirror of `medium_shadow_segment`: the factor by which the medium beyond its
    /// height profile dims the light from `light` (m) to `world` (m), from
    /// `march_steps` midpoint samples of the excess extinction (0 outside the volume).
    pub fn segment(&self, world: Vec3, light: Vec3) -> f32 {
        let steps = self.params.march_steps.max(1);
        let delta = (light - world) / steps as f32;
        let tau: f32 = (0..steps)
            .map(|i| {
                let uvw = self.params.coord(world + delta * (i as f32 + 0.5));
                if uvw.cmpge(Vec3::ZERO).all() && uvw.cmple(Vec3::ONE).all() {
                    self.sample(uvw).y
                } else {
                    0.0
                }
            })
            .sum();
        (-(tau * delta.length()).clamp(-80.0, 80.0)).exp()
    }

    /// The factor for a point, spot or directional light at `world`, as inject's
    /// `light_path_transmittance` takes it: along the segment to a point or spot light,
    /// over `march_length` towards a directional one.
    pub fn light(&self, light: &FogLight, world: Vec3) -> f32 {
        if light.flags & FOG_LIGHT_DIRECTIONAL != 0 {
            self.segment(world, world - light.direction * self.params.march_length)
        } else {
            self.segment(world, light.position)
        }
    }
}

/// The largest extinction (1/m) the pass takes of the medium and of its profile.
pub const MAX_EXTINCTION: f32 = 1e4;
/// The largest optical depth the pass stores (below the largest rgba16float value).
pub const MAX_DEPTH: f32 = 6e4;

/// The medium's extinction (1/m) at `world` beyond its bare height profile, as the pass
/// computes it: the medium inject composes (`particles` added to it clamped at 0)
/// minus `medium_extinction(medium, world, 0, 1)`, each clamped to [0, MAX_EXTINCTION]
/// first.
pub fn excess_extinction(
    inputs: &InjectInputs<'_>,
    custom: Option<CustomMedium<'_>>,
    particles: &[FogParticle],
    world: Vec3,
) -> f32 {
    let (medium, _) = medium_at(inputs, world, custom);
    let sum: f32 = particles.iter().map(|p| particle_density(p, world)).sum();
    let total = medium_with_sample(
        medium.max(glam::Vec4::ZERO),
        &particle_total(glam::Vec4::new(0.0, 0.0, 0.0, sum), Vec3::ZERO),
    );
    total.w.clamp(0.0, MAX_EXTINCTION)
        - medium_extinction(inputs.medium, world, 0.0, 1.0).clamp(0.0, MAX_EXTINCTION)
}

fn texel_index(size: UVec3, c: UVec3) -> usize {
    ((c.z * size.y + c.y) * size.x + c.x) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uniforms::MediumShadowConfig;
    use glam::Mat4;

    /// A volume whose excess is a constant `sigma` everywhere: the tabulated optical
    /// depth grows linearly along the sunlight, so the sun's factor is exp(-sigma d) at
    /// depth d below the sun-side face, exactly (trilinear filtering of a linear
    /// function is exact between the first and last slice centres).
    #[test]
    fn constant_excess_gives_the_closed_form() {
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.5, 40.0);
        let config = MediumShadowConfig {
            size: UVec3::new(8, 8, 32),
            distance: 40.0,
            reach: 10.0,
            march_steps: 16,
        };
        let sun = Vec3::new(0.2, 0.9, 0.3).normalize();
        let params = MediumShadow::fit(&config, Mat4::IDENTITY, proj.inverse(), 40.0, sun).unwrap();
        let sigma = 0.05;
        let size = params.size;
        let mut texels = Vec::new();
        for k in 0..size.z {
            for _ in 0..size.x * size.y {
                let prefix = sigma * params.step * k as f32;
                texels.push(Vec2::new(
                    medium_shadow_texel(prefix, sigma, params.step),
                    sigma,
                ));
            }
        }
        let volume = MediumShadowVolume { params, texels };
        let p = Vec3::new(1.0, -2.0, -10.0);
        let w = params.coord(p).z;
        let depth = w * params.step * size.z as f32;
        assert!((volume.sun(p) - (-sigma * depth).exp()).abs() < 1e-5);
        // A point light 6 m away inside the volume: exp(-sigma 6).
        let light = p + Vec3::new(0.0, 3.6, -4.8);
        assert!((volume.segment(p, light) - (-sigma * 6.0).exp()).abs() < 1e-5);
        // Outside the volume across the sunlight: no excess.
        let far = p + params
            .world_from_volume
            .transform_vector3(Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(volume.sun(far), 1.0);
    }
}
