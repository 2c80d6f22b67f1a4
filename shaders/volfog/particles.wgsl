// volfog::particles — particles in the fog: spheres of smoke, dust or glowing gas that
// an application's particle system writes, added to the medium.
//
// Use:      #import volfog::particles::{particle_sample, particle_density, particle_touches_sphere, particle_optical_depth, particle_total}
// Defines:  none
// Units:    positions and radii in metres (world space), extinction in 1/m, emission
//           in radiance per metre (W / (sr m^3)), optical depth dimensionless.
// Profile:  a particle of radius R, centre c, extinction sigma and falloff f in [0, 1]
//           has, at distance r = |x - c|,
//             sigma(r) = sigma w(r),  w(r) = (1 - f) + f (1 - r^2 / R^2)^2  for r < R,
//           and 0 beyond: f = 0 a uniform sphere, f = 1 a smooth one whose density and
//           slope vanish at R. Its emission follows the same profile; its albedo is
//           constant. Along a line at distance b from the centre, with h^2 = R^2 - b^2
//           and s the signed distance from the line's closest point, sigma(s) =
//           sigma ((1 - f) + f (h^2 - s^2)^2 / R^4) for |s| < h: a polynomial, so the
//           optical depth of any segment has the closed form
//             tau = sigma [F(s1) - F(s0)],
//             F(s) = (1 - f) s + f (h^4 s - 2 h^2 s^3 / 3 + s^5 / 5) / R^4,
//           s0, s1 the segment clamped to [-h, h]; a whole chord gives
//           sigma (2 h (1 - f) + (16 / 15) f h^5 / R^4).
// Blending: particles superpose (their extinctions and emissions add; the albedo of
//           the sum is the extinction-weighted mean: particle_total). Inject adds their
//           total to the medium after the local volumes (volfog::density::
//           medium_with_sample and albedo_with_sample on the medium clamped at 0), so
//           a volume that clears fog does not clear the smoke inside it.
// Reference: Wronski 2014, "Density estimation and volume lighting" (particle
//           injection as an extension of the analytic density shapes).
#define_import_path volfog::particles

#import volfog::types::{FogParticle, FogSample}

// The profile w(r) in [0, 1] of a particle at a world position (see "Profile").
fn particle_weight(p: FogParticle, world: vec3<f32>) -> f32 {
    let d = world - p.position;
    let q = dot(d, d) / (p.radius * p.radius);
    if q >= 1.0 {
        return 0.0;
    }
    let u = 1.0 - q;
    return (1.0 - p.falloff) + p.falloff * u * u;
}

// Extinction (1/m) a particle adds at a world position.
fn particle_density(p: FogParticle, world: vec3<f32>) -> f32 {
    return p.extinction * particle_weight(p, world);
}

// What a particle adds at a world position: its albedo, extinction (1/m) and emission
// per metre (W / (sr m^3)), the latter two times its profile.
fn particle_sample(p: FogParticle, world: vec3<f32>) -> FogSample {
    let w = particle_weight(p, world);
    return FogSample(p.albedo, p.extinction * w, p.emission * w);
}

// Whether a particle can add anything in the world-space sphere (center, radius) (m):
// their spheres overlap.
fn particle_touches_sphere(p: FogParticle, center: vec3<f32>, radius: f32) -> bool {
    return distance(p.position, center) < p.radius + radius;
}

// The antiderivative F(s) of the profile along a line (see "Profile"), h2 = h^2,
// r4 = R^4, f the falloff.
fn particle_chord_integral(s: f32, h2: f32, r4: f32, f: f32) -> f32 {
    let s2 = s * s;
    return (1.0 - f) * s + f * s * (h2 * h2 - (2.0 / 3.0) * h2 * s2 + 0.2 * s2 * s2) / r4;
}

// Optical depth (dimensionless, >= 0) of a particle along the segment from `origin`
// over [0, t_max] (m) of the unit direction `dir` (closed form, see "Profile"); t_max
// may be large (1e9 for a ray without end).
fn particle_optical_depth(p: FogParticle, origin: vec3<f32>, dir: vec3<f32>, t_max: f32) -> f32 {
    let to_center = p.position - origin;
    let t_closest = dot(to_center, dir);
    // The distance from the centre to the line, from the closest point itself (no
    // cancellation between |c - o|^2 and t^2 far from the particle).
    let off = to_center - t_closest * dir;
    let r2 = p.radius * p.radius;
    let h2 = r2 - dot(off, off);
    if h2 <= 0.0 {
        return 0.0;
    }
    let h = sqrt(h2);
    let s0 = clamp(-t_closest, -h, h);
    let s1 = clamp(t_max - t_closest, -h, h);
    if s1 <= s0 {
        return 0.0;
    }
    let r4 = r2 * r2;
    let f = p.falloff;
    return p.extinction * max(
        particle_chord_integral(s1, h2, r4, f) - particle_chord_integral(s0, h2, r4, f), 0.0);
}

// The particles' sum at a point as one medium: `medium` the summed emission (rgb) and
// extinction (a) of their samples, `albedo_extinction` the sum of albedo times
// extinction; the albedo is their extinction-weighted mean (0 where no extinction).
fn particle_total(medium: vec4<f32>, albedo_extinction: vec3<f32>) -> FogSample {
    var albedo = vec3<f32>(0.0);
    if medium.a > 0.0 {
        albedo = albedo_extinction / medium.a;
    }
    return FogSample(albedo, medium.a, medium.rgb);
}
