//! The march of a view ray through its slice: transmittance, lit tests, the shaft term
//! by steps, by the min/max tree and by brute force per pixel.

use glam::{Vec2, Vec3, Vec3Swizzles, Vec4};

use super::height_map::{
    ColorLayer, EpipolarRay, ShadowLayer, color, height, light_texel, view_ray,
};
use super::tree::MinMaxTree;
use super::{LIT_DEPTH, mix};
use crate::cpu::height_fog::height_fog_optical_depth;
use crate::uniforms::{EpipolarFrame, HeightFog};

/// Transmittance of the medium `fog` (view space) from the start of `ray` to the
/// fraction `t` of it; mirror of `volfog::epipolar::epipolar_transmittance`.
pub fn transmittance(fog: &HeightFog, ray: &EpipolarRay, t: f32) -> f32 {
    (-height_fog_optical_depth(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        ray.origin,
        ray.segment * t,
    ))
    .exp()
}

/// Fraction in [0, 1] of `ray` where its projection reaches height-map position `i`
/// (texels); mirror of `volfog::epipolar::epipolar_ray_fraction`.
pub fn ray_fraction(ray: &EpipolarRay, i: f32) -> f32 {
    ((i - ray.start) / (ray.end - ray.start)).clamp(0.0, 1.0)
}

/// Is the part `[ta, tb]` (fractions) of `ray` lit under the height value `h` (its light
/// depth at the middle not beyond `h`)? Mirror of `volfog::epipolar::epipolar_lit`.
pub fn lit(ray: &EpipolarRay, ta: f32, tb: f32, h: f32) -> bool {
    mix(ray.light_start, ray.light_end, 0.5 * (ta + tb)) <= h
}

/// Shaft term S (dimensionless) of `ray` visiting every section of the height map `map`
/// read from `shadow` (Yusov 2012, Algorithm 1); mirror of
/// `volfog::epipolar::epipolar_march_steps`.
pub fn march_steps(
    shadow: &ShadowLayer,
    map: Vec4,
    bias: f32,
    fog: &HeightFog,
    ray: &EpipolarRay,
    colors: Option<&ColorLayer>,
) -> Vec3 {
    let size = shadow.size;
    if ray.end - ray.start < 1.0 {
        let k = (0.5 * (ray.start + ray.end))
            .floor()
            .clamp(0.0, size as f32) as u32;
        let (h, c) = if k < size {
            (height(shadow, map, k, bias), color(colors, map, k))
        } else {
            (LIT_DEPTH, Vec3::ONE)
        };
        return if lit(ray, 0.0, 1.0, h) {
            c * (1.0 - transmittance(fog, ray, 1.0))
        } else {
            Vec3::ZERO
        };
    }
    let stop = ray_fraction(ray, size as f32);
    let mut k = ray.start.floor().max(0.0) as u32;
    let mut ta = 0.0f32;
    let mut t_at_a = 1.0f32;
    let mut sum = Vec3::ZERO;
    while ta < stop && k < size {
        let tb = ray_fraction(ray, (k + 1) as f32).min(stop);
        let t_at_b = transmittance(fog, ray, tb);
        if lit(ray, ta, tb, height(shadow, map, k, bias)) {
            sum += color(colors, map, k) * (t_at_a - t_at_b);
        }
        ta = tb;
        t_at_a = t_at_b;
        k += 1;
    }
    // Beyond the map everything is lit, in white.
    sum + Vec3::splat(t_at_a - transmittance(fog, ray, 1.0))
}

/// Shaft term S (per colour channel) of `ray` through row `slice` of the min/max
/// `tree` (Yusov 2012, Algorithm 2), the same sum as [`march_steps`]; with `colors`
/// (the slice's `map` locates their texels) lit nodes are descended too; mirror of
/// `volfog::epipolar::epipolar_march_tree`.
pub fn march_tree(
    tree: &MinMaxTree,
    slice: u32,
    fog: &HeightFog,
    ray: &EpipolarRay,
    colors: Option<(Vec4, &ColorLayer)>,
) -> Vec3 {
    let size = tree.size;
    let layer = colors.map(|(_, c)| c);
    let map = colors.map_or(Vec4::ZERO, |(m, _)| m);
    if ray.end - ray.start < 1.0 {
        let k = (0.5 * (ray.start + ray.end))
            .floor()
            .clamp(0.0, size as f32) as u32;
        let (h, c) = if k < size {
            (tree.node(slice, 0, k).x, color(layer, map, k))
        } else {
            (LIT_DEPTH, Vec3::ONE)
        };
        return if lit(ray, 0.0, 1.0, h) {
            c * (1.0 - transmittance(fog, ray, 1.0))
        } else {
            Vec3::ZERO
        };
    }
    let top = size.trailing_zeros();
    let stop = ray_fraction(ray, size as f32);
    let mut k = ray.start.floor().max(0.0) as u32;
    let mut level = 0u32;
    let mut ta = 0.0f32;
    // Consecutive lit nodes form one run [lit_from, ta], taken once when it closes.
    let mut lit_from = 0.0f32;
    let mut open = false;
    let mut sum = Vec3::ZERO;
    let mut guard = 0u32;
    while ta < stop && k < size && guard < 8 * size {
        guard += 1;
        // Step 5.1: one level coarser when k starts the parent node.
        if level < top && (k & ((2u32 << level) - 1)) == 0 {
            level += 1;
        }
        let mut is_lit = false;
        let mut tb;
        loop {
            let n = 1u32 << level;
            tb = ray_fraction(ray, (k + n) as f32).min(stop);
            let da = mix(ray.light_start, ray.light_end, ta);
            let db = mix(ray.light_start, ray.light_end, tb);
            let node = tree.node(slice, level, k >> level);
            if da.max(db) <= node.x && (layer.is_none() || level == 0) {
                is_lit = true;
                break;
            }
            if da.min(db) > node.y {
                break;
            }
            if level == 0 {
                is_lit = lit(ray, ta, tb, node.x);
                break;
            }
            level -= 1;
        }
        if layer.is_some() {
            if is_lit {
                sum += color(layer, map, k)
                    * (transmittance(fog, ray, ta) - transmittance(fog, ray, tb));
            }
        } else if is_lit && !open {
            lit_from = ta;
            open = true;
        } else if !is_lit && open {
            sum += Vec3::splat(transmittance(fog, ray, lit_from) - transmittance(fog, ray, ta));
            open = false;
        }
        ta = tb;
        k += 1u32 << level;
    }
    // Beyond the map everything is lit (in white): the remainder joins an open run.
    if !open {
        lit_from = ta;
    }
    sum + Vec3::splat(transmittance(fog, ray, lit_from) - transmittance(fog, ray, 1.0))
}

/// Lit fraction F (see [`lit_fraction`]) of the view ray through `ndc` between the view
/// depths `(depth0, depth1)` (m) by brute force in `steps` equal steps over `shadow`
/// (side `frame.shadow_size`), coloured by `colors` when given; mirror of
/// `volfog::epipolar::epipolar_march_pixel`.
pub fn march_pixel(
    (shadow, colors): (&ShadowLayer, Option<&ColorLayer>),
    frame: &EpipolarFrame,
    fog: &HeightFog,
    ndc: Vec2,
    (depth0, depth1): (f32, f32),
    steps: u32,
) -> Vec3 {
    let dir = view_ray(frame.view_from_clip, ndc);
    let ray = EpipolarRay {
        origin: dir * depth0,
        segment: dir * (depth1.max(depth0) - depth0),
        ..EpipolarRay::default()
    };
    let size = frame.shadow_size as f32;
    let n = steps.max(1);
    let mut t_at_a = 1.0f32;
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        let ta = i as f32 / n as f32;
        let tb = (i + 1) as f32 / n as f32;
        let l = light_texel(frame, ray.origin + ray.segment * (0.5 * (ta + tb)));
        let q = l.xy().floor();
        let mut h = LIT_DEPTH;
        let mut c = Vec3::ONE;
        if q.cmpge(Vec2::ZERO).all() && q.cmplt(Vec2::splat(size)).all() {
            h = shadow.load(q.x as u32, q.y as u32) + frame.depth_bias;
            if let Some(layer) = colors {
                c = layer.colors[(q.y as u32 * layer.size + q.x as u32) as usize];
            }
        }
        let t_at_b = transmittance(fog, &ray, tb);
        if l.z <= h {
            sum += c * (t_at_a - t_at_b);
        }
        t_at_a = t_at_b;
    }
    lit_fraction(fog, &ray, sum)
}

/// The lit fraction F = S / (1 - T(1)) of a ray's shaft term `s`, in [0, 1]; 1 when
/// the ray absorbs almost nothing; mirror of `volfog::epipolar::epipolar_lit_fraction`.
pub fn lit_fraction(fog: &HeightFog, ray: &EpipolarRay, s: Vec3) -> Vec3 {
    let absorbed = 1.0 - transmittance(fog, ray, 1.0);
    if absorbed <= 1e-6 {
        return Vec3::ONE;
    }
    (s / absorbed).clamp(Vec3::ZERO, Vec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::epipolar::test_scene::{Scene, suns};
    use crate::cpu::epipolar::{ray, slice_map};

    /// Algorithm 1 in f64 for uniform fog of extinction `sigma` (1/m): the sum over the
    /// sections of the height map (lit when the light depth at the middle is not behind
    /// h) of T(a) - T(b), the part beyond the map lit.
    fn algorithm_1(shadow: &ShadowLayer, map: Vec4, ray: &EpipolarRay, sigma: f64) -> f64 {
        let size = f64::from(shadow.size);
        let length = ray.segment.as_dvec3().length();
        let t_at = |t: f64| (-sigma * length * t).exp();
        let (s0, s1) = (f64::from(ray.start), f64::from(ray.end));
        let (l0, l1) = (f64::from(ray.light_start), f64::from(ray.light_end));
        let depth_at = |t: f64| l0 + (l1 - l0) * t;
        let h = |k: f64| {
            let qx = (f64::from(map.x) + (k + 0.5) * f64::from(map.z)).floor();
            let qy = (f64::from(map.y) + (k + 0.5) * f64::from(map.w)).floor();
            if qx < 0.0 || qy < 0.0 || qx >= size || qy >= size {
                f64::from(LIT_DEPTH)
            } else {
                f64::from(shadow.load(qx as u32, qy as u32))
            }
        };
        if s1 - s0 < 1.0 {
            let k = (0.5 * (s0 + s1)).floor().clamp(0.0, size);
            return if depth_at(0.5) <= h(k) {
                1.0 - t_at(1.0)
            } else {
                0.0
            };
        }
        let fraction = |i: f64| ((i - s0) / (s1 - s0)).clamp(0.0, 1.0);
        let stop = fraction(size);
        let first = s0.floor().max(0.0);
        let mut sum = 0.0;
        let mut k = first;
        while k < size {
            let ta = if k == first { 0.0 } else { fraction(k) };
            let tb = fraction(k + 1.0).min(stop);
            if ta >= stop {
                break;
            }
            if depth_at(0.5 * (ta + tb)) <= h(k) {
                sum += t_at(ta) - t_at(tb);
            }
            k += 1.0;
        }
        sum + t_at(stop) - t_at(1.0)
    }

    #[test]
    fn tree_march_equals_steps_and_algorithm_1() {
        let mut rng = Rng(4);
        let sigma = 0.02f32;
        let (mut rays, mut lit_some, mut dark_some) = (0, 0, 0);
        // S is a sum of differences of f32 transmittances: its error is absolute
        // (a few 1e-8), so the relative tolerance applies to S >= FLOOR (2e-7 below).
        const FLOOR: f64 = 2e-2;
        let (mut worst_tree, mut worst_ref) = ((0.0f64, String::new()), (0.0f64, String::new()));
        let mut worst_abs = 0.0f64;
        let mut short = 0usize;
        for (i, sun) in suns().into_iter().enumerate() {
            for boxes in [0, 40, 400] {
                let scene = Scene::new(sun, &mut rng, boxes);
                let frame = &scene.frame;
                let shadow = scene.layer();
                let tree = MinMaxTree::build(frame, &shadow);
                let medium = HeightFog::new(Vec3::splat(0.5), sigma, Vec3::Y, 0.0, 0.0).unwrap();
                let fog = EpipolarFrame::medium(&medium, scene.view_from_world);
                for _ in 0..300 {
                    let (j, p) = scene.sample(&mut rng);
                    let depth0 = if rng.unit() < 0.5 {
                        0.0
                    } else {
                        rng.range(0.0, 30.0)
                    };
                    let depth1 = depth0 + rng.range(0.5, 150.0);
                    let map = slice_map(frame, j);
                    let r = ray(frame, map, p, depth0, depth1);
                    let by_tree = f64::from(march_tree(&tree, j, &fog, &r, None).x);
                    let by_steps =
                        f64::from(march_steps(&shadow, map, frame.depth_bias, &fog, &r, None).x);
                    let reference = algorithm_1(&shadow, map, &r, f64::from(sigma));
                    let full = 1.0 - (-f64::from(sigma) * r.segment.as_dvec3().length()).exp();
                    let scale = by_steps.abs().max(reference.abs()).max(FLOOR);
                    let e_tree = (by_tree - by_steps).abs() / scale;
                    let e_ref = (by_steps - reference).abs() / scale;
                    if e_tree > worst_tree.0 {
                        worst_tree = (
                            e_tree,
                            format!(
                                "sun {i} boxes {boxes}: tree {by_tree} steps {by_steps} ({r:?})"
                            ),
                        );
                    }
                    if e_ref > worst_ref.0 {
                        worst_ref = (
                            e_ref,
                            format!(
                                "sun {i} boxes {boxes}: steps {by_steps} f64 {reference} ({r:?})"
                            ),
                        );
                    }
                    worst_abs = worst_abs
                        .max((by_tree - reference).abs())
                        .max((by_steps - reference).abs());
                    assert!(by_tree >= -1e-6 && by_tree <= full + 1e-5);
                    rays += 1;
                    short += usize::from(r.end - r.start < 1.0);
                    if reference > 0.99 * full {
                        lit_some += 1;
                    } else {
                        dark_some += 1;
                    }
                }
            }
        }
        eprintln!(
            "{rays} rays ({lit_some} lit, {dark_some} shadowed, {short} under a texel): \
             tree {:e}, f64 {:e}, abs {worst_abs:e}",
            worst_tree.0, worst_ref.0
        );
        assert!(worst_tree.0 < 1e-5, "{}", worst_tree.1);
        assert!(worst_ref.0 < 1e-5, "{}", worst_ref.1);
        assert!(lit_some > 500 && dark_some > 500, "{lit_some} {dark_some}");
        assert!(short > 20, "{short}");
    }

    #[test]
    fn unshadowed_march_is_the_closed_form() {
        let mut rng = Rng(5);
        let mut checked = 0;
        for sun in suns() {
            let scene = Scene::new(sun, &mut rng, 0);
            let frame = &scene.frame;
            let shadow = scene.layer();
            let tree = MinMaxTree::build(frame, &shadow);
            // Uniform fog and a height fog (view space) against their closed forms.
            let uniform = HeightFog::new(Vec3::ONE, 0.02, Vec3::Y, 0.0, 0.0).unwrap();
            let layered = HeightFog::new(Vec3::ONE, 0.05, Vec3::Y, 0.08, 2.0).unwrap();
            for medium in [uniform, layered] {
                let fog = EpipolarFrame::medium(&medium, scene.view_from_world);
                for _ in 0..200 {
                    let (j, p) = scene.sample(&mut rng);
                    let depth0 = if rng.unit() < 0.5 {
                        0.0
                    } else {
                        rng.range(0.0, 20.0)
                    };
                    let depth1 = depth0 + rng.range(0.5, 140.0);
                    let map = slice_map(frame, j);
                    let r = ray(frame, map, p, depth0, depth1);
                    assert!(
                        r.light_start.max(r.light_end) < 1.0
                            && r.light_start.min(r.light_end) > 0.0
                    );
                    // Closed form in f64: b |d| exp(-c (h - h0)) (1 - exp(-x)) / x.
                    let dir = view_ray(frame.view_from_clip, p).as_dvec3();
                    let (z0, z1) = (f64::from(depth0), f64::from(depth1));
                    let (o, d) = (dir * z0, dir * (z1 - z0));
                    let up = fog.up.as_dvec3();
                    let (b, c) = (f64::from(fog.density), f64::from(fog.falloff));
                    let x = c * d.dot(up);
                    let mean = if x.abs() < 1e-9 {
                        1.0
                    } else {
                        -(-x).exp_m1() / x
                    };
                    let od = b
                        * d.length()
                        * (-c * (o.dot(up) - f64::from(fog.base_height))).exp()
                        * mean;
                    let want = -(-od).exp_m1();
                    let by_tree = f64::from(march_tree(&tree, j, &fog, &r, None).x);
                    let by_steps =
                        f64::from(march_steps(&shadow, map, frame.depth_bias, &fog, &r, None).x);
                    // march_pixel gives the lit fraction: 1 without shadows.
                    let by_pixel = want
                        * f64::from(
                            march_pixel((&shadow, None), frame, &fog, p, (depth0, depth1), 64).x,
                        );
                    for (name, got) in [("tree", by_tree), ("steps", by_steps), ("pixel", by_pixel)]
                    {
                        assert!(
                            (got - want).abs() < 1e-5 * want.max(1.0),
                            "{name}: {got} against {want} ({r:?})"
                        );
                    }
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 2000);
    }
}
