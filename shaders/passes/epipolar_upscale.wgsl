// Pass epipolar_upscale — the lit fraction at full resolution from the downscaled
// resolve (Yusov 2012, 6.8): the four nearest resolved texels, weighted bilinearly and
// kept only where their view depth matches the pixel's; a pixel none serves is
// corrected by a per-pixel march of fix_steps steps. Not needed when downscale is 1.
//
// Dispatch: ceil(width / 8) x ceil(height / 8) workgroups, after epipolar_resolve.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 uniform HeightFog: the medium, in view space
//   2 texture_2d<f32>, unfilterable: the scene depth buffer, full resolution
//   3 texture_2d<f32>, unfilterable: the resolved texture (epipolar_resolve)
//   4 texture_2d_array<f32>: the shadow map
//   5 storage texture rgba16float, write: the shaft texture (layout of the resolve: rgb
//     the lit fraction, a the view depth)
//   6 storage buffer, read_write, array<atomic<u32>>: element 1 counts corrected pixels
//   7 texture_2d<f32>, unfilterable (VOLFOG_EPIPOLAR_COLORED only): the light-space
//     colour texture
// Defines: VOLFOG_EPIPOLAR_COLORED — coloured shafts (the correcting march reads the
//          colour texture).

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::epipolar::{epipolar_continuous, epipolar_march_pixel, epipolar_pixel_ndc, epipolar_view_depth}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var<uniform> medium: HeightFog;
@group(0) @binding(2) var scene_depth: texture_2d<f32>;
@group(0) @binding(3) var low: texture_2d<f32>;
@group(0) @binding(4) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(5) var shaft_texture: texture_storage_2d<rgba16float, write>;
@group(0) @binding(6) var<storage, read_write> counters: array<atomic<u32>>;
#ifdef VOLFOG_EPIPOLAR_COLORED
@group(0) @binding(7) var light_colors: texture_2d<f32>;
#endif

// Weight below which a pixel counts as not served by any texel.
const MIN_WEIGHT: f32 = 1e-3;

@compute @workgroup_size(8, 8, 1)
fn epipolar_upscale(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shaft_texture);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let ndc = epipolar_pixel_ndc(epipolar_frame, vec2<f32>(id.xy) + 0.5);
    let depth = textureLoad(scene_depth, vec2<i32>(id.xy), 0).r;
    let z = epipolar_view_depth(epipolar_frame, ndc, depth);
    let low_size = vec2<i32>(textureDimensions(low));
    let q = (vec2<f32>(id.xy) + 0.5) / f32(epipolar_frame.downscale) - 0.5;
    let q0 = floor(q);
    let w = q - q0;
    var total = vec3<f32>(0.0);
    var weight = 0.0;
    for (var dy = 0; dy < 2; dy += 1) {
        for (var dx = 0; dx < 2; dx += 1) {
            let at = vec2<i32>(q0) + vec2<i32>(dx, dy);
            if any(at < vec2<i32>(0)) || any(at >= low_size) {
                continue;
            }
            let texel = textureLoad(low, at, 0);
            if !epipolar_continuous(texel.a, z, epipolar_frame.depth_threshold) {
                continue;
            }
            let wx = select(1.0 - w.x, w.x, dx == 1);
            let wy = select(1.0 - w.y, w.y, dy == 1);
            total += wx * wy * texel.rgb;
            weight += wx * wy;
        }
    }
    var s = total / max(weight, 1e-30);
    if weight < MIN_WEIGHT {
#ifdef VOLFOG_EPIPOLAR_COLORED
        s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.fix_steps, light_colors);
#else
        s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.fix_steps);
#endif
        atomicAdd(&counters[1], 1u);
    }
    textureStore(shaft_texture, vec2<i32>(id.xy), vec4<f32>(s, z));
}
