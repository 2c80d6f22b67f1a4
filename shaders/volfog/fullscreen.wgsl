// volfog::fullscreen — the one triangle that covers the screen, for fullscreen passes.
//
// Use:      #import volfog::fullscreen::fullscreen_position
//           @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
//               return fullscreen_position(i);
//           }
//           Draw 3 vertices without vertex buffers.
// Defines:  none
// Vertices (-1, -1), (3, -1), (-1, 3) in normalised device coordinates at depth 0:
// the triangle contains the whole [-1, 1]^2 square, so every pixel is shaded once,
// with no diagonal seam as a two-triangle quad would have.
#define_import_path volfog::fullscreen

// Clip-space position of vertex `index` (0, 1 or 2) of the fullscreen triangle.
fn fullscreen_position(index: u32) -> vec4<f32> {
    let xy = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0);
}
