// volfog::noise — Perlin's improved gradient noise in 3D, its fractal sum, and the
// wind-animated form that drives the fog density.
//
// Use:      #import volfog::noise::{perlin_noise, noise_fbm, noise_animated}
// Defines:  none
// Algorithm: Perlin 2002's improved noise, computed arithmetically (no texture):
//           the cell corner hashes come from Perlin's reference permutation of 0..255
//           (NOISE_PERM_PACKED, indexed modulo 256, which equals his table repeated),
//           the gradient of a corner is one of the 12 cube edge directions
//           (+-1, +-1, 0), (+-1, 0, +-1), (0, +-1, +-1) picked by hash & 15 as in his
//           grad() (16 cases, four edges appear twice), and the corner contributions
//           are blended by the quintic fade 6t^5 - 15t^4 + 10t^3, whose first and
//           second derivatives vanish at the lattice, so the noise is C2 across cells.
//           Hence perlin_noise is 0 at every integer point, its gradient there is the
//           corner's gradient vector, and it repeats every 256 units on each axis.
// Range:    the reference value overshoots [-1, 1] in small spots of about 0.04 % of the
//           cells (up to +-1.0364, found by searching all 256^3 cells of a period);
//           perlin_noise clamps it to [-1, 1] and equals the reference everywhere else.
// Precision: the cell is wrapped to 0..255 in f32 before any integer conversion and the
//           fraction p - floor(p) is exact, so every finite input is safe and the detail
//           is limited only by the f32 spacing of p itself (|p| 2^-23: 0.008 at 1e5).
// Units:    noise_animated takes positions in metres, a frequency in 1/m, a wind
//           velocity in m/s and a time in s; the other functions work in lattice units.
// References: Perlin 2002, "Improving Noise" (SIGGRAPH); Green 2005, "Implementing
//           Improved Perlin Noise" (GPU Gems 2, ch. 26); Wronski 2014, "Density
//           estimation and volume lighting": one octave of Perlin noise animated by wind.
#define_import_path volfog::noise

// Perlin's reference permutation of 0..255 (Perlin 2002), four entries per word:
// P[4k + j] is byte j (bits 8j..8j+7) of word k. The table is never written. It is a
// private variable rather than a `const` because naga's SPIR-V output copies a const
// array into a temporary at every dynamically indexed access, which Mesa's lavapipe
// takes minutes to compile; a private variable with an initializer is indexed in place.
var<private> NOISE_PERM_PACKED: array<u32, 64> = array<u32, 64>(
    0x5b89a097u, 0x0d830f5au, 0x35605fc9u, 0xe107e9c2u,
    0x1e67248cu, 0x63088e45u, 0x0a15f025u, 0x9406be17u,
    0x4bea78f7u, 0x3ec51a00u, 0xcbdbfc5eu, 0x200b2375u,
    0x5821b139u, 0x573895edu, 0x887d14aeu, 0xaf44a8abu,
    0x8647a54au, 0xa61b308bu, 0xe79e924du, 0x7ae56f53u,
    0xe685d33cu, 0x295c69dcu, 0x28f52e37u, 0x368f66f4u,
    0xa13f1941u, 0x4950d801u, 0xbb844cd1u, 0xa91259d0u,
    0x8287c4c8u, 0x569fbc74u, 0xc66d64a4u, 0x4003baadu,
    0xfae2d934u, 0xca057b7cu, 0x7e769326u, 0xd45552ffu,
    0xe33bcecfu, 0x113a102fu, 0x2a1cbdb6u, 0xd5aab7dfu,
    0x0298f877u, 0x46a39a2cu, 0x9b6599ddu, 0x09ac2ba7u,
    0xfd271681u, 0x6e6c6213u, 0xe8e0714fu, 0x6870b9b2u,
    0xe461f6dau, 0xc1f222fbu, 0x0c90d2eeu, 0xf1a2b3bfu,
    0xeb913351u, 0x6bef0ef9u, 0x1fd6c031u, 0x9d6ac7b5u,
    0xb0cc54b8u, 0x2d327973u, 0xfe96047fu, 0x5dcdec8au,
    0x1d4372deu, 0x8df34818u, 0x424ec380u, 0xb49c3dd7u
);

// Largest number of octaves noise_fbm sums.
const NOISE_MAX_OCTAVES: u32 = 8u;

// Perlin's table repeated: P[i] for any i (only i & 255 matters).
fn noise_perm(i: u32) -> u32 {
    let j = i & 255u;
    return (NOISE_PERM_PACKED[j >> 2u] >> ((j & 3u) * 8u)) & 255u;
}

// The quintic fade 6t^5 - 15t^4 + 10t^3 on t in [0, 1].
fn noise_fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// a + t (b - a).
fn noise_lerp(t: f32, a: f32, b: f32) -> f32 {
    return a + t * (b - a);
}

// dot(g, (x, y, z)) for the edge gradient g selected by hash & 15 (Perlin's grad()).
fn noise_grad(hash: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15u;
    let u = select(y, x, h < 8u);
    let v = select(select(z, x, h == 12u || h == 14u), y, h < 4u);
    return select(-u, u, (h & 1u) == 0u) + select(-v, v, (h & 2u) == 0u);
}

// Improved Perlin noise at p (lattice units): in [-1, 1], 0 at integer points,
// period 256 on every axis.
fn perlin_noise(p: vec3<f32>) -> f32 {
    let cell = floor(p);
    // The fraction is exact in f32; the cell is reduced modulo 256 in f32 (exact for
    // every finite value) before it becomes an integer.
    let f = p - cell;
    let wrapped = cell - 256.0 * floor(cell * (1.0 / 256.0));
    let c = vec3<u32>(wrapped) & vec3<u32>(255u);

    let a = noise_perm(c.x) + c.y;
    let aa = noise_perm(a) + c.z;
    let ab = noise_perm(a + 1u) + c.z;
    let b = noise_perm(c.x + 1u) + c.y;
    let ba = noise_perm(b) + c.z;
    let bb = noise_perm(b + 1u) + c.z;

    let x = f.x;
    let y = f.y;
    let z = f.z;
    let u = noise_fade(x);
    let v = noise_fade(y);
    let w = noise_fade(z);
    let n = noise_lerp(
        w,
        noise_lerp(
            v,
            noise_lerp(u, noise_grad(noise_perm(aa), x, y, z),
                noise_grad(noise_perm(ba), x - 1.0, y, z)),
            noise_lerp(u, noise_grad(noise_perm(ab), x, y - 1.0, z),
                noise_grad(noise_perm(bb), x - 1.0, y - 1.0, z)),
        ),
        noise_lerp(
            v,
            noise_lerp(u, noise_grad(noise_perm(aa + 1u), x, y, z - 1.0),
                noise_grad(noise_perm(ba + 1u), x - 1.0, y, z - 1.0)),
            noise_lerp(u, noise_grad(noise_perm(ab + 1u), x, y - 1.0, z - 1.0),
                noise_grad(noise_perm(bb + 1u), x - 1.0, y - 1.0, z - 1.0)),
        ),
    );
    return clamp(n, -1.0, 1.0);
}

// Fractal sum of perlin_noise at p (lattice units of the first octave): octave k has
// frequency 2^k and amplitude 0.5^k (lacunarity 2, gain 0.5), and the sum is divided
// by the sum of the amplitudes, so it stays in [-1, 1]. octaves is clamped to 1..=8;
// one octave is perlin_noise itself.
fn noise_fbm(p: vec3<f32>, octaves: u32) -> f32 {
    let count = clamp(octaves, 1u, NOISE_MAX_OCTAVES);
    var sum = 0.0;
    var total = 0.0;
    var amplitude = 1.0;
    var q = p;
    for (var k = 0u; k < count; k++) {
        sum += amplitude * perlin_noise(q);
        total += amplitude;
        amplitude *= 0.5;
        q *= 2.0;
    }
    return sum / total;
}

// Noise of world position p (m) advected by the wind: noise_fbm at (p - wind time) scale,
// with scale the frequency of the first octave (1/m), wind the velocity (m/s) and time
// in s. Result in [-1, 1].
fn noise_animated(p: vec3<f32>, scale: f32, wind: vec3<f32>, time: f32, octaves: u32) -> f32 {
    return noise_fbm((p - wind * time) * scale, octaves);
}
