// volfog::types — uniform structures shared by the passes and the forward snippet.
//
// Use:      #import volfog::types::Froxels
// Defines:  none
// Layout:   every struct here has a Rust twin in `volfog::uniforms` (encase); a test
//           compares their member offsets and sizes with naga's layout.
// Units:    metres, view space right-handed (camera looks down -Z), clip space as in
//           WebGPU (x, y in [-1, 1] with y up, depth in [0, 1]).
#define_import_path volfog::types

// Placement of a camera-aligned froxel volume (Wronski 2014, "Volume texture layout").
// x and y follow the screen (uv in [0, 1], v down), z follows view depth through the
// slice distribution of volfog::froxel.
struct Froxels {
    // Projection of the camera the volume is aligned with (view -> clip).
    clip_from_view: mat4x4<f32>,
    // Inverse of clip_from_view (clip -> view).
    view_from_clip: mat4x4<f32>,
    // Volume size in froxels: screen x, screen y, depth slices; each >= 1.
    size: vec3<u32>,
    // View depth of the front of the first slice, metres, > 0.
    near: f32,
    // View depth of the back of the last slice, metres, > near.
    far: f32,
    // Slice distribution curve, >= 0: 0 gives equal thickness, ln(far / near) gives a
    // constant thickness-to-depth ratio (exponential slices).
    curve: f32,
}
