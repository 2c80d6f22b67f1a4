// Pass froxel_cull — how many leading slices of each froxel column can be seen, from
// the scene's depth buffer (volfog::froxel, "Depth culling"), and the list of froxel
// blocks that hold live froxels, for the indirect dispatches of inject and temporal.
//
// Entry points, run in this order:
//   froxel_cull_cells    dispatch ceil(2 size.x / 8) x ceil(2 size.y / 8) x 1 workgroups
//                        of 8 x 8, one invocation per cell of half a column
//   froxel_cull          dispatch ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups of
//                        8 x 8, one invocation per column; also resets the dispatch
//                        arguments to (0, 1, 1)
//   froxel_cull_compact  dispatch ceil(blocks_x / 8) x ceil(blocks_y / 8) x 1 workgroups
//                        of 8 x 8, blocks_x = ceil(size.x / FROXEL_BLOCK_X), blocks_y
//                        likewise (one invocation per column of blocks)
// Bindings (group 0):
//   0  uniform Froxels
//   1  texture_2d<f32>: the scene depth (depth-buffer values, standard, reversed or
//      infinite projection), bound as unfilterable float; any resolution covering the
//      screen works, e.g. a level of a hierarchical depth buffer that keeps the farthest
//      depth of its texels
//   2  texture_storage_2d<r32uint, read_write>: live slices per column (size.x x
//      size.y), read by inject, temporal and scan under VOLFOG_FROXEL_CULL
//   3  storage, read_write: array<u32>, the live blocks (packed by froxel_block_pack),
//      room for blocks_x * blocks_y * ceil(size.z / FROXEL_BLOCK_Z) items
//   4  storage, read_write: BlockDispatch, the indirect dispatch arguments of inject and
//      temporal (x = number of listed blocks, y = z = 1)
//   5  storage, read_write: array<f32>, the farthest view depth (m) per cell, room for
//      4 size.x size.y values
// Each cell takes the nearest and the farthest depth-buffer value of the texels it
// overlaps (froxel_cull_cell), converts both to view depth and keeps the larger, so the
// direction of the depth range does not matter. A block is listed when a column of it
// has live slices in the block's depth range.
// Defines: none.

#import volfog::types::Froxels
#import volfog::froxel::{froxel_cull_cell, froxel_live_slices, froxel_block_pack, view_from_ndc, FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z}

// Indirect dispatch arguments (12 bytes).
struct BlockDispatch {
    x: atomic<u32>,
    y: u32,
    z: u32,
}

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var scene_depth: texture_2d<f32>;
@group(0) @binding(2) var live_slices: texture_storage_2d<r32uint, read_write>;
@group(0) @binding(3) var<storage, read_write> blocks: array<u32>;
@group(0) @binding(4) var<storage, read_write> dispatch: BlockDispatch;
@group(0) @binding(5) var<storage, read_write> cell_depths: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn froxel_cull_cells(@builtin(global_invocation_id) cell: vec3<u32>) {
    let cells = 2u * froxels.size.xy;
    if any(cell.xy >= cells) {
        return;
    }
    let rect = froxel_cull_cell(cell.xy, cells, textureDimensions(scene_depth));
    var lo = 1.0;
    var hi = 0.0;
    for (var y = rect.y; y <= rect.w; y++) {
        for (var x = rect.x; x <= rect.z; x++) {
            // max/min with 0 and 1 also turn a NaN texel into a bound.
            let d = min(max(textureLoad(scene_depth, vec2<u32>(x, y), 0).r, 0.0), 1.0);
            lo = min(lo, d);
            hi = max(hi, d);
        }
    }
    let a = abs(view_from_ndc(vec3<f32>(0.0, 0.0, lo), froxels.view_from_clip).z);
    let b = abs(view_from_ndc(vec3<f32>(0.0, 0.0, hi), froxels.view_from_clip).z);
    cell_depths[cell.y * cells.x + cell.x] = max(a, b);
}

@compute @workgroup_size(8, 8, 1)
fn froxel_cull(@builtin(global_invocation_id) column: vec3<u32>) {
    if all(column.xy == vec2<u32>(0u)) {
        atomicStore(&dispatch.x, 0u);
        dispatch.y = 1u;
        dispatch.z = 1u;
    }
    let size = froxels.size;
    if any(column.xy >= size.xy) {
        return;
    }
    // Cells 2 i - 1 ..= 2 i + 2 on each axis, within the grid.
    let cells = 2u * size.xy;
    let first = max(2u * column.xy, vec2<u32>(1u)) - 1u;
    let last = min(2u * column.xy + 2u, cells - 1u);
    var deepest = 0.0;
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            deepest = max(deepest, cell_depths[y * cells.x + x]);
        }
    }
    let live = froxel_live_slices(deepest, size.z, froxels.near, froxels.far, froxels.curve);
    textureStore(live_slices, column.xy, vec4<u32>(live, 0u, 0u, 0u));
}

@compute @workgroup_size(8, 8, 1)
fn froxel_cull_compact(@builtin(global_invocation_id) tile: vec3<u32>) {
    let size = froxels.size;
    // Blocks per axis (the block sizes are powers of two: shifts, not divisions).
    let grid = (size.xy + vec2<u32>(FROXEL_BLOCK_X - 1u, FROXEL_BLOCK_Y - 1u)) >> vec2<u32>(2u);
    if any(tile.xy >= grid) {
        return;
    }
    let first = tile.xy * vec2<u32>(FROXEL_BLOCK_X, FROXEL_BLOCK_Y);
    let last = min(first + vec2<u32>(FROXEL_BLOCK_X - 1u, FROXEL_BLOCK_Y - 1u), size.xy - 1u);
    var deepest = 0u;
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            deepest = max(deepest, textureLoad(live_slices, vec2<u32>(x, y)).r);
        }
    }
    let count = (min(deepest, size.z) + FROXEL_BLOCK_Z - 1u) >> 3u;
    let start = atomicAdd(&dispatch.x, count);
    for (var z = 0u; z < count; z++) {
        blocks[start + z] = froxel_block_pack(vec3<u32>(tile.xy, z));
    }
}
