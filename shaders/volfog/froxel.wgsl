// volfog::froxel — mapping between froxels, screen uv and view depth.
//
// Use:      #import volfog::froxel::{slice_depth, slice_coord, ray_scale, ...}
// Defines:  none
// Reference: Wronski 2014, "Volume texture layout": the volume maps the frustum to a
//           cuboid, x and y through normalised device coordinates, z through an
//           exponential depth distribution concentrated near the camera.
//
// Depth slices. With t in [0, 1] the normalised slice coordinate (t = k / N is the
// front of slice k of N) and c >= 0 the curve:
//     z(t) = near + (far - near) * (exp(c t) - 1) / (exp(c) - 1)
// c -> 0 gives linear slices; c = ln(far / near) gives z(t) = near * (far / near)^t.
// Its inverse is t(z) = ln(1 + (z - near) / (far - near) * (exp(c) - 1)) / c.
#define_import_path volfog::froxel

// Below this curve the distribution is evaluated by its series in c (error < 1e-6 of
// the span), which avoids the cancellation of exp(c t) - 1 and exp(c) - 1.
const CURVE_LINEAR_LIMIT: f32 = 1e-3;

// View depth (m) at normalised slice coordinate t (t may lie outside [0, 1]).
fn slice_depth(t: f32, near: f32, far: f32, curve: f32) -> f32 {
    let span = far - near;
    if curve < CURVE_LINEAR_LIMIT {
        return near + span * (t + 0.5 * curve * t * (t - 1.0));
    }
    return near + (exp(curve * t) - 1.0) * (span / (exp(curve) - 1.0));
}

// The slice boundaries of a volume of `slices` slices as a walk, for a caller that visits
// them in order (the scan): with d_0 = 0 and d_(k+1) = a d_k + b, where (a, b) is the
// result, the back of slice k lies at view depth near + d_(k+1). From z(t) above,
// a = exp(curve / slices) and b = (far - near) (a - 1) / (exp(curve) - 1); below
// CURVE_LINEAR_LIMIT b is its series in curve (relative error < 1e-6). No exp or branch
// is left per slice; the rounding of the walk drifts by less than 3e-5 of the depth over
// 256 slices.
fn slice_walk(slices: u32, near: f32, far: f32, curve: f32) -> vec2<f32> {
    let step = 1.0 / f32(slices);
    let a = exp(curve * step);
    let span = far - near;
    if curve < CURVE_LINEAR_LIMIT {
        return vec2<f32>(a, span * step * (1.0 + 0.5 * curve * (step - 1.0)));
    }
    return vec2<f32>(a, span * ((a - 1.0) / (exp(curve) - 1.0)));
}

// Normalised slice coordinate of view depth z (m); z is clamped to >= near, so the
// result is >= 0. Depths beyond far give t > 1.
fn slice_coord(z: f32, near: f32, far: f32, curve: f32) -> f32 {
    let s = max(z - near, 0.0) / (far - near);
    if curve < CURVE_LINEAR_LIMIT {
        return s - 0.5 * curve * s * (s - 1.0);
    }
    return log(1.0 + s * (exp(curve) - 1.0)) / curve;
}

// Normalised device x, y (y up) of a screen uv (v down).
fn ndc_from_uv(uv: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
}

// Screen uv (v down) of normalised device x, y (y up).
fn uv_from_ndc(ndc: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// View-space position of a point given in normalised device coordinates
// (x, y in [-1, 1], depth as stored in the depth buffer). Works for standard,
// reversed and infinite perspective projections; a point at infinity returns a
// position whose depth is the largest finite f32.
fn view_from_ndc(ndc: vec3<f32>, view_from_clip: mat4x4<f32>) -> vec3<f32> {
    let p = view_from_clip * vec4<f32>(ndc, 1.0);
    let w = select(p.w, 1e-30, abs(p.w) < 1e-30);
    return clamp(p.xyz / w, vec3<f32>(-3.0e38), vec3<f32>(3.0e38));
}

// Length of the view ray through screen uv per metre of view depth (>= 1): a slice of
// thickness dz is crossed over a path of dz * ray_scale.
fn ray_scale(uv: vec2<f32>, view_from_clip: mat4x4<f32>) -> f32 {
    // Any depth strictly inside the clip volume lies on the ray; 0.5 stays finite for
    // standard, reversed and infinite projections.
    let p = view_from_ndc(vec3<f32>(ndc_from_uv(uv), 0.5), view_from_clip);
    return length(p) / max(abs(p.z), 1e-30);
}

// Radical inverse of index in the given base (Halton sequence), in [0, 1).
fn halton(index: u32, base: u32) -> f32 {
    var f = 1.0;
    var r = 0.0;
    var i = index;
    let inv = 1.0 / f32(base);
    while i > 0u {
        f *= inv;
        r += f * f32(i % base);
        i /= base;
    }
    return r;
}

// Sample offset inside a froxel for frame `frame` (froxel units, [-0.5, 0.5)^3): the
// Halton (2, 3, 5) point of index frame % 16 + 1 (Wronski 2014, "Sample jittering").
fn froxel_jitter(frame: u32) -> vec3<f32> {
    let i = frame % 16u + 1u;
    return vec3<f32>(halton(i, 2u), halton(i, 3u), halton(i, 5u)) - 0.5;
}

// View-space position (m) of a point inside froxel `id` at offset `offset` from its
// centre (froxel units): x, y through the screen uv, z through the slice distribution.
fn froxel_view_position(
    id: vec3<u32>,
    offset: vec3<f32>,
    size: vec3<u32>,
    view_from_clip: mat4x4<f32>,
    near: f32,
    far: f32,
    curve: f32,
) -> vec3<f32> {
    let cell = (vec3<f32>(id) + 0.5 + offset) / vec3<f32>(size);
    let depth = slice_depth(cell.z, near, far, curve);
    let ray = view_from_ndc(vec3<f32>(ndc_from_uv(cell.xy), 0.5), view_from_clip);
    return ray * (depth / max(abs(ray.z), 1e-30));
}

// Depth culling. The apply pass and the forward snippet read, for a point at view depth
// z, the integrated texels floor(s) - 1 and floor(s) with s = slice_coord(z) * N, and
// integrated texel k depends on the scattering of slices 0..=k; the bilinear look-up in
// x and y reads the columns whose centres lie within one column of the point. So a
// column whose screen footprint, widened by half a column on every side, holds opaque
// surfaces no farther than view depth z_max needs its first floor(s_max) + 1 slices;
// froxel_live_slices adds one more so that the rounding of the depth conversion in
// different passes cannot uncover a skipped slice. Transparent surfaces lie in front
// of the opaque depth, so they read live slices too.

// Number of leading slices (2..=slices) of a column that can be read when its farthest
// opaque surface lies at view depth max_depth (m); depths beyond far give every slice.
fn froxel_live_slices(max_depth: f32, slices: u32, near: f32, far: f32, curve: f32) -> u32 {
    let s = slice_coord(max_depth, near, far, curve) * f32(slices);
    let first = u32(clamp(floor(s), 0.0, f32(slices)));
    return min(first + 2u, slices);
}

// Depth culling reduces the depth buffer in two steps: per cell of half a column on
// each axis (a grid of 2 size.x x 2 size.y cells), then per column over the 4 x 4 cells
// 2 i - 1 ..= 2 i + 2 that make up its footprint widened by half a column on each side
// (the reach of the bilinear look-up); each texel is read once.

// The texels (inclusive min.xy, max.xy) of a depth texture of size texels that overlap
// cell `cell` of a grid of `cells` cells; works for any depth resolution, e.g. a
// conservative (farthest-depth) level of a hierarchical depth buffer.
fn froxel_cull_cell(cell: vec2<u32>, cells: vec2<u32>, texels: vec2<u32>) -> vec4<u32> {
    let scale = vec2<f32>(texels) / vec2<f32>(cells);
    let top = vec2<f32>(texels) - 1.0;
    let lo = vec2<u32>(clamp(floor(vec2<f32>(cell) * scale), vec2<f32>(0.0), top));
    let hi = vec2<u32>(clamp(floor(vec2<f32>(cell + 1u) * scale), vec2<f32>(0.0), top));
    return vec4<u32>(lo, hi);
}

// Froxel blocks. inject and temporal give each workgroup a block of
// FROXEL_BLOCK_X x FROXEL_BLOCK_Y x FROXEL_BLOCK_Z froxels, each invocation a pair of
// slices (2 k, 2 k + 1) of one column. With depth culling the blocks that hold live
// froxels are listed (froxel_cull_compact) and the passes are dispatched indirectly
// over the list, one workgroup per block; a list item packs the block coordinates as
// x | y << 11 | z << 22 (volume axes are at most 2048 froxels).
const FROXEL_BLOCK_X: u32 = 4u;
const FROXEL_BLOCK_Y: u32 = 4u;
const FROXEL_BLOCK_Z: u32 = 8u;

fn froxel_block_pack(block: vec3<u32>) -> u32 {
    return block.x | (block.y << 11u) | (block.z << 22u);
}

fn froxel_block_unpack(item: u32) -> vec3<u32> {
    return vec3<u32>(item & 0x7ffu, (item >> 11u) & 0x7ffu, item >> 22u);
}

// Whether froxel id is injected this frame when injection is amortised over two frames
// in a 3D checkerboard (FogFrame.checkerboard = 1): the froxels with x + y + z + index
// even, one of each pair of slices (2 k, 2 k + 1).
fn froxel_injected(id: vec3<u32>, index: u32, checkerboard: u32) -> bool {
    return checkerboard == 0u || ((id.x + id.y + id.z + index) & 1u) == 0u;
}
