//! Mirror of `volfog::noise`: Perlin's improved gradient noise in 3D (Perlin 2002),
//! its fractal sum and the wind-animated form that drives the fog density.
//!
//! [`perlin_noise`] uses Perlin's reference permutation, the 12 cube-edge gradients
//! picked by `hash & 15` and the quintic fade `6t^5 - 15t^4 + 10t^3`. It is 0 at
//! every integer point, repeats every 256 units on each axis and is clamped to
//! `[-1, 1]` (the reference overshoots to ±1.0364 in about 0.04 % of the cells).
//! See the WGSL module for references.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::noise::{noise_animated, noise_fbm, perlin_noise};
//! // The value Perlin's reference implementation gives at (3.14, 42, 7).
//! assert!((perlin_noise(Vec3::new(3.14, 42.0, 7.0)) - 0.136_92).abs() < 1e-5);
//! // Zero on the lattice, for any number of octaves.
//! assert_eq!(perlin_noise(Vec3::new(-3.0, 17.0, 1000.0)), 0.0);
//! assert_eq!(noise_fbm(Vec3::new(5.0, -2.0, 9.0), 4), 0.0);
//! // Wind carries the pattern: after 10 s at 2 m/s along x it has moved 20 m.
//! let wind = Vec3::new(2.0, 0.0, 0.0);
//! let here = noise_animated(Vec3::new(1.3, 2.2, 0.7), 0.15, wind, 0.0, 2);
//! let there = noise_animated(Vec3::new(21.3, 2.2, 0.7), 0.15, wind, 10.0, 2);
//! assert!((here - there).abs() < 1e-5);
//! ```

use glam::{UVec3, Vec3};

/// Perlin's reference permutation of 0..255 (Perlin 2002).
pub const NOISE_PERM: [u32; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// [`NOISE_PERM`] four entries per word, as the WGSL module stores it: `P[4k + j]` is
/// byte `j` (bits `8j..8j+7`) of word `k`.
pub const NOISE_PERM_PACKED: [u32; 64] = {
    let mut packed = [0u32; 64];
    let mut i = 0;
    while i < 256 {
        packed[i / 4] |= NOISE_PERM[i] << (8 * (i % 4));
        i += 1;
    }
    packed
};

/// Largest number of octaves [`noise_fbm`] sums.
pub const NOISE_MAX_OCTAVES: u32 = 8;

/// Perlin's table repeated: `P[i]` for any `i` (only `i & 255` matters).
pub fn noise_perm(i: u32) -> u32 {
    let j = i & 255;
    (NOISE_PERM_PACKED[(j >> 2) as usize] >> ((j & 3) * 8)) & 255
}

/// The quintic fade `6t^5 - 15t^4 + 10t^3` on `t` in `[0, 1]`.
pub fn noise_fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `a + t (b - a)`.
pub fn noise_lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// `dot(g, (x, y, z))` for the edge gradient `g` selected by `hash & 15`
/// (Perlin's `grad()`).
pub fn noise_grad(hash: u32, x: f32, y: f32, z: f32) -> f32 {
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

/// Improved Perlin noise at `p` (lattice units): in `[-1, 1]`, 0 at integer points,
/// period 256 on every axis.
pub fn perlin_noise(p: Vec3) -> f32 {
    let cell = p.floor();
    // Exact fraction; the cell is reduced modulo 256 in f32 before the conversion.
    let f = p - cell;
    let wrapped = cell - 256.0 * (cell * (1.0 / 256.0)).floor();
    let c = wrapped.as_uvec3() & UVec3::splat(255);

    let a = noise_perm(c.x) + c.y;
    let aa = noise_perm(a) + c.z;
    let ab = noise_perm(a + 1) + c.z;
    let b = noise_perm(c.x + 1) + c.y;
    let ba = noise_perm(b) + c.z;
    let bb = noise_perm(b + 1) + c.z;

    let (x, y, z) = (f.x, f.y, f.z);
    let u = noise_fade(x);
    let v = noise_fade(y);
    let w = noise_fade(z);
    let g = |hash: u32, x: f32, y: f32, z: f32| noise_grad(noise_perm(hash), x, y, z);
    let n = noise_lerp(
        w,
        noise_lerp(
            v,
            noise_lerp(u, g(aa, x, y, z), g(ba, x - 1.0, y, z)),
            noise_lerp(u, g(ab, x, y - 1.0, z), g(bb, x - 1.0, y - 1.0, z)),
        ),
        noise_lerp(
            v,
            noise_lerp(u, g(aa + 1, x, y, z - 1.0), g(ba + 1, x - 1.0, y, z - 1.0)),
            noise_lerp(
                u,
                g(ab + 1, x, y - 1.0, z - 1.0),
                g(bb + 1, x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    );
    n.clamp(-1.0, 1.0)
}

/// Fractal sum of [`perlin_noise`]: octave `k` has frequency `2^k` and amplitude
/// `0.5^k`, divided by the sum of the amplitudes so it stays in `[-1, 1]`.
/// `octaves` is clamped to `1..=8`.
pub fn noise_fbm(p: Vec3, octaves: u32) -> f32 {
    let count = octaves.clamp(1, NOISE_MAX_OCTAVES);
    let mut sum = 0.0;
    let mut total = 0.0;
    let mut amplitude = 1.0;
    let mut q = p;
    for _ in 0..count {
        sum += amplitude * perlin_noise(q);
        total += amplitude;
        amplitude *= 0.5;
        q *= 2.0;
    }
    sum / total
}

/// Noise of world position `p` (m) advected by the wind: [`noise_fbm`] at
/// `(p - wind * time) * scale`, with `scale` the frequency of the first octave (1/m),
/// `wind` in m/s and `time` in s.
pub fn noise_animated(p: Vec3, scale: f32, wind: Vec3, time: f32, octaves: u32) -> f32 {
    noise_fbm((p - wind * time) * scale, octaves)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_table_is_the_permutation() {
        let mut seen = [false; 256];
        for i in 0..512u32 {
            assert_eq!(noise_perm(i), NOISE_PERM[(i % 256) as usize]);
            seen[noise_perm(i) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(NOISE_PERM_PACKED[0], 0x5b89_a097);
        assert_eq!(NOISE_PERM_PACKED[63], 0xb49c_3dd7);
    }
}
