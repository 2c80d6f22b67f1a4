// Pass froxel_cull — how many leading slices of each froxel column can be seen, from
// the scene's depth buffer (volfog::froxel, "Depth culling").
//
// Dispatch: size.x x size.y x 1 workgroups of 8 x 8 (one workgroup per froxel column).
// Bindings (group 0):
//   0  uniform Froxels
//   1  texture_2d<f32>: the scene depth (depth-buffer values, standard, reversed or
//      infinite projection), bound as unfilterable float; any resolution covering the
//      screen works, e.g. a level of a hierarchical depth buffer that keeps the farthest
//      depth of its texels
//   2  texture_storage_2d<r32uint, write>: live slices per column (size.x x size.y),
//      read by inject, temporal and scan under VOLFOG_FROXEL_CULL
// Each column takes the nearest and the farthest depth-buffer value over its footprint
// (froxel_cull_footprint), converts both to view depth and keeps the larger, so the
// direction of the depth range does not matter.
// Defines: none.

#import volfog::types::Froxels
#import volfog::froxel::{froxel_cull_footprint, froxel_live_slices, view_from_ndc}

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var scene_depth: texture_2d<f32>;
@group(0) @binding(2) var live_slices: texture_storage_2d<r32uint, write>;

// Bit patterns of depths in [0, 1]: their order is the order of the values.
var<workgroup> lowest: atomic<u32>;
var<workgroup> highest: atomic<u32>;

@compute @workgroup_size(8, 8, 1)
fn froxel_cull(
    @builtin(workgroup_id) column: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
) {
    if local_index == 0u {
        atomicStore(&lowest, 0x3f800000u);
        atomicStore(&highest, 0u);
    }
    workgroupBarrier();
    let rect = froxel_cull_footprint(column.xy, froxels.size.xy, textureDimensions(scene_depth));
    var lo = 1.0;
    var hi = 0.0;
    for (var y = rect.y + local.y; y <= rect.w; y += 8u) {
        for (var x = rect.x + local.x; x <= rect.z; x += 8u) {
            // max/min with 0 and 1 also turn a NaN texel into a bound.
            let d = min(max(textureLoad(scene_depth, vec2<u32>(x, y), 0).r, 0.0), 1.0);
            lo = min(lo, d);
            hi = max(hi, d);
        }
    }
    atomicMin(&lowest, bitcast<u32>(lo));
    atomicMax(&highest, bitcast<u32>(hi));
    workgroupBarrier();
    if local_index != 0u || any(column.xy >= froxels.size.xy) {
        return;
    }
    let near_value = bitcast<f32>(atomicLoad(&lowest));
    let far_value = bitcast<f32>(atomicLoad(&highest));
    let a = abs(view_from_ndc(vec3<f32>(0.0, 0.0, near_value), froxels.view_from_clip).z);
    let b = abs(view_from_ndc(vec3<f32>(0.0, 0.0, far_value), froxels.view_from_clip).z);
    let live = froxel_live_slices(max(a, b), froxels.size.z, froxels.near, froxels.far, froxels.curve);
    textureStore(live_slices, column.xy, vec4<u32>(live, 0u, 0u, 0u));
}
