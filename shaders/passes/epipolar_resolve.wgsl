// Pass epipolar_resolve — the lit fraction on the (downscaled) screen from the epipolar
// samples (Yusov 2012, 6.6 and 6.7): the pixel's slice and position along it, the two
// nearest slices and two samples on each, weighted bilinearly and kept only where
// their view depth matches the pixel's (bilateral); a pixel no sample serves is
// corrected by a per-pixel march of fix_steps steps.
//
// Dispatch: ceil(width / downscale / 8) x ceil(height / downscale / 8) workgroups,
// after epipolar_interpolate. Texel (x, y) stands for the full-resolution position
// downscale * ((x, y) + 0.5) (pixel units).
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 uniform HeightFog: the medium, in view space
//   2 texture_2d<f32>, unfilterable: the scene depth buffer, full resolution
//   3 texture_2d<f32>, unfilterable: the coordinate texture
//   4 texture_2d<f32>, unfilterable: the interpolated lit fractions
//   5 texture_2d_array<f32>: the shadow map
//   6 storage texture rgba16float, write: rgb the lit fraction F, a the view depth (m)
//   7 storage buffer, read_write, array<atomic<u32>>: element 0 counts corrected pixels
//   8 texture_2d<f32>, unfilterable (VOLFOG_EPIPOLAR_COLORED only): the light-space
//     colour texture
// Defines: VOLFOG_EPIPOLAR_COLORED — coloured shafts (the correcting march reads the
//          colour texture).

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::epipolar::{epipolar_pixel_slice, epipolar_line, epipolar_line_position, epipolar_continuous, epipolar_march_pixel, epipolar_pixel_ndc, epipolar_view_depth, EPIPOLAR_INVALID}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var<uniform> medium: HeightFog;
@group(0) @binding(2) var scene_depth: texture_2d<f32>;
@group(0) @binding(3) var coords: texture_2d<f32>;
@group(0) @binding(4) var interpolated: texture_2d<f32>;
@group(0) @binding(5) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(6) var resolved: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var<storage, read_write> counters: array<atomic<u32>>;
#ifdef VOLFOG_EPIPOLAR_COLORED
@group(0) @binding(8) var light_colors: texture_2d<f32>;
#endif

// Weight below which a pixel counts as not served by any sample.
const MIN_WEIGHT: f32 = 1e-3;

@compute @workgroup_size(8, 8, 1)
fn epipolar_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(resolved);
    if id.x >= out_size.x || id.y >= out_size.y {
        return;
    }
    let f = f32(epipolar_frame.downscale);
    let position = (vec2<f32>(id.xy) + 0.5) * f;
    let full = vec2<i32>(textureDimensions(scene_depth));
    let texel = clamp(vec2<i32>(position), vec2<i32>(0), full - 1);
    let ndc = epipolar_pixel_ndc(epipolar_frame, position);
    let depth = textureLoad(scene_depth, texel, 0).r;
    let z = epipolar_view_depth(epipolar_frame, ndc, depth);

    let n = i32(epipolar_frame.slices);
    let js = epipolar_pixel_slice(epipolar_frame, ndc) - 0.5;
    let j0 = floor(js);
    let wj = js - j0;
    var total = vec3<f32>(0.0);
    var weight = 0.0;
    for (var side = 0; side < 2; side += 1) {
        let slice = ((i32(j0) + side) % n + n) % n;
        let ws = select(1.0 - wj, wj, side == 1);
        let line = epipolar_line(epipolar_frame, u32(slice));
        if line.x == EPIPOLAR_INVALID || ws <= 0.0 {
            continue;
        }
        let kf = epipolar_line_position(line, epipolar_frame.samples, ndc);
        let k0 = floor(kf);
        let wk = kf - k0;
        for (var step = 0; step < 2; step += 1) {
            let k = i32(k0) + step;
            if k < 0 || k >= i32(epipolar_frame.samples) {
                continue;
            }
            let c = textureLoad(coords, vec2<i32>(k, slice), 0);
            if c.w < 0.5 || !epipolar_continuous(c.z, z, epipolar_frame.depth_threshold) {
                continue;
            }
            let w = ws * select(1.0 - wk, wk, step == 1);
            total += w * textureLoad(interpolated, vec2<i32>(k, slice), 0).rgb;
            weight += w;
        }
    }
    var s = total / max(weight, 1e-30);
    if weight < MIN_WEIGHT {
#ifdef VOLFOG_EPIPOLAR_COLORED
        s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.fix_steps, light_colors);
#else
        s = epipolar_march_pixel(shadow_map, epipolar_frame, medium, ndc, epipolar_frame.start_depth, z, epipolar_frame.fix_steps);
#endif
        atomicAdd(&counters[0], 1u);
    }
    textureStore(resolved, vec2<i32>(id.xy), vec4<f32>(s, z));
}
