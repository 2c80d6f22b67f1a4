// Bench pass blit — the floor of a fullscreen pass: one fullscreen triangle whose
// fragment reads one texel of a texture of the target's size and writes it.
//
// Draw: 3 vertices, no vertex buffers; no blending.
// Bindings (group 0):
//   0  texture_2d<f32>, unfilterable: the source, same size as the colour target

@group(0) @binding(0) var source: texture_2d<f32>;

@vertex
fn blit_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // Vertices (-1, -1), (3, -1), (-1, 3) cover the screen.
    let xy = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn blit_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(source, vec2<i32>(frag.xy), 0);
}
