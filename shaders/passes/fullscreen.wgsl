// Pass fullscreen — the vertex shader of every fullscreen pass (apply, hull_composite):
// draw 3 vertices without vertex buffers; it writes only the position.

#import volfog::fullscreen::fullscreen_position

@vertex
fn fullscreen_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(index);
}
