// Pass hull_thickness — accumulates the fog thickness of a hull mesh per pixel (the
// hull sum of volfog::hull: x + w thickness, y camera-inside count, z scene-inside
// count) with additive blending.
//
// Draw: the hull's triangle list (indexed or not), every face. Vertex buffer 0: stride
//   12 bytes, attribute location 0 = world position, Float32x3 at offset 0; triangles
//   wound counter-clockwise seen from outside (front face Ccw). Several hulls of the
//   same density and colour may be drawn into one target, each with its own uniform.
// Pipeline state:
//   primitive   TriangleList, front face Ccw, cull mode none (both sides are needed)
//   depth       no depth-stencil attachment (no depth test: the scene is read from
//               binding 1 instead, and the vertex stage replaces the clip depth)
//   target      Rgba16Float (portable; set FogHull.reference and quantum from the
//               hull's bounds), or Rgba32Float where the adapter has
//               FLOAT32_BLENDABLE (quantum 0); cleared to 0, same size as the scene
//               depth buffer
//   blend       colour and alpha both src * One + dst * One (add), write mask all
// Bindings (group 0):
//   0  uniform FogHull (vertex and fragment)
//   1  texture_2d<f32>, unfilterable: the scene depth buffer (a depth texture bound
//      as unfilterable float; read with textureLoad); clear it to the far value
//      where there is no scene. Under VOLFOG_HULL_RESOLVED the resolved MSAA fog
//      layout instead (volfog::apply::fog_layout: r the view depth in m), so a
//      multisampled scene needs no resolved depth buffer.
// Defines: VOLFOG_HULL_RESOLVED — read the scene's view depth from the resolved layout.
// Reference: Boyd 2001, "Volumetric Rendering in Realtime" (see volfog::hull).

#import volfog::types::FogHull
#import volfog::hull::{HullVertex, hull_clip_position, hull_scene_distance, hull_scene_distance_from_view_depth, hull_contribution}
#import volfog::froxel::ndc_from_uv

@group(0) @binding(0) var<uniform> hull: FogHull;
@group(0) @binding(1) var scene_depth: texture_2d<f32>;

@vertex
fn hull_thickness_vs(@location(0) position: vec3<f32>) -> HullVertex {
    let clip = hull.clip_from_world * vec4<f32>(position, 1.0);
    return HullVertex(hull_clip_position(clip), position - hull.camera_position);
}

@fragment
fn hull_thickness_fs(in: HullVertex, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(scene_depth));
    let depth = textureLoad(scene_depth, vec2<i32>(in.clip.xy), 0).r;
#ifdef VOLFOG_HULL_RESOLVED
    let scene = hull_scene_distance_from_view_depth(in.clip.xy / size, depth, hull.view_from_clip);
#else
    let ndc = vec3<f32>(ndc_from_uv(in.clip.xy / size), depth);
    let scene = hull_scene_distance(ndc, hull.view_from_clip);
#endif
    return hull_contribution(length(in.offset), scene, hull.reference, hull.quantum, front_facing);
}
