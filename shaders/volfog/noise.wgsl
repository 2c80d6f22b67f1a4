// volfog::noise — Perlin's improved gradient noise in 3D, its tileable form, its fractal
// sum, the wind-animated form that drives the fog density, and the same sums read from
// a baked noise texture.
//
// Use:      #import volfog::noise::{perlin_noise, perlin_noise_tiled, noise_fbm, noise_animated}
//           #import volfog::noise::{noise_fbm_texture, noise_animated_texture, noise_texture_coord}
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
//           perlin_noise_tiled reduces both corners of the cell modulo a period
//           (1..=256) before hashing: it repeats every `period` units, equals
//           perlin_noise for period 256, and for any period on the cells 0..period-2.
// Texture:  the noise_bake pass writes perlin_noise_tiled(i / 4, 16) into texel i of a
//           64^3 rgba16float texture (NOISE_TEXTURE_SIZE texels per axis, 4 per lattice
//           unit, one 16-unit period; red channel, 2 MiB); sampled with a linear, repeat
//           sampler at noise_texture_coord(q) it is trilinear interpolation of the tiled
//           noise, seamless across tiles. noise_fbm_texture / noise_animated_texture sum
//           it like noise_fbm / noise_animated: one texture read per octave instead of
//           eight hashed corners, but octave k repeats every 16 / 2^k units and the
//           interpolation smooths the noise. Error against the procedural sum with the
//           same period (1e5 points of a period, f32 texels; the noise itself has a
//           standard deviation of 0.27): one octave max 0.143, RMS 0.034; four octaves
//           max 0.088, RMS 0.021 (bound h^2/8 * sum_i max|d2n/dx_i^2| = 0.24 with
//           h = 1/4 and max|n_ii| ~10.4; the error scales with h^2). The rgba16float
//           texels add at most one f16 step below 1, 2^-11 = 4.9e-4 (the store may round
//           toward zero, as lavapipe's does).
// Range:    the reference value overshoots [-1, 1] in small spots of about 0.04 % of the
//           cells (up to +-1.0364, found by searching all 256^3 cells of a period);
//           perlin_noise clamps it to [-1, 1] and equals the reference everywhere else.
// Precision: the cell is wrapped to 0..255 in f32 before any integer conversion and the
//           fraction p - floor(p) is exact, so every finite input is safe and the detail
//           is limited only by the f32 spacing of p itself (|p| 2^-23: 0.008 at 1e5).
//           perlin_noise_tiled converts the cell clamped to +-2^24 (exact; beyond 2^23
//           every f32 is an integer, where the noise is 0); noise_texture_coord reduces
//           q / 16 modulo 1, so the sampler's coordinate stays in [0, 1.01) (sub-texel
//           precision 2^-18 texel) at any distance.
// Units:    noise_animated(_texture) takes positions in metres, a frequency in 1/m, a wind
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

// Improved Perlin noise in the cell whose low and high lattice corners have the
// indices c0 and c1 on each axis (c1 = c0 + 1 unwrapped, or both reduced modulo a
// period), at the fraction f in [0, 1)^3 of the cell: corner (x, y, z) takes the
// gradient hashed P[P[P[x] + y] + z], the eight contributions are blended by the fade,
// and the sum is clamped to [-1, 1].
fn noise_cell(f: vec3<f32>, c0: vec3<u32>, c1: vec3<u32>) -> f32 {
    let a = noise_perm(c0.x);
    let b = noise_perm(c1.x);
    let aa = noise_perm(a + c0.y);
    let ab = noise_perm(a + c1.y);
    let ba = noise_perm(b + c0.y);
    let bb = noise_perm(b + c1.y);

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
            noise_lerp(u, noise_grad(noise_perm(aa + c0.z), x, y, z),
                noise_grad(noise_perm(ba + c0.z), x - 1.0, y, z)),
            noise_lerp(u, noise_grad(noise_perm(ab + c0.z), x, y - 1.0, z),
                noise_grad(noise_perm(bb + c0.z), x - 1.0, y - 1.0, z)),
        ),
        noise_lerp(
            v,
            noise_lerp(u, noise_grad(noise_perm(aa + c1.z), x, y, z - 1.0),
                noise_grad(noise_perm(ba + c1.z), x - 1.0, y, z - 1.0)),
            noise_lerp(u, noise_grad(noise_perm(ab + c1.z), x, y - 1.0, z - 1.0),
                noise_grad(noise_perm(bb + c1.z), x - 1.0, y - 1.0, z - 1.0)),
        ),
    );
    return clamp(n, -1.0, 1.0);
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
    return noise_cell(f, c, c + 1u);
}

// The lattice index of cell coordinate `cell` (an integer-valued f32) and the next one,
// both reduced modulo n (1..=256) into 0..n-1. Every f32 of magnitude 2^23 or more is an
// integer, where the noise is 0 whatever the corners: clamping to +-2^24 keeps the
// conversion exact and in range. (Per axis, in scalars: the vector forms of % and
// select become vector ?: in HLSL, which HLSL 2021 deprecates.)
fn noise_wrap_axis(cell: f32, n: u32) -> vec2<u32> {
    let i = i32(clamp(cell, -16777216.0, 16777216.0));
    let r = i % i32(n);
    let c0 = u32(select(r, r + i32(n), r < 0));
    let c1 = select(c0 + 1u, 0u, c0 + 1u == n);
    return vec2<u32>(c0, c1);
}

// perlin_noise with period `period` (clamped to 1..=256) on every axis: both corners
// of the cell are reduced modulo the period before hashing, so the pattern repeats
// every `period` units. Equal to perlin_noise for period 256, and for any period at
// every p whose cell lies in [0, period - 1)^3 (corners c and c + 1 below period).
fn perlin_noise_tiled(p: vec3<f32>, period: u32) -> f32 {
    let n = clamp(period, 1u, 256u);
    let cell = floor(p);
    let x = noise_wrap_axis(cell.x, n);
    let y = noise_wrap_axis(cell.y, n);
    let z = noise_wrap_axis(cell.z, n);
    return noise_cell(p - cell, vec3<u32>(x.x, y.x, z.x), vec3<u32>(x.y, y.y, z.y));
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

// Lattice units per tile of the noise texture: the texture holds
// perlin_noise_tiled(., NOISE_TEXTURE_PERIOD) over one period and repeats with it.
const NOISE_TEXTURE_PERIOD: u32 = 16u;
// Texels per lattice unit of the noise texture (texel spacing 1 / 4 lattice unit).
const NOISE_TEXTURE_TEXELS_PER_UNIT: u32 = 4u;
// Texels per axis of the noise texture: NOISE_TEXTURE_PERIOD * NOISE_TEXTURE_TEXELS_PER_UNIT.
const NOISE_TEXTURE_SIZE: u32 = 64u;

// Texture coordinate of lattice point q in the noise texture, whose texel i (0..SIZE-1
// on each axis) holds the noise at i / NOISE_TEXTURE_TEXELS_PER_UNIT:
// q / NOISE_TEXTURE_PERIOD + 0.5 / NOISE_TEXTURE_SIZE, with q / PERIOD reduced modulo 1
// first (the same coordinate under repeat addressing) so that it keeps its sub-texel
// precision far from the origin.
fn noise_texture_coord(q: vec3<f32>) -> vec3<f32> {
    return fract(q / f32(NOISE_TEXTURE_PERIOD)) + 0.5 / f32(NOISE_TEXTURE_SIZE);
}

// noise_fbm with every octave's perlin_noise(q) read from the baked noise texture:
// textureSampleLevel(noise_volume, noise_filter, noise_texture_coord(q), 0.0).r, with
// noise_filter linear with repeat addressing. The same octave clamp, amplitudes and
// normalisation; the pattern repeats every NOISE_TEXTURE_PERIOD / 2^k units in octave k.
fn noise_fbm_texture(noise_volume: texture_3d<f32>, noise_filter: sampler, p: vec3<f32>, octaves: u32) -> f32 {
    let count = clamp(octaves, 1u, NOISE_MAX_OCTAVES);
    var sum = 0.0;
    var total = 0.0;
    var amplitude = 1.0;
    var q = p;
    for (var k = 0u; k < count; k++) {
        let n = textureSampleLevel(noise_volume, noise_filter, noise_texture_coord(q), 0.0).r;
        sum += amplitude * n;
        total += amplitude;
        amplitude *= 0.5;
        q *= 2.0;
    }
    return sum / total;
}

// noise_animated read from the baked noise texture: noise_fbm_texture at
// (p - wind time) scale (p in m, scale in 1/m, wind in m/s, time in s).
fn noise_animated_texture(
    noise_volume: texture_3d<f32>,
    noise_filter: sampler,
    p: vec3<f32>,
    scale: f32,
    wind: vec3<f32>,
    time: f32,
    octaves: u32,
) -> f32 {
    return noise_fbm_texture(noise_volume, noise_filter, (p - wind * time) * scale, octaves);
}
