// volfog::water — underwater fog below a water plane (rivers and the ocean), the light
// reaching a point under water, and the soft fade of the water surface at the shore.
//
// Use:      #import volfog::water::{water_fog, water_light, water_shore_fade, water_scene_depth}
//           // Under water, or looking into the water from above:
//           color = apply_fog(color * water_light(water, p), water_fog(water, eye, p));
//           // In the water surface's own shader (alpha blended over the scene):
//           let scene = water_scene_depth(linear_depth, pixel);
//           alpha *= water_shore_fade(surface_view_depth, scene, water.shore_fade);
// Defines:  none
// Model:    water fills the half-space dot(p, normal) < height; depth below the surface
//           d(p) = height - dot(p, normal). Extinction sigma (1/m) is uniform. Light
//           falls in straight down (along -normal) with radiance L just below the
//           surface and reaches depth d as L exp(-K d) (K per channel, 1/m: the
//           oceanographers' diffuse attenuation; water takes red first). A view segment
//           from the eye to the shaded point is clipped to the water, [u0, u1] along the
//           unit direction w; its in-scattered radiance is
//             S = albedo sigma L p(dot(w, normal), g) * int_0^s exp(-K d(u) - sigma u) du
//           with d(u) = d0 - u dot(w, normal) and s = u1 - u0, in closed form
//             S = albedo sigma L p * s * exp(e0) * E((sigma - K dot(w, normal)) s),
//           E(x) = (1 - exp(-x)) / x (volfog::height_fog), evaluated from the larger end
//           exponent so that it never overflows; transmittance T = exp(-sigma s).
//           Ocean (Wenzel 2007): K > 0, the depth-dependent model. River: K = 0, the
//           uniform model, where S reduces to albedo L p (1 - T) exactly (as a plane fog
//           volume of volfog::fog_volume with uniform density).
// Output:   vec4(in-scattered radiance rgb, transmittance a), as the froxel volume;
//           composite with the other fog (volfog::fog_volume::fog_over) in ray order.
// Shore:    the surface fades in over shore_fade metres of view depth between the
//           surface and the scene behind it. With a resolved multisampled depth the
//           scene depth of a silhouette pixel is an average and may lie in front of the
//           surface; water_scene_depth takes the largest depth of the pixel and its four
//           direct neighbours, which restores "scene behind surface" (Wenzel 2007,
//           "Scene depth based rendering and MSAA: River / Ocean").
// Units:    metres, world space; extinction and attenuation 1/m; view depths in metres
//           along the view axis, positive in front of the eye.
// Robustness: every finite input gives a finite result (positions clamped to +-1e9 m,
//           exponents to +-80); the eye exactly on the surface or a ray along it is fine.
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "River
//           shading", "Ocean shading", "Scene depth based rendering and MSAA".
#define_import_path volfog::water

#import volfog::types::Water
#import volfog::phase::phase_hg
#import volfog::height_fog::{exp_segment_average, FOG_EXPONENT_LIMIT, FOG_POSITION_LIMIT}

// A shore fade shorter than this (m) is a hard depth test.
const WATER_MIN_SHORE_FADE: f32 = 1e-6;

// Depth (m) of p below the surface; negative above it.
fn water_depth(water: Water, p: vec3<f32>) -> f32 {
    let lim = vec3<f32>(FOG_POSITION_LIMIT);
    return clamp(water.height, -FOG_POSITION_LIMIT, FOG_POSITION_LIMIT) - dot(clamp(p, -lim, lim), water.normal);
}

// Ray parameters [t0, t1] within [0, 1] of the part of the segment from camera_pos
// (t = 0) to point (t = 1) below the surface; t0 == t1 when it stays above. A segment
// lying in the surface plane counts as under water (the boundary belongs to the water).
fn water_segment(water: Water, camera_pos: vec3<f32>, point: vec3<f32>) -> vec2<f32> {
    let d0 = water_depth(water, camera_pos);
    let d1 = water_depth(water, point);
    var t = vec2<f32>(0.0, 1.0);
    if d0 < 0.0 && d1 < 0.0 {
        t = vec2<f32>(1.0, 1.0);
    } else if d0 < 0.0 {
        // Enters the water on the way: depth crosses zero at d0 / (d0 - d1).
        t = vec2<f32>(clamp(d0 / (d0 - d1), 0.0, 1.0), 1.0);
    } else if d1 < 0.0 {
        t = vec2<f32>(0.0, clamp(d0 / (d0 - d1), 0.0, 1.0));
    }
    return t;
}

// Light (linear rgb) reaching p under water: light * exp(-attenuation * depth); light
// above the surface. Multiply it into the direct light of surfaces under water.
fn water_light(water: Water, p: vec3<f32>) -> vec3<f32> {
    let d = max(water_depth(water, p), 0.0);
    return water.light * exp(-min(water.attenuation * d, vec3<f32>(FOG_EXPONENT_LIMIT)));
}

// Integral over u in [0, s] of exp(e0 - x u / s): s exp(e0) E(x), evaluated from the
// larger end exponent so that neither a steep rise nor a long fall overflows.
fn water_exp_integral(s: f32, e0: f32, x: f32) -> f32 {
    let e = clamp(max(e0, e0 - x), -FOG_EXPONENT_LIMIT, FOG_EXPONENT_LIMIT);
    return s * exp(e) * exp_segment_average(abs(x));
}

// Underwater fog between camera_pos and point (m, world space): vec4(in-scattered
// radiance rgb, transmittance a). Either end may be above the surface.
fn water_fog(water: Water, camera_pos: vec3<f32>, point: vec3<f32>) -> vec4<f32> {
    let lim = vec3<f32>(FOG_POSITION_LIMIT);
    let eye = clamp(camera_pos, -lim, lim);
    let seg = clamp(point, -lim, lim) - eye;
    let t = water_segment(water, eye, eye + seg);
    let length_all = length(seg);
    let s = (t.y - t.x) * length_all;
    let dir = seg / max(length_all, 1e-30);
    let entry = eye + t.x * seg;
    let d0 = max(water_depth(water, entry), 0.0);
    let up = clamp(dot(dir, water.normal), -1.0, 1.0);
    let sigma = clamp(water.extinction, 0.0, 1e3);
    let k = clamp(water.attenuation, vec3<f32>(0.0), vec3<f32>(1e3));
    let lobe = phase_hg(up, clamp(water.g, -0.999, 0.999));
    let source = water.albedo * water.light * (sigma * lobe);
    let x = (vec3<f32>(sigma) - k * up) * s;
    let e0 = -min(k * d0, vec3<f32>(FOG_EXPONENT_LIMIT));
    let integral = vec3<f32>(
        water_exp_integral(s, e0.x, x.x),
        water_exp_integral(s, e0.y, x.y),
        water_exp_integral(s, e0.z, x.z),
    );
    return vec4<f32>(source * integral, exp(-sigma * s));
}

// Opacity factor in [0, 1] of a water surface at view depth surface_depth in front of
// the scene at view depth scene_depth (m): 0 where they meet, rising linearly to 1
// where the scene lies fade metres of view depth behind the surface.
fn water_shore_fade(surface_depth: f32, scene_depth: f32, fade: f32) -> f32 {
    let gap = clamp(scene_depth - surface_depth, -FOG_POSITION_LIMIT, FOG_POSITION_LIMIT);
    return clamp(gap / max(fade, WATER_MIN_SHORE_FADE), 0.0, 1.0);
}

// The scene's view depth (m) behind a water pixel from a linear view-depth texture
// (red channel): the largest of the pixel and its four direct neighbours, clamped to
// the texture. With a single-sampled depth it is at least the pixel's own depth.
fn water_scene_depth(linear_depth: texture_2d<f32>, pixel: vec2<i32>) -> f32 {
    let hi = vec2<i32>(textureDimensions(linear_depth)) - 1;
    let c = clamp(pixel, vec2<i32>(0), hi);
    var depth = textureLoad(linear_depth, c, 0).r;
    depth = max(depth, textureLoad(linear_depth, clamp(c + vec2<i32>(1, 0), vec2<i32>(0), hi), 0).r);
    depth = max(depth, textureLoad(linear_depth, clamp(c - vec2<i32>(1, 0), vec2<i32>(0), hi), 0).r);
    depth = max(depth, textureLoad(linear_depth, clamp(c + vec2<i32>(0, 1), vec2<i32>(0), hi), 0).r);
    depth = max(depth, textureLoad(linear_depth, clamp(c - vec2<i32>(0, 1), vec2<i32>(0), hi), 0).r);
    return depth;
}
