// Pass epipolar_tree — the 1D min/max binary tree of the shadow map per epipolar slice
// (Yusov 2012, 6.3; Chen et al. 2011), built level by level in two ping-pong textures.
//
// Row j of the tree textures holds the minima of slice j, row slices + j its maxima.
// Level l (0 = the height map h itself) starts at column epipolar_level_offset(
// shadow_size, l) = 2 S - 2 S / 2^l and holds S / 2^l nodes; even levels live in tree
// texture 0, odd levels in texture 1.
// Dispatch: epipolar_tree_init ceil(S / 64) x slices workgroups writing texture 0;
// then for l = 1 .. log2(S) epipolar_tree_level ceil((S >> l) / 64) x slices reading
// the texture of level l - 1 and writing the other (tree_level.x = l).
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 texture_2d_array<f32>: the shadow map (cascades as layers, side shadow_size)
//   2 texture_2d<f32>, unfilterable: the tree texture of level l - 1 (r32float,
//     2 S x 2 slices)
//   3 storage texture r32float (2 S x 2 slices), write: the tree texture of level l
//   4 uniform vec4<u32>: x the level l being built (0 for epipolar_tree_init)

#import volfog::types::EpipolarFrame
#import volfog::epipolar::{epipolar_slice_map, epipolar_height, epipolar_level_offset}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(2) var tree_src: texture_2d<f32>;
@group(0) @binding(3) var tree_dst: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var<uniform> tree_level: vec4<u32>;

@compute @workgroup_size(64, 1, 1)
fn epipolar_tree_init(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= epipolar_frame.shadow_size || id.y >= epipolar_frame.slices {
        return;
    }
    let map = epipolar_slice_map(epipolar_frame, id.y);
    let h = epipolar_height(shadow_map, epipolar_frame.cascade, map, id.x, epipolar_frame.shadow_size);
    textureStore(tree_dst, vec2<i32>(id.xy), vec4<f32>(h, 0.0, 0.0, 0.0));
    textureStore(tree_dst, vec2<i32>(id.xy + vec2<u32>(0u, epipolar_frame.slices)), vec4<f32>(h, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(64, 1, 1)
fn epipolar_tree_level(@builtin(global_invocation_id) id: vec3<u32>) {
    let level = tree_level.x;
    if id.x >= (epipolar_frame.shadow_size >> level) || id.y >= epipolar_frame.slices {
        return;
    }
    let src_at = i32(epipolar_level_offset(epipolar_frame.shadow_size, level - 1u) + 2u * id.x);
    let lo = i32(id.y);
    let hi = i32(id.y + epipolar_frame.slices);
    let min_a = textureLoad(tree_src, vec2<i32>(src_at, lo), 0).r;
    let min_b = textureLoad(tree_src, vec2<i32>(src_at + 1, lo), 0).r;
    let max_a = textureLoad(tree_src, vec2<i32>(src_at, hi), 0).r;
    let max_b = textureLoad(tree_src, vec2<i32>(src_at + 1, hi), 0).r;
    let dst_at = i32(epipolar_level_offset(epipolar_frame.shadow_size, level) + id.x);
    textureStore(tree_dst, vec2<i32>(dst_at, lo), vec4<f32>(min(min_a, min_b), 0.0, 0.0, 0.0));
    textureStore(tree_dst, vec2<i32>(dst_at, hi), vec4<f32>(max(max_a, max_b), 0.0, 0.0, 0.0));
}
