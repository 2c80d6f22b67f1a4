// volfog::local_shadow — shadows and cookies of point and spot lights in the fog:
// exponential shadow maps of the lights' own depth maps, gathered in one atlas.
//
// Use:      #import volfog::local_shadow::{local_shadow_visibility, light_cookie, LOCAL_SHADOW_NONE}
//           (local_shadow_compare: the compare filter against the lights' own depth maps)
//           let p = projections[light.projection];     // when != LOCAL_SHADOW_NONE
//           light_in *= local_shadow_visibility(atlas, p, world)
//               * light_cookie(cookies, cookie_sampler, p, world);
// Defines:  VOLFOG_ESM_LOG_SPACE — the atlas holds log-space values (see volfog::esm).
// Data:     the atlas is an R32Float 2D array; a spot light owns one layer, a point light
//           six (its cube's faces in the order +X, -X, +Y, -Y, +Z, -Z, each laid out as a
//           cube map face: the major axis picks the face, the other two give (u, v) as
//           in the Vulkan / WebGPU cube face table). A texel holds the filtered occluder
//           term of linear depths: the distance along the light's axis (spot) or the
//           face's axis (point) over LightProjection.depth_range, so the ESM exponent
//           c has a metric meaning: behind an occluder the visibility falls below 0.05
//           once the receiver is 3 depth_range / c behind it (the leak band).
// Units:    metres, world space.
// Reference: Wronski 2014, "Density estimation and volume lighting" (point lights in
//           the injection loop) and the bonus slides on ESM in volumetric fog; Annen et
//           al. 2008, "Exponential Shadow Maps" (linear depth, the exponent as a leak
//           length); cube face selection as in the Vulkan specification, "Cube Map Face
//           Selection and Transformations".
#define_import_path volfog::local_shadow

#import volfog::types::LightProjection
#import volfog::esm::{esm_encode, esm_occluder, esm_visibility}
#import volfog::frustum::frustum_depth_from_terms
#import volfog::shadow::{shadow_pcf, shadow_receiver_depth, shadow_depth_increasing}

// No projection (FogLight.projection), no shadow (LightProjection.layer) or no cookie
// (LightProjection.cookie).
const LOCAL_SHADOW_NONE: u32 = 0xffffffffu;
// LightProjection.kind.
const LOCAL_SHADOW_SPOT: u32 = 0u;
const LOCAL_SHADOW_POINT: u32 = 1u;

// Where a direction from a point light falls on its cube map.
struct CubeCoord {
    // Texture coordinate on the face, [0, 1]^2, v down.
    uv: vec2<f32>,
    // Face: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
    face: u32,
    // Distance along the face's axis (the face camera's view depth), >= 0.
    depth: f32,
}

// The cube face, its coordinate and the depth along its axis of a vector in the cube
// map's space (from the light to the point). The largest component picks the face
// (x before y before z on ties).
fn local_shadow_cube(to_point: vec3<f32>) -> CubeCoord {
    let axes = abs(to_point);
    var coord: CubeCoord;
    var st: vec2<f32>;
    if axes.x >= axes.y && axes.x >= axes.z {
        coord.face = select(1u, 0u, to_point.x >= 0.0);
        coord.depth = axes.x;
        st = vec2<f32>(select(to_point.z, -to_point.z, to_point.x >= 0.0), -to_point.y);
    } else if axes.y >= axes.z {
        coord.face = select(3u, 2u, to_point.y >= 0.0);
        coord.depth = axes.y;
        st = vec2<f32>(to_point.x, select(-to_point.z, to_point.z, to_point.y >= 0.0));
    } else {
        coord.face = select(5u, 4u, to_point.z >= 0.0);
        coord.depth = axes.z;
        st = vec2<f32>(select(-to_point.x, to_point.x, to_point.z >= 0.0), -to_point.y);
    }
    coord.uv = 0.5 * st / max(coord.depth, 1e-30) + 0.5;
    return coord;
}

// Texture coordinate (xy, v down) and depth along the axis (z, m; <= 0 behind the
// light) of a world position in a spot light's shadow camera (light_from_world = its
// projection times its view).
fn local_shadow_spot(light_from_world: mat4x4<f32>, world: vec3<f32>) -> vec3<f32> {
    let clip = light_from_world * vec4<f32>(world, 1.0);
    let w = select(clip.w, 1e-30, abs(clip.w) < 1e-30);
    return vec3<f32>(clip.x / w * 0.5 + 0.5, 0.5 - clip.y / w * 0.5, clip.w);
}

// Is a spot coordinate in front of the light and inside its shadow camera's frustum?
fn local_shadow_spot_inside(coord: vec3<f32>) -> bool {
    return coord.z > 0.0 && all(coord.xy >= vec2<f32>(0.0)) && all(coord.xy <= vec2<f32>(1.0));
}

// Linear depth in [0, 1] that the atlas stores for a shadow-map depth value d: the
// view depth from the depth terms of the shadow camera's projection over depth_range.
fn local_shadow_linear_depth(depth_terms: vec4<f32>, d: f32, depth_range: f32) -> f32 {
    return clamp(frustum_depth_from_terms(depth_terms, d) / depth_range, 0.0, 1.0);
}

// Occluder value of one shadow-map depth d (linear or log space; volfog::esm).
fn local_shadow_encode(depth_terms: vec4<f32>, d: f32, depth_range: f32, exponent: f32) -> f32 {
    return esm_encode(local_shadow_linear_depth(depth_terms, d, depth_range), exponent);
}

// Visibility in [0, 1] of a light at a world position through its ESM in the atlas:
// 1 when the light has no shadow (layer LOCAL_SHADOW_NONE) and, for a spot light,
// outside its shadow camera's frustum (where its cone gives no light anyway).
fn local_shadow_visibility(atlas: texture_2d_array<f32>, light_projection: LightProjection, world: vec3<f32>) -> f32 {
    if light_projection.layer == LOCAL_SHADOW_NONE {
        return 1.0;
    }
    var uv: vec2<f32>;
    var layer = light_projection.layer;
    var depth: f32;
    if light_projection.kind == LOCAL_SHADOW_POINT {
        let cube = local_shadow_cube((light_projection.light_from_world * vec4<f32>(world, 1.0)).xyz);
        uv = cube.uv;
        layer += cube.face;
        depth = cube.depth;
    } else {
        let spot = local_shadow_spot(light_projection.light_from_world, world);
        if !local_shadow_spot_inside(spot) {
            return 1.0;
        }
        uv = spot.xy;
        depth = spot.z;
    }
    let receiver = clamp((depth - light_projection.bias) / light_projection.depth_range, 0.0, 1.0);
    return esm_visibility(esm_occluder(atlas, uv, layer), receiver, light_projection.exponent);
}

// Visibility in [0, 1] of a light at a world position by the compare filter
// (volfog::shadow): a 2 x 2 percentage-closer compare against the light's own depth map,
// layer light_projection.layer of the spot lights' maps or, for a point light, the
// face's layer of the cube starting there in the point lights' maps (both depth maps
// bound as unfilterable float). The receiver, moved `bias` nearer the light, is mapped
// into the map's depth through LightProjection.depth_terms. 1 when the light has no
// shadow and, for a spot light, outside its shadow camera's frustum.
fn local_shadow_compare(
    spot_maps: texture_2d_array<f32>,
    point_maps: texture_2d_array<f32>,
    gather: sampler,
    light_projection: LightProjection,
    world: vec3<f32>,
) -> f32 {
    if light_projection.layer == LOCAL_SHADOW_NONE {
        return 1.0;
    }
    let terms = light_projection.depth_terms;
    let increasing = shadow_depth_increasing(terms);
    if light_projection.kind == LOCAL_SHADOW_POINT {
        let cube = local_shadow_cube((light_projection.light_from_world * vec4<f32>(world, 1.0)).xyz);
        let receiver = shadow_receiver_depth(terms, max(cube.depth - light_projection.bias, 0.0));
        return shadow_pcf(point_maps, gather, cube.uv, light_projection.layer + cube.face, receiver, increasing);
    }
    let spot = local_shadow_spot(light_projection.light_from_world, world);
    if !local_shadow_spot_inside(spot) {
        return 1.0;
    }
    let receiver = shadow_receiver_depth(terms, max(spot.z - light_projection.bias, 0.0));
    return shadow_pcf(spot_maps, gather, spot.xy, light_projection.layer, receiver, increasing);
}

// Colour (linear rgb) a spot light's cookie gives its light at a world position: the
// cookie layer sampled at the shadow camera's coordinate, 0 outside its frustum; 1
// without a cookie (cookie LOCAL_SHADOW_NONE) or for a point light.
fn light_cookie(
    cookie_layers: texture_2d_array<f32>,
    cookie_filter: sampler,
    light_projection: LightProjection,
    world: vec3<f32>,
) -> vec3<f32> {
    if light_projection.cookie == LOCAL_SHADOW_NONE || light_projection.kind != LOCAL_SHADOW_SPOT {
        return vec3<f32>(1.0);
    }
    let spot = local_shadow_spot(light_projection.light_from_world, world);
    if !local_shadow_spot_inside(spot) {
        return vec3<f32>(0.0);
    }
    return textureSampleLevel(cookie_layers, cookie_filter, spot.xy, light_projection.cookie, 0.0).rgb;
}
