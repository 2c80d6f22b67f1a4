// volfog::esm — exponential shadow maps for the fog's main light.
//
// Use:      #import volfog::esm::{esm_cascade, esm_shadow_cascade, esm_shadow, ...}
// Defines:  VOLFOG_ESM_LOG_SPACE — the filtered maps hold log(mean(exp(c d))) instead of
//           mean(exp(c d)), so exponents above 88 cannot overflow f32.
// Data:     an ESM texel holds the filtered occluder term mean(exp(c * d)) of shadow-map
//           depths d in [0, 1]; the visibility of a receiver at depth r is
//           saturate(occluder * exp(-c * r)) = saturate(exp(c * (d - r))) for one occluder.
//           Behind an occluder the visibility falls as exp(-c * (r - d)): below 0.05 once
//           the receiver is 3 / c behind it (the leak band).
// Reference: Wronski 2014, bonus slides "Exponential Shadow Maps use in Volumetric Fog"
//           (downsample with exp, separable 11-tap box blur, saturate(occluder / receiver));
//           Annen et al. 2008, "Exponential Shadow Maps".
#define_import_path volfog::esm

#import volfog::types::ShadowCascades

// Occluder value of one shadow-map depth (linear or log space).
fn esm_encode(depth: f32, exponent: f32) -> f32 {
#ifdef VOLFOG_ESM_LOG_SPACE
    return exponent * depth;
#else
    return exp(exponent * depth);
#endif
}

// A running sum for the mean of many occluder values in one pass, four at a time:
// start from ESM_SUM_EMPTY, add with esm_sum_add4, end with esm_sum_mean. In log space
// x is the largest value added so far and y the sum of exp(value - x), rescaled when x
// grows (a streaming log-sum-exp: no second pass to find the largest first, and no
// exponent above 0, so nothing overflows); in linear space y is the plain sum.
const ESM_SUM_EMPTY: vec2<f32> = vec2<f32>(-1.0e30, 0.0);

// Adds the values of v to a running sum, each with weight 1 (added) or 0 (left out).
fn esm_sum_add4(sum: vec2<f32>, v: vec4<f32>, weight: vec4<f32>) -> vec2<f32> {
#ifdef VOLFOG_ESM_LOG_SPACE
    // Left-out values are moved far below every kept one, so they set no peak.
    let masked = v - (1.0 - weight) * 1.0e30;
    let peak = max(sum.x, max(max(masked.x, masked.y), max(masked.z, masked.w)));
    let terms = weight * exp(masked - peak);
    return vec2<f32>(peak, sum.y * exp(sum.x - peak) + dot(terms, vec4<f32>(1.0)));
#else
    return vec2<f32>(sum.x, sum.y + dot(v, weight));
#endif
}

// Mean of the n >= 1 values added to a running sum.
fn esm_sum_mean(sum: vec2<f32>, n: f32) -> f32 {
#ifdef VOLFOG_ESM_LOG_SPACE
    return sum.x + log(sum.y / n);
#else
    return sum.y / n;
#endif
}

// Visibility in [0, 1] of a receiver at depth `receiver` given a filtered occluder value.
fn esm_visibility(occluder: f32, receiver: f32, exponent: f32) -> f32 {
#ifdef VOLFOG_ESM_LOG_SPACE
    return clamp(exp(min(occluder - exponent * receiver, 0.0)), 0.0, 1.0);
#else
    return clamp(occluder * exp(-exponent * receiver), 0.0, 1.0);
#endif
}

// Bilinear filtering of one ESM layer at uv (R32Float is not filterable in WebGPU, so
// the four texels are loaded and weighted here; clamp to edge). In log space the
// occluder values are interpolated in their linear domain.
fn esm_occluder(esm: texture_2d_array<f32>, uv: vec2<f32>, layer: u32) -> f32 {
    let size = vec2<i32>(textureDimensions(esm));
    let texel = uv * vec2<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let lo = clamp(vec2<i32>(base), vec2<i32>(0), size - 1);
    let hi = clamp(vec2<i32>(base) + 1, vec2<i32>(0), size - 1);
    let v = vec4<f32>(
        textureLoad(esm, vec2<i32>(lo.x, lo.y), layer, 0).r,
        textureLoad(esm, vec2<i32>(hi.x, lo.y), layer, 0).r,
        textureLoad(esm, vec2<i32>(lo.x, hi.y), layer, 0).r,
        textureLoad(esm, vec2<i32>(hi.x, hi.y), layer, 0).r,
    );
    let w = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
#ifdef VOLFOG_ESM_LOG_SPACE
    let m = max(max(v.x, v.y), max(v.z, v.w));
    return m + log(max(dot(exp(v - m), w), 1e-30));
#else
    return dot(v, w);
#endif
}

// Cascade index for a view depth (m): the first cascade whose split exceeds it, or
// `count` when the depth lies beyond the last cascade.
fn esm_cascade(view_depth: f32, splits: vec4<f32>, count: u32) -> u32 {
    var i = 0u;
    while i < count && view_depth >= splits[i] {
        i += 1u;
    }
    return i;
}

// Shadow-map uv (v down) and depth of a world position in a cascade.
fn esm_shadow_coord(light_from_world: mat4x4<f32>, world: vec3<f32>) -> vec3<f32> {
    let clip = light_from_world * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / clip.w;
    return vec3<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5, ndc.z);
}

// Visibility in [0, 1] of the directional light at a world position in one cascade:
// light_from_world is that cascade's matrix and layer its ESM array layer; 1 outside the
// cascade's shadow map. Passes that hold the cascades in a uniform call this with
// `cascades.light_from_world[esm_cascade(...)]` read from the uniform: indexing a
// by-value ShadowCascades with a varying index makes some drivers copy the four
// matrices to scratch memory per invocation (lavapipe: 40 % of the inject pass).
fn esm_shadow_cascade(
    esm: texture_2d_array<f32>,
    light_from_world: mat4x4<f32>,
    layer: u32,
    exponent: f32,
    world: vec3<f32>,
) -> f32 {
    let coord = esm_shadow_coord(light_from_world, world);
    if any(coord.xy < vec2<f32>(0.0)) || any(coord.xy > vec2<f32>(1.0)) || coord.z > 1.0 {
        return 1.0;
    }
    let occluder = esm_occluder(esm, coord.xy, layer);
    return esm_visibility(occluder, clamp(coord.z, 0.0, 1.0), exponent);
}

// Visibility of the directional light at a world position and view depth, from the
// cascades' filtered ESM array (1 outside every cascade). The cascade's matrix is
// picked with constant indices (see esm_shadow_cascade for the faster form).
fn esm_shadow(
    esm: texture_2d_array<f32>,
    cascades: ShadowCascades,
    world: vec3<f32>,
    view_depth: f32,
) -> f32 {
    let i = esm_cascade(view_depth, cascades.splits, cascades.count);
    if i >= cascades.count {
        return 1.0;
    }
    var light_from_world = cascades.light_from_world[0];
    if i == 1u {
        light_from_world = cascades.light_from_world[1];
    } else if i == 2u {
        light_from_world = cascades.light_from_world[2];
    } else if i == 3u {
        light_from_world = cascades.light_from_world[3];
    }
    return esm_shadow_cascade(esm, light_from_world, i, cascades.exponent, world);
}
