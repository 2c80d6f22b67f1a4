// volfog::frustum — world positions from depth for fullscreen passes, the cheap way:
// rays through the screen's corners interpolated by the rasterizer, one multiply-add
// per pixel.
//
// Use:      @vertex fn vs(@builtin(vertex_index) i: u32) -> Out {
//               let v = frustum_vertex(rays, i);   // clip position and corner ray
//           }
//           @fragment: let p = frustum_world_position(rays, in.ray,
//                          frustum_view_depth(rays, depth_buffer_value));
// Defines:  none
// Method:   the vectors from the camera to the points at view depth 1 through the
//           four corners are affine in screen uv (they lie on one plane), so the
//           vertex stage's value at the fullscreen triangle's corners, interpolated
//           linearly (perspective-correctly: w is 1), is the exact ray of every pixel;
//           the pixel's world position is camera + ray * view depth. The view depth
//           comes from the depth-buffer value with two terms of the inverse projection
//           (standard, reversed or infinite depth).
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited",
//           "Recovering World Space Position from Depth".
#define_import_path volfog::frustum

#import volfog::types::FrustumRays
#import volfog::fullscreen::fullscreen_position

// A vertex of the fullscreen triangle with its corner ray.
struct FrustumVertex {
    clip: vec4<f32>,
    ray: vec3<f32>,
}

// The world-space ray (to view depth 1) through screen uv (v down), bilinear in the
// corners (exactly linear for a perspective projection).
fn frustum_ray(rays: FrustumRays, uv: vec2<f32>) -> vec3<f32> {
    let top = mix(rays.corners[0].xyz, rays.corners[1].xyz, uv.x);
    let bottom = mix(rays.corners[2].xyz, rays.corners[3].xyz, uv.x);
    return mix(top, bottom, uv.y);
}

// Vertex `index` of the fullscreen triangle and its ray (interpolate it to the pixels).
fn frustum_vertex(rays: FrustumRays, index: u32) -> FrustumVertex {
    let clip = fullscreen_position(index);
    let uv = vec2<f32>(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5);
    // Field by field: a constructor expression becomes a helper function in HLSL,
    // outside the snippet's volfog_ names.
    var v: FrustumVertex;
    v.clip = clip;
    v.ray = frustum_ray(rays, uv);
    return v;
}

// View depth (m, positive in front of the camera) of a depth value d given the depth
// terms t of a perspective projection: -(t.x d + t.y) / (t.z d + t.w), the depth rows
// of the inverse projection (FrustumRays.depth_terms); at most 1e30 (a point at
// infinity).
fn frustum_depth_from_terms(t: vec4<f32>, d: f32) -> f32 {
    let w = t.z * d + t.w;
    return min(-(t.x * d + t.y) / select(w, 1e-30, abs(w) < 1e-30), 1e30);
}

// View depth (m, positive in front of the camera) of a depth-buffer value; at most
// 1e30 (a point at infinity).
fn frustum_view_depth(rays: FrustumRays, depth: f32) -> f32 {
    return frustum_depth_from_terms(rays.depth_terms, depth);
}

// Is a pixel at this view depth the sky (at or beyond the far plane)?
fn frustum_is_sky(rays: FrustumRays, view_depth: f32) -> bool {
    return view_depth >= 0.9999 * rays.camera.w;
}

// World position of the pixel with ray `ray` (from frustum_vertex, interpolated) at
// view depth view_depth: one multiply-add.
fn frustum_world_position(rays: FrustumRays, ray: vec3<f32>, view_depth: f32) -> vec3<f32> {
    return rays.camera.xyz + ray * view_depth;
}
