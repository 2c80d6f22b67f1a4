// Pass local_shadow_downsample — point and spot lights' shadow depth maps to the
// local-light ESM atlas: each atlas texel averages the exponential occluder term of the
// linear depths of a factor x factor block of depth texels (factor = source size / atlas
// size, a whole number), one atlas layer per workgroup z. Then esm_blur filters the
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
//   4  sampler, non-filtering (nearest), clamp to edge: used by textureGather
// Defines: VOLFOG_ESM_LOG_SPACE (see volfog::esm): the mean is a streaming log-sum-exp
//          (volfog::esm::esm_sum_add4), so exponents above 88 cannot overflow f32.

#import volfog::types::LocalShadowSource
#import volfog::local_shadow::local_shadow_encode
#import volfog::esm::{ESM_SUM_EMPTY, esm_sum_add4, esm_sum_mean}

@group(0) @binding(0) var<storage, read> sources: array<LocalShadowSource>;
@group(0) @binding(1) var spot_maps: texture_2d_array<f32>;
@group(0) @binding(2) var point_maps: texture_2d_array<f32>;
@group(0) @binding(3) var atlas: texture_storage_2d_array<r32float, write>;
@group(0) @binding(4) var gather_sampler: sampler;

// Adds the occluder values of the factor x factor block of depth texels at `origin` to
// a running sum, one gather of 2 x 2 texels at a time (where factor is odd, the texels
// of the last gathers past the block's edge are left out), over `rows` rows of
// gathers: ceil(factor / 2), or 0 for the maps the source does not use, so that the
// loop rather than a branch skips them.
fn block_sum(
    sum: vec2<f32>,
    maps: texture_2d_array<f32>,
    source: LocalShadowSource,
    origin: vec2<u32>,
    factor: u32,
    rows: u32,
) -> vec2<f32> {
    var total = sum;
    let size = vec2<f32>(textureDimensions(maps));
    let last = origin + factor - 1u;
    for (var j = 0u; j < rows; j++) {
        for (var i = 0u; i < rows; i++) {
            // Texels a to a + 1 on both axes, gathered (at their shared corner) as
            // (a.x, a.y + 1), (a.x + 1, a.y + 1), (a.x + 1, a.y), (a.x, a.y).
            let a = origin + 2u * vec2<u32>(i, j);
            let d = textureGather(0, maps, gather_sampler, (vec2<f32>(a) + 1.0) / size, source.source_layer);
            let inside = vec2<f32>(a + 1u <= last);
            let weight = vec4<f32>(inside.y, inside.x * inside.y, inside.x, 1.0);
            let encode = vec4<f32>(
                local_shadow_encode(source.depth_terms, d.x, source.depth_range, source.exponent),
                local_shadow_encode(source.depth_terms, d.y, source.depth_range, source.exponent),
                local_shadow_encode(source.depth_terms, d.z, source.depth_range, source.exponent),
                local_shadow_encode(source.depth_terms, d.w, source.depth_range, source.exponent),
            );
            total = esm_sum_add4(total, encode, weight);
        }
    }
    return total;
}

@compute @workgroup_size(8, 8, 1)
fn local_shadow_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(atlas);
    if id.x >= size.x || id.y >= size.y || id.z >= arrayLength(&sources) {
        return;
    }
    let source = sources[id.z];
    let point = source.source == 1u;
    let maps_size = select(textureDimensions(spot_maps).x, textureDimensions(point_maps).x, point);
    let factor = max(maps_size / size.x, 1u);
    let rows = (factor + 1u) / 2u;
    var sum = block_sum(ESM_SUM_EMPTY, point_maps, source, id.xy * factor, factor, select(0u, rows, point));
    sum = block_sum(sum, spot_maps, source, id.xy * factor, factor, select(rows, 0u, point));
    let value = esm_sum_mean(sum, f32(factor * factor));
    textureStore(atlas, id.xy, source.atlas_layer, vec4<f32>(value, 0.0, 0.0, 0.0));
}
