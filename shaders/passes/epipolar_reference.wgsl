// Pass epipolar_reference — the brute-force reference of the shaft texture: every
// pixel marched on its own with reference_steps fixed steps, reading the shadow map at
// each (no epipolar sampling, no tree).
//
// Dispatch: ceil(width / 8) x ceil(height / 8) workgroups.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 uniform HeightFog: the medium, in view space
//   2 texture_2d<f32>, unfilterable: the scene depth buffer, full resolution
//   3 texture_2d_array<f32>: the shadow map
//   4 storage texture rgba16float, write: the shaft texture (rgb the lit fraction F, a
//     the view depth)
//   5 texture_2d<f32>, unfilterable (VOLFOG_EPIPOLAR_COLORED only): the light-space
//     colour texture
// Defines: VOLFOG_EPIPOLAR_COLORED — coloured shafts.

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::epipolar::{epipolar_march_pixel, epipolar_pixel_ndc, epipolar_view_depth}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var<uniform> medium: HeightFog;
@group(0) @binding(2) var scene_depth: texture_2d<f32>;
@group(0) @binding(3) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(4) var shaft_texture: texture_storage_2d<rgba16float, write>;
#ifdef VOLFOG_EPIPOLAR_COLORED
@group(0) @binding(5) var light_colors: texture_2d<f32>;
#endif

@compute @workgroup_size(8, 8, 1)
fn epipolar_reference(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shaft_texture);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ndc = epipolar_pixel_ndc(epipolar_frame, vec2<f32>(id.xy) + 0.5);
    let depth = textureLoad(scene_depth, vec2<i32>(id.xy), 0).r;
    let z = epipolar_view_depth(epipolar_frame, ndc, depth);
#ifdef VOLFOG_EPIPOLAR_COLORED
    let s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.reference_steps, light_colors);
#else
    let s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.reference_steps);
#endif
    textureStore(shaft_texture, vec2<i32>(id.xy), vec4<f32>(s, z));
}
