// volfog::stereo_apply — stereo fog for any shaded point of a multiview draw: the eye's
// fog selected by the view index, for forward shaders and the multiview apply pass.
//
// Use:      #import volfog::stereo_apply::{stereo_fog_view, stereo_fog_world}
//           let fog = stereo_fog_world(view_index, world_pos, left_froxels, right_froxels,
//               left_view_from_world, right_view_from_world, left_volume, right_volume,
//               volume_sampler, left_tail, right_tail);
//           color = apply_fog(color, fog);  (volfog::apply)
//           volfog::stereo_bindings passes its group's bindings to these functions:
//           stereo_bindings::stereo_fog_at_world(view_index, world_pos) is the same call.
// Defines:  none (the bindings live in volfog::stereo_bindings).
// Eyes:     view_index is @builtin(view_index) of a multiview render pass whose layer 0
//           is the left eye, 1 the right: 0 selects the left eye's inputs, any other
//           value the right eye's. Each eye has its own froxel placement (Froxels), its
//           own integrated volume (rgb in-scatter, a transmittance, from volfog::scan)
//           and its own analytic tail beyond the far plane (a HeightFog in that eye's
//           VIEW space), as StereoFog prepares them. The fog of an eye is exactly the
//           mono fog of volfog::apply with that eye's inputs.
// Sampling: the volume is chosen by branching on view_index, which is the same for
//           every invocation of one view; the look-ups use an explicit level
//           (textureSampleLevel, textureLoad), valid in any control flow.
#define_import_path volfog::stereo_apply

#import volfog::types::{Froxels, HeightFog}
#import volfog::apply::{fog_coord_from_view, fog_load, fog_sample, fog_tail, fog_view_position, fog_with_tail}

// The froxel placement of the eye view_index (0 left, else right).
fn stereo_eye_froxels(view_index: u32, left: Froxels, right: Froxels) -> Froxels {
    if view_index == 0u {
        return left;
    }
    return right;
}

// The analytic tail (view space of its eye) of the eye view_index (0 left, else right).
fn stereo_eye_tail(view_index: u32, left: HeightFog, right: HeightFog) -> HeightFog {
    if view_index == 0u {
        return left;
    }
    return right;
}

// The world -> view transform (m) of the eye view_index (0 left, else right).
fn stereo_eye_view_from_world(view_index: u32, left: mat4x4<f32>, right: mat4x4<f32>) -> mat4x4<f32> {
    if view_index == 0u {
        return left;
    }
    return right;
}

// Fog (rgb in-scatter, a transmittance) of the eye view_index at a fog coordinate of
// that eye (volfog::apply::fog_coord...), filtered by the sampler (linear filtering,
// clamp-to-edge addressing).
fn stereo_fog_sample(
    view_index: u32,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    volume_sampler: sampler,
    coord: vec4<f32>,
) -> vec4<f32> {
    if view_index == 0u {
        return fog_sample(left_volume, volume_sampler, coord);
    }
    return fog_sample(right_volume, volume_sampler, coord);
}

// stereo_fog_sample without a sampler: eight texel loads filtered in the shader
// (volfog::apply::fog_load), for volumes that are not filterable.
fn stereo_fog_load(
    view_index: u32,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    coord: vec4<f32>,
) -> vec4<f32> {
    if view_index == 0u {
        return fog_load(left_volume, coord);
    }
    return fog_load(right_volume, coord);
}

// The whole fog of the eye view_index at a position in that eye's VIEW space (m): the
// volume's fog followed by the tail beyond the far plane. Blend it with
// volfog::apply::apply_fog.
fn stereo_fog_view(
    view_index: u32,
    view_pos: vec3<f32>,
    left_froxels: Froxels,
    right_froxels: Froxels,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    volume_sampler: sampler,
    left_tail: HeightFog,
    right_tail: HeightFog,
) -> vec4<f32> {
    let froxels = stereo_eye_froxels(view_index, left_froxels, right_froxels);
    let fog = stereo_fog_sample(
        view_index, left_volume, right_volume, volume_sampler,
        fog_coord_from_view(view_pos, froxels));
    let tail = fog_tail(froxels, stereo_eye_tail(view_index, left_tail, right_tail), view_pos);
    return fog_with_tail(fog, tail);
}

// The whole fog of the eye view_index at a WORLD position (m), with each eye's
// world -> view transform (FogView.view_from_world).
fn stereo_fog_world(
    view_index: u32,
    world_pos: vec3<f32>,
    left_froxels: Froxels,
    right_froxels: Froxels,
    left_view_from_world: mat4x4<f32>,
    right_view_from_world: mat4x4<f32>,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    volume_sampler: sampler,
    left_tail: HeightFog,
    right_tail: HeightFog,
) -> vec4<f32> {
    let view_from_world = stereo_eye_view_from_world(view_index, left_view_from_world, right_view_from_world);
    return stereo_fog_view(
        view_index, fog_view_position(world_pos, view_from_world), left_froxels, right_froxels,
        left_volume, right_volume, volume_sampler, left_tail, right_tail);
}

// stereo_fog_view without a sampler (stereo_fog_load).
fn stereo_fog_view_load(
    view_index: u32,
    view_pos: vec3<f32>,
    left_froxels: Froxels,
    right_froxels: Froxels,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    left_tail: HeightFog,
    right_tail: HeightFog,
) -> vec4<f32> {
    let froxels = stereo_eye_froxels(view_index, left_froxels, right_froxels);
    let fog = stereo_fog_load(view_index, left_volume, right_volume, fog_coord_from_view(view_pos, froxels));
    let tail = fog_tail(froxels, stereo_eye_tail(view_index, left_tail, right_tail), view_pos);
    return fog_with_tail(fog, tail);
}

// stereo_fog_world without a sampler (stereo_fog_load).
fn stereo_fog_world_load(
    view_index: u32,
    world_pos: vec3<f32>,
    left_froxels: Froxels,
    right_froxels: Froxels,
    left_view_from_world: mat4x4<f32>,
    right_view_from_world: mat4x4<f32>,
    left_volume: texture_3d<f32>,
    right_volume: texture_3d<f32>,
    left_tail: HeightFog,
    right_tail: HeightFog,
) -> vec4<f32> {
    let view_from_world = stereo_eye_view_from_world(view_index, left_view_from_world, right_view_from_world);
    return stereo_fog_view_load(
        view_index, fog_view_position(world_pos, view_from_world), left_froxels, right_froxels,
        left_volume, right_volume, left_tail, right_tail);
}
