//! The march of a view ray through its slice: transmittance, lit tests, the shaft term
//! by steps, by the min/max tree and by brute force per pixel.

use glam::{Vec2, Vec3, Vec3Swizzles, Vec4};

use super::height_map::{
    ColorLayer, EpipolarRay, ShadowLayer, color, height, light_texel, view_ray,
};
use super::tree::MinMaxTree;
use super::{LIT_DEPTH, mix};
use crate::cpu::height_fog::{height_fog_lit_integral, height_fog_optical_depth_below};
use crate::uniforms::{EpipolarFrame, HeightFog};

/// Transmittance of the medium `fog` (view space, below its top) from the start of
/// `ray` to the fraction `t` of it; mirror of `volfog::epipolar::epipolar_transmittance`.
pub fn transmittance(fog: &HeightFog, ray: &EpipolarRay, t: f32) -> f32 {
    (-height_fog_optical_depth_below(
        fog.density,
        fog.falloff,
        fog.base_height,
        fog.up,
        fog.top_height,
        ray.origin,
        ray.segment * t,
    ))
    .exp()
}

/// The share (dimensionless, per unit of the phase term) of the lit part `[ta, tb]`
/// (fractions) of `ray` in the shaft term, given the transmittances `t_at_a` = T(ta)
/// and `t_at_b` = T(tb) from its start: `T(ta) - T(tb)`, the integral of `sigma T`
/// over the part, or with `fog.sun_transmittance` the integral of `sigma T T_sun`,
/// `T(ta)` times [`height_fog_lit_integral`] of the part
/// (`exp(-min(F(ta), F(tb))) tau E(|r| tau)`, `F = tau_view + tau_light`); mirror of
/// `volfog::epipolar::epipolar_lit_section`.
pub fn lit_section(
    fog: &HeightFog,
    ray: &EpipolarRay,
    (ta, tb): (f32, f32),
    t_at_a: f32,
    t_at_b: f32,
) -> f32 {
    if fog.sun_transmittance != 0 {
        return t_at_a
            * height_fog_lit_integral(
                fog.density,
                fog.falloff,
                fog.base_height,
                fog.up,
                fog.top_height,
                ray.origin + ray.segment * ta,
                ray.segment * (tb - ta),
                fog.sun_direction,
            );
    }
    t_at_a - t_at_b
}

/// `S_open`, the shaft term of `ray` with nothing shadowing it: `1 - T(1)`, or with
/// `fog.sun_transmittance` the closed-form light of the sun the ray scatters; mirror of
/// `volfog::epipolar::epipolar_lit_open`.
pub fn lit_open(fog: &HeightFog, ray: &EpipolarRay) -> f32 {
    lit_section(fog, ray, (0.0, 1.0), 1.0, transmittance(fog, ray, 1.0))
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

/// Shaft term S (dimensionless: the sum of [`lit_section`] over the lit sections) of
/// `ray` visiting every section of the height map `map` read from `shadow` (Yusov 2012,
/// Algorithm 1); mirror of
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
            c * lit_open(fog, ray)
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
            sum += color(colors, map, k) * lit_section(fog, ray, (ta, tb), t_at_a, t_at_b);
        }
        ta = tb;
        t_at_a = t_at_b;
        k += 1;
    }
    // Beyond the map everything is lit, in white.
    sum + Vec3::splat(lit_section(
        fog,
        ray,
        (ta, 1.0),
        t_at_a,
        transmittance(fog, ray, 1.0),
    ))
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
            c * lit_open(fog, ray)
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
                    * lit_section(
                        fog,
                        ray,
                        (ta, tb),
                        transmittance(fog, ray, ta),
                        transmittance(fog, ray, tb),
                    );
            }
        } else if is_lit && !open {
            lit_from = ta;
            open = true;
        } else if !is_lit && open {
            sum += Vec3::splat(lit_section(
                fog,
                ray,
                (lit_from, ta),
                transmittance(fog, ray, lit_from),
                transmittance(fog, ray, ta),
            ));
            open = false;
        }
        ta = tb;
        k += 1u32 << level;
    }
    // Beyond the map everything is lit (in white): the remainder joins an open run.
    if !open {
        lit_from = ta;
    }
    sum + Vec3::splat(lit_section(
        fog,
        ray,
        (lit_from, 1.0),
        transmittance(fog, ray, lit_from),
        transmittance(fog, ray, 1.0),
    ))
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
            sum += c * lit_section(fog, &ray, (ta, tb), t_at_a, t_at_b);
        }
        t_at_a = t_at_b;
    }
    lit_fraction(fog, &ray, sum)
}

/// The lit fraction F = S / S_open ([`lit_open`]) of a ray's shaft term `s`, in
/// [0, 1]; 1 when the ray absorbs almost nothing (1 - T <= 1e-6) or the sun reaches
/// none of it; mirror of `volfog::epipolar::epipolar_lit_fraction`.
pub fn lit_fraction(fog: &HeightFog, ray: &EpipolarRay, s: Vec3) -> Vec3 {
    let absorbed = 1.0 - transmittance(fog, ray, 1.0);
    let open = lit_open(fog, ray);
    if absorbed <= 1e-6 || open <= 0.0 {
        return Vec3::ONE;
    }
    (s / open).clamp(Vec3::ZERO, Vec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::epipolar::test_scene::{Scene, suns};
    use crate::cpu::epipolar::{ray, slice_map};

    /// Algorithm 1 in f64: the sum over the sections of the height map (lit when the
    /// light depth at the middle is not behind h) of `share(a, b)`, the part beyond the
    /// map lit.
    fn algorithm_1(
        shadow: &ShadowLayer,
        map: Vec4,
        ray: &EpipolarRay,
        share: &dyn Fn(f64, f64) -> f64,
    ) -> f64 {
        let size = f64::from(shadow.size);
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
                share(0.0, 1.0)
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
                sum += share(ta, tb);
            }
            k += 1.0;
        }
        sum + share(stop, 1.0)
    }

    /// The share of the part `[ta, tb]` of `ray` in f64 for uniform fog (extinction
    /// `fog.density`, 1/m, below `fog.top_height`, view space): without sun
    /// transmittance T(ta) - T(tb); with it the integral of sigma T T_sun in closed form,
    /// independent of the f32 code: below the top F(t) = tau_view(0..t) + sigma (top -
    /// h(t)) / mu grows linearly, dF/dt = sigma L (1 - v / mu), so the integral over
    /// [a, b] is sigma L exp(-F(a)) (b - a) E(F'(b - a)), E(x) = -expm1(-x) / x.
    fn uniform_share(fog: &HeightFog, ray: &EpipolarRay, ta: f64, tb: f64) -> f64 {
        let sigma = f64::from(fog.density);
        let up = fog.up.as_dvec3();
        let (o, d) = (ray.origin.as_dvec3(), ray.segment.as_dvec3());
        let length = d.length();
        let top = f64::from(fog.top_height);
        let (h0, dh) = (o.dot(up), d.dot(up));
        // [t0, t1]: the part of [0, 1] below the top.
        let (t0, t1) = if dh == 0.0 {
            if h0 <= top { (0.0, 1.0) } else { (0.0, 0.0) }
        } else if dh > 0.0 {
            (0.0, ((top - h0) / dh).clamp(0.0, 1.0))
        } else {
            (((top - h0) / dh).clamp(0.0, 1.0), 1.0)
        };
        let below = |t: f64| (t.min(t1) - t0).max(0.0);
        let t_at = |t: f64| (-sigma * length * below(t)).exp();
        if fog.sun_transmittance == 0 {
            return t_at(ta) - t_at(tb);
        }
        let mu = fog.sun_direction.as_dvec3().dot(up);
        let (a, b) = (ta.max(t0), tb.min(t1));
        if b <= a || mu <= 0.0 {
            return 0.0;
        }
        let f_a = sigma * length * below(a) + sigma * (top - (h0 + a * dh)) / mu;
        let x = sigma * length * (1.0 - dh / length / mu) * (b - a);
        let mean = if x == 0.0 { 1.0 } else { -(-x).exp_m1() / x };
        sigma * length * (-f_a).exp() * (b - a) * mean
    }

    #[test]
    fn tree_march_equals_steps_and_algorithm_1() {
        // Uniform fog without the sun's transmittance (S = sum of T(a) - T(b)), and with
        // it, ending 15 m above the ground (10 m above the camera) so rays cross the top.
        for transmittance in [false, true] {
            let medium = HeightFog::new(Vec3::splat(0.5), 0.02, Vec3::Y, 0.0, 0.0).unwrap();
            let medium = if transmittance {
                medium.with_top(15.0).unwrap().with_sun_transmittance(true)
            } else {
                medium
            };
            tree_march_case(medium);
        }
    }

    fn tree_march_case(medium: HeightFog) {
        let mut rng = Rng(4);
        let on = medium.sun_transmittance != 0;
        let (mut rays, mut lit_some, mut dark_some) = (0, 0, 0);
        // S is a sum of differences of f32 transmittances (without sun transmittance) or
        // of f32 closed forms: its error is absolute (a few 1e-8), so the relative
        // tolerance applies to S >= FLOOR (2e-7 below).
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
                let fog = EpipolarFrame::medium(
                    &HeightFog {
                        sun_direction: sun,
                        ..medium
                    },
                    scene.view_from_world,
                );
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
                    let share = |a: f64, b: f64| uniform_share(&fog, &r, a, b);
                    let reference = algorithm_1(&shadow, map, &r, &share);
                    let full = share(0.0, 1.0);
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
            "sun transmittance {on}: {rays} rays ({lit_some} lit, {dark_some} shadowed, {short} \
             under a texel): tree vs steps {:e}, steps vs f64 algorithm 1 {:e} relative \
             (bound 1e-5 of max(S, 2e-2)), abs {worst_abs:e}",
            worst_tree.0, worst_ref.0
        );
        assert!(worst_tree.0 < 1e-5, "{}", worst_tree.1);
        assert!(worst_ref.0 < 1e-5, "{}", worst_ref.1);
        assert!(lit_some > 500 && dark_some > 500, "{lit_some} {dark_some}");
        assert!(short > 20, "{short}");
    }

    /// The light of the sun scattered along `ray` with nothing shadowing it, by a
    /// 20k-step midpoint rule in f64 over the part below the top: the integral of
    /// sigma(t) exp(-tau_view(t)) exp(-tau_light(t)) dt, tau_view accumulated by the
    /// same steps (its value at a midpoint from the half step before it, second order)
    /// and tau_light(h) from the analytic formulas: sigma (top - h) / mu for uniform fog
    /// (c = 0) under a top, sigma(h) / (c mu) for exponential fog without one.
    fn numeric_open(fog: &HeightFog, ray: &EpipolarRay) -> f64 {
        const STEPS: usize = 20_000;
        let up = fog.up.as_dvec3();
        let (o, d) = (ray.origin.as_dvec3(), ray.segment.as_dvec3());
        let length = d.length();
        let (b, c, h0) = (
            f64::from(fog.density),
            f64::from(fog.falloff),
            f64::from(fog.base_height),
        );
        let top = f64::from(fog.top_height);
        let mu = fog.sun_direction.as_dvec3().dot(up);
        let sigma = |h: f64| b * (-c * (h - h0)).exp();
        let tau_light = |h: f64| {
            if c == 0.0 {
                sigma(h) * (top - h) / mu
            } else {
                sigma(h) / (c * mu)
            }
        };
        let (hs, dh) = (o.dot(up), d.dot(up));
        let (t0, t1) = if dh == 0.0 {
            if hs <= top { (0.0, 1.0) } else { (0.0, 0.0) }
        } else if dh > 0.0 {
            (0.0, ((top - hs) / dh).clamp(0.0, 1.0))
        } else {
            (((top - hs) / dh).clamp(0.0, 1.0), 1.0)
        };
        let dt = (t1 - t0) / STEPS as f64;
        let ds = dt * length;
        let (mut tau, mut sum) = (0.0f64, 0.0f64);
        for i in 0..STEPS {
            let t = t0 + (i as f64 + 0.5) * dt;
            let h = hs + t * dh;
            let tau_mid = tau + sigma(hs + (t - 0.25 * dt) * dh) * 0.5 * ds;
            sum += sigma(h) * (-tau_mid - tau_light(h)).exp() * ds;
            tau += sigma(h) * ds;
        }
        sum
    }

    #[test]
    fn unshadowed_march_with_sun_transmittance_is_the_numerical_integral() {
        let mut rng = Rng(6);
        // Uniform fog 20 m deep (the camera 5 m up) and an exponential fog without a
        // top, under the test suns and one 2.9 degrees above the horizon.
        let uniform = HeightFog::new(Vec3::ONE, 0.02, Vec3::Y, 0.0, 0.0)
            .unwrap()
            .with_top(20.0)
            .unwrap();
        let layered = HeightFog::new(Vec3::ONE, 0.05, Vec3::Y, 0.08, 2.0).unwrap();
        let mut all = suns();
        all.push(Vec3::new(0.3, 0.05, -0.95).normalize());
        let (mut worst, mut worst_fraction, mut worst_fog) = (0.0f64, 0.0f32, 0.0f32);
        let mut checked = 0;
        for sun in all {
            let scene = Scene::new(sun, &mut rng, 0);
            let frame = &scene.frame;
            let shadow = scene.layer();
            let tree = MinMaxTree::build(frame, &shadow);
            for medium in [uniform, layered] {
                // No constant colour: the composed fog is the sun's light alone.
                let world = HeightFog {
                    color: Vec3::ZERO,
                    ..medium
                }
                .with_sun(sun, Vec3::new(2.0, 1.8, 1.5), 0.5)
                .unwrap()
                .with_sun_transmittance(true);
                let fog = EpipolarFrame::medium(&world, scene.view_from_world);
                for _ in 0..100 {
                    let (j, p) = scene.sample(&mut rng);
                    let depth0 = if rng.unit() < 0.5 {
                        0.0
                    } else {
                        rng.range(0.0, 20.0)
                    };
                    let depth1 = depth0 + rng.range(0.5, 140.0);
                    let map = slice_map(frame, j);
                    let r = ray(frame, map, p, depth0, depth1);
                    let want = numeric_open(&fog, &r);
                    let by_tree = f64::from(march_tree(&tree, j, &fog, &r, None).x);
                    let by_steps =
                        f64::from(march_steps(&shadow, map, frame.depth_bias, &fog, &r, None).x);
                    let open = f64::from(lit_open(&fog, &r));
                    for (name, got) in [("tree", by_tree), ("steps", by_steps), ("open", open)] {
                        let e = (got - want).abs() / want.max(1e-30);
                        worst = worst.max(e);
                        assert!(
                            (got - want).abs() <= 1e-4 * want + 1e-12,
                            "{name}: {got} against {want} (sun {sun}, {fog:?}, {r:?})"
                        );
                    }
                    // Nothing shadows: F = 1 in every march, and the fog the passes
                    // compose from it carries the sun's light P * S exactly.
                    let pixel =
                        march_pixel((&shadow, None), frame, &fog, p, (depth0, depth1), 64).x;
                    let fraction = lit_fraction(&fog, &r, Vec3::splat(by_steps as f32)).x;
                    worst_fraction = worst_fraction
                        .max((fraction - 1.0).abs())
                        .max((pixel - 1.0).abs());
                    let view_pos = r.origin + r.segment;
                    if r.segment.length() > 0.0 && depth0 == 0.0 {
                        let lit = super::super::resolve::fog(
                            &EpipolarFrame {
                                start_depth: 0.0,
                                max_depth: 1e4,
                                ..*frame
                            },
                            &fog,
                            view_pos,
                            Vec3::ONE,
                        );
                        let p_term =
                            super::super::resolve::phase(frame, &fog, r.segment.normalize());
                        let sun_light = lit.truncate();
                        let want_light = p_term * by_steps as f32;
                        worst_fog = worst_fog.max(
                            ((sun_light - want_light).abs() / want_light.max(Vec3::splat(1e-12)))
                                .max_element(),
                        );
                    }
                    checked += 1;
                }
            }
        }
        eprintln!(
            "{checked} unshadowed rays with the sun's transmittance: tree, steps and S_open \
             vs the f64 20k-step integral worst {worst:.2e} relative (bound 1e-4); lit \
             fraction vs 1 worst {worst_fraction:.2e} (bound 1e-5); the composed sun light \
             vs P S worst {worst_fog:.2e} relative (bound 1e-4)"
        );
        assert_eq!(checked, 1200);
        assert!(worst_fraction <= 1e-5, "{worst_fraction}");
        assert!(worst_fog <= 1e-4, "{worst_fog}");
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
