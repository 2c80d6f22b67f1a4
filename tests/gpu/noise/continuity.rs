//! The noise's smoothness: continuity across cells and periods within its slope bound,
//! and the gradient at lattice points against the gradient table of Green 2005.

use super::{Rng, eval_gpu, reference};
use crate::common::gpu;
use glam::Vec3;

/// The 16 gradients indexed by hash & 15, written out as in Green 2005 (GPU Gems 2,
/// ch. 26): the 12 cube edges, then (1,1,0), (0,-1,1), (-1,1,0), (0,-1,-1) again.
const GREEN_GRADIENTS: [[f32; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, -1.0],
];

/// Bound of |dn/dx_i| for perlin_noise: the fade derivative is at most 30/16 and
/// multiplies a difference of two corner terms of at most 2 each, and the blended
/// gradients add at most 1: 1.875 * 4 + 1. For noise_fbm, octave k adds
/// 0.5^k * 2^k times this, so m octaves give m * 8.5 / sum(0.5^k).
const AXIS_SLOPE_BOUND: f32 = 8.5;

fn fbm_slope_bound(octaves: u32) -> f32 {
    let total: f32 = (0..octaves).map(|k| 0.5f32.powi(k as i32)).sum();
    AXIS_SLOPE_BOUND * octaves as f32 / total
}

#[test]
fn noise_is_continuous_across_cells_and_periods() {
    let gpu = gpu();
    let mut rng = Rng(23);
    let h = 1e-4f32;
    // Pairs (a, b) straddling a face, an edge or a corner of a cell: the crossing
    // coordinates are an integer -+ h/2, the others random. Faces at period
    // boundaries (multiples of 256) check the wrap of the permutation.
    let mut pairs: Vec<(Vec3, Vec3, u32)> = Vec::new();
    for i in 0..60_000 {
        let span = if i % 3 == 0 { 40 } else { 600 };
        let mut cell = Vec3::new(
            rng.int(-span, span) as f32,
            rng.int(-span, span) as f32,
            rng.int(-span, span) as f32,
        );
        if i % 10 == 0 {
            cell.x = 256.0 * rng.int(-2, 2) as f32;
        }
        let crossing = rng.int(1, 7) as usize; // bit mask of crossed axes
        let mut a = cell + rng.vec(0.0, 1.0);
        let mut b = a;
        for axis in 0..3 {
            if crossing & (1 << axis) != 0 {
                a[axis] = cell[axis] - 0.5 * h;
                b[axis] = cell[axis] + 0.5 * h;
                assert!(a[axis] < cell[axis] && cell[axis] < b[axis]);
            }
        }
        pairs.push((a, b, 1 + (i % 4) as u32));
    }
    let items: Vec<(Vec3, u32)> = pairs
        .iter()
        .flat_map(|&(a, b, o)| [(a, o), (b, o)])
        .collect();
    let out = eval_gpu(gpu, &items);
    let mut worst_ratio = [0.0f32; 4];
    let mut worst_jump = 0.0f32;
    for (k, &(a, b, o)) in pairs.iter().enumerate() {
        let (na, fa) = out[2 * k];
        let (nb, fb) = out[2 * k + 1];
        // The actual f32 displacement, summed over axes (the bound is per axis).
        let d = (b - a).abs();
        let dist = d.x + d.y + d.z;
        let slack = 1e-5;
        assert!(
            (nb - na).abs() <= AXIS_SLOPE_BOUND * dist + slack,
            "perlin_noise jumps across a cell: {a} -> {b}: {na} -> {nb}"
        );
        assert!(
            (fb - fa).abs() <= fbm_slope_bound(o) * dist + slack,
            "noise_fbm({o}) jumps across a cell: {a} -> {b}: {fa} -> {fb}"
        );
        worst_ratio[0] = worst_ratio[0].max((nb - na).abs() / dist);
        worst_ratio[o as usize - 1] = worst_ratio[o as usize - 1].max((fb - fa).abs() / dist);
        worst_jump = worst_jump.max((nb - na).abs()).max((fb - fa).abs());
    }
    eprintln!(
        "continuity: {} pairs {h:e} apart per crossed axis; largest |difference| {worst_jump:e}; \
         largest |difference| / distance by octaves 1..=4: {worst_ratio:?} (bounds {:?})",
        pairs.len(),
        (1..=4).map(fbm_slope_bound).collect::<Vec<_>>()
    );
}

#[test]
fn noise_gradient_on_lattice_is_the_selected_edge_gradient() {
    let gpu = gpu();
    let mut rng = Rng(53);
    // Central differences at lattice points P with a step h = 2^-10 (P +- h exact).
    // Near P the noise is g_P . (x - P) plus terms of order fade(h) ~ 10 h^3 from the
    // other corners, so the difference quotient is g_P within ~20 h^2 = 2e-5.
    let h = 1.0f32 / 1024.0;
    let mut lattice = Vec::new();
    for i in 0..3000 {
        let span = if i % 2 == 0 { 300 } else { 4000 };
        lattice.push((
            rng.int(-span, span),
            rng.int(-span, span),
            rng.int(-span, span),
        ));
    }
    let mut items = Vec::new();
    for &(x, y, z) in &lattice {
        let p = Vec3::new(x as f32, y as f32, z as f32);
        for axis in 0..3 {
            let mut e = Vec3::ZERO;
            e[axis] = h;
            items.push((p + e, 1));
            items.push((p - e, 1));
        }
    }
    let out = eval_gpu(gpu, &items);
    let mut worst = 0.0f32;
    let mut used = [false; 16];
    for (k, &(x, y, z)) in lattice.iter().enumerate() {
        let hash = reference::corner_hash(x as i64, y as i64, z as i64) & 15;
        used[hash] = true;
        let g = GREEN_GRADIENTS[hash];
        for axis in 0..3 {
            let plus = out[6 * k + 2 * axis].0;
            let minus = out[6 * k + 2 * axis + 1].0;
            let d = (plus - minus) / (2.0 * h);
            worst = worst.max((d - g[axis]).abs());
            assert!(
                (d - g[axis]).abs() <= 1e-4,
                "d noise / d x{axis} at ({x}, {y}, {z}) = {d}, gradient {g:?} (hash {hash})"
            );
        }
    }
    assert!(used.iter().all(|&u| u), "every gradient case was exercised");
    eprintln!(
        "lattice gradients: {} points, all 16 hash cases; |central difference - Green's \
         gradient| <= {worst:e} (bound 1e-4)",
        lattice.len()
    );
}
