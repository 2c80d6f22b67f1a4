// Pass hull_composite — fogs a lit colour target with the thickness accumulated by
// hull_thickness: one fullscreen triangle.
//
// Draw: 3 vertices with the fullscreen pass's vertex shader (fullscreen_vs), no vertex
// buffers, onto the lit colour target (load, no depth
// attachment, same size as the thickness target). The fragment writes (in-scatter,
// transmittance) = (colour * (1 - T), T) with T = exp(-density * thickness); blend
//   colour: src * One + dst * SrcAlpha      alpha: src * Zero + dst * One
// which gives lit * T + colour * (1 - T) without reading the lit colour.
// Bindings (group 0):
//   0  uniform FogHull (density and colour; the other members are unused here)
//   1  texture_2d<f32>, unfilterable: the hull sum written by hull_thickness
//      (Rgba16Float or Rgba32Float; read with textureLoad)
// Reference: Boyd 2001, "Volumetric Rendering in Realtime" (see volfog::hull).

#import volfog::types::FogHull
#import volfog::hull::{hull_thickness, hull_fog}

@group(0) @binding(0) var<uniform> hull: FogHull;
@group(0) @binding(1) var hull_sum: texture_2d<f32>;

@fragment
fn hull_composite_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let sum = textureLoad(hull_sum, vec2<i32>(frag.xy), 0);
    return hull_fog(hull_thickness(sum), hull.density, hull.color);
}
