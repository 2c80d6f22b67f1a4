// volfog::stereo_bindings — the stereo fog bind group: both eyes' fog in one group, for
// shaders that draw both eyes in one multiview render pass (@builtin(view_index)): the
// multiview apply pass and multiview forward shaders.
//
// Use:      #import volfog::stereo_bindings
//           let fog = stereo_bindings::stereo_fog_at_world(view_index, world_pos);
//           color = apply_fog(color, fog);  (volfog::apply)
//           The stereo_fog_at_* functions pass this group's bindings to the functions of
//           volfog::stereo_apply, which take them as parameters.
// Defines:  VOLFOG_STEREO_FOG_GROUP=N — the bind group index of the stereo group
//           (default 0; set it to a group your shader leaves free).
//           VOLFOG_BINDINGS_NO_SAMPLER — omit the sampler (manual filtering, as the
//           mono group volfog::bindings under the same define).
// Layout:   each eye has the bindings of the mono fog group (volfog::bindings), the
//           left eye at the mono numbers, the right eye at the mono numbers + 5; the
//           one sampler serves both eyes:
//           binding 0  uniform Froxels (160 bytes), the left eye's froxel placement
//           binding 1  texture_3d<f32>, the left eye's integrated volume (rgba16float,
//                      filterable): rgb in-scattered radiance, a transmittance
//           binding 2  sampler, linear filtering, clamp-to-edge (absent with NO_SAMPLER)
//           binding 3  uniform HeightFog (64 bytes): the left eye's tail beyond the far
//                      plane, in the left eye's VIEW space; density 0 disables it
//           binding 4  uniform FogView (64 bytes): the left eye's world -> view transform
//           binding 5  uniform Froxels, the right eye's
//           binding 6  texture_3d<f32>, the right eye's integrated volume
//           binding 8  uniform HeightFog, the right eye's tail (its view space)
//           binding 9  uniform FogView, the right eye's
//           (binding 7 is unused: the right eye's sampler would sit there.)
#define_import_path volfog::stereo_bindings

#import volfog::types::{Froxels, HeightFog, FogView}
#import volfog::stereo_apply::{stereo_fog_view, stereo_fog_view_load, stereo_fog_world, stereo_fog_world_load}

#ifdef VOLFOG_STEREO_FOG_GROUP
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(0) var<uniform> stereo_left_froxels: Froxels;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(1) var stereo_left_integrated: texture_3d<f32>;
#ifndef VOLFOG_BINDINGS_NO_SAMPLER
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(2) var stereo_sampler: sampler;
#endif
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(3) var<uniform> stereo_left_tail: HeightFog;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(4) var<uniform> stereo_left_view: FogView;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(5) var<uniform> stereo_right_froxels: Froxels;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(6) var stereo_right_integrated: texture_3d<f32>;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(8) var<uniform> stereo_right_tail: HeightFog;
@group(#{VOLFOG_STEREO_FOG_GROUP}) @binding(9) var<uniform> stereo_right_view: FogView;
#else
@group(0) @binding(0) var<uniform> stereo_left_froxels: Froxels;
@group(0) @binding(1) var stereo_left_integrated: texture_3d<f32>;
#ifndef VOLFOG_BINDINGS_NO_SAMPLER
@group(0) @binding(2) var stereo_sampler: sampler;
#endif
@group(0) @binding(3) var<uniform> stereo_left_tail: HeightFog;
@group(0) @binding(4) var<uniform> stereo_left_view: FogView;
@group(0) @binding(5) var<uniform> stereo_right_froxels: Froxels;
@group(0) @binding(6) var stereo_right_integrated: texture_3d<f32>;
@group(0) @binding(8) var<uniform> stereo_right_tail: HeightFog;
@group(0) @binding(9) var<uniform> stereo_right_view: FogView;
#endif

// The fog (rgb in-scatter, a transmittance) of the eye view_index (0 left, 1 right) at
// a position in that eye's VIEW space (m), tail included.
fn stereo_fog_at_view(view_index: u32, view_pos: vec3<f32>) -> vec4<f32> {
#ifdef VOLFOG_BINDINGS_NO_SAMPLER
    return stereo_fog_view_load(
        view_index, view_pos, stereo_left_froxels, stereo_right_froxels,
        stereo_left_integrated, stereo_right_integrated, stereo_left_tail, stereo_right_tail);
#else
    return stereo_fog_view(
        view_index, view_pos, stereo_left_froxels, stereo_right_froxels,
        stereo_left_integrated, stereo_right_integrated, stereo_sampler,
        stereo_left_tail, stereo_right_tail);
#endif
}

// The fog of the eye view_index (0 left, 1 right) at a WORLD position (m), tail included.
fn stereo_fog_at_world(view_index: u32, world_pos: vec3<f32>) -> vec4<f32> {
#ifdef VOLFOG_BINDINGS_NO_SAMPLER
    return stereo_fog_world_load(
        view_index, world_pos, stereo_left_froxels, stereo_right_froxels,
        stereo_left_view.view_from_world, stereo_right_view.view_from_world,
        stereo_left_integrated, stereo_right_integrated, stereo_left_tail, stereo_right_tail);
#else
    return stereo_fog_world(
        view_index, world_pos, stereo_left_froxels, stereo_right_froxels,
        stereo_left_view.view_from_world, stereo_right_view.view_from_world,
        stereo_left_integrated, stereo_right_integrated, stereo_sampler,
        stereo_left_tail, stereo_right_tail);
#endif
}
