//! The froxel renderer of the path-tracer comparison (`volfog_testkit::truth::volfog`)
//! checked on its own against closed forms and numerical integrals (f64, 10k midpoint
//! steps) of single scattering in a homogeneous medium.
//!
//! volfog's volume starts at the view depth `camera.near`: the medium in front of it
//! neither scatters nor attenuates. The references integrate from there (ray distance
//! `t0 = near * |ray| / |ray.z|`, transmittance 1 at `t0`) to the ray's hit; the error
//! against the whole ray from the eye is printed, not asserted.

use crate::common::gpu;
use glam::{DVec3, UVec3, Vec3};
use volfog_testkit::truth::compare::{ErrorStats, channel_mean, penumbra_mask, stats};
use volfog_testkit::truth::floor::grid_floor;
use volfog_testkit::truth::scene::{
    TruthBox, TruthCamera, TruthImage, TruthMedium, TruthPoint, TruthScene, TruthSun,
};
use volfog_testkit::truth::volfog::{VolfogOptions, pixel_depths, pixel_ray, render, trace};

const W: u32 = 160;
const H: u32 = 90;
/// Extinction of the homogeneous medium (1/m).
const SIGMA: f64 = 0.03;
/// Single-scattering albedo (grey).
const ALBEDO: f64 = 0.8;
/// HG mean cosine.
const G: f64 = 0.5;
/// The medium's top (m).
const TOP: f64 = 10.0;
/// The ground's top face (m).
const GROUND: f32 = -20.0;

/// A camera at the origin pitched 35 degrees down (30 degree vertical field of view,
/// 16:9): every ray meets the ground at y = -20 m within 64 m, view depth <= 57 m.
fn camera() -> TruthCamera {
    let pitch = 35f32.to_radians();
    TruthCamera {
        position: Vec3::ZERO,
        target: Vec3::new(0.0, -pitch.sin(), -pitch.cos()),
        fov_y_deg: 30.0,
        near: 0.5,
        far: 80.0,
    }
}

fn medium() -> TruthMedium {
    TruthMedium {
        density: SIGMA as f32,
        falloff: 0.0,
        base_height: 0.0,
        albedo: Vec3::splat(ALBEDO as f32),
        phase_g: G as f32,
        top: TOP as f32,
        bounds_min: Vec3::new(-2000.0, GROUND, -2000.0),
        bounds_max_xz: [2000.0, 2000.0],
    }
}

/// The ground box: top face at y = -20 m, 4 km wide.
fn ground() -> TruthBox {
    TruthBox {
        min: Vec3::new(-2000.0, GROUND - 1.0, -2000.0),
        max: Vec3::new(2000.0, GROUND, 2000.0),
    }
}

fn scene(name: &str) -> TruthScene {
    TruthScene {
        name: name.into(),
        resolution: [W, H],
        camera: camera(),
        medium: medium(),
        sun: None,
        points: vec![],
        spots: vec![],
        areas: vec![],
        volumes: vec![],
        occluders: vec![ground()],
    }
}

/// One frame without jitter or history, the lamps unshadowed: each froxel sampled at
/// its centre, as the references below integrate.
fn options(slices: u32, light_transmittance: bool) -> VolfogOptions {
    VolfogOptions {
        frames: 1,
        ..VolfogOptions::default()
    }
    .with_config(|c| {
        c.volume_size = UVec3::new(160, 90, slices);
        c.light_transmittance = light_transmittance;
        c.jitter = false;
        c.temporal = false;
        c.local_shadows = None;
    })
}

/// The image of one frame ([`options`]).
fn image(scene: &TruthScene, options: &VolfogOptions) -> TruthImage {
    render(gpu(), scene, options).unwrap().converged
}

/// Henyey-Greenstein phase function (1/sr).
fn hg(cos: f64, g: f64) -> f64 {
    (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * cos).powf(1.5))
}

/// Midpoint rule with `steps` steps over [a, b].
fn integrate(a: f64, b: f64, steps: u32, f: impl Fn(f64) -> f64) -> f64 {
    let h = (b - a) / f64::from(steps);
    (0..steps)
        .map(|i| f(a + (f64::from(i) + 0.5) * h))
        .sum::<f64>()
        * h
}

/// Ray distance (m) from the eye to the froxel volume's near plane along `dir`.
fn near_distance(scene: &TruthScene, dir: Vec3) -> f64 {
    let c = &scene.camera;
    let forward = (c.target - c.position).normalize();
    f64::from(c.near) / f64::from(dir.dot(forward))
}

/// Every 10th pixel in x and y, starting at (5, 5): 16 x 9 pixels.
fn sampled() -> impl Iterator<Item = (u32, u32)> {
    (0..H / 10).flat_map(|j| (0..W / 10).map(move |i| (10 * i + 5, 10 * j + 5)))
}

fn report(label: &str, s: &ErrorStats) {
    eprintln!(
        "{label}: relative error mean {:.2e}, p95 {:.2e}, max {:.2e} over {} pixels",
        s.mean, s.p95, s.max, s.pixels
    );
}

#[test]
fn transmittance_follows_the_closed_form() {
    // No lights, a wall 30 m ahead of a level camera.
    let mut scene = scene("truth_transmittance");
    scene.camera = TruthCamera {
        position: Vec3::new(0.0, 2.0, 0.0),
        target: Vec3::new(0.0, 2.0, -1.0),
        fov_y_deg: 60.0,
        near: 0.5,
        far: 40.0,
    };
    // The medium reaches above the highest ray's hit (19.3 m).
    scene.medium.top = 100.0;
    scene.occluders = vec![TruthBox {
        min: Vec3::new(-500.0, -500.0, -31.0),
        max: Vec3::new(500.0, 500.0, -30.0),
    }];
    let image = image(&scene, &options(128, true));
    let depths = pixel_depths(&scene);
    let (mut worst, mut worst_full, mut brightest) = (0.0f64, 0.0f64, 0.0f32);
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let length = f64::from(depths[i]);
            assert!(
                length.is_finite() && length < 60.0,
                "every ray hits the wall"
            );
            let start = near_distance(&scene, pixel_ray(&scene, x, y));
            let want = (-SIGMA * (length - start)).exp();
            let t = image.transmittance[i];
            assert!((t.max_element() - t.min_element()) < 1e-6, "grey");
            worst = worst.max((f64::from(t.x) - want).abs());
            worst_full = worst_full.max((f64::from(t.x) - (-SIGMA * length).exp()).abs());
            brightest = brightest.max(image.radiance[i].max_element());
        }
    }
    eprintln!(
        "transmittance: max |T - exp(-sigma (L - L_near))| = {worst:.2e} (bound 1e-3); \
         against exp(-sigma L) from the eye {worst_full:.2e}; radiance max {brightest:.1e}"
    );
    // Measured 2.1e-4 on lavapipe (rgba16float integrated volume, rgba32float target).
    assert!(worst <= 1e-3, "{worst}");
    assert_eq!(brightest, 0.0, "no lights, no in-scattering");
}

/// The sun's single scattering along each sampled pixel's ray to the ground,
/// E sigma_s HG(v.s, g) exp(-sigma (t - t0)) [exp(-sigma (top - y) / s.y)] dt from the
/// near plane at t0, and (second) from the eye with exp(-sigma t).
fn sun_reference(scene: &TruthScene, sun: &TruthSun, transmittance: bool) -> Vec<(f64, f64)> {
    let depths = pixel_depths(scene);
    let s = sun.direction.normalize().as_dvec3();
    let e = f64::from(sun.color.x);
    let eye = scene.camera.position.as_dvec3();
    sampled()
        .map(|(x, y)| {
            let dir = pixel_ray(scene, x, y);
            let v = dir.as_dvec3();
            let end = f64::from(depths[(y * W + x) as usize]);
            let phase = hg(v.dot(s), G);
            let scattered = |t: f64| {
                let height = (eye + v * t).y;
                let light = if transmittance {
                    (-SIGMA * (TOP - height) / s.y).exp()
                } else {
                    1.0
                };
                e * ALBEDO * SIGMA * phase * light
            };
            let t0 = near_distance(scene, dir);
            (
                integrate(t0, end, 10_000, |t| {
                    scattered(t) * (-SIGMA * (t - t0)).exp()
                }),
                integrate(0.0, end, 10_000, |t| scattered(t) * (-SIGMA * t).exp()),
            )
        })
        .collect()
}

/// Relative errors of the sampled pixels' radiance (channel mean) where `keep`.
fn errors(image: &TruthImage, reference: &[f64], keep: impl Fn(usize) -> bool) -> ErrorStats {
    let mut e: Vec<f32> = sampled()
        .zip(reference)
        .enumerate()
        .filter(|(k, _)| keep(*k))
        .map(|(_, ((x, y), want))| {
            let got = f64::from(channel_mean(image.radiance[(y * W + x) as usize]));
            ((got - want).abs() / want) as f32
        })
        .collect();
    stats(&mut e)
}

#[test]
fn sun_scattering_follows_the_integral() {
    let mut scene = scene("truth_sun");
    let sun = TruthSun {
        direction: Vec3::new(0.3, 0.64, -0.7).normalize(),
        color: Vec3::splat(3.0),
    };
    scene.sun = Some(sun);
    let mut measured = Vec::new();
    for transmittance in [true, false] {
        let reference = sun_reference(&scene, &sun, transmittance);
        let froxel: Vec<f64> = reference.iter().map(|r| r.0).collect();
        let whole: Vec<f64> = reference.iter().map(|r| r.1).collect();
        for slices in [128, 256] {
            let image = image(&scene, &options(slices, transmittance));
            let label = format!("sun, light transmittance {transmittance}, 160 x 90 x {slices}");
            let s = errors(&image, &froxel, |_| true);
            report(&label, &s);
            report(
                &format!("{label}, against the whole ray"),
                &errors(&image, &whole, |_| true),
            );
            measured.push((transmittance, slices, s));
        }
    }
    // Measured on lavapipe (the compare filter, its taps kept in front of the ground by
    // the scene depth): max 1.3e-3 (transmittance on) and 1.7e-3 (off) at 128 slices,
    // 1.4e-3 and 1.9e-3 at 256, mean 7e-4 to 9e-4. The sun's light varies
    // by a few percent across a slice here, so the slices' error is far below the
    // rgba16float quantisation of the scattering and integrated volumes (4.9e-4 per
    // value), which sets this floor: finer slices change it by less than 1e-4.
    for (transmittance, slices, s) in &measured {
        assert!(
            s.max <= 2e-3,
            "transmittance {transmittance}, {slices} slices: {s:?}"
        );
    }
}

/// A point light's single scattering along each sampled pixel's ray:
/// sigma_s I / r^2 HG(v.l, g) exp(-sigma (t - t0)) [exp(-sigma r)] dt from the near
/// plane at t0, the same from the eye with exp(-sigma t), and the closest approach (m)
/// of the ray to the light.
fn point_reference(
    scene: &TruthScene,
    light: &TruthPoint,
    transmittance: bool,
) -> Vec<(f64, f64, f64)> {
    let depths = pixel_depths(scene);
    let q = light.position.as_dvec3();
    let intensity = f64::from(light.color.x);
    let eye = scene.camera.position.as_dvec3();
    sampled()
        .map(|(x, y)| {
            let dir = pixel_ray(scene, x, y);
            let v = dir.as_dvec3();
            let end = f64::from(depths[(y * W + x) as usize]);
            let scattered = |t: f64| {
                let to_light: DVec3 = q - (eye + v * t);
                let r = to_light.length();
                let phase = hg(v.dot(to_light / r), G);
                let light = if transmittance {
                    (-SIGMA * r).exp()
                } else {
                    1.0
                };
                ALBEDO * SIGMA * intensity / (r * r) * phase * light
            };
            let t0 = near_distance(scene, dir);
            let along = (q - eye).dot(v).clamp(0.0, end);
            (
                integrate(t0, end, 10_000, |t| {
                    scattered(t) * (-SIGMA * (t - t0)).exp()
                }),
                integrate(0.0, end, 10_000, |t| scattered(t) * (-SIGMA * t).exp()),
                (eye + v * along).distance(q),
            )
        })
        .collect()
}

#[test]
fn point_light_scattering_follows_the_integral() {
    let mut scene = scene("truth_point");
    // In view, 8 m above the ground and 28 m from the eye.
    let light = TruthPoint {
        position: Vec3::new(2.0, -12.0, -25.0),
        color: Vec3::splat(50.0),
    };
    scene.points = vec![light];
    let mut measured = Vec::new();
    for transmittance in [true, false] {
        let reference = point_reference(&scene, &light, transmittance);
        let froxel: Vec<f64> = reference.iter().map(|r| r.0).collect();
        let whole: Vec<f64> = reference.iter().map(|r| r.1).collect();
        // Rays passing within 3 m of the light meet a peak a few froxels wide: reported,
        // not asserted.
        let away = |k: usize| reference[k].2 > 3.0;
        for slices in [128, 256] {
            let image = image(&scene, &options(slices, transmittance));
            let label = format!("point, light transmittance {transmittance}, 160 x 90 x {slices}");
            let far = errors(&image, &froxel, away);
            let all = errors(&image, &froxel, |_| true);
            report(&format!("{label}, all pixels"), &all);
            report(&format!("{label}, rays > 3 m from the light"), &far);
            report(
                &format!("{label}, rays > 3 m from the light, against the whole ray"),
                &errors(&image, &whole, away),
            );
            measured.push((transmittance, slices, all, far));
        }
    }
    // Measured on lavapipe, rays more than 3 m from the light: max 1.2e-3 at 128 and
    // 256 slices (mean 7e-4, the rgba16float floor as for the sun); all pixels: max
    // 8.4e-3 (on) and 7.4e-3 (off) at 128 slices, 1.2e-3 at 256: near the light the
    // slices' error shows, and falls with more slices.
    for (transmittance, slices, all, far) in &measured {
        let label = format!("transmittance {transmittance}, {slices} slices");
        assert!(far.max <= 2e-3, "{label}: {far:?}");
        let bound = if *slices == 128 { 1.2e-2 } else { 2e-3 };
        assert!(all.max <= bound, "{label}: {all:?}");
    }
    for pair in measured.chunks(2) {
        assert!(
            pair[1].2.max < 0.5 * pair[0].2.max,
            "finer slices, smaller error near the light: {pair:?}"
        );
    }
}

#[test]
fn a_roof_shadows_the_sun_through_the_cascades() {
    // A roof over x < 8 m between 4 and 5 m above the eye: below it the sun's light
    // reaches a point when its ray towards the sun passes the roof's edge. The eye is
    // in its shadow; rays swinging right reach the light past the edge.
    let mut scene = scene("truth_roof");
    let sun = TruthSun {
        direction: Vec3::new(0.3, 0.64, -0.7).normalize(),
        color: Vec3::splat(3.0),
    };
    scene.sun = Some(sun);
    scene.occluders.push(TruthBox {
        min: Vec3::new(-2000.0, 4.0, -2000.0),
        max: Vec3::new(8.0, 5.0, 2000.0),
    });
    let depths = pixel_depths(&scene);
    let penumbra = penumbra_mask(&scene, &depths, 2.0);
    let s = sun.direction.normalize();
    let eye = scene.camera.position.as_dvec3();
    // The reference: E sigma_s HG exp(-sigma (t - t0)) exp(-sigma (top - y) / s.y) V(t).
    let reference: Vec<f64> = sampled()
        .map(|(x, y)| {
            let dir = pixel_ray(&scene, x, y);
            let v = dir.as_dvec3();
            let t0 = near_distance(&scene, dir);
            let phase = hg(v.dot(s.as_dvec3()), G);
            let end = f64::from(depths[(y * W + x) as usize]);
            integrate(t0, end, 2_000, |t| {
                let p = eye + v * t;
                let lit = trace(p.as_vec3(), s, &scene.occluders).is_none();
                let light = (-SIGMA * (TOP - p.y) / f64::from(s.y)).exp();
                f64::from(sun.color.x)
                    * ALBEDO
                    * SIGMA
                    * phase
                    * light
                    * (-SIGMA * (t - t0)).exp()
                    * f64::from(u8::from(lit))
            })
        })
        .collect();
    let lit_part = reference.iter().copied().fold(0.0f64, f64::max);
    // Errors relative to the brightest reference pixel (shadowed pixels are near 0),
    // away from the edge and near it, and the shadowed pixels away from it.
    let against = |image: &TruthImage| {
        let (mut away, mut near) = (Vec::new(), Vec::new());
        let mut shadowed = 0;
        for ((x, y), want) in sampled().zip(&reference) {
            let i = (y * W + x) as usize;
            let got = f64::from(channel_mean(image.radiance[i]));
            let e = ((got - want).abs() / lit_part) as f32;
            if penumbra[i] {
                near.push(e);
            } else {
                shadowed += usize::from(*want < 0.01 * lit_part);
                away.push(e);
            }
        }
        (stats(&mut away), stats(&mut near), shadowed)
    };
    let options = options(128, true);
    let (away, near, shadowed) = against(&image(&scene, &options));
    let floor = grid_floor(&scene, &options).unwrap();
    let (floor_away, floor_near, _) = against(&floor.image);
    let penumbral = near.pixels;
    eprintln!(
        "roof: {penumbral} of 144 sampled pixels within 2 m of the shadow edge, {shadowed} \
         of the others fully shadowed; error relative to the brightest pixel ({lit_part:.3}): \
         mean {:.2e}, p95 {:.2e}, max {:.2e} over {} pixels",
        away.mean, away.p95, away.max, away.pixels
    );
    eprintln!(
        "roof, pixels near the edge: mean {:.2e}, p95 {:.2e}, max {:.2e} (not asserted)",
        near.mean, near.p95, near.max
    );
    eprintln!(
        "roof, grid floor ({} froxels, {} sub-sampled): away from the edge mean {:.2e}, \
         max {:.2e}; near it mean {:.2e}, max {:.2e}",
        floor.froxels,
        floor.sampled,
        floor_away.mean,
        floor_away.max,
        floor_near.mean,
        floor_near.max
    );
    assert!(
        shadowed > 20 && penumbral > 20,
        "the shadow and its edge are seen"
    );
    // The grid floor (a perfect shadow term at the same grid) follows the integral
    // everywhere, the edge included. Measured on lavapipe: max 0 away from the edge,
    // 7.6e-4 near it (mean 1.6e-4), where the image (the compare filter, one frame
    // without jitter) errs by up to 8.3e-3 and the ESM's by 0.143.
    assert!(floor_away.max <= 2e-3, "{floor_away:?}");
    assert!(floor_near.max <= 2e-3, "{floor_near:?}");
    assert!(floor.sampled > 0, "froxels across the edge are sub-sampled");
    // Measured on lavapipe: max 0 away from the edge with the compare filter, 1.4e-5
    // with the ESM (the roof lies 6 m or more above every receiver along the sun,
    // where the ESM no longer leaks).
    assert!(away.max <= 2e-3, "{away:?}");
}
