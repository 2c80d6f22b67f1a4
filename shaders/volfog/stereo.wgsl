// volfog::stereo — stereo fog: where an eye's froxel lands in the volume shared by both
// eyes.
//
// Use:      #import volfog::stereo::{stereo_resample_column, stereo_resample_uvw}
// Defines:  none
// Stereo fog injects (and temporally stabilises) one volume for both eyes, aligned with
// a centre eye whose frustum encloses both eyes' frusta (its apex behind the eyes where
// the left eye's left plane meets the right eye's right plane). Each eye then scans its
// own froxel grid, reading the shared volume trilinearly at the world position of each
// of its froxels' centres (the scan's VOLFOG_SCAN_RESAMPLE variant). The density and
// lighting of a world point are the same for both eyes; what the shared volume cannot
// hold per eye is the phase function's view direction (the centre eye's, off by about
// the eye's distance from the centre apex over the point's distance, in radians) and
// detail finer than one froxel of the shared grid (shadow edges blur by about one
// froxel of it).
#define_import_path volfog::stereo

#import volfog::types::Froxels
#import volfog::froxel::{slice_coord, uv_from_ndc}

// The shared volume's clip coordinates along an eye's froxel column: the point at eye
// view depth z (m) of the world-space ray origin + ray * z (ray per metre of eye view
// depth, the eye's column ray) lands at column[0] * z + column[1] in the clip space of
// the centre eye (centre_clip_from_world: its projection times its view). Every slice
// of a column shares the ray, so the scan computes it once per column.
fn stereo_resample_column(
    origin: vec3<f32>,
    ray: vec3<f32>,
    centre_clip_from_world: mat4x4<f32>,
) -> mat2x4<f32> {
    return mat2x4<f32>(
        centre_clip_from_world * vec4<f32>(ray, 0.0),
        centre_clip_from_world * vec4<f32>(origin, 1.0));
}

// The shared volume's texture coordinates (each in [0, 1], clamped to its edges) of the
// point at eye view depth z (m) of a column (stereo_resample_column); `centre` is the
// shared volume's froxel placement. The centre eye's view depth is its clip w (every
// perspective projection has w = -z_view); points behind the centre apex (w <= 0, which
// the enclosing frustum never holds) clamp to its near slice.
fn stereo_resample_uvw(column: mat2x4<f32>, z: f32, centre: Froxels) -> vec3<f32> {
    let clip = column[0] * z + column[1];
    let w = max(clip.w, 1e-6);
    let uv = uv_from_ndc(clip.xy / w);
    let t = slice_coord(w, centre.near, centre.far, centre.curve);
    return clamp(vec3<f32>(uv, t), vec3<f32>(0.0), vec3<f32>(1.0));
}
