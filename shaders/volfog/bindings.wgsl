// volfog::bindings — the bind group a shader needs to read the integrated volume:
// the layout of the fullscreen apply pass and of forward shaders that apply fog.
//
// Use:      #import volfog::bindings  (then bindings::fog_froxels, ...)
// Defines:  VOLFOG_BINDINGS_APPLY_GROUP=N (required) — the bind group index.
//           VOLFOG_BINDINGS_NO_SAMPLER — omit the sampler (use volfog::apply::fog_load).
// Layout:   binding 0  uniform Froxels (160 bytes)
//           binding 1  texture_3d<f32>, the integrated volume (rgba16float, filterable)
//           binding 2  sampler, linear filtering, clamp-to-edge (absent with NO_SAMPLER)
//           binding 3  uniform HeightFog (64 bytes): the analytic tail beyond the far
//                      plane, in VIEW space (up, base height and sun direction relative
//                      to the camera); density 0 disables it
#define_import_path volfog::bindings

#import volfog::types::{Froxels, HeightFog}

@group(#{VOLFOG_BINDINGS_APPLY_GROUP}) @binding(0) var<uniform> fog_froxels: Froxels;
@group(#{VOLFOG_BINDINGS_APPLY_GROUP}) @binding(1) var fog_volume: texture_3d<f32>;
#ifndef VOLFOG_BINDINGS_NO_SAMPLER
@group(#{VOLFOG_BINDINGS_APPLY_GROUP}) @binding(2) var fog_sampler: sampler;
#endif
@group(#{VOLFOG_BINDINGS_APPLY_GROUP}) @binding(3) var<uniform> fog_height: HeightFog;
