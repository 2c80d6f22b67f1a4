// Pass epipolar_tree — the 1D min/max binary tree of the shadow map per epipolar slice
// (Yusov 2012, 6.3; Chen et al. 2011), built level by level.
//
// Row j of the tree texture (rgba32float, shadow_size x slices) holds slice j's levels
// one after the other, two (min, max) nodes per texel (volfog::epipolar::
// epipolar_tree_node): level l (0 = the height map h itself) starts at node
// epipolar_level_offset(shadow_size, l) = 2 S - 2 S / 2^l and has S / 2^l nodes.
// Dispatch: epipolar_tree_init ceil(S / 2 / 64) x slices workgroups writing level 0
// into the tree texture (binding 3; binding 2 is then the scratch texture, unread).
// Then for l = 1 .. log2(S): epipolar_tree_level ceil(max(S >> l, 2) / 2 / 64) x slices
// reading level l - 1 from the tree texture (binding 2) into texel 0.. of the scratch
// texture (binding 3, rgba32float, at least S / 4 x slices), followed by a copy of
// those max(S >> l, 2) / 2 texels into the tree texture at texel
// epipolar_level_offset(S, l) / 2 (tree_level.x = l).
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 texture_2d_array<f32>, unfilterable: the shadow map (cascades as layers, side
//     shadow_size)
//   2 texture_2d<f32>, unfilterable: the tree texture (levels below l)
//   3 storage texture rgba32float, write: the tree texture (init) or the scratch
//     texture (levels)
//   4 uniform vec4<u32>: x the level l being built (0 for epipolar_tree_init)

#import volfog::types::EpipolarFrame
#import volfog::epipolar::{epipolar_slice_map, epipolar_height, epipolar_level_offset}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(2) var tree_src: texture_2d<f32>;
@group(0) @binding(3) var tree_dst: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var<uniform> tree_level: vec4<u32>;

@compute @workgroup_size(64, 1, 1)
fn epipolar_tree_init(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = epipolar_frame.shadow_size;
    if 2u * id.x >= size || id.y >= epipolar_frame.slices {
        return;
    }
    let map = epipolar_slice_map(epipolar_frame, id.y);
    let bias = epipolar_frame.depth_bias;
    let h0 = epipolar_height(shadow_map, epipolar_frame.cascade, map, 2u * id.x, size, bias);
    let h1 = epipolar_height(shadow_map, epipolar_frame.cascade, map, 2u * id.x + 1u, size, bias);
    textureStore(tree_dst, vec2<i32>(id.xy), vec4<f32>(h0, h0, h1, h1));
}

@compute @workgroup_size(64, 1, 1)
fn epipolar_tree_level(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = epipolar_frame.shadow_size;
    let level = tree_level.x;
    let nodes = size >> level;
    if 2u * id.x >= nodes || id.y >= epipolar_frame.slices {
        return;
    }
    // Output nodes 2x and 2x + 1 come from input nodes 4x .. 4x + 3: texels 2x, 2x + 1.
    let src = i32(epipolar_level_offset(size, level - 1u) / 2u + 2u * id.x);
    let row = i32(id.y);
    let a = textureLoad(tree_src, vec2<i32>(src, row), 0);
    var out = vec4<f32>(min(a.x, a.z), max(a.y, a.w), 0.0, 0.0);
    if nodes > 1u {
        let b = textureLoad(tree_src, vec2<i32>(src + 1, row), 0);
        out = vec4<f32>(out.xy, min(b.x, b.z), max(b.y, b.w));
    }
    textureStore(tree_dst, vec2<i32>(id.xy), out);
}
