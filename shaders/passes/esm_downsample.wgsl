// Pass esm_downsample — shadow map depth to exponential shadow map, 4x smaller, one
// layer per cascade (Wronski 2014, bonus slide: four GatherRed of exp(depth * EXPONENT),
// averaged with weight 1/16).
//
// Dispatch: ceil(esm_width / 8) x ceil(esm_height / 8) x cascades workgroups of 8 x 8 x 1.
// Bindings (group 0):
//   0  uniform ShadowCascades (its exponent)
//   1  texture_2d_array<f32>: the cascaded shadow map (a depth texture bound as
//      unfilterable float), 4x the ESM size
//   2  sampler, non-filtering (nearest), clamp to edge: used by textureGather
//   3  texture_storage_2d_array<r32float, write>: the ESM
// Defines: VOLFOG_ESM_LOG_SPACE (see volfog::esm).
//          VOLFOG_ESM_REVERSED_Z: the shadow map holds reversed depth (1 at the light's
//          near plane, as reverse-Z renderers draw it); each texel d is read as 1 - d,
//          the standard depth that ShadowCascades.light_from_world gives receivers.

#import volfog::types::ShadowCascades
#import volfog::esm::{esm_encode, esm_sum_add4, esm_sum_mean, ESM_SUM_EMPTY}

@group(0) @binding(0) var<uniform> shadow_cascades: ShadowCascades;
@group(0) @binding(1) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(2) var gather_sampler: sampler;
@group(0) @binding(3) var esm_out: texture_storage_2d_array<r32float, write>;

// Occluder values of four gathered shadow-map texels.
fn encode4(gathered: vec4<f32>) -> vec4<f32> {
#ifdef VOLFOG_ESM_REVERSED_Z
    let d = 1.0 - gathered;
#else
    let d = gathered;
#endif
    let c = shadow_cascades.exponent;
    return vec4<f32>(esm_encode(d.x, c), esm_encode(d.y, c), esm_encode(d.z, c), esm_encode(d.w, c));
}

@compute @workgroup_size(8, 8, 1)
fn esm_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(esm_out);
    if id.x >= out_size.x || id.y >= out_size.y {
        return;
    }
    let in_size = vec2<f32>(textureDimensions(shadow_map));
    // The centre of the 4x4 block's top-left 2x2 quad: gathers at offsets (0,0), (2,0),
    // (0,2), (2,2) cover the whole block; their 16 values are summed in one pass
    // (volfog::esm, the running sum).
    let uv = (vec2<f32>(id.xy * 4u) + 1.0) / in_size;
    let layer = id.z;
    let kept = vec4<f32>(1.0);
    var sum = esm_sum_add4(ESM_SUM_EMPTY,
        encode4(textureGather(0, shadow_map, gather_sampler, uv, layer, vec2<i32>(0, 0))), kept);
    sum = esm_sum_add4(sum,
        encode4(textureGather(0, shadow_map, gather_sampler, uv, layer, vec2<i32>(2, 0))), kept);
    sum = esm_sum_add4(sum,
        encode4(textureGather(0, shadow_map, gather_sampler, uv, layer, vec2<i32>(0, 2))), kept);
    sum = esm_sum_add4(sum,
        encode4(textureGather(0, shadow_map, gather_sampler, uv, layer, vec2<i32>(2, 2))), kept);
    textureStore(esm_out, id.xy, layer, vec4<f32>(esm_sum_mean(sum, 16.0), 0.0, 0.0, 0.0));
}
