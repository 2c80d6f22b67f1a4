// Pass epipolar_interpolate — the lit fraction of every sample from its two ray-marching
// sources, linearly along the slice (Yusov 2012, 6.5).
//
// Dispatch: ceil(samples / 64) x slices workgroups, after epipolar_march.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 texture_2d<u32>: the packed interpolation sources (epipolar_refine)
//   2 texture_2d<f32>, unfilterable: the marched lit fractions (epipolar_march, rgb)
//   3 storage texture rgba32float (samples x slices), write: the interpolated lit
//     fraction (rgb; a 1)

#import volfog::types::EpipolarFrame
#import volfog::epipolar::epipolar_unpack_sources

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var source_pairs: texture_2d<u32>;
@group(0) @binding(2) var marched: texture_2d<f32>;
@group(0) @binding(3) var interpolated: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(64, 1, 1)
fn epipolar_interpolate(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= epipolar_frame.samples || id.y >= epipolar_frame.slices {
        return;
    }
    let src = epipolar_unpack_sources(textureLoad(source_pairs, vec2<i32>(id.xy), 0).r);
    let s0 = textureLoad(marched, vec2<i32>(i32(src.x), i32(id.y)), 0).rgb;
    let s1 = textureLoad(marched, vec2<i32>(i32(src.y), i32(id.y)), 0).rgb;
    let t = f32(id.x - src.x) / f32(max(src.y - src.x, 1u));
    textureStore(interpolated, vec2<i32>(id.xy), vec4<f32>(mix(s0, s1, t), 1.0));
}
