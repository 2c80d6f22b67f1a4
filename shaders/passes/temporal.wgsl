// Pass temporal — blends the newly injected scattering volume with the previous
// frame's, reprojected (Wronski 2014, "Temporal reprojection", "Volumetric reprojection").
//
// Dispatch: ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 8) workgroups of
// 4 x 4 x 4, each covering a block of 4 x 4 x 8 froxels, each invocation the pair of
// slices (2 k, 2 k + 1) of one column (volfog::froxel, "Froxel blocks"); under
// VOLFOG_FROXEL_CULL indirectly, as inject.
// Bindings (group 0):
//   0  uniform Froxels             1  uniform FogFrame
//   2  texture_3d<f32>: this frame's scattering volume (textureLoad)
//   3  texture_3d<f32>: the history (last frame's output), filterable
//   4  sampler, linear, clamp to edge
//   5  texture_storage_3d<rgba16float, write>: the stabilised volume (next frame's history)
//   6  storage, read: HistoryState of the history (binding 3)
//   7  storage, read_write: HistoryState of the stabilised volume (binding 5); invocation
//      (0, 0, 0) of block (0, 0, 0) writes this frame's camera into it
//   8  texture_2d<u32>: live slices of this frame (VOLFOG_FROXEL_CULL only)
//   9  texture_2d<u32>: live slices the history was written with (VOLFOG_FROXEL_CULL only)
//  10  storage, read: array<u32>, the live blocks (VOLFOG_FROXEL_CULL only)
// Ping-pong two volumes and their two HistoryState buffers by frame parity. The froxel's
// centre is projected with the camera the history was written with (its HistoryState,
// not the previous frame's inputs: a frame that was never submitted leaves both the
// volume and its state unchanged), and the history is used only when it lands inside
// that volume. The centre, not the jittered
// sample, is reprojected: each history texel stands for its whole froxel, so a static
// camera reads history texels exactly and the jitter averages out instead of being
// re-blurred by interpolation weights that change every frame. Limits: history is
// view-dependent (anisotropic phase), so fast camera rotation with strong forward
// scattering lags by about 1 / (1 - history_weight) frames; the same lag applies to
// lighting changes (0.9: error below 5 % after 29 frames, below 1 % after 44).
// Amortised injection (FogFrame.checkerboard = 1): a froxel inject skipped this frame
// takes the reprojected history alone, and where there is none (first frame, camera
// cut, disocclusion) the value inject wrote for its pair. Each froxel then takes new
// light every other frame, so a lighting change settles in about twice as many frames
// (0.9: below 5 % after 57, below 1 % after 91).
// Depth culling (VOLFOG_FROXEL_CULL): froxels behind their column's live slices are
// neither read nor written, so the history may hold stale texels there. The history is
// used only when every texel its trilinear look-up weighs by HISTORY_REACH or more was
// live when the history was written; otherwise the froxel starts again from this
// frame's value. A stale texel thus weighs less than HISTORY_REACH per axis (a static
// camera weighs neighbours by rounding error only) and only where the history is
// kept.
// Defines: VOLFOG_FROXEL_CULL.

#import volfog::types::{Froxels, FogFrame, HistoryState}
#import volfog::froxel::{froxel_view_position, froxel_injected, froxel_block_unpack, slice_coord, uv_from_ndc, FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z}

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var<uniform> frame: FogFrame;
@group(0) @binding(2) var current: texture_3d<f32>;
@group(0) @binding(3) var history: texture_3d<f32>;
@group(0) @binding(4) var history_sampler: sampler;
@group(0) @binding(5) var stabilised: texture_storage_3d<rgba16float, write>;
@group(0) @binding(6) var<storage, read> history_state: HistoryState;
@group(0) @binding(7) var<storage, read_write> stabilised_state: HistoryState;
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(8) var live_slices: texture_2d<u32>;
@group(0) @binding(9) var history_live_slices: texture_2d<u32>;
@group(0) @binding(10) var<storage, read> live_blocks: array<u32>;
#endif

// Below this trilinear weight (per axis) a history texel is not required to be live.
const HISTORY_REACH: f32 = 0.015625;

// Live slices of column xy this frame (every slice without culling).
fn live(xy: vec2<u32>) -> u32 {
#ifdef VOLFOG_FROXEL_CULL
    return textureLoad(live_slices, xy, 0).r;
#else
    return froxels.size.z;
#endif
}

// Whether every texel the trilinear look-up of the history at uvw weighs by
// HISTORY_REACH or more was live when the history was written.
fn history_live(uvw: vec3<f32>) -> bool {
#ifdef VOLFOG_FROXEL_CULL
    let size = froxels.size;
    let texel = uvw * vec3<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let top = vec3<f32>(size - 1u);
    let lo = vec3<u32>(clamp(base, vec3<f32>(0.0), top));
    let hi = vec3<u32>(clamp(base + 1.0, vec3<f32>(0.0), top));
    // The columns and the deepest slice that carry weight.
    let x0 = select(hi.x, lo.x, 1.0 - f.x >= HISTORY_REACH);
    let x1 = select(lo.x, hi.x, f.x >= HISTORY_REACH);
    let y0 = select(hi.y, lo.y, 1.0 - f.y >= HISTORY_REACH);
    let y1 = select(lo.y, hi.y, f.y >= HISTORY_REACH);
    let deepest = select(lo.z, hi.z, f.z >= HISTORY_REACH);
    let a = min(textureLoad(history_live_slices, vec2<u32>(x0, y0), 0).r,
                textureLoad(history_live_slices, vec2<u32>(x1, y0), 0).r);
    let b = min(textureLoad(history_live_slices, vec2<u32>(x0, y1), 0).r,
                textureLoad(history_live_slices, vec2<u32>(x1, y1), 0).r);
    return deepest < min(a, b);
#else
    return true;
#endif
}

// The stabilised value of froxel id.
fn stabilise(id: vec3<u32>) -> vec4<f32> {
    let now = textureLoad(current, id, 0);
    let view = froxel_view_position(
        id, vec3<f32>(0.0), froxels.size, froxels.view_from_clip, froxels.near, froxels.far, froxels.curve);
    let world = frame.world_from_view * vec4<f32>(view, 1.0);
    let clip = history_state.clip_from_world * world;
    if frame.history_enabled == 0u || history_state.valid == 0u || clip.w <= 1e-6 {
        return now;
    }
    let uv = uv_from_ndc(clip.xy / clip.w);
    let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
    let uvw = vec3<f32>(uv, w);
    if any(uvw < vec3<f32>(0.0)) || any(uvw > vec3<f32>(1.0)) || !history_live(uvw) {
        return now;
    }
    let past = textureSampleLevel(history, history_sampler, uvw, 0.0);
    if froxel_injected(id, frame.index, frame.checkerboard) {
        return mix(now, past, clamp(frame.history_weight, 0.0, 1.0));
    }
    return past;
}

@compute @workgroup_size(4, 4, 4)
fn temporal(
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(workgroup_id) group: vec3<u32>,
) {
#ifdef VOLFOG_FROXEL_CULL
    let block = froxel_block_unpack(live_blocks[group.x]);
#else
    let block = group;
#endif
    let pair = block * vec3<u32>(FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z)
        + vec3<u32>(local.xy, 2u * local.z);
    if all(pair == vec3<u32>(0u)) {
        stabilised_state = HistoryState(frame.clip_from_world, 1u);
    }
    if any(pair >= froxels.size) {
        return;
    }
    let slices = min(live(pair.xy), froxels.size.z);
    for (var id = pair; id.z < min(pair.z + 2u, slices); id.z++) {
        textureStore(stabilised, id, stabilise(id));
    }
}
