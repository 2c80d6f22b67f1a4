//! Improved Perlin noise on the GPU: against the CPU mirror and against an f64 port
//! of Perlin's reference implementation, its range, zeros on the lattice, continuity
//! across cells and periods, statistics, the wind animation, the gradient on the
//! lattice against the explicit gradient table of Green 2005, the baked noise texture
//! and its sampled fractal sum against the CPU bake, and the translation of kernels
//! using them to every target.

use crate::common;

use common::{gpu, run_f32};
use glam::Vec3;
use volfog::cpu::inject::DensityTexture;
use volfog::cpu::noise::{
    NOISE_TEXTURE_SIZE, bake_noise_texture, noise_animated, noise_animated_texture, noise_fbm,
    noise_fbm_texture, perlin_noise, perlin_noise_tiled,
};
use volfog::pipeline::noise::{NOISE_TEXTURE_BYTES, NoiseBake, noise_sampler};
use volfog_testkit::Gpu;

/// perlin_noise and noise_fbm per point: input (x, y, z, octaves), two outputs.
const EVAL_KERNEL: &str = r#"
#import volfog::noise::{perlin_noise, noise_fbm}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let p = input[i].xyz;
    output[2u * i] = perlin_noise(p);
    output[2u * i + 1u] = noise_fbm(p, u32(input[i].w));
}
"#;

/// noise_animated and noise_fbm of the advected point, per item: input (p, scale),
/// (wind, time), (octaves, 0, 0, 0); two outputs.
const ANIM_KERNEL: &str = r#"
#import volfog::noise::{noise_fbm, noise_animated}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if 3u * i >= arrayLength(&input) { return; }
    let p = input[3u * i].xyz;
    let scale = input[3u * i].w;
    let wind = input[3u * i + 1u].xyz;
    let time = input[3u * i + 1u].w;
    let octaves = u32(input[3u * i + 2u].x);
    output[2u * i] = noise_animated(p, scale, wind, time, octaves);
    output[2u * i + 1u] = noise_fbm((p - wind * time) * scale, octaves);
}
"#;

/// perlin_noise_tiled, noise_fbm_texture and noise_animated_texture per point: input
/// (x, y, z, octaves), three outputs; the noise texture and its sampler at bindings 2
/// and 3. The animation uses the wind (2, -0.5, 1.25) m/s, time 3 s and scale 0.5 / m
/// (dyadic: the advected point is exact in f32).
const TEXTURE_KERNEL: &str = r#"
#import volfog::noise::{perlin_noise_tiled, noise_fbm_texture, noise_animated_texture, NOISE_TEXTURE_PERIOD}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;
@group(0) @binding(2) var noise_texture: texture_3d<f32>;
@group(0) @binding(3) var noise_sampler: sampler;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let p = input[i].xyz;
    let octaves = u32(input[i].w);
    output[3u * i] = perlin_noise_tiled(p, NOISE_TEXTURE_PERIOD);
    output[3u * i + 1u] = noise_fbm_texture(noise_texture, noise_sampler, p, octaves);
    output[3u * i + 2u] = noise_animated_texture(
        noise_texture, noise_sampler, p, 0.5, vec3<f32>(2.0, -0.5, 1.25), 3.0, octaves);
}
"#;

/// The wind, time and scale of TEXTURE_KERNEL's noise_animated_texture.
const TEXTURE_KERNEL_ANIMATION: (Vec3, f32, f32) = (Vec3::new(2.0, -0.5, 1.25), 3.0, 0.5);

/// Deterministic generator (splitmix64) for sample points.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    fn int(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1) as u64) as i32
    }
}

/// Runs EVAL_KERNEL: (perlin_noise(p), noise_fbm(p, octaves)) per point.
fn eval_gpu(gpu: &Gpu, points: &[(Vec3, u32)]) -> Vec<(f32, f32)> {
    let inputs: Vec<f32> = points
        .iter()
        .flat_map(|(p, o)| [p.x, p.y, p.z, *o as f32])
        .collect();
    let out = run_f32(
        gpu,
        EVAL_KERNEL,
        &inputs,
        2 * points.len(),
        points.len() as u32,
    );
    out.chunks(2).map(|c| (c[0], c[1])).collect()
}

/// Runs TEXTURE_KERNEL with `texture` (sampled with the runtime's noise sampler):
/// (perlin_noise_tiled(p, 16), noise_fbm_texture(p, octaves),
/// noise_animated_texture(p, ..., octaves)) per point.
fn eval_texture_gpu(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    points: &[(Vec3, u32)],
) -> Vec<(f32, f32, f32)> {
    let inputs: Vec<f32> = points
        .iter()
        .flat_map(|(p, o)| [p.x, p.y, p.z, *o as f32])
        .collect();
    let module = gpu.shader_from_naga("noise texture kernel", common::compose(TEXTURE_KERNEL, &[]));
    let view = texture.create_view(&Default::default());
    let sampler = noise_sampler(&gpu.device);
    let bytes = gpu
        .run_kernel_with(
            &module,
            "main",
            bytemuck::cast_slice(&inputs),
            (3 * 4 * points.len()) as u64,
            points.len() as u32,
            &[
                wgpu::BindingResource::TextureView(&view),
                wgpu::BindingResource::Sampler(&sampler),
            ],
        )
        .expect("kernel runs");
    let out: &[f32] = bytemuck::cast_slice(&bytes);
    out.chunks(3).map(|c| (c[0], c[1], c[2])).collect()
}

/// Bakes the noise texture on the GPU and reads it back: the texture and its red
/// channel as a CPU texture (x fastest).
fn baked_noise(gpu: &Gpu) -> (wgpu::Texture, Vec<glam::Vec4>) {
    let texture = NoiseBake::bake(&gpu.device, &gpu.queue).expect("the bake pass compiles");
    let texels = common::scene::read_volume(gpu, &texture);
    (texture, texels)
}

/// Perlin's reference implementation (his Java `ImprovedNoise`), ported in f64 with
/// its 512-entry table and its `grad()`, unclamped.
mod reference {
    const PERMUTATION: [usize; 256] = [
        151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
        69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
        252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171,
        168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60,
        211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1,
        216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86,
        164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118,
        126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170,
        213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39,
        253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34,
        242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49,
        192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254,
        138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
    ];

    /// p[i] for i in 0..512: the permutation twice.
    pub fn p(i: usize) -> usize {
        assert!(i < 512);
        PERMUTATION[if i < 256 { i } else { i - 256 }]
    }

    fn fade(t: f64) -> f64 {
        t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
    }

    fn lerp(t: f64, a: f64, b: f64) -> f64 {
        a + t * (b - a)
    }

    fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
        let h = hash & 15;
        let u = if h < 8 { x } else { y };
        let v = if h < 4 {
            y
        } else if h == 12 || h == 14 {
            x
        } else {
            z
        };
        (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
    }

    /// The corner hash of the lattice point (X, Y, Z) as the low corner of its cell.
    pub fn corner_hash(x: i64, y: i64, z: i64) -> usize {
        let (xi, yi, zi) = (
            x.rem_euclid(256) as usize,
            y.rem_euclid(256) as usize,
            z.rem_euclid(256) as usize,
        );
        p(p(p(xi) + yi) + zi)
    }

    pub fn noise(x: f64, y: f64, z: f64) -> f64 {
        let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
        let xi = (fx as i64).rem_euclid(256) as usize;
        let yi = (fy as i64).rem_euclid(256) as usize;
        let zi = (fz as i64).rem_euclid(256) as usize;
        let (x, y, z) = (x - fx, y - fy, z - fz);
        let (u, v, w) = (fade(x), fade(y), fade(z));
        let a = p(xi) + yi;
        let aa = p(a) + zi;
        let ab = p(a + 1) + zi;
        let b = p(xi + 1) + yi;
        let ba = p(b) + zi;
        let bb = p(b + 1) + zi;
        lerp(
            w,
            lerp(
                v,
                lerp(u, grad(p(aa), x, y, z), grad(p(ba), x - 1.0, y, z)),
                lerp(
                    u,
                    grad(p(ab), x, y - 1.0, z),
                    grad(p(bb), x - 1.0, y - 1.0, z),
                ),
            ),
            lerp(
                v,
                lerp(
                    u,
                    grad(p(aa + 1), x, y, z - 1.0),
                    grad(p(ba + 1), x - 1.0, y, z - 1.0),
                ),
                lerp(
                    u,
                    grad(p(ab + 1), x, y - 1.0, z - 1.0),
                    grad(p(bb + 1), x - 1.0, y - 1.0, z - 1.0),
                ),
            ),
        )
    }
}

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
fn noise_statistics_are_centred() {
    let gpu = gpu();
    let mut rng = Rng(31);
    let n = 1 << 18;
    // Points uniform over two full periods per axis, far apart compared with the
    // correlation length (1 lattice unit), so the samples are nearly independent.
    let pts: Vec<Vec3> = (0..n).map(|_| rng.vec(-256.0, 256.0)).collect();
    let mut report = Vec::new();
    for octaves in 1..=4u32 {
        let items: Vec<(Vec3, u32)> = pts.iter().map(|&p| (p, octaves)).collect();
        let out = eval_gpu(gpu, &items);
        let values: Vec<f64> = out.iter().map(|&(_, f)| f as f64).collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let std = var.sqrt();
        let positive = values.iter().filter(|&&v| v > 0.0).count() as f64 / n as f64;
        // Standard error of the mean is std / sqrt(n) ~ 4e-4: the bound is ~7 of them.
        assert!(mean.abs() < 3e-3, "octaves {octaves}: mean {mean}");
        assert!(
            (0.15..0.3).contains(&std),
            "octaves {octaves}: standard deviation {std}"
        );
        assert!(
            (positive - 0.5).abs() < 5e-3,
            "octaves {octaves}: fraction positive {positive}"
        );
        report.push(format!(
            "{octaves} octave(s): mean {mean:+.2e}, std {std:.4}, positive {positive:.4}"
        ));
    }
    eprintln!(
        "statistics over {n} points (|mean| < 3e-3, std in [0.15, 0.3], positive 0.5 +- 5e-3): {}",
        report.join("; ")
    );
}

#[test]
fn animated_noise_is_advected_fbm() {
    let gpu = gpu();
    let mut rng = Rng(41);
    let mut inputs: Vec<f32> = Vec::new();
    let mut cases = Vec::new();
    // Dyadic inputs (p in 1/64 m, wind in 1/16 m/s, time in 1/8 s, scale m / 2^k with
    // m odd < 8): (p - wind time) scale is exact in f32 however a compiler contracts
    // it, so the comparison sees the noise, not the rounding of its argument.
    let dyadic =
        |rng: &mut Rng, lo: f32, hi: f32, steps: f32| (rng.range(lo, hi) * steps).round() / steps;
    for i in 0..20_000 {
        let p = Vec3::new(
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
            dyadic(&mut rng, -2000.0, 2000.0, 64.0),
        );
        let scale = (1 + 2 * rng.int(0, 3)) as f32 / (1 << rng.int(2, 7)) as f32;
        let wind = Vec3::new(
            dyadic(&mut rng, -15.0, 15.0, 16.0),
            dyadic(&mut rng, -15.0, 15.0, 16.0),
            dyadic(&mut rng, -15.0, 15.0, 16.0),
        );
        let time = if i % 5 == 0 {
            0.0
        } else {
            dyadic(&mut rng, 0.0, 600.0, 8.0)
        };
        let octaves = 1 + (i % 4) as u32;
        inputs.extend_from_slice(&[p.x, p.y, p.z, scale, wind.x, wind.y, wind.z, time]);
        inputs.extend_from_slice(&[octaves as f32, 0.0, 0.0, 0.0]);
        cases.push((p, scale, wind, time, octaves));
    }
    let out = run_f32(
        gpu,
        ANIM_KERNEL,
        &inputs,
        2 * cases.len(),
        cases.len() as u32,
    );
    let tol = 1e-5f32;
    let (mut worst_same, mut worst_cpu) = (0.0f32, 0.0f32);
    for (k, &(p, s, w, t, o)) in cases.iter().enumerate() {
        let (anim, fbm) = (out[2 * k], out[2 * k + 1]);
        let cpu = noise_animated(p, s, w, t, o);
        worst_same = worst_same.max((anim - fbm).abs());
        worst_cpu = worst_cpu.max((anim - cpu).abs());
        assert!(
            (anim - fbm).abs() <= tol,
            "noise_animated {anim} vs fbm {fbm}"
        );
        assert!(
            (anim - cpu).abs() <= tol,
            "noise_animated gpu {anim} cpu {cpu}"
        );
    }

    // The pattern moves with the wind: at time t, the point p + wind t shows what p
    // showed at time 0. Values chosen so that every product and sum is exact in f32.
    let wind = Vec3::new(2.0, -0.5, 1.25);
    let mut inputs = Vec::new();
    let mut starts = Vec::new();
    for _ in 0..4096 {
        let p = (rng.vec(-100.0, 100.0) * 64.0).round() / 64.0;
        let t = rng.int(1, 300) as f32;
        starts.push(p);
        for (q, time) in [(p, 0.0), (p + wind * t, t)] {
            inputs.extend_from_slice(&[q.x, q.y, q.z, 0.25, wind.x, wind.y, wind.z, time]);
            inputs.extend_from_slice(&[3.0, 0.0, 0.0, 0.0]);
        }
    }
    let n = 2 * starts.len();
    let moved = run_f32(gpu, ANIM_KERNEL, &inputs, 2 * n, n as u32);
    let mut worst_move = 0.0f32;
    for k in 0..starts.len() {
        let (before, after) = (moved[4 * k], moved[4 * k + 2]);
        worst_move = worst_move.max((before - after).abs());
        assert!(
            (before - after).abs() <= 1e-6,
            "at {}: {before} at t = 0, {after} after advection",
            starts[k]
        );
    }
    eprintln!(
        "animation: {} cases, |noise_animated - noise_fbm((p - w t) s)| <= {worst_same:e}, \
         |gpu - cpu| <= {worst_cpu:e} (bound {tol:e}); advected pattern: max change {worst_move:e} \
         (bound 1e-6) over {} points",
        cases.len(),
        starts.len()
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

/// The bake pass writes perlin_noise_tiled on the texel lattice: the texture read back
/// against the CPU bake. The values are in [-1, 1], where an f16 has an ulp of at most
/// 2^-11 below 1 (and 1 is exact): the store rounds to nearest (half an ulp, 2^-12) or,
/// as Vulkan also allows, toward zero (a whole ulp, 2^-11 = 4.9e-4); 5e-4 allows either
/// plus the f32 difference of the two evaluations (~1e-7).
#[test]
fn noise_bake_matches_cpu_bake() {
    let gpu = gpu();
    let (texture, texels) = baked_noise(gpu);
    let n = NOISE_TEXTURE_SIZE;
    assert_eq!(
        (texture.size().width, texture.size().height),
        (n, n),
        "{:?}",
        texture.size()
    );
    assert_eq!(texture.size().depth_or_array_layers, n);
    assert_eq!(texture.format(), wgpu::TextureFormat::Rgba16Float);
    assert_eq!(
        texture.usage(),
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
    );
    assert_eq!(NOISE_TEXTURE_BYTES, u64::from(n).pow(3) * 8);
    assert_eq!(NOISE_TEXTURE_BYTES, 2 << 20);
    let cpu = bake_noise_texture();
    assert_eq!(texels.len(), cpu.texels.len());
    let tol = 5e-4f32;
    let (mut worst, mut nearest, mut toward_zero) = (0.0f32, 0usize, 0usize);
    for (k, (t, &want)) in texels.iter().zip(&cpu.texels).enumerate() {
        let e = (t.x - want).abs();
        worst = worst.max(e);
        // The two roundings Vulkan allows: to nearest, and toward zero (one f16 step
        // closer to zero when the nearest one is farther from zero than the value).
        let rte = half::f16::from_f32(want);
        let rtz = if rte.to_f32().abs() > want.abs() {
            half::f16::from_bits(rte.to_bits() - 1)
        } else {
            rte
        };
        nearest += usize::from(t.x == rte.to_f32());
        toward_zero += usize::from(t.x == rtz.to_f32());
        assert!(e <= tol, "texel {k}: gpu {} cpu {want}", t.x);
        assert_eq!((t.y, t.z, t.w), (0.0, 0.0, 1.0), "texel {k}");
    }
    eprintln!(
        "noise bake: {n}^3 texels, max |gpu - cpu| {worst:e} (bound {tol:e}); of {}, {nearest} \
         equal the CPU value rounded to the nearest f16 and {toward_zero} rounded toward zero",
        texels.len()
    );
}

/// Test points for the texture form: random near the origin, in the first tiles, far
/// away, and on the texel lattice and the tile seams; octaves 0..=9 (clamped to 1..=8).
fn texture_points() -> Vec<(Vec3, u32)> {
    let mut rng = Rng(61);
    let mut pts = Vec::new();
    for i in 0..40_000u32 {
        let span = [16.0f32, 40.0, 1.0e3, 1.0e4][(i % 4) as usize];
        pts.push((
            rng.vec(-span, span),
            [1, 2, 4, 8, 3, 0, 9, 1][(i % 8) as usize],
        ));
    }
    for _ in 0..2000 {
        // Texel centres (quarter lattice units) and tile seams (multiples of 16).
        let q = Vec3::new(
            rng.int(-128, 128) as f32,
            rng.int(-128, 128) as f32,
            rng.int(-128, 128) as f32,
        ) * 0.25;
        pts.push((q, 1));
        let mut seam = rng.vec(-40.0, 40.0);
        seam.x = 16.0 * rng.int(-2, 2) as f32 + rng.range(-1e-3, 1e-3);
        pts.push((seam, 2));
    }
    pts
}

/// noise_fbm_texture sampled on the GPU from the GPU-baked texture against the CPU
/// mirror on the CPU bake, and against the CPU mirror on the texels read back (which
/// isolates the sampler's filtering), plus perlin_noise_tiled and
/// noise_animated_texture.
///
/// Bound: the texels differ by at most 5e-4 (see noise_bake_matches_cpu_bake), and a
/// trilinear filter is a convex combination, so that carries over to each octave and to
/// the normalised sum. The sampler computes its weights in reduced precision (lavapipe:
/// 8-bit fixed point, as Vulkan's subTexelPrecisionBits = 8 minimum allows): a weight off
/// by up to 2^-8 moves a sample by that times the difference of the two texels it
/// blends, at most D = the largest difference of neighbouring texels, on each of the
/// three axes: 5e-4 + 3 * 2^-8 * D.
#[test]
fn noise_fbm_texture_matches_cpu_mirror() {
    let gpu = gpu();
    let (texture, texels) = baked_noise(gpu);
    let cpu = bake_noise_texture();
    let read_back = DensityTexture {
        size: cpu.size,
        texels: texels.iter().map(|t| t.x).collect(),
    };
    let n = NOISE_TEXTURE_SIZE as i32;
    let at = |x: i32, y: i32, z: i32| {
        let w = |v: i32| v.rem_euclid(n) as usize;
        cpu.texels[(w(z) * n as usize + w(y)) * n as usize + w(x)]
    };
    let mut neighbour = 0.0f32;
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let here = at(x, y, z);
                for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    neighbour = neighbour.max((at(x + dx, y + dy, z + dz) - here).abs());
                }
            }
        }
    }
    let tol = 5e-4 + 3.0 * neighbour / 256.0;
    let pts = texture_points();
    let out = eval_texture_gpu(gpu, &texture, &pts);
    let (wind, time, scale) = TEXTURE_KERNEL_ANIMATION;
    let (mut worst_tiled, mut worst_bake, mut worst_filter, mut worst_anim) =
        (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut sum2 = 0.0f64;
    for (&(p, o), &(tiled, fbm, anim)) in pts.iter().zip(&out) {
        let e = (tiled - perlin_noise_tiled(p, 16)).abs();
        worst_tiled = worst_tiled.max(e);
        assert!(e <= 1e-5, "perlin_noise_tiled({p}): gpu {tiled}");
        let want = noise_fbm_texture(&cpu, p, o);
        let e = (fbm - want).abs();
        worst_bake = worst_bake.max(e);
        sum2 += f64::from(e) * f64::from(e);
        assert!(
            e <= tol,
            "noise_fbm_texture({p}, {o}): gpu {fbm} cpu {want}"
        );
        let e = (fbm - noise_fbm_texture(&read_back, p, o)).abs();
        worst_filter = worst_filter.max(e);
        let want = noise_animated_texture(&cpu, p, scale, wind, time, o);
        let e = (anim - want).abs();
        worst_anim = worst_anim.max(e);
        assert!(
            e <= tol,
            "noise_animated_texture({p}, {o}): gpu {anim} cpu {want}"
        );
    }
    // Octaves clamp to 1..=8 as in noise_fbm.
    let probe = Vec3::new(1.3, -2.7, 5.1);
    let clamp = eval_texture_gpu(
        gpu,
        &texture,
        &[(probe, 0), (probe, 1), (probe, 9), (probe, 8)],
    );
    assert_eq!(clamp[0].1, clamp[1].1);
    assert_eq!(clamp[2].1, clamp[3].1);
    eprintln!(
        "noise texture sampling: {} points; noise_fbm_texture |gpu - cpu bake| max {worst_bake:e} \
         RMS {:.2e} (bound 5e-4 + 3 * 2^-8 * {neighbour:.4} = {tol:.2e}); |gpu - cpu on the \
         texels read back| max {worst_filter:e} (the filtering alone); noise_animated_texture \
         max {worst_anim:e}; perlin_noise_tiled |gpu - cpu| max {worst_tiled:e} (bound 1e-5)",
        pts.len(),
        (sum2 / pts.len() as f64).sqrt()
    );
}

#[test]
fn noise_kernel_translates_to_every_target() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gpu_noise_translate");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, kernel) in [("noise", EVAL_KERNEL), ("noise_texture", TEXTURE_KERNEL)] {
        let module = common::compose(kernel, &[]);
        let entries = volfog_codegen::translate::translate(
            &format!("{name}_test"),
            module,
            &Default::default(),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(entries.len(), 1);
        let entry = &entries[0];
        for (target, text) in [
            ("wgsl", &entry.wgsl),
            ("glsl", &entry.glsl),
            ("hlsl", &entry.hlsl),
            ("msl", &entry.msl),
        ] {
            // The permutation travels as a table in the shader (first word 0x5b89a097).
            assert!(
                text.contains("1535746199") || text.contains("0x5b89a097"),
                "{name} {target}: no permutation table"
            );
        }
        let spv = dir.join(format!("{name}.spv"));
        std::fs::write(&spv, entry.bytes(volfog_codegen::Target::Spirv)).unwrap();
        let glsl = dir.join(format!("{name}.comp"));
        std::fs::write(&glsl, &entry.glsl).unwrap();
        // Kept beside them for review: there is no HLSL or MSL compiler here.
        std::fs::write(dir.join(format!("{name}.hlsl")), &entry.hlsl).unwrap();
        std::fs::write(dir.join(format!("{name}.metal")), &entry.msl).unwrap();
        const HINT: &str = "apt-get update && apt-get install -y spirv-tools glslang-tools";
        for (tool, args) in [
            (
                "spirv-val",
                vec!["--target-env", "vulkan1.1", spv.to_str().unwrap()],
            ),
            ("glslangValidator", vec![glsl.to_str().unwrap()]),
        ] {
            let o = std::process::Command::new(tool)
                .args(&args)
                .output()
                .unwrap_or_else(|_| panic!("{tool} is not installed; install it with: {HINT}"));
            assert!(
                o.status.success(),
                "{name}: {tool}: {}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
        }
    }
}
