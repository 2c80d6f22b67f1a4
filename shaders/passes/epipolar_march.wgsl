// Pass epipolar_march — the lit fraction at every ray-marching sample (Yusov 2012, 6.4):
// the shaft term of the min/max tree march (Algorithm 2), or under
// VOLFOG_EPIPOLAR_BRUTE_FORCE of every section of the slice's height map read from the
// shadow map (Algorithm 1, the same sum), over S_open, the same ray's term with nothing
// shadowing it (1 - T, or under HeightFog.sun_transmittance the sun's light that
// reaches the ray through the medium; volfog::epipolar::epipolar_lit_fraction). Other
// samples get 1.
//
// Dispatch: ceil(samples / 64) x slices workgroups, after epipolar_refine and
// epipolar_tree.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 uniform HeightFog: the medium, in view space
//   2 texture_2d<f32>, unfilterable: the coordinate texture
//   3 texture_2d<u32>: the packed interpolation sources (epipolar_refine)
//   4 texture_2d<f32>, unfilterable: the tree texture (epipolar_tree, rgba32float);
//     under VOLFOG_EPIPOLAR_BRUTE_FORCE the shadow map, texture_2d_array<f32>
//   5 storage texture rgba32float (samples x slices), write: rgb the lit fraction F, a 1
//   6 texture_2d<f32>, unfilterable (VOLFOG_EPIPOLAR_COLORED only): the light-space
//     colour texture, texel-aligned with the shadow map's cascade
// Defines: VOLFOG_EPIPOLAR_BRUTE_FORCE — march without the tree (reference, benchmark).
//          VOLFOG_EPIPOLAR_COLORED — coloured shafts.

#import volfog::types::{EpipolarFrame, HeightFog}
#import volfog::epipolar::{epipolar_slice_map, epipolar_ray, epipolar_march_tree, epipolar_march_steps, epipolar_lit_fraction, epipolar_unpack_sources}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var<uniform> medium: HeightFog;
@group(0) @binding(2) var coords: texture_2d<f32>;
@group(0) @binding(3) var source_pairs: texture_2d<u32>;
#ifdef VOLFOG_EPIPOLAR_BRUTE_FORCE
@group(0) @binding(4) var shadow_map: texture_2d_array<f32>;
#else
@group(0) @binding(4) var tree_levels: texture_2d<f32>;
#endif
@group(0) @binding(5) var marched: texture_storage_2d<rgba32float, write>;
#ifdef VOLFOG_EPIPOLAR_COLORED
@group(0) @binding(6) var light_colors: texture_2d<f32>;
#endif

@compute @workgroup_size(64, 1, 1)
fn epipolar_march(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= epipolar_frame.samples || id.y >= epipolar_frame.slices {
        return;
    }
    let at = vec2<i32>(id.xy);
    let c = textureLoad(coords, at, 0);
    let src = epipolar_unpack_sources(textureLoad(source_pairs, at, 0).r);
    var f = vec3<f32>(1.0);
    if c.w > 0.5 && src.x == src.y {
        let map = epipolar_slice_map(epipolar_frame, id.y);
        let ray = epipolar_ray(epipolar_frame, map, c.xy, epipolar_frame.start_depth, c.z);
        let size = epipolar_frame.shadow_size;
#ifdef VOLFOG_EPIPOLAR_BRUTE_FORCE
#ifdef VOLFOG_EPIPOLAR_COLORED
        let s = epipolar_march_steps(shadow_map, epipolar_frame.cascade, map, size, epipolar_frame.depth_bias, medium, ray, light_colors);
#else
        let s = epipolar_march_steps(shadow_map, epipolar_frame.cascade, map, size, epipolar_frame.depth_bias, medium, ray);
#endif
#else
#ifdef VOLFOG_EPIPOLAR_COLORED
        let s = epipolar_march_tree(tree_levels, id.y, size, medium, ray, map, light_colors);
#else
        let s = epipolar_march_tree(tree_levels, id.y, size, medium, ray);
#endif
#endif
        f = epipolar_lit_fraction(medium, ray, s);
    }
    textureStore(marched, at, vec4<f32>(f, 1.0));
}
