// Bench pass blit — the floor of a fullscreen pass: one fullscreen triangle whose
// fragment reads one texel of a texture of the target's size and writes it.
//
// Draw: 3 vertices, no vertex buffers; no blending.
// Bindings (group 0):
//   0  texture_2d<f32>, unfilterable: the source, same size as the colour target

#import volfog::fullscreen::fullscreen_position

@group(0) @binding(0) var source: texture_2d<f32>;

@vertex
fn blit_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(index);
}

@fragment
fn blit_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(source, vec2<i32>(frag.xy), 0);
}
