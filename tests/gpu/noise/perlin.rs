//! perlin_noise and noise_fbm against the CPU mirror and Perlin's f64 reference, their
//! range, and their zeros on the lattice.

use super::{Rng, eval_gpu, reference};
use crate::common::gpu;
use glam::Vec3;
use volfog::cpu::noise::{noise_fbm, perlin_noise};

/// A point of the reference noise where it overshoots [-1, 1] most (|n| = 1.03635,
/// cell (12, 187, 5), found by searching every cell of a period).
const OVERSHOOT: [f32; 3] = [12.355_257, 187.518_51, 5.5];

/// Test points: random, negative, large, on lattice points, on and next to cell faces
/// and period boundaries.
fn mirror_points() -> Vec<Vec3> {
    let mut rng = Rng(7);
    let mut pts = Vec::new();
    for _ in 0..4000 {
        pts.push(rng.vec(-300.0, 300.0));
    }
    for _ in 0..1000 {
        pts.push(rng.vec(-4.0, 4.0));
    }
    for scale in [1.0e3f32, 1.0e4, 6.5536e4, 1.0e5] {
        for _ in 0..500 {
            pts.push(rng.vec(-scale, scale));
        }
    }
    for _ in 0..500 {
        let base = Vec3::new(
            rng.int(-600, 600) as f32,
            rng.int(-600, 600) as f32,
            rng.int(-600, 600) as f32,
        );
        pts.push(base);
        // On one, two or three cell faces, and just either side of them.
        let axis = rng.int(0, 2) as usize;
        let mut on_face = base + rng.vec(0.0, 1.0);
        on_face[axis] = base[axis];
        pts.push(on_face);
        for d in [-1e-3f32, 1e-3, -2.0e-5, 2.0e-5] {
            let mut q = on_face;
            q[axis] += d;
            pts.push(q);
            pts.push(base + Vec3::splat(d));
        }
    }
    for k in [-512.0f32, -256.0, -1.0, 0.0, 255.0, 256.0, 512.0, 65536.0] {
        for _ in 0..20 {
            let mut q = rng.vec(-3.0, 3.0);
            q.x = k + rng.range(-1e-3, 1e-3);
            pts.push(q);
        }
    }
    pts.push(Vec3::from(OVERSHOOT));
    pts.push(-Vec3::from(OVERSHOOT));
    pts
}

#[test]
// (3.14, 42, 7) is the point of Perlin's published check value, not an approximation of pi.
#[allow(clippy::approx_constant)]
fn noise_matches_cpu_mirror_and_reference() {
    let gpu = gpu();
    let pts = mirror_points();
    // Octaves 0 and 9 check the clamping to 1..=8.
    let octaves = [0u32, 1, 2, 3, 4, 8, 9];
    let items: Vec<(Vec3, u32)> = octaves
        .iter()
        .flat_map(|&o| pts.iter().map(move |&p| (p, o)))
        .collect();
    let out = eval_gpu(gpu, &items);
    let tol = 1e-5f32;
    let mut worst_mirror = [0.0f32; 7];
    let mut worst_noise = 0.0f32;
    let mut worst_ref = 0.0f64;
    for (k, (&(p, o), &(n, f))) in items.iter().zip(&out).enumerate() {
        let e = (f - noise_fbm(p, o)).abs();
        let slot = octaves.iter().position(|&x| x == o).unwrap();
        worst_mirror[slot] = worst_mirror[slot].max(e);
        assert!(
            e <= tol,
            "noise_fbm({p}, {o}): gpu {f} cpu {}",
            noise_fbm(p, o)
        );
        if k < pts.len() {
            let e = (n - perlin_noise(p)).abs();
            worst_noise = worst_noise.max(e);
            assert!(
                e <= tol,
                "perlin_noise({p}): gpu {n} cpu {}",
                perlin_noise(p)
            );
            // The f32 input is exact in f64: the reference sees the same point.
            let want = reference::noise(p.x as f64, p.y as f64, p.z as f64).clamp(-1.0, 1.0);
            let e = (n as f64 - want).abs();
            worst_ref = worst_ref.max(e);
            assert!(
                e <= tol as f64,
                "perlin_noise({p}): gpu {n} reference {want}"
            );
        }
    }
    // Clamping of the octave count: 0 acts as 1 and 9 as 8.
    for (i, _) in pts.iter().enumerate() {
        assert_eq!(out[i].1, out[pts.len() + i].1, "octaves 0 vs 1");
        assert_eq!(
            out[6 * pts.len() + i].1,
            out[5 * pts.len() + i].1,
            "octaves 9 vs 8"
        );
    }
    // Perlin's published value at (3.14, 42, 7); the GPU sees 3.14 rounded to f32.
    let anchor = reference::noise(3.14, 42.0, 7.0);
    assert!((anchor - 0.136_919_958_784).abs() < 1e-12);
    let g = eval_gpu(gpu, &[(Vec3::new(3.14, 42.0, 7.0), 1)])[0].0;
    assert!((g as f64 - anchor).abs() < 2e-6, "gpu {g}");
    eprintln!(
        "noise: {} points; perlin_noise |gpu - cpu| <= {worst_noise:e}, |gpu - f64 reference| \
         <= {worst_ref:e}; noise_fbm |gpu - cpu| by octaves {octaves:?}: {worst_mirror:?} \
         (bound {tol:e}); at (3.14, 42, 7): gpu {g}, reference {anchor}",
        pts.len()
    );
}

#[test]
fn noise_stays_in_range_and_vanishes_on_lattice() {
    let gpu = gpu();
    let mut rng = Rng(11);
    let n = 1 << 18;
    let mut items: Vec<(Vec3, u32)> = (0..n)
        .map(|i| (rng.vec(-512.0, 512.0), 1 + (i % 4) as u32))
        .collect();
    // Around the largest overshoot of the unclamped reference, on both signs.
    for _ in 0..4096 {
        let d = rng.vec(-0.05, 0.05);
        items.push((Vec3::from(OVERSHOOT) + d, 1));
        items.push((-Vec3::from(OVERSHOOT) - d, 1));
    }
    let out = eval_gpu(gpu, &items);
    // Extremes over the random samples only (the overshoot spot sits at +-1).
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    let (mut flo, mut fhi) = (f32::MAX, f32::MIN);
    for (k, (&(p, o), &(v, f))) in items.iter().zip(&out).enumerate() {
        assert!(
            v.is_finite() && (-1.0..=1.0).contains(&v),
            "perlin_noise({p}) = {v}"
        );
        assert!(
            f.is_finite() && (-1.0..=1.0).contains(&f),
            "noise_fbm({p}, {o}) = {f}"
        );
        if k < n {
            lo = lo.min(v);
            hi = hi.max(v);
            flo = flo.min(f);
            fhi = fhi.max(f);
        }
    }
    let peak = reference::noise(
        OVERSHOOT[0] as f64,
        OVERSHOOT[1] as f64,
        OVERSHOOT[2] as f64,
    );
    assert!(peak.abs() > 1.03, "the reference overshoots there: {peak}");
    let at_peak = eval_gpu(gpu, &[(Vec3::from(OVERSHOOT), 1)])[0].0;
    assert_eq!(at_peak, peak.signum() as f32);

    // Integer points, small to large, for 1..=8 octaves.
    let mut lattice = Vec::new();
    for i in 0..8192 {
        let span = [4, 300, 40_000, 1_000_000][i % 4];
        let q = Vec3::new(
            rng.int(-span, span) as f32,
            rng.int(-span, span) as f32,
            rng.int(-span, span) as f32,
        );
        lattice.push((q, 1 + (i % 8) as u32));
    }
    let zeros = eval_gpu(gpu, &lattice);
    let mut worst = 0.0f32;
    for (&(p, o), &(v, f)) in lattice.iter().zip(&zeros) {
        worst = worst.max(v.abs()).max(f.abs());
        assert!(
            v.abs() <= 1e-7 && f.abs() <= 1e-7,
            "at lattice point {p}: {v}, fbm({o}) {f}"
        );
    }
    eprintln!(
        "range: {} samples in [-1, 1]; over the {n} random ones perlin_noise spans \
         [{lo}, {hi}] and noise_fbm (1..=4 octaves) [{flo}, {fhi}]; at the reference's \
         overshoot {peak:.6} the gpu gives {at_peak}; {} lattice points: max |value| \
         {worst:e} (bound 1e-7)",
        items.len(),
        lattice.len()
    );
}
