// Pass epipolar_coords — the coordinate texture of epipolar sampling (Yusov 2012, 6.1):
// for sample k of slice j, its position on the screen and the view depth there.
//
// Dispatch: ceil(samples / 64) x slices workgroups.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 texture_2d<f32>, unfilterable: the scene depth buffer (a depth texture bound as
//     unfilterable float), full resolution
//   2 storage texture rgba32float (samples x slices), write: xy the sample's normalised
//     device position, z its view depth (m, at most max_depth), w 1; samples off the
//     screen get (EPIPOLAR_INVALID, EPIPOLAR_INVALID, EPIPOLAR_INVALID_DEPTH, 0).

#import volfog::types::EpipolarFrame
#import volfog::epipolar::{epipolar_line, epipolar_sample_position, epipolar_view_depth, EPIPOLAR_INVALID, EPIPOLAR_INVALID_DEPTH}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var scene_depth: texture_2d<f32>;
@group(0) @binding(2) var coords: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(64, 1, 1)
fn epipolar_coords(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= epipolar_frame.samples || id.y >= epipolar_frame.slices {
        return;
    }
    let p = epipolar_sample_position(epipolar_line(epipolar_frame, id.y), epipolar_frame.samples, id.x);
    var out = vec4<f32>(EPIPOLAR_INVALID, EPIPOLAR_INVALID, EPIPOLAR_INVALID_DEPTH, 0.0);
    if p.x != EPIPOLAR_INVALID {
        let size = vec2<i32>(textureDimensions(scene_depth));
        let uv = vec2<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5);
        let texel = clamp(vec2<i32>(floor(uv * vec2<f32>(size))), vec2<i32>(0), size - 1);
        let depth = textureLoad(scene_depth, texel, 0).r;
        out = vec4<f32>(p, epipolar_view_depth(epipolar_frame, p, depth), 1.0);
    }
    textureStore(coords, vec2<i32>(id.xy), out);
}
