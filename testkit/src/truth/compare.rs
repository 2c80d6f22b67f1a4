//! Comparing two renderings of a [`TruthScene`]: relative error statistics over the
//! pixels a mask keeps, and the masks that drop pixels no renderer of finite
//! resolution can agree on (occluder silhouettes, faint pixels, sun penumbrae).
//!
//! Masks are per pixel, row-major from the top; `true` means "compare this pixel"
//! for [`edge_mask`], [`floor_mask`] and [`comparison_mask`], and "this pixel sees a
//! shadow boundary" for [`penumbra_mask`] (negate it to drop those pixels).

use glam::Vec3;

use super::scene::TruthScene;
use super::volfog::{far_distance, inside, pixel_ray, trace};

/// Relative errors over the compared pixels.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ErrorStats {
    /// Mean relative error.
    pub mean: f32,
    /// 95th percentile (nearest rank: the smallest error that at least 95 % of the
    /// pixels do not exceed).
    pub p95: f32,
    /// Largest relative error.
    pub max: f32,
    /// Pixels compared (0: every statistic is 0).
    pub pixels: usize,
}

/// The mean of the three channels: the luminance-like value the errors are taken of.
pub fn channel_mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

/// Per pixel where `mask` is true, the relative error
/// `|mean(test) - mean(ref)| / max(mean(ref), floor)` of the channel means, and its
/// statistics. `floor` (> 0) keeps faint reference pixels from dominating. Pixels past
/// the shortest of the three slices are not compared; non-finite errors count as
/// infinite.
pub fn relative_error(test: &[Vec3], reference: &[Vec3], mask: &[bool], floor: f32) -> ErrorStats {
    let mut errors: Vec<f32> = test
        .iter()
        .zip(reference)
        .zip(mask)
        .filter(|(_, keep)| **keep)
        .map(|((t, r), _)| {
            let r = channel_mean(*r);
            let e = (channel_mean(*t) - r).abs() / r.max(floor);
            if e.is_nan() { f32::INFINITY } else { e }
        })
        .collect();
    stats(&mut errors)
}

/// Statistics of a list of errors (sorted in place).
pub fn stats(errors: &mut [f32]) -> ErrorStats {
    let n = errors.len();
    if n == 0 {
        return ErrorStats::default();
    }
    errors.sort_by(f32::total_cmp);
    let sum: f64 = errors.iter().map(|&e| f64::from(e)).sum();
    // Nearest rank: the ceil(0.95 n)-th smallest.
    let rank = (0.95 * n as f64).ceil() as usize;
    ErrorStats {
        mean: (sum / n as f64) as f32,
        p95: errors[rank.clamp(1, n) - 1],
        max: errors[n - 1],
        pixels: n,
    }
}

/// Pixels away from occluder silhouettes: false for a pixel when one of its eight
/// neighbours (or itself against a neighbour) differs in hit distance by more than
/// 5 % of the nearer one, or one hits an occluder and the other does not. `depths`
/// are [`pixel_depths`](super::volfog::pixel_depths) (infinity for a miss); pixels
/// missing from it count as misses. Surfaces seen at grazing angles, whose distance
/// changes by more than 5 % per pixel, are dropped as well.
pub fn edge_mask(scene: &TruthScene, depths: &[f32]) -> Vec<bool> {
    let [w, h] = scene.resolution;
    let depth = |x: u32, y: u32| {
        depths
            .get((y * w + x) as usize)
            .copied()
            .unwrap_or(f32::INFINITY)
    };
    let differ = |a: f32, b: f32| match (a.is_finite(), b.is_finite()) {
        (true, true) => (a - b).abs() > 0.05 * a.min(b),
        (false, false) => false,
        _ => true,
    };
    let mut mask = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let d = depth(x, y);
            let mut keep = true;
            for ny in y.saturating_sub(1)..=(y + 1).min(h - 1) {
                for nx in x.saturating_sub(1)..=(x + 1).min(w - 1) {
                    keep &= !differ(d, depth(nx, ny));
                }
            }
            mask.push(keep);
        }
    }
    mask
}

/// Pixels whose reference radiance (channel mean) is at least `floor`.
pub fn floor_mask(reference: &[Vec3], floor: f32) -> Vec<bool> {
    reference
        .iter()
        .map(|r| channel_mean(*r) >= floor)
        .collect()
}

/// The pixels compared by default: away from silhouettes ([`edge_mask`]) and at
/// least `floor` bright in the reference ([`floor_mask`]).
pub fn comparison_mask(
    scene: &TruthScene,
    depths: &[f32],
    reference: &[Vec3],
    floor: f32,
) -> Vec<bool> {
    edge_mask(scene, depths)
        .into_iter()
        .zip(floor_mask(reference, floor))
        .map(|(a, b)| a && b)
        .collect()
}

/// Points sampled along each camera ray by [`penumbra_mask`].
pub const PENUMBRA_SAMPLES: u32 = 64;

/// Pixels whose camera ray passes near a boundary of the sun's shadow (true: near
/// one). Along each ray, up to its hit (`depths`, see
/// [`pixel_depths`](super::volfog::pixel_depths)) or for a miss up to the froxel
/// volume's far plane, [`PENUMBRA_SAMPLES`] points are taken at the centres of equal
/// steps; a point is lit when a ray from it towards the sun hits no occluder. The pixel
/// is penumbral when some point's lit state differs from that of one of the four
/// points displaced by `width` (m) along `±a` and `±b`, two unit axes perpendicular to
/// the sun: the point lies within about `width` of a shadow boundary across the sun's
/// rays. Displaced points inside an occluder are skipped. Without a sun no pixel is
/// penumbral. (A shadow boundary is where visibility changes across the light's rays,
/// so displacing along the sun would find none; ESM filtering softens shadows in both
/// directions, which `width` should be chosen to cover.)
pub fn penumbra_mask(scene: &TruthScene, depths: &[f32], width: f32) -> Vec<bool> {
    let [w, h] = scene.resolution;
    let n = (w * h) as usize;
    let Some(sun) = scene.sun.as_ref() else {
        return vec![false; n];
    };
    let s = sun.direction.normalize_or_zero();
    let boxes = &scene.occluders;
    let a = s.any_orthonormal_vector();
    let b = s.cross(a);
    let offsets = [a, -a, b, -b].map(|v| v * width);
    let lit = |p: Vec3| trace(p, s, boxes).is_none();
    let eye = scene.camera.position;
    (0..n)
        .map(|i| {
            let (x, y) = (i as u32 % w, i as u32 / w);
            let dir = pixel_ray(scene, x, y);
            let end = match depths.get(i).copied() {
                Some(d) if d.is_finite() => d,
                _ => far_distance(scene, dir),
            };
            (0..PENUMBRA_SAMPLES).any(|k| {
                let p = eye + dir * (end * (k as f32 + 0.5) / PENUMBRA_SAMPLES as f32);
                if inside(p, boxes) {
                    return false;
                }
                let here = lit(p);
                offsets.iter().any(|o| {
                    let q = p + *o;
                    !inside(q, boxes) && lit(q) != here
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::scene::{TruthBox, TruthCamera, TruthMedium, TruthSun};

    #[test]
    fn stats_of_known_errors() {
        // Errors 0.01, 0.02, ..., 1.00: mean 0.505, the 95th smallest is 0.95.
        let reference: Vec<Vec3> = (0..100).map(|_| Vec3::new(1.0, 2.0, 3.0)).collect();
        let test: Vec<Vec3> = (1..=100)
            .map(|i| Vec3::new(1.0, 2.0, 3.0) * (1.0 + i as f32 / 100.0))
            .collect();
        let s = relative_error(&test, &reference, &[true; 100], 1e-3);
        assert_eq!(s.pixels, 100);
        assert!((s.mean - 0.505).abs() < 1e-5, "{s:?}");
        assert!((s.p95 - 0.95).abs() < 1e-5, "{s:?}");
        assert!((s.max - 1.0).abs() < 1e-5, "{s:?}");
    }

    #[test]
    fn mask_and_floor_are_applied() {
        let reference = [Vec3::splat(2.0), Vec3::splat(0.0), Vec3::splat(1.0)];
        let test = [Vec3::splat(3.0), Vec3::splat(0.1), Vec3::splat(100.0)];
        // The third pixel is masked out; the second is faint: 0.1 / floor 0.5.
        let s = relative_error(&test, &reference, &[true, true, false], 0.5);
        assert_eq!(s.pixels, 2);
        assert!((s.mean - 0.35).abs() < 1e-6, "{s:?}");
        assert!((s.max - 0.5).abs() < 1e-6, "{s:?}");
        assert!((s.p95 - 0.5).abs() < 1e-6, "{s:?}");
        // The channel mean is compared, not each channel.
        let s = relative_error(
            &[Vec3::new(1.0, 2.0, 3.0)],
            &[Vec3::new(3.0, 2.0, 1.0)],
            &[true],
            1e-3,
        );
        assert_eq!(s.max, 0.0);
        assert_eq!(
            relative_error(&[], &[], &[], 1.0),
            ErrorStats::default(),
            "no pixels, no errors"
        );
    }

    #[test]
    fn p95_is_the_nearest_rank() {
        let mut e: Vec<f32> = (1..=20).map(|i| i as f32).collect();
        e.reverse();
        let s = stats(&mut e);
        // ceil(0.95 * 20) = 19th smallest.
        assert_eq!(s.p95, 19.0);
        assert_eq!(s.max, 20.0);
        assert!((s.mean - 10.5).abs() < 1e-6);
    }

    fn wall_scene() -> TruthScene {
        TruthScene {
            name: "wall".into(),
            resolution: [64, 32],
            camera: TruthCamera {
                position: Vec3::ZERO,
                target: Vec3::new(0.0, 0.0, -1.0),
                fov_y_deg: 40.0,
                near: 0.5,
                far: 60.0,
            },
            medium: TruthMedium {
                density: 0.02,
                falloff: 0.0,
                base_height: 0.0,
                albedo: Vec3::splat(0.9),
                phase_g: 0.0,
                top: 50.0,
                bounds_min: Vec3::splat(-100.0),
                bounds_max_xz: [100.0, 100.0],
            },
            sun: Some(TruthSun {
                direction: Vec3::Y,
                color: Vec3::ONE,
            }),
            points: vec![],
            spots: vec![],
            areas: vec![],
            volumes: vec![],
            // A wall covering the left half of the view at 20 m, and a wide one at 40 m.
            occluders: vec![
                TruthBox {
                    min: Vec3::new(-100.0, -100.0, -21.0),
                    max: Vec3::new(0.0, 100.0, -20.0),
                },
                TruthBox {
                    min: Vec3::new(-100.0, -100.0, -41.0),
                    max: Vec3::new(100.0, 100.0, -40.0),
                },
            ],
        }
    }

    #[test]
    fn edge_mask_drops_the_silhouette_columns() {
        let scene = wall_scene();
        let depths = super::super::volfog::pixel_depths(&scene);
        let mask = edge_mask(&scene, &depths);
        for y in 0..32 {
            let row: Vec<bool> = (0..64).map(|x| mask[y * 64 + x]).collect();
            // The silhouette is between columns 31 and 32.
            let want: Vec<bool> = (0..64).map(|x| !(31..=32).contains(&x)).collect();
            assert_eq!(row, want, "row {y}");
        }
    }

    #[test]
    fn penumbra_mask_finds_the_shadow_edge_of_a_roof() {
        // An overhead sun and a roof over x < 0 at 10 m: rays looking down x = 0 pass
        // the shadow edge (x = 0 below the roof).
        let mut scene = wall_scene();
        scene.occluders = vec![
            TruthBox {
                min: Vec3::new(-100.0, 10.0, -100.0),
                max: Vec3::new(0.0, 11.0, 100.0),
            },
            TruthBox {
                min: Vec3::new(-100.0, -101.0, -41.0),
                max: Vec3::new(100.0, 100.0, -40.0),
            },
        ];
        let depths = super::super::volfog::pixel_depths(&scene);
        let mask = penumbra_mask(&scene, &depths, 0.5);
        // Every ray starts at the eye, right under the roof's edge: all penumbral.
        assert!(mask.iter().all(|m| *m));
        // Move the roof's edge 5 m to the left: only rays swinging left of x = -4.5
        // come near the boundary.
        scene.occluders[0].max.x = -5.0;
        let mask = penumbra_mask(&scene, &depths, 0.5);
        assert!(mask[16 * 64], "the leftmost column crosses x = -5");
        assert!(!mask[16 * 64 + 63], "the rightmost column stays lit");
    }
}
