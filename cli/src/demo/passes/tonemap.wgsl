// Demo tonemap: linear HDR radiance -> display colour (the target is an sRGB format,
// so the hardware applies the sRGB transfer function on store).
//
// Bindings (group 0): 0 the HDR colour (texture_2d<f32>, read with textureLoad),
//                     1 exposure (f32 uniform, multiplies the radiance).
// Curve: Narkowicz's fit of the ACES filmic curve.

#import volfog::fullscreen::fullscreen_position

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<uniform> exposure: vec4<f32>;

@vertex
fn tonemap_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(index);
}

fn aces(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

@fragment
fn tonemap_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(frag.xy), 0).rgb;
    return vec4<f32>(aces(max(c, vec3<f32>(0.0)) * exposure.x), 1.0);
}
