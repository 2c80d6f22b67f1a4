// Pass epipolar_apply — sun shafts on their own (a post-process without a froxel
// volume): the medium's fog with the shaft term over the lit colour target, one
// fullscreen triangle (Yusov 2012, "applied to the attenuated background").
//
// Draw: 3 vertices with the fullscreen pass's vertex shader (fullscreen_vs), no vertex
// buffers. The fragment writes (in-scatter, transmittance); blend it onto the colour
// target with
//   colour: src * One + dst * SrcAlpha      alpha: src * Zero + dst * One
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 uniform HeightFog: the medium, in view space
//   2 texture_2d<f32>, unfilterable: the scene depth buffer
//   3 texture_2d<f32>, unfilterable: the shaft texture (epipolar_upscale,
//     epipolar_resolve at downscale 1, or epipolar_reference)

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::epipolar::{epipolar_fog, epipolar_view_ray, epipolar_pixel_ndc}
#import volfog::froxel::view_from_ndc

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var<uniform> medium: HeightFog;
@group(0) @binding(2) var scene_depth: texture_2d<f32>;
@group(0) @binding(3) var shaft_texture: texture_2d<f32>;

@fragment
fn epipolar_apply_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let ndc = epipolar_pixel_ndc(epipolar_frame, frag.xy);
    let depth = textureLoad(scene_depth, vec2<i32>(frag.xy), 0).r;
    let z = abs(view_from_ndc(vec3<f32>(ndc, depth), epipolar_frame.view_from_clip).z);
    let view = epipolar_view_ray(epipolar_frame.view_from_clip, ndc) * min(z, 3.0e37);
    let s = textureLoad(shaft_texture, vec2<i32>(frag.xy), 0).rgb;
    return epipolar_fog(epipolar_frame, medium, view, s);
}
