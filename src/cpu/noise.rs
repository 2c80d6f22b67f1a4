//! Mirror of `volfog::noise`: Perlin's improved gradient noise in 3D (Perlin 2002),
//! its tileable form, its fractal sum, the wind-animated form that drives the fog
//! density, and the same sums read from the baked noise texture.
//!
//! [`perlin_noise`] uses Perlin's reference permutation, the 12 cube-edge gradients
//! picked by `hash & 15` and the quintic fade `6t^5 - 15t^4 + 10t^3`. It is 0 at
//! every integer point, repeats every 256 units on each axis and is clamped to
//! `[-1, 1]` (the reference overshoots to ±1.0364 in about 0.04 % of the cells).
//! [`perlin_noise_tiled`] wraps the cell corners modulo a smaller period;
//! [`bake_noise_texture`] holds one 16-unit period of it, 4 texels per unit, and
//! [`noise_fbm_texture`] interpolates it trilinearly (error against the procedural
//! sum: max 0.14, RMS 0.034 for one octave). See the WGSL module for references and
//! the measured errors.
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

use crate::cpu::texture::DensityTexture;

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

/// Improved Perlin noise in the cell whose low and high lattice corners have the
/// indices `c0` and `c1` on each axis (`c1 = c0 + 1` unwrapped, or both reduced modulo
/// a period), at the fraction `f` in `[0, 1)^3` of the cell: corner `(x, y, z)` takes
/// the gradient hashed `P[P[P[x] + y] + z]`, the eight contributions are blended by the
/// fade, and the sum is clamped to `[-1, 1]`.
fn noise_cell(f: Vec3, c0: UVec3, c1: UVec3) -> f32 {
    let a = noise_perm(c0.x);
    let b = noise_perm(c1.x);
    let aa = noise_perm(a + c0.y);
    let ab = noise_perm(a + c1.y);
    let ba = noise_perm(b + c0.y);
    let bb = noise_perm(b + c1.y);

    let (x, y, z) = (f.x, f.y, f.z);
    let u = noise_fade(x);
    let v = noise_fade(y);
    let w = noise_fade(z);
    let g = |hash: u32, x: f32, y: f32, z: f32| noise_grad(noise_perm(hash), x, y, z);
    let (z0, z1) = (c0.z, c1.z);
    let n = noise_lerp(
        w,
        noise_lerp(
            v,
            noise_lerp(u, g(aa + z0, x, y, z), g(ba + z0, x - 1.0, y, z)),
            noise_lerp(
                u,
                g(ab + z0, x, y - 1.0, z),
                g(bb + z0, x - 1.0, y - 1.0, z),
            ),
        ),
        noise_lerp(
            v,
            noise_lerp(
                u,
                g(aa + z1, x, y, z - 1.0),
                g(ba + z1, x - 1.0, y, z - 1.0),
            ),
            noise_lerp(
                u,
                g(ab + z1, x, y - 1.0, z - 1.0),
                g(bb + z1, x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    );
    n.clamp(-1.0, 1.0)
}

/// Improved Perlin noise at `p` (lattice units): in `[-1, 1]`, 0 at integer points,
/// period 256 on every axis.
pub fn perlin_noise(p: Vec3) -> f32 {
    let cell = p.floor();
    // Exact fraction; the cell is reduced modulo 256 in f32 before the conversion.
    let f = p - cell;
    let wrapped = cell - 256.0 * (cell * (1.0 / 256.0)).floor();
    let c = wrapped.as_uvec3() & UVec3::splat(255);
    noise_cell(f, c, c + 1)
}

/// [`perlin_noise`] with period `period` (clamped to `1..=256`) on every axis: both
/// corners of the cell are reduced modulo the period before hashing, so the pattern
/// repeats every `period` units. Equal to [`perlin_noise`] for period 256, and for any
/// period at every `p` whose cell lies in `[0, period - 1)^3` (corners `c` and `c + 1`
/// below the period).
///
/// ```
/// use glam::Vec3;
/// use volfog::cpu::noise::{perlin_noise, perlin_noise_tiled};
/// let p = Vec3::new(3.3, 7.6, 12.1);
/// assert_eq!(perlin_noise_tiled(p, 16), perlin_noise(p));
/// let shifted = perlin_noise_tiled(p + Vec3::new(-32.0, 16.0, 48.0), 16);
/// assert!((shifted - perlin_noise(p)).abs() < 1e-5);
/// ```
pub fn perlin_noise_tiled(p: Vec3, period: u32) -> f32 {
    let n = period.clamp(1, 256);
    let cell = p.floor();
    let (x0, x1) = noise_wrap_axis(cell.x, n);
    let (y0, y1) = noise_wrap_axis(cell.y, n);
    let (z0, z1) = noise_wrap_axis(cell.z, n);
    noise_cell(p - cell, UVec3::new(x0, y0, z0), UVec3::new(x1, y1, z1))
}

/// The lattice index of cell coordinate `cell` (an integer-valued f32) and the next
/// one, both reduced modulo `n` (`1..=256`) into `0..n`. Every f32 of magnitude 2^23 or
/// more is an integer, where the noise is 0 whatever the corners: clamping to ±2^24
/// keeps the conversion exact.
fn noise_wrap_axis(cell: f32, n: u32) -> (u32, u32) {
    let i = cell.clamp(-16_777_216.0, 16_777_216.0) as i32;
    let c0 = i.rem_euclid(n as i32) as u32;
    let c1 = if c0 + 1 == n { 0 } else { c0 + 1 };
    (c0, c1)
}

/// The fractal sum of `noise` at `p`: octave `k` reads `noise(2^k p)` with amplitude
/// `0.5^k`, divided by the sum of the amplitudes; `octaves` is clamped to `1..=8`.
fn fractal_sum(p: Vec3, octaves: u32, noise: impl Fn(Vec3) -> f32) -> f32 {
    let count = octaves.clamp(1, NOISE_MAX_OCTAVES);
    let mut sum = 0.0;
    let mut total = 0.0;
    let mut amplitude = 1.0;
    let mut q = p;
    for _ in 0..count {
        sum += amplitude * noise(q);
        total += amplitude;
        amplitude *= 0.5;
        q *= 2.0;
    }
    sum / total
}

/// Fractal sum of [`perlin_noise`]: octave `k` has frequency `2^k` and amplitude
/// `0.5^k`, divided by the sum of the amplitudes so it stays in `[-1, 1]`.
/// `octaves` is clamped to `1..=8`.
pub fn noise_fbm(p: Vec3, octaves: u32) -> f32 {
    fractal_sum(p, octaves, perlin_noise)
}

/// Noise of world position `p` (m) advected by the wind: [`noise_fbm`] at
/// `(p - wind * time) * scale`, with `scale` the frequency of the first octave (1/m),
/// `wind` in m/s and `time` in s.
pub fn noise_animated(p: Vec3, scale: f32, wind: Vec3, time: f32, octaves: u32) -> f32 {
    noise_fbm((p - wind * time) * scale, octaves)
}

/// Lattice units per tile of the noise texture: it holds
/// [`perlin_noise_tiled`]`(., NOISE_TEXTURE_PERIOD)` over one period.
pub const NOISE_TEXTURE_PERIOD: u32 = 16;

/// Texels per lattice unit of the noise texture (texel spacing 1/4 lattice unit).
pub const NOISE_TEXTURE_TEXELS_PER_UNIT: u32 = 4;

/// Texels per axis of the noise texture:
/// [`NOISE_TEXTURE_PERIOD`]` * `[`NOISE_TEXTURE_TEXELS_PER_UNIT`].
pub const NOISE_TEXTURE_SIZE: u32 = NOISE_TEXTURE_PERIOD * NOISE_TEXTURE_TEXELS_PER_UNIT;

/// Texture coordinate of lattice point `q` in the noise texture, whose texel `i` holds
/// the noise at `i / NOISE_TEXTURE_TEXELS_PER_UNIT`: `q / NOISE_TEXTURE_PERIOD +
/// 0.5 / NOISE_TEXTURE_SIZE`, with `q / PERIOD` reduced modulo 1 first (the same
/// coordinate under repeat addressing, with its sub-texel precision kept far from the
/// origin).
pub fn noise_texture_coord(q: Vec3) -> Vec3 {
    (q / NOISE_TEXTURE_PERIOD as f32).fract_gl() + 0.5 / NOISE_TEXTURE_SIZE as f32
}

/// The noise texture as the `noise_bake` pass writes it (in f32; the GPU stores
/// rgba16float): [`NOISE_TEXTURE_SIZE`]^3 texels, x fastest, texel `i` holding
/// [`perlin_noise_tiled`]`(i / NOISE_TEXTURE_TEXELS_PER_UNIT, NOISE_TEXTURE_PERIOD)`.
pub fn bake_noise_texture() -> DensityTexture {
    let n = NOISE_TEXTURE_SIZE;
    let mut texels = Vec::with_capacity((n * n * n) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let q = UVec3::new(x, y, z).as_vec3() / NOISE_TEXTURE_TEXELS_PER_UNIT as f32;
                texels.push(perlin_noise_tiled(q, NOISE_TEXTURE_PERIOD));
            }
        }
    }
    DensityTexture {
        size: [n; 3],
        texels,
    }
}

/// [`noise_fbm`] with every octave's [`perlin_noise`]`(q)` read from the noise texture
/// (trilinear, repeat addressing) at [`noise_texture_coord`]`(q)`. The same octave
/// clamp, amplitudes and normalisation; octave `k` repeats every
/// `NOISE_TEXTURE_PERIOD / 2^k` units.
///
/// ```
/// use glam::Vec3;
/// use volfog::cpu::noise::{bake_noise_texture, noise_fbm_texture, perlin_noise_tiled};
/// let texture = bake_noise_texture();
/// // On a texel, one octave reads the tiled noise back exactly.
/// let q = Vec3::new(2.25, 7.5, 13.75);
/// assert_eq!(noise_fbm_texture(&texture, q, 1), perlin_noise_tiled(q, 16));
/// ```
pub fn noise_fbm_texture(texture: &DensityTexture, p: Vec3, octaves: u32) -> f32 {
    fractal_sum(p, octaves, |q| texture.sample(noise_texture_coord(q)))
}

/// [`noise_animated`] read from the noise texture: [`noise_fbm_texture`] at
/// `(p - wind * time) * scale` (`p` in m, `scale` in 1/m, `wind` in m/s, `time` in s).
pub fn noise_animated_texture(
    texture: &DensityTexture,
    p: Vec3,
    scale: f32,
    wind: Vec3,
    time: f32,
    octaves: u32,
) -> f32 {
    noise_fbm_texture(texture, (p - wind * time) * scale, octaves)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;

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

    #[test]
    fn tiled_equals_untiled_inside_the_first_period() {
        let mut rng = Rng(3);
        let mut count = 0;
        for period in [2u32, 3, 5, 7, 16, 100, 255, 256] {
            for _ in 0..20_000 {
                // A cell in 0..=period - 2 on each axis: corners c and c + 1 below period.
                let cell = UVec3::new(
                    rng.int(0, period - 2),
                    rng.int(0, period - 2),
                    rng.int(0, period - 2),
                );
                let p = cell.as_vec3() + rng.vec(0.0, 1.0);
                assert_eq!(
                    perlin_noise_tiled(p, period).to_bits(),
                    perlin_noise(p).to_bits(),
                    "period {period} at {p}"
                );
                count += 1;
            }
        }
        // And the texture's period on the faces, edges and corners of those cells.
        for x in 0..15 {
            for y in 0..15 {
                let p = Vec3::new(x as f32, y as f32 + 0.5, 14.0 + 0.25 * (x % 4) as f32);
                assert_eq!(perlin_noise_tiled(p, 16), perlin_noise(p), "{p}");
            }
        }
        assert!(count > 0);
    }

    #[test]
    fn tiled_noise_repeats_every_period() {
        let mut rng = Rng(5);
        let mut worst = 0.0f32;
        for period in [1u32, 2, 3, 7, 16, 64, 200, 256] {
            let t = period as f32;
            for i in 0..20_000 {
                let mut p = rng.vec(-3.0 * t, 3.0 * t);
                if i % 2 == 0 {
                    // On a 2^-12 grid, where p + k period is exact: the same fraction in
                    // the same wrapped cell, hence the same bits.
                    p = (p * 4096.0).round() / 4096.0;
                }
                let here = perlin_noise_tiled(p, period);
                for axis in 0..3 {
                    for k in [-2.0f32, 1.0, 3.0] {
                        let mut q = p;
                        q[axis] += k * t;
                        let there = perlin_noise_tiled(q, period);
                        if i % 2 == 0 {
                            assert_eq!(there.to_bits(), here.to_bits(), "{p} + {k} * {t}");
                        }
                        // Otherwise p + k period rounds in f32 (|p| < 4 * 256: spacing at
                        // most 2^-14) and the noise moves by at most 8.5 times that.
                        let e = (there - here).abs();
                        let shift = (q - p - k * t).abs().max_element();
                        worst = worst.max(e);
                        assert!(e <= 1e-6 + 8.5 * shift, "period {period} at {p}: {e}");
                    }
                }
            }
        }
        // Period 1: every corner is corner 0, so the noise is the same in every cell.
        let p = Vec3::new(0.25, 0.625, 0.875);
        assert_eq!(
            perlin_noise_tiled(p, 1),
            perlin_noise_tiled(p + Vec3::new(5.0, -9.0, 113.0), 1)
        );
        // Out-of-range periods are clamped to 1..=256.
        assert_eq!(perlin_noise_tiled(p, 0), perlin_noise_tiled(p, 1));
        assert_eq!(
            perlin_noise_tiled(p + 300.0, 1000),
            perlin_noise_tiled(p + 300.0, 256)
        );
        assert!(worst <= 1e-3, "{worst}");
    }

    #[test]
    fn period_256_is_perlin_noise() {
        let mut rng = Rng(7);
        for i in 0..100_000 {
            let span = [4.0f32, 300.0, 1e4, 1e6, 2e7][i % 5];
            let p = rng.vec(-span, span);
            let (tiled, plain) = (perlin_noise_tiled(p, 256), perlin_noise(p));
            if span < 1e7 {
                assert_eq!(tiled.to_bits(), plain.to_bits(), "{p}");
            } else {
                // Integers only: both are a zero (of either sign).
                assert!(tiled == 0.0 && plain == 0.0, "{p}: {tiled} vs {plain}");
            }
        }
        for p in [
            Vec3::splat(255.5),
            Vec3::splat(-0.5),
            Vec3::new(-256.5, 511.9, 0.1),
        ] {
            assert_eq!(perlin_noise_tiled(p, 256), perlin_noise(p), "{p}");
        }
    }

    #[test]
    fn baked_texture_holds_the_tiled_noise_on_its_texels() {
        let texture = bake_noise_texture();
        let n = NOISE_TEXTURE_SIZE;
        assert_eq!(n, 64);
        assert_eq!(texture.size, [n; 3]);
        assert_eq!(texture.texels.len(), (n * n * n) as usize);
        let mut rng = Rng(9);
        for _ in 0..5000 {
            let i = UVec3::new(rng.int(0, n - 1), rng.int(0, n - 1), rng.int(0, n - 1));
            let q = i.as_vec3() * 0.25;
            let texel = texture.texels[((i.z * n + i.y) * n + i.x) as usize];
            assert_eq!(texel, perlin_noise_tiled(q, NOISE_TEXTURE_PERIOD));
            // Texel centres sit on the lattice points, in this tile and in the next ones.
            assert_eq!(noise_fbm_texture(&texture, q, 1), texel, "{q}");
            let shifted = q + Vec3::new(16.0, -32.0, 48.0);
            assert_eq!(noise_fbm_texture(&texture, shifted, 1), texel, "{shifted}");
            assert_eq!(
                noise_texture_coord(q),
                (i.as_vec3() + 0.5) / n as f32,
                "{q}"
            );
        }
        // Zero on the integer lattice points (every fourth texel).
        for (k, v) in texture.texels.iter().enumerate() {
            let (x, y, z) = (k as u32 % n, k as u32 / n % n, k as u32 / (n * n));
            if x % 4 == 0 && y % 4 == 0 && z % 4 == 0 {
                assert_eq!(*v, 0.0);
            }
            assert!((-1.0..=1.0).contains(v));
        }
        // noise_animated_texture is noise_fbm_texture of the advected point.
        let (p, wind) = (Vec3::new(3.0, -1.5, 8.25), Vec3::new(2.0, 0.0, -1.0));
        assert_eq!(
            noise_animated_texture(&texture, p, 0.5, wind, 4.0, 3),
            noise_fbm_texture(&texture, (p - wind * 4.0) * 0.5, 3)
        );
    }

    /// noise_fbm with every octave from perlin_noise_tiled at the texture's period: what
    /// noise_fbm_texture approximates (octave k then repeats every 16 / 2^k units).
    fn fbm_tiled(p: Vec3, octaves: u32) -> f32 {
        fractal_sum(p, octaves, |q| perlin_noise_tiled(q, NOISE_TEXTURE_PERIOD))
    }

    /// Second derivatives d2f/dx_i^2 of perlin_noise_tiled by central differences.
    fn second_derivatives(p: Vec3) -> Vec3 {
        let d = 1.0 / 64.0;
        let f = |q: Vec3| perlin_noise_tiled(q, NOISE_TEXTURE_PERIOD) as f64;
        let here = f(p);
        let mut out = Vec3::ZERO;
        for axis in 0..3 {
            let mut e = Vec3::ZERO;
            e[axis] = d;
            out[axis] = ((f(p + e) - 2.0 * here + f(p - e)) / (d as f64 * d as f64)) as f32;
        }
        out
    }

    /// Accuracy of the texture form: trilinear interpolation of texels 1/4 lattice unit
    /// apart against the procedural noise it samples, over one period.
    #[test]
    fn texture_form_error_against_the_procedural_noise() {
        let texture = bake_noise_texture();
        let mut rng = Rng(11);
        let n = 100_000;
        let points: Vec<Vec3> = (0..n).map(|_| rng.vec(0.0, 16.0)).collect();
        // Where every octave's cell lies in [0, 15)^3, the tiled sums are noise_fbm itself.
        for &p in &points {
            if p.max_element() < 15.0 {
                assert_eq!(fbm_tiled(p, 1).to_bits(), noise_fbm(p, 1).to_bits());
            }
            let inner = p * (15.0 / 16.0 / 8.0);
            assert_eq!(fbm_tiled(inner, 4).to_bits(), noise_fbm(inner, 4).to_bits());
        }
        // Curvature of the noise over the same points.
        let mut max_f2 = Vec3::ZERO;
        let mut predicted = 0.0f64;
        for &p in &points {
            let f2 = second_derivatives(p);
            max_f2 = max_f2.max(f2.abs());
            // Trilinear error -(h^2 / 2) sum_i t_i (1 - t_i) f_ii to leading order, with the
            // t_i uniform and independent: E[(t(1-t))^2] = 1/30, E[t(1-t)]^2 = 1/36.
            let f = f2.as_dvec3();
            let cross = f.x * f.y + f.y * f.z + f.z * f.x;
            predicted += f.length_squared() / 30.0 + 2.0 * cross / 36.0;
        }
        let h = 1.0 / NOISE_TEXTURE_TEXELS_PER_UNIT as f64;
        let predicted_rms = (h.powi(4) / 4.0 * predicted / n as f64).sqrt();
        // |f - trilinear f| <= h^2 / 8 (max|f_xx| + max|f_yy| + max|f_zz|) for a C2 f;
        // the maxima are over the sample points, and 10 % is left for the maxima
        // between them.
        let bound = h * h / 8.0 * max_f2.element_sum() as f64 * 1.1;
        let mut report = Vec::new();
        for octaves in [1u32, 4] {
            let (mut max, mut sum2) = (0.0f64, 0.0f64);
            for &p in &points {
                let want = if octaves == 1 {
                    perlin_noise_tiled(p, NOISE_TEXTURE_PERIOD)
                } else {
                    fbm_tiled(p, octaves)
                };
                let e = (noise_fbm_texture(&texture, p, octaves) - want) as f64;
                max = max.max(e.abs());
                sum2 += e * e;
            }
            let rms = (sum2 / n as f64).sqrt();
            // Octave k's error has the same bound in its own lattice units, so the
            // normalised sum keeps the one-octave bound; independent octave errors give
            // an RMS of sqrt(sum a_k^2) / sum a_k times the one-octave RMS.
            let (a2, a): (f64, f64) = (0..octaves)
                .map(|k| (0.25f64.powi(k as i32), 0.5f64.powi(k as i32)))
                .fold((0.0, 0.0), |(s2, s), (x2, x)| (s2 + x2, s + x));
            let expected_rms = predicted_rms * a2.sqrt() / a;
            report.push(format!(
                "{octaves} octave(s): max {max:.3e}, RMS {rms:.3e} (predicted RMS \
                 {expected_rms:.3e})"
            ));
            assert!(max <= bound, "{octaves} octaves: max error {max} > {bound}");
            assert!(
                (0.75 * expected_rms..=1.25 * expected_rms).contains(&rms),
                "{octaves} octaves: RMS {rms}, predicted {expected_rms}"
            );
        }
        eprintln!(
            "noise texture vs procedural over {n} points of one period: {}; bound on the \
             max h^2/8 * sum max|f_ii| * 1.1 = {bound:.3e} (max |f_ii| {max_f2:?})",
            report.join("; ")
        );
    }
}
