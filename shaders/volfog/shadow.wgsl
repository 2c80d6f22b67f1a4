// volfog::shadow — the fog's compare filter: depth compares against the full-resolution
// shadow maps at points spread over each froxel.
//
// Use:      #import volfog::shadow::{shadow_pcf, shadow_cascade_compare, shadow_receiver_depth}
// Defines:  none
// Data:     shadow maps are depth textures bound as unfilterable float 2D arrays and read
//           with textureGather through a non-filtering (nearest, clamp-to-edge) sampler.
//           A depth map stores the nearest occluder per texel; a receiver is lit by a
//           texel whose stored depth is not nearer the light than its own.
// Why:      a froxel spans many shadow-map texels; prefiltering the map (the ESM of
//           volfog::esm) spreads an occluder's edge over the blur's footprint, so light
//           leaks around shafts. Compares taken at points that move through the froxel
//           from frame to frame, blended by the temporal reprojection (volfog::temporal),
//           converge to the visibility averaged over the froxel's own volume and leak
//           nothing beyond it (the sampling of Wronski 2014, "Sample jittering", applied
//           to the shadow term; a 2 x 2 percentage-closer filter per compare, Reeves et
//           al. 1987, keeps a tap's edge to one texel).
// Units:    uv in [0, 1] (v down), depths as stored in the maps.
#define_import_path volfog::shadow

#import volfog::esm::esm_shadow_coord
#import volfog::frustum::frustum_depth_from_terms

// Visibility in [0, 1] of a receiver at depth `receiver` through the 2 x 2 texels around
// uv of layer `layer`, each compare weighted bilinearly (percentage-closer filtering).
// `increasing`: the stored depth grows away from the light (standard depth), so a texel
// lights the receiver when it holds a depth >= receiver; otherwise (reversed depth) when
// it holds a depth <= receiver. Texels beyond the edge repeat the edge (clamp to edge).
fn shadow_pcf(
    map: texture_2d_array<f32>,
    gather: sampler,
    uv: vec2<f32>,
    layer: u32,
    receiver: f32,
    increasing: bool,
) -> f32 {
    let size = vec2<f32>(textureDimensions(map));
    let texel = uv * size - 0.5;
    let base = floor(texel);
    let f = texel - base;
    // Gathered at the corner the four texels share, so the footprint is the one the
    // weights assume whatever the hardware's sub-texel rounding.
    let depths = textureGather(0, map, gather, (base + 1.0) / size, layer);
    let farther = vec4<f32>(depths >= vec4<f32>(receiver));
    let nearer = vec4<f32>(depths <= vec4<f32>(receiver));
    // 1 where a texel lights the receiver.
    let lit = select(nearer, farther, increasing);
    // textureGather order: x (u0, v1), y (u1, v1), z (u1, v0), w (u0, v0).
    let w = vec4<f32>((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    return dot(lit, w);
}

// Visibility in [0, 1] of the directional light at a world position through one
// cascade of its shadow map: light_from_world is the cascade's matrix (standard depth
// in [0, 1], volfog::esm::esm_shadow_coord) and layer its array layer; `reversed`: the
// map holds 1 - depth. 1 outside the cascade's map and beyond its far plane.
fn shadow_cascade_compare(
    map: texture_2d_array<f32>,
    gather: sampler,
    light_from_world: mat4x4<f32>,
    layer: u32,
    world: vec3<f32>,
    reversed: bool,
) -> f32 {
    let coord = esm_shadow_coord(light_from_world, world);
    if any(coord.xy < vec2<f32>(0.0)) || any(coord.xy > vec2<f32>(1.0)) || coord.z > 1.0 {
        return 1.0;
    }
    let depth = clamp(coord.z, 0.0, 1.0);
    return shadow_pcf(map, gather, coord.xy, layer, select(depth, 1.0 - depth, reversed), !reversed);
}

// The view depth (m) at which a shadow tap samples the fog the camera sees: a tap at
// screen uv (v down) and view depth `view_depth` in a froxel spanning view depths
// [near, far] (m) is moved, with every tap of that screen position, into the part of
// the span in front of the opaque surface the scene depth holds there,
// near + (view_depth - near) clamp((surface - near) / (far - near), 0, 1). The fog
// ends at that surface, and a tap behind it, inside an object, would read the object's
// own shadow; uniform taps over the froxel stay uniform over its visible part (at the
// near face where the surface hides all of it). `surface_depth` is the camera's
// depth texture (device depth, any mip level), interpolated bilinearly between texel
// centres: device depth is affine in screen position across a plane, so a plane's
// depth comes out exact between texels (at a grazing view one texel spans metres of
// depth); `depth_terms` are the camera projection's depth terms (volfog::frustum).
fn shadow_tap_visible_depth(
    surface_depth: texture_2d<f32>,
    uv: vec2<f32>,
    view_depth: f32,
    near: f32,
    far: f32,
    depth_terms: vec4<f32>,
) -> f32 {
    let size = vec2<i32>(textureDimensions(surface_depth));
    let texel = clamp(uv, vec2<f32>(0.0), vec2<f32>(1.0)) * vec2<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let lo = clamp(vec2<i32>(base), vec2<i32>(0), size - 1);
    let hi = clamp(vec2<i32>(base) + 1, vec2<i32>(0), size - 1);
    let top = mix(textureLoad(surface_depth, lo, 0).r, textureLoad(surface_depth, vec2<i32>(hi.x, lo.y), 0).r, f.x);
    let bottom = mix(textureLoad(surface_depth, vec2<i32>(lo.x, hi.y), 0).r, textureLoad(surface_depth, hi, 0).r, f.x);
    let surface = frustum_depth_from_terms(depth_terms, mix(top, bottom, f.y));
    let visible = clamp((surface - near) / max(far - near, 1e-6), 0.0, 1.0);
    return near + (view_depth - near) * visible;
}

// Depth value in [0, 1] a perspective shadow camera stores for view depth z (m, > 0),
// given its depth terms (view depth of a depth value d: -(x d + y) / (z d + w); the
// inverse is d = -(y + w z) / (x + z z)), clamped to [0, 1] so that a receiver beyond
// the far plane compares like the far plane and one before the near plane like the
// near plane.
fn shadow_receiver_depth(depth_terms: vec4<f32>, view_depth: f32) -> f32 {
    let den = depth_terms.x + depth_terms.z * view_depth;
    let d = -(depth_terms.y + depth_terms.w * view_depth) / select(den, 1e-30, abs(den) < 1e-30);
    return clamp(d, 0.0, 1.0);
}

// Whether the depth values of a camera with these depth terms grow with view depth
// (standard depth) rather than fall (reversed depth).
fn shadow_depth_increasing(depth_terms: vec4<f32>) -> bool {
    // d(z) = -(y + w z) / (x + z z) has the derivative -(w x - z y) / (x + z z)^2.
    return depth_terms.w * depth_terms.x - depth_terms.z * depth_terms.y < 0.0;
}
