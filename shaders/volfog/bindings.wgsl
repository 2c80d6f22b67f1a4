// volfog::bindings — the fog bind group: what a shader needs to read the integrated
// volume. The fullscreen apply pass and forward shaders that apply fog share it.
//
// Use:      #import volfog::bindings  (then bindings::fog_froxels, ...)
// Defines:  VOLFOG_FOG_GROUP=N — the bind group index of the fog group (default 0; set
//           it to a group your shader leaves free).
//           VOLFOG_BINDINGS_NO_SAMPLER — omit the sampler (use volfog::apply::fog_load).
// Layout:   binding 0  uniform Froxels (160 bytes)
//           binding 1  texture_3d<f32>, the integrated volume (rgba16float, filterable):
//                      rgb in-scattered radiance, a transmittance
//           binding 2  sampler, linear filtering, clamp-to-edge (absent with NO_SAMPLER)
//           binding 3  uniform HeightFog (64 bytes): the analytic tail beyond the far
//                      plane, in VIEW space (up, base height and sun direction relative
//                      to the camera); density 0 disables it
//           binding 4  uniform FogView (64 bytes): the camera's world -> view transform,
//                      for fog_coord_from_world
#define_import_path volfog::bindings

#import volfog::types::{Froxels, HeightFog, FogView}

#ifdef VOLFOG_FOG_GROUP
@group(#{VOLFOG_FOG_GROUP}) @binding(0) var<uniform> fog_froxels: Froxels;
@group(#{VOLFOG_FOG_GROUP}) @binding(1) var fog_integrated: texture_3d<f32>;
#ifndef VOLFOG_BINDINGS_NO_SAMPLER
@group(#{VOLFOG_FOG_GROUP}) @binding(2) var fog_sampler: sampler;
#endif
@group(#{VOLFOG_FOG_GROUP}) @binding(3) var<uniform> fog_far_tail: HeightFog;
@group(#{VOLFOG_FOG_GROUP}) @binding(4) var<uniform> fog_view: FogView;
#else
@group(0) @binding(0) var<uniform> fog_froxels: Froxels;
@group(0) @binding(1) var fog_integrated: texture_3d<f32>;
#ifndef VOLFOG_BINDINGS_NO_SAMPLER
@group(0) @binding(2) var fog_sampler: sampler;
#endif
@group(0) @binding(3) var<uniform> fog_far_tail: HeightFog;
@group(0) @binding(4) var<uniform> fog_view: FogView;
#endif
