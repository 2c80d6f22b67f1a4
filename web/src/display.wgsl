// The web demo's display pass: the fogged HDR image into the canvas through exposure
// and an exponential tone curve (the canvas view is sRGB, so the GPU encodes it).

@group(0) @binding(0) var display_source: texture_2d<f32>;

@vertex
fn display_vertex(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn display_fragment(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let hdr = textureLoad(display_source, vec2<i32>(pixel.xy), 0).rgb;
    // Exposure 1.5 and 1 - exp(-x); the canvas format is sRGB-encoded by the view.
    return vec4(1.0 - exp(-1.5 * max(hdr, vec3(0.0))), 1.0);
}
