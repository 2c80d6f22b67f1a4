// Pass clouds — the cloud layer's fullscreen passes over the lit scene (volfog::clouds),
// each pixel's world position from the depth buffer through the frustum's corner rays
// (volfog::frustum): cloud shadows, distance clouds and the lit cloud layer.
//
// Draw: 3 vertices with clouds_vs, no vertex buffers, onto the lit colour target (load,
// no depth attachment). Blend colour: src * One + dst * SrcAlpha (add); alpha: src * Zero
// + dst * One (add), as the apply pass. cloud_shadow_fs writes (0, T): the lit colour is
// multiplied by the clouds' shadow; distance_clouds_fs and cloud_layer_fs write
// (in-scatter, transmittance). Pixels at or beyond the far plane are the sky: no
// shadow, and the clouds in front of them unbounded.
// Bindings (group 0):
//   0  uniform FrustumRays        1  uniform CloudLayer
//   2  texture_2d<f32>: the cloud density map (red channel, filterable)
//   3  sampler: linear, repeat
//   4  texture_2d<f32>, unfilterable: the scene depth buffer (textureLoad)

#import volfog::types::{FrustumRays, CloudLayer}
#import volfog::frustum::{frustum_vertex, frustum_view_depth, frustum_world_position, frustum_is_sky}
#import volfog::clouds::{cloud_shadow, distance_clouds, cloud_layer}

@group(0) @binding(0) var<uniform> frustum_rays: FrustumRays;
@group(0) @binding(1) var<uniform> cloud_layer_params: CloudLayer;
@group(0) @binding(2) var cloud_map: texture_2d<f32>;
@group(0) @binding(3) var cloud_sampler: sampler;
@group(0) @binding(4) var cloud_scene_depth: texture_2d<f32>;

struct CloudVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) ray: vec3<f32>,
}

@vertex
fn clouds_vs(@builtin(vertex_index) index: u32) -> CloudVertex {
    let v = frustum_vertex(frustum_rays, index);
    return CloudVertex(v.clip, v.ray);
}

// View depth of the pixel's scene point.
fn pixel_view_depth(frag: vec4<f32>) -> f32 {
    return frustum_view_depth(frustum_rays, textureLoad(cloud_scene_depth, vec2<i32>(frag.xy), 0).r);
}

// The sky (at or beyond the far plane) gets no shadow.
@fragment
fn cloud_shadow_fs(in: CloudVertex) -> @location(0) vec4<f32> {
    let depth = pixel_view_depth(in.clip);
    let p = frustum_world_position(frustum_rays, in.ray, depth);
    let shadow = cloud_shadow(cloud_map, cloud_sampler, cloud_layer_params, p);
    return vec4<f32>(0.0, 0.0, 0.0, select(shadow, 1.0, frustum_is_sky(frustum_rays, depth)));
}

// The scene's distance along the unit view direction (the ray has view depth 1); the
// sky is infinitely far.
fn scene_distance(in: CloudVertex) -> f32 {
    let depth = pixel_view_depth(in.clip);
    return select(depth * length(in.ray), 1e30, frustum_is_sky(frustum_rays, depth));
}

@fragment
fn distance_clouds_fs(in: CloudVertex) -> @location(0) vec4<f32> {
    let dir = normalize(in.ray);
    return distance_clouds(cloud_map, cloud_sampler, cloud_layer_params, frustum_rays.camera.xyz, dir, scene_distance(in));
}

@fragment
fn cloud_layer_fs(in: CloudVertex) -> @location(0) vec4<f32> {
    let dir = normalize(in.ray);
    return cloud_layer(cloud_map, cloud_sampler, cloud_layer_params, frustum_rays.camera.xyz, dir, scene_distance(in));
}
