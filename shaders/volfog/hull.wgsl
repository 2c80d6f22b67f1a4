// volfog::hull — fog hulls: the thickness of fog inside closed meshes per pixel,
// measured from the distances of the hull's faces along each view ray, and the fog of
// a homogeneous medium of that thickness.
//
// Use:      #import volfog::hull::{HullVertex, hull_clip_position, hull_scene_distance,
//                                  hull_contribution, hull_thickness, hull_fog,
//                                  hull_camera_inside, hull_scene_inside}
//           (see shaders/passes/hull_thickness.wgsl and hull_composite.wgsl)
// Defines:  none
// Data:     a hull is a closed, orientable triangle mesh without holes (every ray enters
//           it as often as it leaves), faces wound counter-clockwise seen from outside.
//           Along a view ray, the fog between the camera and the scene is
//               thickness = sum over exits min(d, D) - sum over entries min(d, D)
//           with d the distance of a face crossing and D the distance of the scene
//           (the opaque surface seen in the pixel). Every fragment of the hull adds its
//           signed term (exit = back face +, entry = front face -) into a float target
//           with additive blending; a "hull sum" is the result per pixel:
//             x  thickness (m) in front of the scene: the multiples of the quantum
//             y  exits - entries over all faces: 1 where the ray starts inside the
//                hull (the camera is in fog), 0 outside
//             z  exits - entries over the faces behind the scene: 1 where the scene
//                point lies inside the hull, 0 outside
//             w  thickness (m): the remainders below the quantum (see Precision)
//           so that thickness = x + w. Clamping each term to D handles objects inside
//           the hull, concave hulls and the camera inside the hull at once: crossings
//           behind the scene add +-D and cancel in pairs except for the exit of a hull
//           the scene point lies in, which leaves the D - entry of Boyd's "objects in
//           the fog" (z is the count his inside/outside test multiplies D by); a ray
//           that starts inside has one exit more than entries, and its entry at
//           distance 0 contributes nothing.
// Reference: Boyd 2001, "Volumetric Rendering in Realtime": fog depth as the difference
//           of exit and entry depths (Stokes' theorem with constant flux), concave hulls
//           by summing all entries and all exits, objects in the fog, the camera in the
//           fog, the vertex-shader near-plane clamp and (supplement) the higher
//           precision carried across two channels; fog = colour * (1 - T) over the
//           scene attenuated by T, with T = exp(-density * thickness) (Beer-Lambert)
//           in place of the paper's linear 1 - density * thickness.
// Precision: terms are stored relative to a per-hull reference distance (a lower bound
//           of the distance of every hull point: the distance from the camera to the
//           hull's bounding box, 0 when the camera is inside it), so they lie in
//           [0, extent], extent the hull's depth range behind the reference. For an
//           rgba16float target each term v is split, like the supplement's carry
//           channels, into floor(v / q) * q (x) and the remainder (w) with q the
//           power-of-two quantum: the multiples of q add exactly in fp16 while partial
//           sums stay within 2048 q, and the remainders are below q, so the sum errs by
//           about crossings * q * 2^-12 instead of crossings * extent * 2^-12. An
//           rgba32float target (FLOAT32_BLENDABLE) needs no split (quantum 0) and errs
//           by about 2^-24 of the distances.
#define_import_path volfog::hull

#import volfog::froxel::ray_scale

// Clip w (m of view depth for a perspective projection) below which the hull is
// clipped: only the part within 1 mm of the camera plane and behind it is lost.
const HULL_MIN_W: f32 = 1e-3;

// Output of a hull vertex stage and input of its fragment stage.
struct HullVertex {
    // hull_clip_position of the vertex.
    @builtin(position) clip: vec4<f32>,
    // Position relative to the camera (m, world axes); its length at a fragment is the
    // distance of the face crossing along that pixel's view ray.
    @location(0) offset: vec3<f32>,
}

// Replaces the clip depth of a hull vertex so that neither the near nor the far plane
// clips the hull: z = w - HULL_MIN_W lies in [0, w] for every w >= HULL_MIN_W, so
// only the plane w = HULL_MIN_W clips. This is Boyd's vertex-shader clamp done on the
// clipping volume instead of on the vertices, so the triangles keep their shape; the
// hull faces between the camera and the near plane still add their terms, which a
// camera inside (or just outside) the hull needs. The depth it writes is meaningless:
// draw the hull without a depth attachment.
fn hull_clip_position(clip: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clip.xy, clip.w - HULL_MIN_W, clip.w);
}

// Distance (m) from the camera to the scene point at normalised device coordinates
// ndc (x, y in [-1, 1] with y up, z the depth-buffer value) given the inverse
// projection view_from_clip. Standard, reversed and infinite projections; a point at
// infinity gives a distance of at least 1e30.
fn hull_scene_distance(ndc: vec3<f32>, view_from_clip: mat4x4<f32>) -> f32 {
    let p = view_from_clip * vec4<f32>(ndc, 1.0);
    if abs(p.w) * 1e30 <= length(p.xyz) {
        return 1e30;
    }
    return min(length(p.xyz / p.w), 1e30);
}

// Distance (m) from the camera to the scene point at screen uv (v down) and view depth
// view_depth (m, the r channel of the resolved MSAA fog layout, volfog::apply::
// fog_layout): the view depth times the view ray's length per metre of view depth; at
// most 1e30.
fn hull_scene_distance_from_view_depth(uv: vec2<f32>, view_depth: f32, view_from_clip: mat4x4<f32>) -> f32 {
    return min(max(view_depth, 0.0) * ray_scale(uv, view_from_clip), 1e30);
}

// The signed term of one hull fragment: a face at face_distance (m) from the camera,
// the scene at scene_distance (m), the hull's reference distance (m, a lower bound of
// face distances, >= 0) and quantum (m, a power of two, or 0 for no split); entry is
// true for a front face (the ray enters the hull). Add it into the hull sum (see Data).
fn hull_contribution(
    face_distance: f32,
    scene_distance: f32,
    reference: f32,
    quantum: f32,
    entry: bool,
) -> vec4<f32> {
    let side = select(1.0, -1.0, entry);
    let v = max(min(face_distance, scene_distance), reference) - reference;
    var whole = v;
    if quantum > 0.0 {
        // Exact: dividing and multiplying by a power of two only moves the exponent.
        whole = floor(v / quantum) * quantum;
    }
    let behind = select(0.0, 1.0, face_distance >= scene_distance);
    return side * vec4<f32>(whole, 1.0, behind, v - whole);
}

// Fog thickness (m) in front of the scene from a hull sum, >= 0 (rounding can leave
// tiny negative sums where there is no fog).
fn hull_thickness(sum: vec4<f32>) -> f32 {
    return max(sum.x + sum.w, 0.0);
}

// Whether the view ray of a hull sum starts inside the hull (the camera is in fog).
fn hull_camera_inside(sum: vec4<f32>) -> bool {
    return sum.y > 0.5;
}

// Whether the scene point of a hull sum lies inside the hull.
fn hull_scene_inside(sum: vec4<f32>) -> bool {
    return sum.z > 0.5;
}

// Fog of a homogeneous medium of extinction density (1/m, >= 0) and in-scattered
// colour (linear rgb, the colour thick fog tends to) over thickness (m, >= 0):
// rgb = colour * (1 - T), a = T = exp(-density * thickness), the (in-scatter,
// transmittance) pair of volfog::apply, applied as colour * T + in-scatter.
fn hull_fog(thickness: f32, density: f32, color: vec3<f32>) -> vec4<f32> {
    let t = exp(-max(density, 0.0) * max(thickness, 0.0));
    return vec4<f32>(color * (1.0 - t), t);
}
