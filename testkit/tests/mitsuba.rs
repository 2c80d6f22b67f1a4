//! The Mitsuba harness (`volfog_testkit::truth::mitsuba`, tools/mitsuba/render.py)
//! checked against physics computed here, not against itself: Beer-Lambert
//! transmittance through homogeneous fog, height fog and local volumes, and single
//! scattering of the sun, a point light and a spot light, each integrated numerically
//! along the camera rays of the pinhole (`truth::scenes::film_ray`).
//!
//! Radiance is compared on blocks of pixels, each within four times Mitsuba's own
//! noise on that block (measured from two seeds) plus 1 % for the reference's
//! quadrature and pixel sampling; the whole image within four times its noise plus
//! 0.5 %. Mitsuba must be installed (`cargo xtask tools`): the tests fail without it.

use glam::Vec3;
use volfog_testkit::truth::mitsuba::{self, MitsubaOptions, RadiancePair};
use volfog_testkit::truth::scene::{
    TruthBox, TruthCamera, TruthMedium, TruthPoint, TruthScene, TruthShape, TruthSpot, TruthSun,
    TruthVolume,
};
use volfog_testkit::truth::scenes::{check, film_ray, first_occluder, ray_box};
use volfog_testkit::truth::shadow_maps::lit;

const RES: [u32; 2] = [64, 36];
/// Radiance blocks (pixels).
const BLOCK: [u32; 2] = [8, 6];
/// Film sub-positions per pixel side where the reference radiance and transmittance
/// are evaluated (their mean stands for the box-filtered pixel).
const SUB: u32 = 2;
const SUB_TRANSMITTANCE: u32 = 6;
/// Midpoint steps along a ray for the sun (uniform in distance) and for a point or spot
/// light (uniform in the angle seen from the light), and along a chord through a local
/// volume.
const STEPS_SUN: usize = 256;
const STEPS_LOCAL: usize = 512;
const STEPS_VOLUME: usize = 200;
const SPP: u32 = 1024;

fn expect<T>(r: Result<T, mitsuba::MitsubaError>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

fn camera(position: Vec3, pitch_deg: f32, far: f32) -> TruthCamera {
    let p = pitch_deg.to_radians();
    TruthCamera {
        position,
        target: position + Vec3::new(0.0, -p.sin(), -p.cos()) * 10.0,
        fov_y_deg: 40.0,
        near: 0.1,
        far,
    }
}

fn sun(elevation_deg: f32, azimuth_deg: f32, color: Vec3) -> TruthSun {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    TruthSun {
        direction: Vec3::new(a.sin() * e.cos(), e.sin(), -a.cos() * e.cos()),
        color,
    }
}

/// A scene in a medium box of +-`half` m around the origin in x and z, the ground
/// under all of it.
fn scene(name: &str, camera: TruthCamera, medium: TruthMedium, half: f32) -> TruthScene {
    let mut medium = medium;
    medium.bounds_min = Vec3::new(-half, -0.5, -half);
    medium.bounds_max_xz = [half, half];
    TruthScene {
        name: name.to_string(),
        resolution: RES,
        camera,
        medium,
        sun: None,
        points: Vec::new(),
        spots: Vec::new(),
        areas: Vec::new(),
        volumes: Vec::new(),
        occluders: vec![TruthBox {
            min: Vec3::new(-half, -1.0, -half),
            max: Vec3::new(half, 0.0, half),
        }],
    }
}

fn medium(density: f32, falloff: f32, albedo: Vec3, g: f32, top: f32) -> TruthMedium {
    TruthMedium {
        density,
        falloff,
        base_height: 0.0,
        albedo,
        phase_g: g,
        top,
        bounds_min: Vec3::ZERO,
        bounds_max_xz: [0.0, 0.0],
    }
}

/// Henyey-Greenstein, cos_theta between the light's travel and the scattered ray.
fn hg(cos_theta: f32, g: f32) -> f32 {
    let d = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * d * d.sqrt())
}

/// Optical depth of the global medium (no local volumes) from `p` along the unit `d`
/// over `len` m: integral of density exp(-falloff (y - base)).
fn global_depth(m: &TruthMedium, p: Vec3, d: Vec3, len: f32) -> f32 {
    let (k, dy) = (m.falloff as f64, d.y as f64);
    let base = m.density as f64 * (-(k * (p.y - m.base_height) as f64)).exp();
    let kl = k * dy * len as f64;
    let depth = if kl.abs() < 1e-6 {
        base * len as f64 * (1.0 - 0.5 * kl)
    } else {
        base * (1.0 - (-kl).exp()) / (k * dy)
    };
    depth as f32
}

fn global_extinction(m: &TruthMedium, p: Vec3) -> f32 {
    m.density * (-m.falloff * (p.y - m.base_height)).exp()
}

fn volume_extinction(v: &TruthVolume, p: Vec3) -> f32 {
    let u = (p - v.center) / v.half_extents;
    let m = match v.shape {
        TruthShape::Box => u.abs().max_element(),
        TruthShape::Ellipsoid => u.length(),
    };
    v.density * ((1.0 - m) / v.edge).clamp(0.0, 1.0)
}

/// Single-scattered radiance along the camera ray (origin `o`, unit `v`, ending at
/// `len` m), each light's share at a point taken when the ray from the point to the
/// light meets no occluder (`truth::shadow_maps::lit`), no local volumes.
fn inscatter(s: &TruthScene, g: f32, o: Vec3, v: Vec3, len: f32) -> Vec3 {
    let m = &s.medium;
    let mut total = Vec3::ZERO;
    if let Some(sun) = &s.sun {
        // Uniform midpoint steps in t.
        let dt = len / STEPS_SUN as f32;
        let mut sum = 0.0;
        for i in 0..STEPS_SUN {
            let t = (i as f32 + 0.5) * dt;
            let p = o + v * t;
            let to_top = (m.top - p.y) / sun.direction.y;
            let tr = (-global_depth(m, o, v, t) - global_depth(m, p, sun.direction, to_top)).exp();
            let seen = f32::from(u8::from(lit(p, sun.direction, false, &s.occluders)));
            sum += global_extinction(m, p) * tr * seen * dt;
        }
        total += sun.color * m.albedo * hg(sun.direction.dot(v), g) * sum;
    }
    let locals = s
        .points
        .iter()
        .map(|p| (p.position, p.color, None))
        .chain(s.spots.iter().map(|sp| (sp.position, sp.color, Some(*sp))));
    for (l, color, spot) in locals {
        // Equiangular steps: t = tc + b tan(phi), dt / r^2 = dphi / b.
        let tc = (l - o).dot(v);
        let b = (l - o - v * tc).length().max(1e-4);
        let (a0, a1) = ((-tc / b).atan(), ((len - tc) / b).atan());
        let dphi = (a1 - a0) / STEPS_LOCAL as f32;
        let mut sum = Vec3::ZERO;
        for i in 0..STEPS_LOCAL {
            let phi = a0 + (i as f32 + 0.5) * dphi;
            let t = tc + b * phi.tan();
            let p = o + v * t;
            let to_light = l - p;
            let r = to_light.length();
            let w = to_light / r;
            let mut falloff = 1.0;
            if let Some(sp) = spot {
                // Mitsuba's spot: linear in angle from beam_width to cutoff_angle.
                let angle = (-w).dot(sp.direction).clamp(-1.0, 1.0).acos().to_degrees();
                falloff = ((sp.outer_deg - angle) / (sp.outer_deg - sp.inner_deg)).clamp(0.0, 1.0);
            }
            let tr = (-global_depth(m, o, v, t) - global_depth(m, p, w, r)).exp();
            let seen = f32::from(u8::from(lit(p, to_light, true, &s.occluders)));
            sum += Vec3::splat(
                global_extinction(m, p) * hg(w.dot(v), g) * tr * falloff * seen * dphi / b,
            );
        }
        total += color * m.albedo * sum;
    }
    total
}

/// The box-filtered pixel by the mean over SUB x SUB film positions.
fn reference(s: &TruthScene, f: impl Fn(Vec3, f32) -> Vec3) -> Vec<Vec3> {
    reference_at(s, SUB, f)
}

/// The box-filtered pixel by the mean over sub x sub film positions.
fn reference_at(s: &TruthScene, sub: u32, f: impl Fn(Vec3, f32) -> Vec3) -> Vec<Vec3> {
    let [w, h] = s.resolution;
    let mut out = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let mut sum = Vec3::ZERO;
            for sj in 0..sub {
                for si in 0..sub {
                    let x = i as f32 + (si as f32 + 0.5) / sub as f32;
                    let y = j as f32 + (sj as f32 + 0.5) / sub as f32;
                    let v = film_ray(&s.camera, s.resolution, x, y);
                    let len = first_occluder(s, s.camera.position, v).expect("every ray ends");
                    sum += f(v, len);
                }
            }
            out.push(sum / (sub * sub) as f32);
        }
    }
    out
}

/// Block sums of the channel mean.
fn blocks(values: &[Vec3], keep: &dyn Fn(u32, u32) -> bool) -> Vec<f64> {
    let bx = RES[0] / BLOCK[0];
    let mut out = vec![0.0; (bx * (RES[1] / BLOCK[1])) as usize];
    for (k, v) in values.iter().enumerate() {
        let (i, j) = (k as u32 % RES[0], k as u32 / RES[0]);
        if keep(i, j) {
            out[(j / BLOCK[1] * bx + i / BLOCK[0]) as usize] += ((v.x + v.y + v.z) / 3.0) as f64;
        }
    }
    out
}

struct Verdict {
    worst: f64,
    mean_error: f64,
}

/// Compares Mitsuba's radiance with the reference block by block and over the image;
/// returns the worst block's error over its tolerance and the image mean's relative
/// error.
fn compare(
    name: &str,
    pair: &RadiancePair,
    expected: &[Vec3],
    keep: &dyn Fn(u32, u32) -> bool,
) -> Verdict {
    let a = blocks(&pair.first, keep);
    let b = blocks(&pair.second, keep);
    let e = blocks(expected, keep);
    let mut worst: f64 = 0.0;
    let mut sums = (0.0, 0.0, 0.0, 0.0);
    // Per-pixel noise, squared and summed per block.
    let bx = RES[0] / BLOCK[0];
    let mut var = vec![0.0; a.len()];
    for (k, (p, q)) in pair.first.iter().zip(&pair.second).enumerate() {
        let (i, j) = (k as u32 % RES[0], k as u32 / RES[0]);
        if keep(i, j) {
            let d = ((p.x + p.y + p.z) - (q.x + q.y + q.z)) as f64 / 3.0;
            var[(j / BLOCK[1] * bx + i / BLOCK[0]) as usize] += d * d * 0.5;
        }
    }
    for k in 0..a.len() {
        if e[k] <= 0.0 {
            continue;
        }
        let noise = var[k].sqrt() / e[k];
        let error = (a[k] - e[k]).abs() / e[k];
        let tolerance = 4.0 * noise + 0.01;
        worst = worst.max(error / tolerance);
        sums.0 += a[k];
        sums.1 += e[k];
        sums.2 += var[k];
        sums.3 += b[k];
    }
    let mean_error = (sums.0 - sums.1) / sums.1;
    let mean_noise = sums.2.sqrt() / sums.1;
    println!(
        "{name}: worst block at {worst:.2} of its tolerance, image mean off by {:.3} % (noise {:.3} %, second seed {:.3} %)",
        mean_error * 100.0,
        mean_noise * 100.0,
        (sums.3 - sums.1) / sums.1 * 100.0
    );
    assert!(
        mean_error.abs() < 4.0 * mean_noise + 0.005,
        "{name}: the image mean is off by {:.3} % (noise {:.3} %)",
        mean_error * 100.0,
        mean_noise * 100.0
    );
    Verdict { worst, mean_error }
}

fn radiance(s: &TruthScene) -> RadiancePair {
    check(s).unwrap();
    expect(mitsuba::render_noise(
        s,
        &MitsubaOptions { spp: SPP, seed: 7 },
    ))
}

fn all(_: u32, _: u32) -> bool {
    true
}

#[test]
fn transmittance_follows_beer_lambert_in_homogeneous_fog() {
    // Looking level at a wall 20 m ahead: every ray ends on it.
    let mut s = scene(
        "test_transmittance_wall",
        camera(Vec3::new(0.0, 10.0, 0.0), 0.0, 40.0),
        medium(0.05, 0.0, Vec3::splat(0.9), 0.0, 45.0),
        80.0,
    );
    s.occluders.push(TruthBox {
        min: Vec3::new(-60.0, 0.0, -21.0),
        max: Vec3::new(60.0, 40.0, -20.0),
    });
    check(&s).unwrap();
    let got = expect(mitsuba::render_transmittance(&s, 3));
    let sigma = s.medium.density;
    let want = reference_at(&s, SUB_TRANSMITTANCE, |_, len| {
        Vec3::splat((-sigma * len).exp())
    });
    let worst = got
        .iter()
        .zip(&want)
        .map(|(g, w)| (*g - *w).abs().max_element())
        .fold(0.0, f32::max);
    println!("transmittance, homogeneous: worst pixel off by {worst:.2e}");
    assert!(worst < 1e-3, "worst transmittance error {worst}");
}

#[test]
fn transmittance_integrates_height_fog_and_local_volumes() {
    let mut s = scene(
        "test_transmittance_height_volumes",
        camera(Vec3::new(0.0, 6.0, 0.0), 8.0, 40.0),
        medium(0.1, 0.2, Vec3::splat(0.9), 0.0, 40.0),
        80.0,
    );
    s.occluders.push(TruthBox {
        min: Vec3::new(-60.0, 0.0, -26.0),
        max: Vec3::new(60.0, 35.0, -25.0),
    });
    s.volumes = vec![
        TruthVolume {
            shape: TruthShape::Box,
            center: Vec3::new(-3.0, 3.0, -12.0),
            half_extents: Vec3::new(2.5, 2.0, 2.0),
            density: 0.3,
            edge: 0.25,
        },
        TruthVolume {
            shape: TruthShape::Ellipsoid,
            center: Vec3::new(4.0, 4.0, -16.0),
            half_extents: Vec3::new(3.0, 2.0, 2.5),
            density: 0.2,
            edge: 0.4,
        },
    ];
    check(&s).unwrap();
    let got = expect(mitsuba::render_transmittance(&s, 3));
    let o = s.camera.position;
    let want = reference_at(&s, SUB_TRANSMITTANCE, |v, len| {
        // Each volume's extinction over the ray's chord through its box.
        let mut local = 0.0;
        for vol in &s.volumes {
            let (lo, hi) = (vol.center - vol.half_extents, vol.center + vol.half_extents);
            let Some((t0, t1)) = ray_box(o, v, lo, hi) else {
                continue;
            };
            let t1 = t1.min(len);
            let n = STEPS_VOLUME;
            let dt = (t1 - t0).max(0.0) / n as f32;
            local += (0..n)
                .map(|i| volume_extinction(vol, o + v * (t0 + (i as f32 + 0.5) * dt)) * dt)
                .sum::<f32>();
        }
        Vec3::splat((-global_depth(&s.medium, o, v, len) - local).exp())
    });
    let (mut worst, mut at) = (0.0, 0);
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        let e = (*g - *w).abs().max_element();
        if e > worst {
            (worst, at) = (e, k);
        }
    }
    let (i, j) = (at as u32 % RES[0], at as u32 / RES[0]);
    println!("transmittance, height fog and volumes: worst pixel off by {worst:.2e} at ({i}, {j})");
    assert!(
        worst < 2e-3,
        "worst transmittance error {worst} at pixel ({i}, {j}): {} vs {}",
        got[at],
        want[at]
    );
}

/// Sun ahead, 15 degrees up; g = 0.6: the rays that look towards it (the top rows)
/// see the forward peak.
fn sun_scene(falloff: f32, density: f32) -> TruthScene {
    let mut s = scene(
        "test_sun",
        camera(Vec3::new(0.0, 6.0, 0.0), 25.0, 100.0),
        medium(density, falloff, Vec3::new(0.9, 0.8, 0.7), 0.6, 20.0),
        200.0,
    );
    s.sun = Some(sun(15.0, 0.0, Vec3::new(3.0, 2.0, 1.0)));
    s
}

#[test]
fn sun_inscattering_matches_the_formula_and_g_is_forward() {
    let s = sun_scene(0.0, 0.04);
    let pair = radiance(&s);
    let g = s.medium.phase_g;
    let o = s.camera.position;
    let want = reference(&s, |v, len| inscatter(&s, g, o, v, len));
    let verdict = compare("sun", &pair, &want, &all);
    assert!(
        verdict.worst < 1.0,
        "a block is off by {:.2} of its tolerance",
        verdict.worst
    );

    // Channels: the rgb ratios follow irradiance times albedo.
    let total = |img: &[Vec3]| img.iter().fold(Vec3::ZERO, |a, &b| a + b);
    let (got, exp) = (total(&pair.first), total(&want));
    let ratio = got / exp;
    assert!(
        (ratio / ratio.x - Vec3::ONE).abs().max_element() < 0.01,
        "channel ratios {ratio}"
    );

    // g's sign: the top rows look towards the sun and must be the brighter ones, as
    // the formula says; with -g the formula would disagree far beyond the noise.
    let rows = |img: &[Vec3], range: std::ops::Range<u32>| {
        let w = RES[0] as usize;
        range
            .flat_map(|j| img[j as usize * w..(j as usize + 1) * w].iter())
            .map(|v| (v.x + v.y + v.z) as f64)
            .sum::<f64>()
    };
    let top_over_bottom = |img: &[Vec3]| rows(img, 0..6) / rows(img, 30..36);
    let (got_ratio, want_ratio) = (top_over_bottom(&pair.first), top_over_bottom(&want));
    println!("sun: top / bottom rows {got_ratio:.3} (formula {want_ratio:.3})");
    assert!(
        want_ratio > 1.5,
        "the scene does not show the forward peak: {want_ratio}"
    );
    assert!(
        (got_ratio / want_ratio - 1.0).abs() < 0.05,
        "{got_ratio} vs {want_ratio}"
    );
    let flipped = top_over_bottom(&reference(&s, |v, len| inscatter(&s, -g, o, v, len)));
    println!("sun: with -g the formula's top / bottom would be {flipped:.3}");
    assert!(
        got_ratio / flipped > 2.0,
        "{got_ratio} vs {flipped} with -g"
    );
}

#[test]
fn sun_inscattering_in_height_fog_matches_the_formula() {
    let s = sun_scene(0.15, 0.08);
    let pair = radiance(&s);
    let o = s.camera.position;
    let want = reference(&s, |v, len| inscatter(&s, s.medium.phase_g, o, v, len));
    let verdict = compare("height fog", &pair, &want, &all);
    assert!(
        verdict.worst < 1.0,
        "a block is off by {:.2} of its tolerance",
        verdict.worst
    );
}

/// Pixels away from a light's image (the reference cannot resolve the 1 / distance
/// peak inside the pixel that holds it).
fn away_from(s: &TruthScene, light: Vec3) -> impl Fn(u32, u32) -> bool {
    let cam = s.camera;
    let res = s.resolution;
    // The light's film position by search over pixel centres.
    let dir = (light - cam.position).normalize();
    let mut best = (0, 0, -2.0);
    for j in 0..res[1] {
        for i in 0..res[0] {
            let c = film_ray(&cam, res, i as f32 + 0.5, j as f32 + 0.5).dot(dir);
            if c > best.2 {
                best = (i, j, c);
            }
        }
    }
    move |i, j| (i as i64 - best.0 as i64).abs() > 2 || (j as i64 - best.1 as i64).abs() > 2
}

#[test]
fn point_light_inscattering_matches_the_formula() {
    let mut s = scene(
        "test_point",
        camera(Vec3::new(0.0, 4.0, 0.0), 25.0, 80.0),
        medium(0.05, 0.0, Vec3::splat(0.9), 0.3, 20.0),
        100.0,
    );
    // Right of and below the image centre: a mirrored or flipped image fails.
    let light = Vec3::new(2.5, 2.0, -12.0);
    s.points = vec![TruthPoint {
        position: light,
        color: Vec3::new(100.0, 80.0, 60.0),
    }];
    let pair = radiance(&s);
    let o = s.camera.position;
    let want = reference(&s, |v, len| inscatter(&s, s.medium.phase_g, o, v, len));
    let keep = away_from(&s, light);
    let verdict = compare("point", &pair, &want, &keep);
    assert!(
        verdict.worst < 1.0,
        "a block is off by {:.2} of its tolerance",
        verdict.worst
    );
    assert!(verdict.mean_error.abs() < 0.02);
}

#[test]
fn spot_light_inscattering_matches_the_formula() {
    let mut s = scene(
        "test_spot",
        camera(Vec3::new(0.0, 4.0, 0.0), 25.0, 80.0),
        medium(0.05, 0.0, Vec3::splat(0.9), 0.3, 20.0),
        100.0,
    );
    let light = Vec3::new(-3.0, 6.0, -14.0);
    s.spots = vec![TruthSpot {
        position: light,
        direction: Vec3::new(0.5, -1.0, -0.2).normalize(),
        color: Vec3::new(300.0, 280.0, 250.0),
        inner_deg: 20.0,
        outer_deg: 25.0,
    }];
    let pair = radiance(&s);
    let o = s.camera.position;
    let want = reference(&s, |v, len| inscatter(&s, s.medium.phase_g, o, v, len));
    let keep = away_from(&s, light);
    let verdict = compare("spot", &pair, &want, &keep);
    assert!(
        verdict.worst < 1.0,
        "a block is off by {:.2} of its tolerance",
        verdict.worst
    );
}

/// Mitsuba shadows a point light by the occluders as it does the sun: a wall beside
/// the light (a box 0.5 m thick, 5 m high and 4 m long, 1.5 m to its left) casts a
/// shadow across the fog in view. Mitsuba matches the formula with the wall's shadow,
/// block by block, and misses the formula without it where the shadow lies.
#[test]
fn point_light_is_shadowed_by_the_occluders() {
    let mut s = scene(
        "test_point_shadow",
        camera(Vec3::new(0.0, 4.0, 0.0), 25.0, 80.0),
        medium(0.05, 0.0, Vec3::splat(0.9), 0.3, 20.0),
        100.0,
    );
    let light = Vec3::new(2.5, 2.0, -12.0);
    s.points = vec![TruthPoint {
        position: light,
        color: Vec3::new(100.0, 80.0, 60.0),
    }];
    s.occluders.push(TruthBox {
        min: Vec3::new(0.5, 0.0, -14.0),
        max: Vec3::new(1.0, 5.0, -10.0),
    });
    let pair = radiance(&s);
    let o = s.camera.position;
    let want = reference(&s, |v, len| inscatter(&s, s.medium.phase_g, o, v, len));
    let keep = away_from(&s, light);
    let verdict = compare("point behind a wall", &pair, &want, &keep);
    assert!(
        verdict.worst < 1.0,
        "a block is off by {:.2} of its tolerance",
        verdict.worst
    );
    // Without the wall's shadow the formula is far from Mitsuba in the shadowed blocks.
    let mut open = s.clone();
    open.occluders.truncate(1);
    let unshadowed = reference(&s, |v, len| inscatter(&open, s.medium.phase_g, o, v, len));
    let (got, bright) = (blocks(&pair.first, &keep), blocks(&unshadowed, &keep));
    let dark = got
        .iter()
        .zip(&bright)
        .filter(|(g, b)| **b > 0.0 && **g < 0.5 * **b)
        .count();
    println!("point behind a wall: {dark} blocks at less than half their unshadowed radiance");
    assert!(dark >= 5, "the wall's shadow is missing: {dark} blocks");
}

/// Renders the scenes of `truth::scenes` at the recommended samples per pixel (two
/// seeds, and the transmittance) and prints the times and Mitsuba's noise; writes
/// each scene's JSON to target/truth-cache/scenes/. Run with
/// `VOLFOG_TRUTH_CACHE=off cargo test -p volfog-testkit --test mitsuba -- --ignored --nocapture`
/// to time fresh renders.
#[test]
#[ignore = "renders every reference scene (minutes)"]
fn report_reference_scenes() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/truth-cache/scenes");
    std::fs::create_dir_all(&dir).unwrap();
    let options = MitsubaOptions::default();
    let total = std::time::Instant::now();
    for s in volfog_testkit::truth::scenes::all() {
        std::fs::write(
            dir.join(format!("{}.json", s.name)),
            serde_json::to_string_pretty(&s).unwrap(),
        )
        .unwrap();
        let start = std::time::Instant::now();
        let pair = expect(mitsuba::render_noise(&s, &options));
        let radiance = start.elapsed().as_secs_f64() / 2.0;
        let start = std::time::Instant::now();
        let t = expect(mitsuba::render_transmittance(&s, options.seed));
        let transmittance = start.elapsed().as_secs_f64();
        let n = pair.noise();
        let tmin = t.iter().map(|v| v.x).fold(1.0, f32::min);
        println!(
            "{:20} radiance {:6.1} s per seed, transmittance {:5.1} s; noise {:.2} % per pixel, {:.3} % image mean ({} px); transmittance min {tmin:.3}",
            s.name,
            radiance,
            transmittance,
            n.per_pixel * 100.0,
            n.image_mean * 100.0,
            n.pixels
        );
    }
    println!("total {:.1} s", total.elapsed().as_secs_f64());
}

/// The references committed under `tests/truth-references` are exactly the renders the
/// truth suites compare with (`truth::report::Reference::render` of every scene of
/// `scenes::all` and `scenes::area_lights` at `truth::report::SPP`), each of the
/// scene's size: a clean checkout compares without rendering them, and no render
/// that nothing reads is kept.
#[test]
fn committed_references_are_the_suites_renders() {
    use volfog_testkit::truth::{report, scenes, stored};
    let options = MitsubaOptions {
        spp: report::SPP,
        ..MitsubaOptions::default()
    };
    let mut wanted = std::collections::BTreeMap::new();
    for s in scenes::all().into_iter().chain(scenes::area_lights()) {
        for key in expect(mitsuba::reference_keys(&s, &options)) {
            wanted.insert(key, s.clone());
        }
    }
    let committed = stored::committed_keys();
    let missing: std::collections::BTreeSet<&str> = wanted
        .iter()
        .filter(|(k, _)| !committed.contains(k))
        .map(|(_, s)| s.name.as_str())
        .collect();
    let stale: Vec<&String> = committed
        .iter()
        .filter(|k| !wanted.contains_key(*k))
        .collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "{}: renders of {missing:?} are missing, {stale:?} are read by nothing. Write the \
         missing ones with `{}=write cargo test -p volfog --test gpu truth` (they are read \
         from target/truth-cache when there, else rendered) and delete the stale files",
        stored::REFERENCES,
        stored::WRITE_REFERENCES,
    );
    for (key, scene) in &wanted {
        let path = stored::references_dir().join(format!("{key}.bin"));
        let bytes = std::fs::read(&path).unwrap();
        let expected = (scene.resolution[0] * scene.resolution[1] * 12) as usize;
        assert_eq!(bytes.len(), expected, "{}", path.display());
        assert!(
            bytes
                .chunks_exact(4)
                .all(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]).is_finite()),
            "{} holds a value that is not finite",
            path.display()
        );
    }
}
