//! Mirror of `volfog::particles`: particles in the fog, their profile, their sum at a
//! point and the closed-form optical depth of a segment through one.
//!
//! A particle of radius `R`, extinction `sigma` and falloff `f` has, at a distance `r`
//! from its centre, the extinction `sigma w(r)`, `w(r) = (1 - f) + f (1 - r^2/R^2)^2`
//! for `r < R` and 0 beyond. Along a line passing at a distance `b` from the centre
//! (`h^2 = R^2 - b^2`, `s` the signed distance from the closest point) it is a
//! polynomial in `s`, so a segment's optical depth is exact:
//! `tau = sigma [F(s1) - F(s0)]`, `F(s) = (1 - f) s + f (h^4 s - 2 h^2 s^3 / 3 + s^5 / 5) / R^4`
//! with `s0, s1` clamped to `[-h, h]`; a whole chord gives
//! `sigma (2 h (1 - f) + 16 f h^5 / (15 R^4))`.
//!
//! ```
//! use volfog::cpu::particles::particle_optical_depth;
//! use volfog::glam::Vec3;
//! use volfog::uniforms::FogParticle;
//!
//! // Through the centre of a smooth particle: sigma 16 R / 15.
//! let p = FogParticle::smoke(Vec3::ZERO, 2.0, 0.5, Vec3::ONE);
//! let tau = particle_optical_depth(&p, Vec3::new(-5.0, 0.0, 0.0), Vec3::X, 1e9);
//! assert!((tau - 0.5 * 16.0 * 2.0 / 15.0).abs() < 1e-5);
//! ```

use glam::{Vec3, Vec4};

use super::density::{albedo_with_sample, medium_with_sample};
use crate::uniforms::{FogParticle, FogSample};

/// The profile `w(r)` in [0, 1] of a particle at a world position.
pub fn particle_weight(p: &FogParticle, world: Vec3) -> f32 {
    let d = world - p.position;
    let q = d.dot(d) / (p.radius * p.radius);
    if q >= 1.0 {
        return 0.0;
    }
    let u = 1.0 - q;
    (1.0 - p.falloff) + p.falloff * u * u
}

/// Extinction (1/m) a particle adds at a world position.
pub fn particle_density(p: &FogParticle, world: Vec3) -> f32 {
    p.extinction * particle_weight(p, world)
}

/// What a particle adds at a world position: its albedo, and its extinction and
/// emission times its profile.
pub fn particle_sample(p: &FogParticle, world: Vec3) -> FogSample {
    let w = particle_weight(p, world);
    FogSample {
        albedo: p.albedo,
        extinction: p.extinction * w,
        emission: p.emission * w,
    }
}

/// Whether a particle can add anything in the sphere `(center, radius)` (m).
pub fn particle_touches_sphere(p: &FogParticle, center: Vec3, radius: f32) -> bool {
    p.position.distance(center) < p.radius + radius
}

/// The antiderivative `F(s)` of the profile along a line, `h2 = h^2`, `r4 = R^4`.
pub fn particle_chord_integral(s: f32, h2: f32, r4: f32, f: f32) -> f32 {
    let s2 = s * s;
    (1.0 - f) * s + f * s * (h2 * h2 - (2.0 / 3.0) * h2 * s2 + 0.2 * s2 * s2) / r4
}

/// Optical depth (>= 0) of a particle along the segment from `origin` over
/// `[0, t_max]` (m) of the unit direction `dir`, in closed form.
pub fn particle_optical_depth(p: &FogParticle, origin: Vec3, dir: Vec3, t_max: f32) -> f32 {
    let to_center = p.position - origin;
    let t_closest = to_center.dot(dir);
    let off = to_center - t_closest * dir;
    let r2 = p.radius * p.radius;
    let h2 = r2 - off.dot(off);
    if h2 <= 0.0 {
        return 0.0;
    }
    let h = h2.sqrt();
    let s0 = (-t_closest).clamp(-h, h);
    let s1 = (t_max - t_closest).clamp(-h, h);
    if s1 <= s0 {
        return 0.0;
    }
    let (r4, f) = (r2 * r2, p.falloff);
    p.extinction
        * (particle_chord_integral(s1, h2, r4, f) - particle_chord_integral(s0, h2, r4, f)).max(0.0)
}

/// The particles' sum as one medium from their summed emission (rgb) and extinction
/// (a) and the sum of albedo times extinction: the albedo is the extinction-weighted
/// mean.
pub fn particle_total(medium: Vec4, albedo_extinction: Vec3) -> FogSample {
    FogSample {
        albedo: if medium.w > 0.0 {
            albedo_extinction / medium.w
        } else {
            Vec3::ZERO
        },
        extinction: medium.w,
        emission: medium.truncate(),
    }
}

/// The sum of `particles` at a world position, as [`particle_total`] takes it:
/// (emission, extinction) and albedo times extinction.
pub fn particles_sum(particles: &[FogParticle], world: Vec3) -> (Vec4, Vec3) {
    let mut medium = Vec4::ZERO;
    let mut albedo = Vec3::ZERO;
    for p in particles {
        let s = particle_sample(p, world);
        medium += s.emission.extend(s.extinction);
        albedo += s.albedo * s.extinction;
    }
    (medium, albedo)
}

/// The medium (rgb emission per metre, a extinction) of albedo `albedo` with the
/// particles added as inject adds them after the local volumes: the medium clamped at
/// 0, then their sum ([`particles_sum`], [`particle_total`]) with its albedo mixed in
/// by extinction. Returns the medium and its albedo.
pub fn medium_with_particles(
    medium: Vec4,
    albedo: Vec3,
    particles: &[FogParticle],
    world: Vec3,
) -> (Vec4, Vec3) {
    let (sum, albedo_extinction) = particles_sum(particles, world);
    let total = particle_total(sum, albedo_extinction);
    let medium = medium.max(Vec4::ZERO);
    (
        medium_with_sample(medium, &total),
        albedo_with_sample(medium, albedo, &total),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng;

    /// The optical depth by the midpoint rule over `n` steps of the profile itself.
    fn quadrature(p: &FogParticle, origin: Vec3, dir: Vec3, t_max: f32, n: usize) -> f64 {
        let dt = t_max as f64 / n as f64;
        (0..n)
            .map(|i| {
                let t = (i as f64 + 0.5) * dt;
                particle_density(p, origin + dir * t as f32) as f64 * dt
            })
            .sum()
    }

    /// The closed form against a 200,000-step quadrature of the profile on random
    /// particles, rays and segment ends (some inside the particle): within 1e-4
    /// relative, plus sigma dt where the profile jumps at the radius (falloff below 1:
    /// the midpoint rule is off by up to half a step of sigma at each edge).
    #[test]
    fn optical_depth_matches_quadrature() {
        let mut rng = TestRng(41);
        let mut worst = 0.0f64;
        for _ in 0..200 {
            let p = FogParticle {
                position: Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 4.0),
                radius: rng.range(0.3, 2.0),
                albedo: Vec3::ONE,
                extinction: rng.range(0.1, 3.0),
                emission: Vec3::ZERO,
                falloff: rng.unit(),
            };
            let dir = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 1.0).normalize();
            let t_max = rng.range(2.0, 8.0);
            let got = particle_optical_depth(&p, Vec3::ZERO, dir, t_max) as f64;
            let want = quadrature(&p, Vec3::ZERO, dir, t_max, 200_000);
            let jump = (1.0 - p.falloff as f64) * p.extinction as f64 * t_max as f64 / 200_000.0;
            let err = ((got - want).abs() - jump).max(0.0) / want.max(1e-3);
            worst = worst.max(err);
            assert!(err < 1e-4, "{got} vs {want} for {p:?}, t_max {t_max}");
        }
        eprintln!("particle optical depth vs quadrature: worst {worst:e}");
    }

    /// The whole chord through the centre: 2 R sigma (uniform), 16 R sigma / 15
    /// (smooth); a ray that misses: 0.
    #[test]
    fn chord_through_the_centre() {
        let p = FogParticle::smoke(Vec3::new(0.0, 0.0, 10.0), 1.5, 2.0, Vec3::ONE);
        let tau = |f: f32| {
            particle_optical_depth(&FogParticle { falloff: f, ..p }, Vec3::ZERO, Vec3::Z, 1e9)
        };
        assert!((tau(0.0) - 6.0).abs() < 1e-5);
        assert!((tau(1.0) - 2.0 * 16.0 * 1.5 / 15.0).abs() < 1e-5);
        assert_eq!(
            particle_optical_depth(&p, Vec3::new(2.0, 0.0, 0.0), Vec3::Z, 1e9),
            0.0
        );
    }

    /// Particles add to a medium cleared below 0, and the albedo is the
    /// extinction-weighted mean.
    #[test]
    fn particles_add_to_the_clamped_medium() {
        let white = FogParticle::smoke(Vec3::ZERO, 1.0, 0.3, Vec3::ONE);
        let black = FogParticle {
            albedo: Vec3::ZERO,
            extinction: 0.1,
            ..white
        };
        let (m, a) = medium_with_particles(
            Vec4::new(0.0, 0.0, 0.0, -5.0),
            Vec3::splat(0.5),
            &[white, black],
            Vec3::ZERO,
        );
        assert!((m.w - 0.4).abs() < 1e-6, "{m}");
        assert!((a - Vec3::splat(0.75)).abs().max_element() < 1e-6, "{a}");
        let (m, a) = medium_with_particles(
            Vec4::new(0.0, 0.0, 0.0, 0.4),
            Vec3::splat(0.5),
            &[white],
            Vec3::ZERO,
        );
        assert!((m.w - 0.7).abs() < 1e-6);
        assert!((a.x - (0.5 * 0.4 + 0.3) / 0.7).abs() < 1e-6, "{a}");
    }
}
