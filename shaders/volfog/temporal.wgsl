// volfog::temporal — temporal reprojection of the froxel volume: where a froxel's
// centre lands in the history volume, whether the history holds live texels there, and
// how the history blends with this frame's value.
//
// Use:      #import volfog::temporal::{temporal_history_column, temporal_history_slice_uvw, temporal_blend, ...}
// Defines:  none
// Reference: Wronski 2014, "Temporal reprojection" and "Volumetric reprojection": each
//           frame's froxels are blended with last frame's volume, sampled where the
//           froxel's world position projects with last frame's camera, so jittered
//           samples accumulate over frames.
// Used by the temporal pass and, fused, by inject under VOLFOG_INJECT_TEMPORAL (the
// passes' headers describe the bindings and the ping-pong of the history volumes).
#define_import_path volfog::temporal

#import volfog::types::{Froxels, HistoryState}
#import volfog::froxel::{ndc_from_uv, slice_coord, slice_depth, uv_from_ndc, view_from_ndc}

// Below this trilinear weight (per axis) a history texel is not required to be live.
const TEMPORAL_HISTORY_REACH: f32 = 0.015625;

// The history camera's clip coordinates along the centre ray of froxel column xy of
// the volume `grid`: the point of the ray at view depth z (m) lands at
// column[0] * z + column[1], with the camera the history was written with (state,
// not the previous frame's inputs). Every slice of a column shares the ray, so a pass
// that reprojects several froxels of one column (a pair of slices) computes it once.
fn temporal_history_column(
    xy: vec2<u32>,
    grid: Froxels,
    world_from_view: mat4x4<f32>,
    state: HistoryState,
) -> mat2x4<f32> {
    let cell = (vec2<f32>(xy) + 0.5) / vec2<f32>(grid.size.xy);
    let ray = view_from_ndc(vec3<f32>(ndc_from_uv(cell), 0.5), grid.view_from_clip);
    // The ray per metre of view depth.
    let step = ray / max(abs(ray.z), 1e-30);
    return mat2x4<f32>(
        state.clip_from_world * (world_from_view * vec4<f32>(step, 0.0)),
        state.clip_from_world * world_from_view[3]);
}

// The history volume's texture coordinates (xyz in [0, 1]) of the centre of the
// froxel in slice `slice` of a column (temporal_history_column) of the volume `grid`
// (not its jittered sample: each history texel stands for its whole froxel, so a
// static camera reads history texels exactly). w is 1 where the history is usable
// there, 0 where it is not: history_enabled 0 (a camera cut), a history never written
// (valid 0, HistoryState.valid), the centre behind the history's camera or outside its
// volume.
fn temporal_history_slice_uvw(
    column: mat2x4<f32>,
    slice: u32,
    grid: Froxels,
    valid: u32,
    history_enabled: u32,
) -> vec4<f32> {
    let depth = slice_depth((f32(slice) + 0.5) / f32(grid.size.z), grid.near, grid.far, grid.curve);
    let clip = column[0] * depth + column[1];
    if history_enabled == 0u || valid == 0u || clip.w <= 1e-6 {
        return vec4<f32>(0.0);
    }
    let uv = uv_from_ndc(clip.xy / clip.w);
    let uvw = vec3<f32>(uv, slice_coord(clip.w, grid.near, grid.far, grid.curve));
    if any(uvw < vec3<f32>(0.0)) || any(uvw > vec3<f32>(1.0)) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(uvw, 1.0);
}

// temporal_history_slice_uvw for froxel id alone (its column computed for it).
fn temporal_history_uvw(
    id: vec3<u32>,
    grid: Froxels,
    world_from_view: mat4x4<f32>,
    state: HistoryState,
    history_enabled: u32,
) -> vec4<f32> {
    let column = temporal_history_column(id.xy, grid, world_from_view, state);
    return temporal_history_slice_uvw(column, id.z, grid, state.valid, history_enabled);
}

// Whether every texel the trilinear look-up of a volume of `size` froxels at uvw weighs
// by TEMPORAL_HISTORY_REACH or more lies within the live slices the volume was written
// with (written_live: one r32uint texel per column, froxel_cull). With depth
// culling a volume holds stale texels behind its columns' live slices; a stale texel
// then weighs less than TEMPORAL_HISTORY_REACH per axis where the history is used.
fn temporal_history_live(uvw: vec3<f32>, size: vec3<u32>, written_live: texture_2d<u32>) -> bool {
    let texel = uvw * vec3<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let top = vec3<f32>(size - 1u);
    let lo = vec3<u32>(clamp(base, vec3<f32>(0.0), top));
    let hi = vec3<u32>(clamp(base + 1.0, vec3<f32>(0.0), top));
    // The columns and the deepest slice that carry weight.
    let x0 = select(hi.x, lo.x, 1.0 - f.x >= TEMPORAL_HISTORY_REACH);
    let x1 = select(lo.x, hi.x, f.x >= TEMPORAL_HISTORY_REACH);
    let y0 = select(hi.y, lo.y, 1.0 - f.y >= TEMPORAL_HISTORY_REACH);
    let y1 = select(lo.y, hi.y, f.y >= TEMPORAL_HISTORY_REACH);
    let deepest = select(lo.z, hi.z, f.z >= TEMPORAL_HISTORY_REACH);
    let a = min(textureLoad(written_live, vec2<u32>(x0, y0), 0).r,
                textureLoad(written_live, vec2<u32>(x1, y0), 0).r);
    let b = min(textureLoad(written_live, vec2<u32>(x0, y1), 0).r,
                textureLoad(written_live, vec2<u32>(x1, y1), 0).r);
    return deepest < min(a, b);
}

// This frame's value `now` of a froxel (rgb = sigma_s L_in, a = sigma_t) with its
// reprojected history `past`: an injected froxel (volfog::froxel::froxel_injected) blends
// them, exponential moving average with history_weight in [0, 1) (clamped to [0, 1]);
// a froxel the checkerboard skipped this frame takes the history alone.
fn temporal_blend(now: vec4<f32>, past: vec4<f32>, injected: bool, history_weight: f32) -> vec4<f32> {
    if injected {
        return mix(now, past, clamp(history_weight, 0.0, 1.0));
    }
    return past;
}
