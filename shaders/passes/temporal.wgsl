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
// Defines: none.

#import volfog::types::{Froxels, FogFrame, HistoryState}
#import volfog::froxel::{froxel_view_position, slice_coord, uv_from_ndc}

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var<uniform> frame: FogFrame;
@group(0) @binding(2) var current: texture_3d<f32>;
@group(0) @binding(3) var history: texture_3d<f32>;
@group(0) @binding(4) var history_sampler: sampler;
@group(0) @binding(5) var stabilised: texture_storage_3d<rgba16float, write>;
@group(0) @binding(6) var<storage, read> history_state: HistoryState;
@group(0) @binding(7) var<storage, read_write> stabilised_state: HistoryState;

@compute @workgroup_size(4, 4, 4)
fn temporal(@builtin(global_invocation_id) id: vec3<u32>) {
    if all(id == vec3<u32>(0u)) {
        stabilised_state = HistoryState(frame.clip_from_world, 1u);
    }
    if any(id >= froxels.size) {
        return;
    }
    let now = textureLoad(current, id, 0);
    let view = froxel_view_position(
        id, vec3<f32>(0.0), froxels.size, froxels.view_from_clip, froxels.near, froxels.far, froxels.curve);
    let world = frame.world_from_view * vec4<f32>(view, 1.0);
    let clip = history_state.clip_from_world * world;
    var result = now;
    if frame.history_enabled != 0u && history_state.valid != 0u && clip.w > 1e-6 {
        let uv = uv_from_ndc(clip.xy / clip.w);
        let w = slice_coord(clip.w, froxels.near, froxels.far, froxels.curve);
        let uvw = vec3<f32>(uv, w);
        if all(uvw >= vec3<f32>(0.0)) && all(uvw <= vec3<f32>(1.0)) {
            let past = textureSampleLevel(history, history_sampler, uvw, 0.0);
            result = mix(now, past, clamp(frame.history_weight, 0.0, 1.0));
        }
    }
    textureStore(stabilised, id, result);
}
