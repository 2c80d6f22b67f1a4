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
// The reprojection and the blend are volfog::temporal's; inject under
// VOLFOG_INJECT_TEMPORAL runs the same blend fused, without this pass.
// Defines: VOLFOG_FROXEL_CULL.

#import volfog::types::{Froxels, FogFrame, HistoryState}
#import volfog::froxel::{froxel_injected, froxel_block_unpack, FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z}
#import volfog::temporal::{temporal_history_column, temporal_history_slice_uvw, temporal_blend}
#ifdef VOLFOG_FROXEL_CULL
#import volfog::temporal::temporal_history_live
#endif

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

// Live slices of column xy this frame (every slice without culling).
fn live(xy: vec2<u32>) -> u32 {
#ifdef VOLFOG_FROXEL_CULL
    return textureLoad(live_slices, xy, 0).r;
#else
    return froxels.size.z;
#endif
}

// The stabilised value of froxel id, whose value this frame is now.
fn stabilise(column: mat2x4<f32>, id: vec3<u32>, now: vec4<f32>) -> vec4<f32> {
    let at = temporal_history_slice_uvw(column, id.z, froxels, history_state.valid, frame.history_enabled);
    if at.w == 0.0 {
        return now;
    }
#ifdef VOLFOG_FROXEL_CULL
    if !temporal_history_live(at.xyz, froxels.size, history_live_slices) {
        return now;
    }
#endif
    let past = textureSampleLevel(history, history_sampler, at.xyz, 0.0);
    return temporal_blend(now, past, froxel_injected(id, frame.index, frame.checkerboard), frame.history_weight);
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
    let column = temporal_history_column(pair.xy, froxels, frame.world_from_view, history_state);
    for (var id = pair; id.z < min(pair.z + 2u, slices); id.z++) {
        textureStore(stabilised, id, stabilise(column, id, textureLoad(current, id, 0)));
    }
}
