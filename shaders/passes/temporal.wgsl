// Pass temporal — blends the newly injected scattering volume with the previous
// frame's, reprojected (Wronski 2014, "Temporal reprojection", "Volumetric reprojection").
//
// Dispatch: ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 4) workgroups of 4 x 4 x 4.
// Bindings (group 0):
//   0  uniform Froxels             1  uniform FogFrame
//   2  texture_3d<f32>: this frame's scattering volume (textureLoad)
//   3  texture_3d<f32>: the history (last frame's output), filterable
//   4  sampler, linear, clamp to edge
//   5  texture_storage_3d<rgba16float, write>: the stabilised volume (next frame's history)
//   6  storage, read: HistoryState of the history (binding 3)
//   7  storage, read_write: HistoryState of the stabilised volume (binding 5); invocation
//      (0, 0, 0) writes this frame's camera into it
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
// takes the reprojected history alone; where there is none (first frame, camera cut,
// disocclusion) it takes the mean of its live face neighbours, which inject wrote this
// frame. Each froxel then takes new light every other frame, so a lighting change
// settles in about twice as many frames (0.9: below 5 % after 57, below 1 % after 91).
// Depth culling (VOLFOG_FROXEL_CULL): froxels behind their column's live slices are
// neither read nor written, and the history look-up gives no weight to texels that
// were not live when the history was written (see history_at): where they would carry
// half the weight or more the froxel starts again from this frame's value, so skipped
// (stale) texels never reach the volume.
//   8  texture_2d<u32>: live slices of this frame (froxel_cull)
//   9  texture_2d<u32>: live slices the history was written with
// Defines: VOLFOG_FROXEL_CULL.

#import volfog::types::{Froxels, FogFrame, HistoryState}
#import volfog::froxel::{froxel_view_position, froxel_injected, slice_coord, uv_from_ndc}

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
#endif

// Live slices of column xy this frame (every slice without culling).
fn live(xy: vec2<u32>) -> u32 {
#ifdef VOLFOG_FROXEL_CULL
    return textureLoad(live_slices, xy, 0).r;
#else
    return froxels.size.z;
#endif
}

// The history at texture coordinate uvw and whether there is one (weight 1 or 0).
// Without culling it is one filtered sample. With culling, when
// every texel the trilinear look-up can touch was live when the history was written,
// it is the same sample; otherwise the eight texels are loaded, those that were not
// live get no weight and the others are renormalised, and there is no history
// (weight 0) when the live texels carry less than half the weight.
struct Past {
    value: vec4<f32>,
    weight: f32,
}

fn history_at(uvw: vec3<f32>) -> Past {
#ifdef VOLFOG_FROXEL_CULL
    let size = froxels.size;
    let texel = uvw * vec3<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let lo = vec3<u32>(clamp(base, vec3<f32>(0.0), vec3<f32>(size - 1u)));
    let hi = min(lo + 1u, size - 1u);
    let a = min(textureLoad(history_live_slices, lo.xy, 0).r, textureLoad(history_live_slices, vec2<u32>(hi.x, lo.y), 0).r);
    let b = min(textureLoad(history_live_slices, vec2<u32>(lo.x, hi.y), 0).r, textureLoad(history_live_slices, hi.xy, 0).r);
    if hi.z < min(a, b) {
        return Past(textureSampleLevel(history, history_sampler, uvw, 0.0), 1.0);
    }
    var sum = vec4<f32>(0.0);
    var weight = 0.0;
    for (var k = 0u; k < 8u; k++) {
        let corner = vec3<u32>(k & 1u, (k >> 1u) & 1u, k >> 2u);
        let w = select(1.0 - f.x, f.x, corner.x == 1u)
            * select(1.0 - f.y, f.y, corner.y == 1u)
            * select(1.0 - f.z, f.z, corner.z == 1u);
        let p = vec3<u32>(clamp(base + vec3<f32>(corner), vec3<f32>(0.0), vec3<f32>(size - 1u)));
        if w > 0.0 && p.z < textureLoad(history_live_slices, p.xy, 0).r {
            sum += w * textureLoad(history, p, 0);
            weight += w;
        }
    }
    if weight < 0.5 {
        return Past(vec4<f32>(0.0), 0.0);
    }
    return Past(sum / weight, 1.0);
#else
    return Past(textureSampleLevel(history, history_sampler, uvw, 0.0), 1.0);
#endif
}

@compute @workgroup_size(4, 4, 4)
fn temporal(@builtin(global_invocation_id) id: vec3<u32>) {
    if all(id == vec3<u32>(0u)) {
        stabilised_state = HistoryState(frame.clip_from_world, 1u);
    }
    if any(id >= froxels.size) || id.z >= live(id.xy) {
        return;
    }
    let view = froxel_view_position(
        id, vec3<f32>(0.0), froxels.size, froxels.view_from_clip, froxels.near, froxels.far, froxels.curve);
    let world = frame.world_from_view * vec4<f32>(view, 1.0);
    let clip = history_state.clip_from_world * world;
    var has_past = false;
    var past = vec4<f32>(0.0);
    if frame.history_enabled != 0u && history_state.valid != 0u && clip.w > 1e-6 {
        let uv = uv_from_ndc(clip.xy / clip.w);
        let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
        let uvw = vec3<f32>(uv, w);
        if all(uvw >= vec3<f32>(0.0)) && all(uvw <= vec3<f32>(1.0)) {
            let sample = history_at(uvw);
            past = sample.value;
            has_past = sample.weight > 0.0;
        }
    }
    var result: vec4<f32>;
    if froxel_injected(id, frame.index, frame.checkerboard) {
        result = textureLoad(current, id, 0);
        if has_past {
            result = mix(result, past, clamp(frame.history_weight, 0.0, 1.0));
        }
    } else if has_past {
        result = past;
    } else {
        // Every face neighbour was injected this frame; average those that are live.
        var sum = vec4<f32>(0.0);
        var count = 0.0;
        for (var k = 0u; k < 6u; k++) {
            let step = select(-1, 1, (k & 1u) == 1u);
            var offset = vec3<i32>(0, 0, step);
            if k < 2u {
                offset = vec3<i32>(step, 0, 0);
            } else if k < 4u {
                offset = vec3<i32>(0, step, 0);
            }
            let n = vec3<i32>(id) + offset;
            if all(n >= vec3<i32>(0)) && all(n < vec3<i32>(froxels.size)) {
                let m = vec3<u32>(n);
                if m.z < live(m.xy) {
                    sum += textureLoad(current, m, 0);
                    count += 1.0;
                }
            }
        }
        result = sum / max(count, 1.0);
    }
    textureStore(stabilised, id, result);
}
