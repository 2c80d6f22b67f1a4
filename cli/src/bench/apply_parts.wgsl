// Bench pass apply_parts — the fullscreen apply cut short after each of its stages, so
// the report shows where its time goes. Every part loads the pixel's depth and blends
// its result onto the target as apply does (src * One + dst * SrcAlpha):
//   APPLY_PART_DEPTH      the depth texel alone
//   APPLY_PART_UNPROJECT  + the pixel's view-space position (volfog::froxel::view_from_ndc)
//   APPLY_PART_LOOKUP     + its fog coordinate and the trilinear look-up of the
//                         integrated volume (volfog::apply::fog_coord, fog_sample):
//                         apply without the tail
//   APPLY_PART_UNTAKEN    the whole apply with the tail behind a branch no pixel takes
//                         (a uniform that is never negative): what a branch saves on
//                         the adapter
// The whole pass (shaders/passes/apply.wgsl) adds the analytic tail beyond the far
// plane (volfog::apply::fog_tail) for the pixels beyond it; the bench scene has no
// tail, so the fog draws the variant without it (VOLFOG_APPLY_NO_TAIL), and
// APPLY_PART_UNTAKEN stands for the cost of an apply with a tail.
//
// Draw: 3 vertices, no vertex buffers.
// Bindings: group 0 the fog group (volfog::bindings), group 1 binding 0 the scene depth
// (unfilterable float), as apply.

#import volfog::bindings
#import volfog::apply::{fog_coord, fog_sample, fog_load, fog_tail, fog_with_tail}
#import volfog::froxel::{ndc_from_uv, view_from_ndc}
#import volfog::fullscreen::fullscreen_position

@group(1) @binding(0) var scene_depth: texture_2d<f32>;

@vertex
fn parts_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(index);
}

@fragment
fn parts_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let depth = textureLoad(scene_depth, vec2<i32>(frag.xy), 0).r;
#ifdef APPLY_PART_DEPTH
    return vec4<f32>(depth, 0.0, 0.0, 1.0);
#else
    let uv = frag.xy / vec2<f32>(textureDimensions(scene_depth));
    let froxels = bindings::fog_froxels;
    let view = view_from_ndc(vec3<f32>(ndc_from_uv(uv), depth), froxels.view_from_clip);
#ifdef APPLY_PART_UNPROJECT
    return vec4<f32>(view, 1.0);
#else
    let coord = fog_coord(uv, abs(view.z), froxels);
#ifdef VOLFOG_BINDINGS_NO_SAMPLER
    let fog = fog_load(bindings::fog_integrated, coord);
#else
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler, coord);
#endif
#ifdef APPLY_PART_LOOKUP
    return fog;
#else
    var tail = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if froxels.far < 0.0 {
        tail = fog_tail(froxels, bindings::fog_far_tail, view);
    }
    return fog_with_tail(fog, tail);
#endif
#endif
#endif
}
