// Pass local_shadow_downsample — point and spot lights' shadow depth maps to the
// local-light ESM atlas: each atlas texel averages the exponential occluder term of the
// linear depths of a factor x factor block of depth texels (factor = source size / atlas
// size, a power of two), one atlas layer per workgroup z. Then esm_blur filters the
// written layers (Wronski 2014, bonus slides: downsample with exp, separable box blur).
//
// Dispatch: ceil(atlas_size / 8) x ceil(atlas_size / 8) x (number of sources)
//           workgroups of 8 x 8 x 1, after the lights' shadow maps are rendered.
// Bindings (group 0):
//   0  storage, read: array<LocalShadowSource>, one per atlas layer to fill
//   1  texture_2d_array<f32>: the spot lights' shadow maps (a depth texture bound as
//      unfilterable float), factor x the atlas size
//   2  texture_2d_array<f32>: the point lights' cube shadow maps as a 2D array (six
//      layers a cube, faces +X, -X, +Y, -Y, +Z, -Z), factor x the atlas size
//   3  texture_storage_2d_array<r32float, write>: the atlas
// Defines: VOLFOG_ESM_LOG_SPACE (see volfog::esm): the mean is a log-sum-exp around the
//          block's largest value, so exponents above 88 cannot overflow f32.

#import volfog::types::LocalShadowSource
#import volfog::local_shadow::{local_shadow_linear_depth, local_shadow_encode}

@group(0) @binding(0) var<storage, read> sources: array<LocalShadowSource>;
@group(0) @binding(1) var spot_maps: texture_2d_array<f32>;
@group(0) @binding(2) var point_maps: texture_2d_array<f32>;
@group(0) @binding(3) var atlas: texture_storage_2d_array<r32float, write>;

// Mean occluder value of the block of `factor` x `factor` depth texels at `origin`.
fn block_mean(maps: texture_2d_array<f32>, source: LocalShadowSource, origin: vec2<u32>, factor: u32) -> f32 {
    let n = f32(factor * factor);
#ifdef VOLFOG_ESM_LOG_SPACE
    // Log space: the encoded value c z grows with z, so the block's largest is that
    // of its farthest depth.
    var far = 0.0;
    for (var j = 0u; j < factor; j++) {
        for (var i = 0u; i < factor; i++) {
            let d = textureLoad(maps, origin + vec2<u32>(i, j), source.source_layer, 0).r;
            far = max(far, local_shadow_linear_depth(source.depth_terms, d, source.depth_range));
        }
    }
    let peak = source.exponent * far;
    var sum = 0.0;
    for (var j = 0u; j < factor; j++) {
        for (var i = 0u; i < factor; i++) {
            let d = textureLoad(maps, origin + vec2<u32>(i, j), source.source_layer, 0).r;
            sum += exp(local_shadow_encode(source.depth_terms, d, source.depth_range, source.exponent) - peak);
        }
    }
    return peak + log(sum / n);
#else
    var sum = 0.0;
    for (var j = 0u; j < factor; j++) {
        for (var i = 0u; i < factor; i++) {
            let d = textureLoad(maps, origin + vec2<u32>(i, j), source.source_layer, 0).r;
            sum += local_shadow_encode(source.depth_terms, d, source.depth_range, source.exponent);
        }
    }
    return sum / n;
#endif
}

@compute @workgroup_size(8, 8, 1)
fn local_shadow_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(atlas);
    if id.x >= size.x || id.y >= size.y || id.z >= arrayLength(&sources) {
        return;
    }
    let source = sources[id.z];
    var value: f32;
    if source.source == 1u {
        let factor = max(textureDimensions(point_maps).x / size.x, 1u);
        value = block_mean(point_maps, source, id.xy * factor, factor);
    } else {
        let factor = max(textureDimensions(spot_maps).x / size.x, 1u);
        value = block_mean(spot_maps, source, id.xy * factor, factor);
    }
    textureStore(atlas, id.xy, source.atlas_layer, vec4<f32>(value, 0.0, 0.0, 0.0));
}
