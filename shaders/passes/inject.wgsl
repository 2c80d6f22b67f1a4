// Pass inject — density and in-scattered light of every froxel in one compute pass
// (Wronski 2014, "Density estimation and volume lighting", as in Assassin's Creed 4).
//
// Dispatch: ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 8) workgroups, each
// covering a block of 4 x 4 x 8 froxels (volfog::froxel, "Froxel blocks"): 4 x 4 x 8
// invocations, one per froxel, or under VOLFOG_INJECT_CHECKERBOARD 4 x 4 x 4, one per
// pair of slices (2 k, 2 k + 1), injecting the froxel of the pair that
// volfog::froxel::froxel_injected picks this frame and writing its value to both (temporal
// reads it for the other one only where that has no history). Under VOLFOG_FROXEL_CULL
// dispatch indirectly with the arguments froxel_cull_compact wrote, one workgroup per
// listed block.
// Output: rgb = sigma_s * L_in (radiance scattered towards the eye per metre),
//         a = sigma_t (1/m), written to a write-only rgba16float 3D texture (under
//         VOLFOG_INJECT_TEMPORAL blended with the history first); froxels behind
//         their column's live slices (depth culling) are not written.
// Bindings (group 0):
//   0  uniform Froxels            1  uniform FogFrame         2  uniform FogMedium
//   3  uniform FogLighting        4  uniform ShadowCascades
//   5  texture_2d_array<f32>: filtered ESM, one layer per cascade (R32Float, textureLoad);
//      under VOLFOG_INJECT_SHADOW_COMPARE the sun's cascaded shadow map itself (a depth
//      texture bound as unfilterable float, one layer per cascade, any size)
//   6  storage, read: array<FogLight> (point and spot lights)
//   7  storage, read: array<LocalVolume>
//   8  texture_storage_3d<rgba16float, write>: the scattering volume
//   9  texture_3d<f32>: density texture (VOLFOG_INJECT_DENSITY_TEXTURE only)
//  10  sampler, linear, repeat (VOLFOG_INJECT_DENSITY_TEXTURE only)
//  11  texture_2d<u32>: live slices per column from froxel_cull (VOLFOG_FROXEL_CULL only)
//  12  texture_3d<f32>: the baked noise texture (VOLFOG_INJECT_NOISE_TEXTURE only)
//  13  sampler, linear, repeat (VOLFOG_INJECT_NOISE_TEXTURE only)
//  14  storage, read: array<u32>, the live blocks from froxel_cull_compact
//      (VOLFOG_FROXEL_CULL only)
//  15  uniform CloudLayer; 16 texture_2d<f32>: the cloud density map (red channel);
//  17  sampler, linear, repeat (VOLFOG_INJECT_CLOUD_SHADOW only)
//  18  texture_2d_array<f32>: the local-light ESM atlas (R32Float, textureLoad;
//      local_shadow_downsample and esm_blur fill it)
//  19  storage, read: array<LightProjection>, indexed by FogLight.projection
//  20  texture_2d_array<f32>: the spot lights' cookies (filterable float)
//  21  sampler, linear, clamp to edge: the cookies' (18-21 VOLFOG_INJECT_LOCAL_SHADOWS
//      only)
//  22  texture_3d<f32>: the history (last frame's stabilised volume), filterable
//  23  sampler, linear, clamp to edge: the history's
//  24  storage, read: HistoryState of the history (binding 22)
//  25  storage, read_write: HistoryState of the stabilised volume (binding 8); invocation
//      0 of block (0, 0, 0) writes this frame's camera into it
//  26  texture_2d<u32>: live slices the history was written with (with
//      VOLFOG_FROXEL_CULL; 22-26 VOLFOG_INJECT_TEMPORAL only)
//  31  uniform FogCustomParams: the custom density's parameters
//      (VOLFOG_INJECT_CUSTOM_DENSITY only)
//  27  uniform ShadowTaps: where in each froxel the lights' visibility is tested
//  28  sampler, non-filtering (nearest), clamp to edge: the shadow maps' gathers
//  29  texture_2d_array<f32>: the spot lights' shadow maps (depth as unfilterable float)
//  30  texture_2d_array<f32>: the point lights' cube shadow maps, six layers a cube
//      (27-28 VOLFOG_INJECT_SHADOW_COMPARE only; 29-30 with VOLFOG_INJECT_LOCAL_SHADOWS,
//      which then binds no atlas at 18)
//  32  texture_2d<f32>: the scene depth depth culling reads (froxel_cull's binding 1),
//      bound as unfilterable float: shadow taps are moved in front of its opaque
//      surface when ShadowTaps.use_scene_depth is 1 (VOLFOG_INJECT_SHADOW_COMPARE with
//      VOLFOG_FROXEL_CULL only; bind a 1 x 1 texture where there is none)
//  33  storage, read: array<AreaLight>, every element (range 0: unused slot)
//      (VOLFOG_INJECT_AREA_LIGHTS only; culled per block as the point lights)
//  34  storage, read: array<FogParticle>, the first FogMedium.particle_count elements
//      (VOLFOG_INJECT_PARTICLES only)
//  35  texture_3d<f32>: the medium-shadow volume the medium_shadow pass wrote
//  36  sampler, linear, clamp to edge: the medium-shadow volume's
//  37  uniform MediumShadow: its placement (35-37 VOLFOG_INJECT_MEDIUM_SHADOW only)
// Lights and local volumes are culled per workgroup: those whose range or extent touches
// the block's bounding sphere are gathered in workgroup memory (at most 64 lights; when
// more than 64 local volumes touch a block, every volume is evaluated), so distant ones
// cost nothing. The local volumes blend into the medium in buffer order
// (volfog::density::local_volume_blend: add, subtract, multiply, min, max, overwrite):
// the gathered ones are put back in that order (each finds its rank among them) before
// any froxel reads them. Particles (VOLFOG_INJECT_PARTICLES) are gathered in chunks of
// one particle per invocation: each chunk's particles that touch the block's sphere are
// listed in workgroup memory (three lists in turn, one barrier a chunk) and every
// froxel of the block evaluates the list, so every particle that touches a block is
// evaluated there, however many they are, and none that does not.
// Shadows. By default the sun's shadow is read from its filtered ESM (and shadowed
// point and spot lights' from the local-light ESM atlas). Under
// VOLFOG_INJECT_SHADOW_COMPARE each light's visibility is the mean of
// ShadowTaps.count depth compares (ShadowTaps.fresh where the froxel has no history)
// against the full-resolution maps at points spread over the froxel
// (volfog::shadow); the temporal blend accumulates them over frames.
// Under FogLighting.transmittance the light of the sun and of every point, spot and
// directional light is attenuated by the medium's height profile on its way to the
// froxel (volfog::density::medium_light_transmittance for the sun and directional
// lights, medium_segment_transmittance for the others); the ambient light is not.
// Under VOLFOG_INJECT_MEDIUM_SHADOW the rest of the medium (noise, density texture,
// custom density, local volumes) dims it too (volfog::medium_shadow), the product of
// the two factors clamped at 1; area lights keep the height profile alone.
// A froxel without extinction gets no lighting (its in-scattering is 0 whatever the light);
// the emission of the medium and of the local volumes is added to rgb, so the scan
// integrates it with the in-scattering.
// Defines:
//   VOLFOG_INJECT_JITTER            sample each froxel at FogFrame.jitter instead of its centre
//   VOLFOG_INJECT_TWO_COLOR_PHASE   AC4's two-colour sun phase instead of Henyey-Greenstein
//   VOLFOG_INJECT_DENSITY_TEXTURE   multiply the density by a user 3D texture (r channel),
//                                   and that of the local volumes with
//                                   LocalVolume.textured in their own space
//   VOLFOG_INJECT_NOISE_TEXTURE     read the noise from the baked tileable texture
//                                   (noise_bake) instead of evaluating Perlin noise
//   VOLFOG_INJECT_NOISE_OCTAVES=N   fbm octaves, 1..=8 (default 1, as in the seed)
//   VOLFOG_FROXEL_CULL              skip froxels behind the column's live slices and
//                                   blocks without live froxels
//   VOLFOG_INJECT_CHECKERBOARD      amortise over two frames (FogFrame.checkerboard = 1)
//   VOLFOG_ESM_LOG_SPACE            the ESM holds log-space values (see volfog::esm)
//   VOLFOG_INJECT_CLOUD_SHADOW      the sun term also passes the cloud layer
//                                   (volfog::clouds::cloud_shadow): the fog carries
//                                   the clouds' moving shadows
//   VOLFOG_INJECT_TEMPORAL          temporal reprojection fused into injection: each
//                                   froxel's value is blended with its reprojected
//                                   history (volfog::temporal, as the temporal pass
//                                   does) and binding 8 receives the stabilised volume
//                                   (next frame's history), so no scattering volume is
//                                   written and read back; the temporal pass does not
//                                   run. Ping-pong the volumes and their HistoryState
//                                   buffers by frame parity as for the temporal pass.
//                                   The blend takes the froxel's value before it is
//                                   rounded to rgba16float.
//   VOLFOG_INJECT_SHADOW_COMPARE    the compare filter (see "Shadows" above) instead of
//                                   the ESM; VOLFOG_ESM_LOG_SPACE does not apply
//   VOLFOG_INJECT_CUSTOM_DENSITY    the user's medium: a module the composer holds at
//                                   volfog::custom_density (given by the runtime or
//                                   the export, never prebuilt) defines
//                                   fn volfog_custom_density(world: vec3<f32>,
//                                   time: f32, params: FogCustomParams) -> FogSample;
//                                   its sample at each froxel's position is added to the
//                                   medium before the local volumes blend, its albedo
//                                   mixed in by extinction
//                                   (volfog::density::medium_with_sample)
//   VOLFOG_INJECT_AREA_LIGHTS       rectangle and disk emitters (binding 33) added to
//                                   the lights (volfog::area_lights)
//   VOLFOG_INJECT_PARTICLES         particles (binding 34, volfog::particles) added to
//                                   the medium after the local volumes: the medium
//                                   clamped at 0, then their sum, its albedo mixed in
//                                   by extinction (volfog::density::medium_with_sample)
//   VOLFOG_INJECT_MEDIUM_SHADOW     the medium's shadows on itself (bindings 35-37,
//                                   see "Under FogLighting.transmittance" above)
//   VOLFOG_INJECT_LOCAL_SHADOWS     point and spot lights with a projection
//                                   (FogLight.projection) pass their shadow (in the
//                                   atlas, or their own depth maps under
//                                   VOLFOG_INJECT_SHADOW_COMPARE) and, for spot
//                                   lights, their cookie
//                                   (volfog::local_shadow); such lights are gathered
//                                   apart and looked up only where they shine, so a
//                                   block no such light touches runs the plain light
//                                   loop alone (frames without any are best run with
//                                   the variant without this define, as VolumetricFog
//                                   does)

#import volfog::types::{Froxels, FogFrame, FogMedium, FogLighting, ShadowCascades, FogLight, LocalVolume}
#import volfog::froxel::{froxel_view_position, froxel_injected, froxel_block_unpack, FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z}
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
#import volfog::noise::noise_animated_texture
#else
#import volfog::noise::noise_animated
#endif
#import volfog::density::{medium_shape, medium_light_transmittance, medium_segment_transmittance, local_volume_blend, local_volume_touches_sphere}
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
#import volfog::density::{local_volume_blend_textured, local_volume_texture_coord}
#endif
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
#import volfog::types::FogCustomParams
#import volfog::density::{medium_with_sample, albedo_with_sample}
#import volfog::custom_density::volfog_custom_density
#endif
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
#import volfog::types::ShadowTaps
#import volfog::froxel::{ndc_from_uv, slice_depth}
#import volfog::esm::esm_cascade
#import volfog::shadow::shadow_cascade_compare
#ifdef VOLFOG_FROXEL_CULL
#import volfog::shadow::shadow_tap_visible_depth
#endif
#else
#import volfog::esm::{esm_cascade, esm_shadow_cascade}
#endif
#ifdef VOLFOG_INJECT_CLOUD_SHADOW
#import volfog::types::CloudLayer
#import volfog::clouds::cloud_shadow
#endif
#import volfog::lights::{light_touches_sphere, fog_light_inscatter, sun_inscatter, sun_inscatter_two_color, ambient_inscatter, FOG_LIGHT_DIRECTIONAL}
#ifdef VOLFOG_INJECT_AREA_LIGHTS
#import volfog::types::AreaLight
#import volfog::area_lights::{area_light_touches_sphere, area_light_inscatter}
#endif
#ifdef VOLFOG_INJECT_PARTICLES
#import volfog::types::FogParticle
#import volfog::particles::{particle_sample, particle_touches_sphere, particle_total}
#ifndef VOLFOG_INJECT_CUSTOM_DENSITY
#import volfog::density::{medium_with_sample, albedo_with_sample}
#endif
#endif
#ifdef VOLFOG_INJECT_MEDIUM_SHADOW
#import volfog::types::MediumShadow
#import volfog::medium_shadow::{medium_shadow_sun, medium_shadow_segment}
#endif
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
#import volfog::types::LightProjection
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
#import volfog::local_shadow::{local_shadow_compare, light_cookie}
#else
#import volfog::local_shadow::{local_shadow_visibility, light_cookie}
#endif
#endif
#ifdef VOLFOG_INJECT_TEMPORAL
#import volfog::types::HistoryState
#import volfog::temporal::{temporal_history_column, temporal_history_slice_uvw, temporal_blend}
#ifdef VOLFOG_FROXEL_CULL
#import volfog::temporal::temporal_history_live
#endif
#endif

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var<uniform> frame: FogFrame;
@group(0) @binding(2) var<uniform> fog_medium: FogMedium;
@group(0) @binding(3) var<uniform> fog_lighting: FogLighting;
@group(0) @binding(4) var<uniform> shadow_cascades: ShadowCascades;
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
@group(0) @binding(5) var shadow_map: texture_2d_array<f32>;
@group(0) @binding(27) var<uniform> shadow_taps: ShadowTaps;
@group(0) @binding(28) var gather_sampler: sampler;
#else
@group(0) @binding(5) var esm_array: texture_2d_array<f32>;
#endif
@group(0) @binding(6) var<storage, read> lights: array<FogLight>;
@group(0) @binding(7) var<storage, read> local_volumes: array<LocalVolume>;
@group(0) @binding(8) var scattering: texture_storage_3d<rgba16float, write>;
#ifdef VOLFOG_INJECT_CLOUD_SHADOW
@group(0) @binding(15) var<uniform> cloud_shadow_layer: CloudLayer;
@group(0) @binding(16) var cloud_shadow_map: texture_2d<f32>;
@group(0) @binding(17) var cloud_shadow_sampler: sampler;
#endif
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
@group(0) @binding(9) var density_texture: texture_3d<f32>;
@group(0) @binding(10) var density_sampler: sampler;
#endif
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(11) var live_slices: texture_2d<u32>;
@group(0) @binding(14) var<storage, read> live_blocks: array<u32>;
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
@group(0) @binding(32) var scene_depth: texture_2d<f32>;
#endif
#endif
#ifdef VOLFOG_INJECT_AREA_LIGHTS
@group(0) @binding(33) var<storage, read> area_lights: array<AreaLight>;
var<workgroup> tile_areas: array<u32, 64>;
var<workgroup> tile_area_count: atomic<u32>;
#endif
#ifdef VOLFOG_INJECT_PARTICLES
@group(0) @binding(34) var<storage, read> particles: array<FogParticle>;
// Three lists of gathered particle indices used in turn, chunk k in list k % 3 (at
// 128 (k % 3)), so one barrier a chunk separates a list's reads from its next writes
// (see gather_particles).
var<workgroup> tile_particles: array<u32, 384>;
var<workgroup> tile_particle_count: array<atomic<u32>, 3>;
// The particles' sum at this invocation's froxel sample: rgb emission, a extinction
// (particle_medium) and albedo times extinction (particle_albedo).
var<private> particle_medium: vec4<f32>;
var<private> particle_albedo: vec3<f32>;
#endif
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
@group(0) @binding(31) var<uniform> custom_params: FogCustomParams;
#endif
#ifdef VOLFOG_INJECT_MEDIUM_SHADOW
@group(0) @binding(35) var medium_shadow_volume: texture_3d<f32>;
@group(0) @binding(36) var medium_shadow_sampler: sampler;
@group(0) @binding(37) var<uniform> medium_shadow: MediumShadow;
#endif
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
@group(0) @binding(12) var noise_texture: texture_3d<f32>;
@group(0) @binding(13) var noise_sampler: sampler;
#endif
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
@group(0) @binding(29) var spot_shadow_maps: texture_2d_array<f32>;
@group(0) @binding(30) var point_shadow_maps: texture_2d_array<f32>;
#else
@group(0) @binding(18) var local_shadow_atlas: texture_2d_array<f32>;
#endif
@group(0) @binding(19) var<storage, read> light_projections: array<LightProjection>;
@group(0) @binding(20) var cookies: texture_2d_array<f32>;
@group(0) @binding(21) var cookie_sampler: sampler;
#endif
#ifdef VOLFOG_INJECT_TEMPORAL
@group(0) @binding(22) var history: texture_3d<f32>;
@group(0) @binding(23) var history_sampler: sampler;
@group(0) @binding(24) var<storage, read> history_state: HistoryState;
@group(0) @binding(25) var<storage, read_write> stabilised_state: HistoryState;
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(26) var history_live_slices: texture_2d<u32>;
#endif
#endif

const NOISE_OCTAVES: u32 = #{VOLFOG_INJECT_NOISE_OCTAVES}u;
#ifdef VOLFOG_INJECT_CHECKERBOARD
const WORKGROUP_Z: u32 = 4u;
#else
const WORKGROUP_Z: u32 = 8u;
#endif
const TILE_LIGHTS: u32 = 64u;
const TILE_VOLUMES: u32 = 64u;
const HALF_MAX: f32 = 65504.0;

var<workgroup> tile_lights: array<u32, 64>;
var<workgroup> tile_count: atomic<u32>;
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
// The gathered lights with a projection, apart from the others: a block none of them
// touches runs the plain light loop only.
var<workgroup> tile_shadowed: array<u32, 64>;
var<workgroup> tile_shadowed_count: atomic<u32>;
#endif
var<workgroup> tile_volumes: array<u32, 64>;
var<workgroup> tile_volume_count: atomic<u32>;
var<workgroup> tile_sphere: vec4<f32>;
var<workgroup> tile_corners: array<vec3<f32>, 5>;

fn world_of(id: vec3<u32>, offset: vec3<f32>) -> vec3<f32> {
    let view = froxel_view_position(
        id, offset, froxels.size, froxels.view_from_clip, froxels.near, froxels.far, froxels.curve);
    return (frame.world_from_view * vec4<f32>(view, 1.0)).xyz;
}

// Shadow taps of a froxel: the compare filter's ShadowTaps.count where this pass blends
// in its history or blends none (the temporal pass may; without temporal reprojection
// the runtime sets count to fresh), ShadowTaps.fresh where the fused blend finds no
// history (1, unused, for the ESM).
fn froxel_taps(has_history: bool) -> u32 {
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
    return select(shadow_taps.fresh, shadow_taps.count, has_history);
#else
    return 1u;
#endif
}

// Live slices of column xy (every slice without culling).
fn live(xy: vec2<u32>) -> u32 {
#ifdef VOLFOG_FROXEL_CULL
    return textureLoad(live_slices, xy, 0).r;
#else
    return froxels.size.z;
#endif
}

#ifdef VOLFOG_INJECT_TEMPORAL
// The history's clip coordinates along column xy (volfog::temporal).
fn history_column(xy: vec2<u32>) -> mat2x4<f32> {
    return temporal_history_column(xy, froxels, frame.world_from_view, history_state);
}

// Where froxel id of column `column` (history_column) lies in the history: xyz its
// texture coordinate, w 1 where the history holds it, else 0 (no history).
fn history_at(column: mat2x4<f32>, id: vec3<u32>) -> vec4<f32> {
    let at = temporal_history_slice_uvw(column, id.z, froxels, history_state.valid, frame.history_enabled);
#ifdef VOLFOG_FROXEL_CULL
    if at.w != 0.0 && !temporal_history_live(at.xyz, froxels.size, history_live_slices) {
        return vec4<f32>(0.0);
    }
#endif
    return at;
}

// The stabilised value of froxel id, found at `at` in the history (history_at), whose
// value this frame is now (as the temporal pass computes it).
fn stabilise(at: vec4<f32>, id: vec3<u32>, now: vec4<f32>) -> vec4<f32> {
    if at.w == 0.0 {
        return now;
    }
    let past = textureSampleLevel(history, history_sampler, at.xyz, 0.0);
    return temporal_blend(now, past, froxel_injected(id, frame.index, frame.checkerboard), frame.history_weight);
}
#endif

#ifdef VOLFOG_INJECT_SHADOW_COMPARE
// World position (xyz) and view depth (w, m) of shadow tap t of froxel id: the camera
// plus the taps' affine ray of its screen position times its view depth (no matrix, so
// the lights' loops keep few values live). With depth culling's scene depth
// (ShadowTaps.use_scene_depth) the depth is moved in front of the scene's surface
// (shadow_tap_visible_depth).
fn shadow_tap(id: vec3<u32>, t: u32) -> vec4<f32> {
    let cell = (vec3<f32>(id) + 0.5 + shadow_taps.offsets[t].xyz) / vec3<f32>(froxels.size);
    let ndc = ndc_from_uv(cell.xy);
    var depth = slice_depth(cell.z, froxels.near, froxels.far, froxels.curve);
#ifdef VOLFOG_FROXEL_CULL
    if shadow_taps.use_scene_depth != 0u {
        let size = f32(froxels.size.z);
        let near = slice_depth(f32(id.z) / size, froxels.near, froxels.far, froxels.curve);
        let far = slice_depth(f32(id.z + 1u) / size, froxels.near, froxels.far, froxels.curve);
        depth = shadow_tap_visible_depth(scene_depth, cell.xy, depth, near, far, shadow_taps.camera_depth_terms);
    }
#endif
    let ray = shadow_taps.ray_origin + shadow_taps.ray_x * ndc.x + shadow_taps.ray_y * ndc.y;
    return vec4<f32>(frame.camera_position + ray * depth, depth);
}

// Tap 0 of froxel id: the froxel's sample at `world` and view depth `view_depth`, or
// through shadow_tap where the scene depth may move it.
fn first_tap(id: vec3<u32>, world: vec3<f32>, view_depth: f32) -> vec4<f32> {
#ifdef VOLFOG_FROXEL_CULL
    if shadow_taps.use_scene_depth != 0u {
        return shadow_tap(id, 0u);
    }
#endif
    return vec4<f32>(world, view_depth);
}

// The sun's visibility at a world position and view depth through the cascade that
// holds it (1 beyond the last cascade). The cascade's matrix is read from the uniform
// with the varying index (see volfog::esm::esm_shadow_cascade).
fn sun_compare(world: vec3<f32>, view_depth: f32) -> f32 {
    let cascade = esm_cascade(view_depth, shadow_cascades.splits, shadow_cascades.count);
    if cascade >= shadow_cascades.count {
        return 1.0;
    }
    return shadow_cascade_compare(shadow_map, gather_sampler, shadow_cascades.light_from_world[cascade],
        cascade, world, shadow_taps.sun_reversed_z != 0u);
}

// The sun's visibility in froxel id: the mean over `taps` taps, tap 0 at world
// position `first.xyz` and view depth `first.w` (first_tap).
fn sun_visibility(id: vec3<u32>, first: vec4<f32>, taps: u32) -> f32 {
    var sum = sun_compare(first.xyz, first.w);
    for (var t = 1u; t < taps; t++) {
        let tap = shadow_tap(id, t);
        sum += sun_compare(tap.xyz, tap.w);
    }
    return sum / f32(taps);
}

#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
// A shadowed point or spot light's visibility in froxel id: the mean over `taps` taps,
// tap 0 at `world` (first_tap).
fn local_visibility(p: LightProjection, id: vec3<u32>, world: vec3<f32>, taps: u32) -> f32 {
    var sum = local_shadow_compare(spot_shadow_maps, point_shadow_maps, gather_sampler, p, world);
    for (var t = 1u; t < taps; t++) {
        sum += local_shadow_compare(spot_shadow_maps, point_shadow_maps, gather_sampler, p, shadow_tap(id, t).xyz);
    }
    return sum / f32(taps);
}
#endif
#endif

// Density and in-scattered light of froxel id (rgb = sigma_s L_in, a = sigma_t),
// with the lights gathered for the workgroup; the compare filter takes `taps` shadow
// taps (the ESM ignores them).
fn froxel_scattering(id: vec3<u32>, tile_light_count: u32, tile_volume_count: u32, taps: u32) -> vec4<f32> {
#ifdef VOLFOG_INJECT_JITTER
    let offset = frame.jitter;
#else
    let offset = vec3<f32>(0.0);
#endif
    let view = froxel_view_position(
        id, offset, froxels.size, froxels.view_from_clip, froxels.near, froxels.far, froxels.curve);
    let world = (frame.world_from_view * vec4<f32>(view, 1.0)).xyz;
    let view_dir = normalize(world - frame.camera_position);

    // Density.
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
    let noise = noise_animated_texture(noise_texture, noise_sampler, world, fog_medium.noise_scale, fog_medium.wind, frame.time, NOISE_OCTAVES);
#else
    let noise = noise_animated(world, fog_medium.noise_scale, fog_medium.wind, frame.time, NOISE_OCTAVES);
#endif
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
    let uvw = world * fog_medium.texture_scale + fog_medium.texture_offset - fog_medium.wind * frame.time * fog_medium.texture_scale;
    let texture_factor = select(1.0,
        textureSampleLevel(density_texture, density_sampler, uvw, 0.0).r, fog_medium.textured != 0u);
#else
    let texture_factor = 1.0;
#endif
    let shape = medium_shape(fog_medium, world, noise, texture_factor);
    // rgb the emitted radiance per metre, a the extinction.
    var medium = vec4<f32>(fog_medium.emission, fog_medium.density) * shape;
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
    // The user's own medium at the sample, added before the local volumes blend.
    let custom = volfog_custom_density(world, frame.time, custom_params);
    let albedo = albedo_with_sample(medium, fog_medium.albedo, custom);
    medium = medium_with_sample(medium, custom);
#else
    let albedo = fog_medium.albedo;
#endif
    // The gathered volumes (in buffer order), or every volume when more than
    // TILE_VOLUMES touch the block (one loop, so SIMD hardware that runs both sides of
    // a branch pays once), each blended into the medium by its mode.
    let gathered = tile_volume_count <= TILE_VOLUMES;
    let all_volumes = min(fog_medium.local_volume_count, arrayLength(&local_volumes));
    let volume_count = select(all_volumes, tile_volume_count, gathered);
    for (var i = 0u; i < volume_count; i++) {
        let v = select(i, tile_volumes[min(i, TILE_VOLUMES - 1u)], gathered);
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
        // A textured volume reads the density texture in its own space (the volume is
        // the same for the whole workgroup, so an untextured one skips the look-up).
        let volume = local_volumes[v];
        var volume_factor = 1.0;
        if volume.textured != 0u {
            volume_factor = textureSampleLevel(density_texture, density_sampler,
                local_volume_texture_coord(volume, world), 0.0).r;
        }
        medium = local_volume_blend_textured(medium, volume, world, volume_factor);
#else
        medium = local_volume_blend(medium, local_volumes[v], world);
#endif
    }
#ifdef VOLFOG_INJECT_PARTICLES
    // The particles' sum (gathered in inject) added to the medium clamped at 0.
    let particle_sum = particle_total(particle_medium, particle_albedo);
    medium = max(medium, vec4<f32>(0.0));
    let blended_albedo = albedo_with_sample(medium, albedo, particle_sum);
    medium = medium_with_sample(medium, particle_sum);
#endif
    let emission = max(medium.rgb, vec3<f32>(0.0));
    let sigma_t = max(medium.a, 0.0);
    if sigma_t <= 0.0 {
        return min(vec4<f32>(emission, 0.0), vec4<f32>(HALF_MAX));
    }

    // Lighting.
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
    let first = first_tap(id, world, abs(view.z));
    var shadow = 1.0;
    if shadow_cascades.count > 0u {
        shadow = sun_visibility(id, first, taps);
    }
#else
    // The cascade's matrix is read from the uniform with the varying index (see
    // volfog::esm::esm_shadow_cascade).
    let cascade = esm_cascade(abs(view.z), shadow_cascades.splits, shadow_cascades.count);
    var shadow = 1.0;
    if cascade < shadow_cascades.count {
        shadow = esm_shadow_cascade(esm_array, shadow_cascades.light_from_world[cascade], cascade,
            shadow_cascades.exponent, world);
    }
#endif
#ifdef VOLFOG_INJECT_CLOUD_SHADOW
    shadow *= cloud_shadow(cloud_shadow_map, cloud_shadow_sampler, cloud_shadow_layer, world);
#endif
    // The light's way through the medium (FogLighting.transmittance): the height
    // profile between the froxel and the sun, up to the medium's top.
    let through = fog_lighting.transmittance != 0u;
    if through {
#ifdef VOLFOG_INJECT_MEDIUM_SHADOW
        shadow *= min(medium_light_transmittance(fog_medium, world, fog_lighting.sun.direction)
            * medium_shadow_sun(medium_shadow_volume, medium_shadow_sampler, medium_shadow, world), 1.0);
#else
        shadow *= medium_light_transmittance(fog_medium, world, fog_lighting.sun.direction);
#endif
    }
#ifdef VOLFOG_INJECT_TWO_COLOR_PHASE
    var light = sun_inscatter_two_color(fog_lighting.sun, shadow, view_dir);
#else
    var light = sun_inscatter(fog_lighting.sun, shadow, view_dir, fog_medium.phase_g);
#endif
    light += ambient_inscatter(fog_lighting.ambient_r, fog_lighting.ambient_g, fog_lighting.ambient_b, view_dir, fog_medium.phase_g);
    for (var i = 0u; i < tile_light_count; i++) {
        let local_light = lights[tile_lights[i]];
        var inscatter = fog_light_inscatter(local_light, world, view_dir, fog_medium.phase_g);
        if through {
            inscatter *= light_path_transmittance(local_light, world);
        }
        light += inscatter;
    }
#ifdef VOLFOG_INJECT_AREA_LIGHTS
    for (var i = 0u; i < min(atomicLoad(&tile_area_count), TILE_LIGHTS); i++) {
        light += area_light_inscatter(area_lights[tile_areas[i]], fog_medium, through, world, view_dir, fog_medium.phase_g);
    }
#endif
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
    let shadowed_count = min(atomicLoad(&tile_shadowed_count), TILE_LIGHTS);
    for (var i = 0u; i < shadowed_count; i++) {
        let local_light = lights[tile_shadowed[i]];
        var inscatter = fog_light_inscatter(local_light, world, view_dir, fog_medium.phase_g);
        // Outside the light's range or cone its shadow is not looked up.
        if max(inscatter.r, max(inscatter.g, inscatter.b)) > 0.0 {
            if through {
                inscatter *= light_path_transmittance(local_light, world);
            }
            let p = light_projections[local_light.projection];
#ifdef VOLFOG_INJECT_SHADOW_COMPARE
            let visibility = local_visibility(p, id, first.xyz, taps);
#else
            let visibility = local_shadow_visibility(local_shadow_atlas, p, world);
#endif
            light += inscatter * (visibility * light_cookie(cookies, cookie_sampler, p, world));
        }
    }
#endif

    // Clamped to the largest finite rgba16float value so no texel becomes Inf.
#ifdef VOLFOG_INJECT_PARTICLES
    let sigma_s = blended_albedo * sigma_t;
#else
    let sigma_s = albedo * sigma_t;
#endif
    return min(vec4<f32>(sigma_s * light + emission, sigma_t), vec4<f32>(HALF_MAX));
}

// The medium's transmittance between a froxel and a light: along the segment to a
// point or spot light, up to the medium's top towards a directional one (under
// VOLFOG_INJECT_MEDIUM_SHADOW times the rest of the medium's, marched over
// MediumShadow.march_length towards a directional light, clamped at 1).
fn light_path_transmittance(light: FogLight, world: vec3<f32>) -> f32 {
#ifdef VOLFOG_INJECT_MEDIUM_SHADOW
    if (light.flags & FOG_LIGHT_DIRECTIONAL) != 0u {
        return min(medium_light_transmittance(fog_medium, world, -light.direction)
            * medium_shadow_segment(medium_shadow_volume, medium_shadow_sampler, medium_shadow,
                world, world - light.direction * medium_shadow.march_length), 1.0);
    }
    return min(medium_segment_transmittance(fog_medium, world, light.position)
        * medium_shadow_segment(medium_shadow_volume, medium_shadow_sampler, medium_shadow,
            world, light.position), 1.0);
#else
    if (light.flags & FOG_LIGHT_DIRECTIONAL) != 0u {
        return medium_light_transmittance(fog_medium, world, -light.direction);
    }
    return medium_segment_transmittance(fog_medium, world, light.position);
#endif
}

#ifdef VOLFOG_INJECT_PARTICLES
// The froxel this invocation injects (the one froxel_scattering is called for, in
// range or not): first + local, or under the checkerboard the one of its pair of
// slices that froxel_injected picks this frame.
fn invocation_froxel(first: vec3<u32>, local: vec3<u32>) -> vec3<u32> {
#ifdef VOLFOG_INJECT_CHECKERBOARD
    let pair = first + vec3<u32>(local.xy, 2u * local.z);
    if pair.z + 1u < froxels.size.z && !froxel_injected(pair, frame.index, 1u) {
        return pair + vec3<u32>(0u, 0u, 1u);
    }
    return pair;
#else
    return first + local;
#endif
}

// Sums every particle that touches the block's bounding sphere at this invocation's
// froxel sample into particle_medium and particle_albedo. Called by every invocation
// of the workgroup (its barriers are in uniform control flow): chunk k tests the
// particles k * n .. k * n + n - 1 (n invocations, one each), lists those that touch
// the block in tile_particles[k % 3], and after the chunk's barrier every invocation
// evaluates the list; the list of chunk k + 2 is cleared then (its last reads were in
// chunk k - 1, before this barrier; its writes come after the next one).
fn gather_particles(first: vec3<u32>, local: vec3<u32>, local_index: u32, sphere: vec4<f32>) {
#ifdef VOLFOG_INJECT_JITTER
    let offset = frame.jitter;
#else
    let offset = vec3<f32>(0.0);
#endif
    let world = world_of(invocation_froxel(first, local), offset);
    particle_medium = vec4<f32>(0.0);
    particle_albedo = vec3<f32>(0.0);
    let invocations = 4u * 4u * WORKGROUP_Z;
    let count = min(fog_medium.particle_count, arrayLength(&particles));
    var list = 0u;
    for (var start = 0u; start < count; start += invocations) {
        let i = start + local_index;
        if i < count && particle_touches_sphere(particles[i], sphere.xyz, sphere.w) {
            // At most one slot per invocation: the list never overflows.
            tile_particles[128u * list + atomicAdd(&tile_particle_count[list], 1u)] = i;
        }
        workgroupBarrier();
        if local_index == 0u {
            atomicStore(&tile_particle_count[(list + 2u) % 3u], 0u);
        }
        let listed = min(atomicLoad(&tile_particle_count[list]), invocations);
        for (var j = 0u; j < listed; j++) {
            let s = particle_sample(particles[tile_particles[128u * list + j]], world);
            particle_medium += vec4<f32>(s.emission, s.extinction);
            particle_albedo += s.albedo * s.extinction;
        }
        list = (list + 1u) % 3u;
    }
}
#endif

@compute @workgroup_size(4, 4, WORKGROUP_Z)
fn inject(
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) local_index: u32,
    @builtin(workgroup_id) group: vec3<u32>,
) {
#ifdef VOLFOG_FROXEL_CULL
    let block = froxel_block_unpack(live_blocks[group.x]);
#else
    let block = group;
#endif
    let span = vec3<u32>(FROXEL_BLOCK_X, FROXEL_BLOCK_Y, FROXEL_BLOCK_Z);
    let first = block * span;
    // Bounding sphere of the block: the corners of its first and last froxel and three
    // more corners of its far face (whole-froxel extent, so every jittered sample is
    // inside), one corner per invocation.
    if local_index < 5u {
        let last = min(first + span - 1u, froxels.size - 1u);
        let k = local_index;
        let high_x = k == 1u || k == 3u;
        let high_y = k == 1u || k == 4u;
        let corner = vec3<u32>(select(first.x, last.x, high_x), select(first.y, last.y, high_y),
            select(last.z, first.z, k == 0u));
        let offset = vec3<f32>(select(-0.5, 0.5, high_x), select(-0.5, 0.5, high_y),
            select(0.5, -0.5, k == 0u));
        tile_corners[k] = world_of(corner, offset);
    }
    workgroupBarrier();
    if local_index == 0u {
        let center = 0.5 * (tile_corners[0] + tile_corners[1]);
        var radius = 0.0;
        for (var k = 0u; k < 5u; k++) {
            radius = max(radius, distance(center, tile_corners[k]));
        }
        tile_sphere = vec4<f32>(center, radius);
        atomicStore(&tile_count, 0u);
        atomicStore(&tile_volume_count, 0u);
#ifdef VOLFOG_INJECT_AREA_LIGHTS
        atomicStore(&tile_area_count, 0u);
#endif
#ifdef VOLFOG_INJECT_PARTICLES
        for (var k = 0u; k < 3u; k++) {
            atomicStore(&tile_particle_count[k], 0u);
        }
#endif
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
        atomicStore(&tile_shadowed_count, 0u);
#endif
    }
    workgroupBarrier();
#ifdef VOLFOG_INJECT_TEMPORAL
    if all(block == vec3<u32>(0u)) && local_index == 0u {
        stabilised_state = HistoryState(frame.clip_from_world, 1u);
    }
#endif
    let sphere = tile_sphere;
    let light_count = min(fog_lighting.light_count, arrayLength(&lights));
    for (var i = local_index; i < light_count; i += 4u * 4u * WORKGROUP_Z) {
        if light_touches_sphere(lights[i], sphere.xyz, sphere.w) {
#ifdef VOLFOG_INJECT_LOCAL_SHADOWS
            if lights[i].projection < arrayLength(&light_projections) {
                let slot = atomicAdd(&tile_shadowed_count, 1u);
                if slot < TILE_LIGHTS {
                    tile_shadowed[slot] = i;
                }
                continue;
            }
#endif
            let slot = atomicAdd(&tile_count, 1u);
            if slot < TILE_LIGHTS {
                tile_lights[slot] = i;
            }
        }
    }
#ifdef VOLFOG_INJECT_AREA_LIGHTS
    for (var i = local_index; i < arrayLength(&area_lights); i += 4u * 4u * WORKGROUP_Z) {
        if area_light_touches_sphere(area_lights[i], sphere.xyz, sphere.w) {
            let slot = atomicAdd(&tile_area_count, 1u);
            if slot < TILE_LIGHTS {
                tile_areas[slot] = i;
            }
        }
    }
#endif
    let volume_count = min(fog_medium.local_volume_count, arrayLength(&local_volumes));
    for (var i = local_index; i < volume_count; i += 4u * 4u * WORKGROUP_Z) {
        if local_volume_touches_sphere(local_volumes[i], sphere.xyz, sphere.w) {
            let slot = atomicAdd(&tile_volume_count, 1u);
            if slot < TILE_VOLUMES {
                tile_volumes[slot] = i;
            }
        }
    }
    workgroupBarrier();
    let tile_light_count = min(atomicLoad(&tile_count), TILE_LIGHTS);
    // Above TILE_VOLUMES every volume is evaluated.
    let tile_volume_count = atomicLoad(&tile_volume_count);
    // The volumes blend in buffer order: each gathered index moves to its rank among
    // them (the number of gathered indices below it; they are distinct).
    let tile_gathered = min(tile_volume_count, TILE_VOLUMES);
    var gathered_volume = 0u;
    var rank = 0u;
    if local_index < tile_gathered {
        gathered_volume = tile_volumes[local_index];
        for (var other = 0u; other < tile_gathered; other++) {
            rank += select(0u, 1u, tile_volumes[other] < gathered_volume);
        }
    }
    workgroupBarrier();
    if local_index < tile_gathered {
        tile_volumes[rank] = gathered_volume;
    }
    workgroupBarrier();
#ifdef VOLFOG_INJECT_PARTICLES
    gather_particles(first, local, local_index, sphere);
#endif

#ifdef VOLFOG_INJECT_CHECKERBOARD
    let pair = first + vec3<u32>(local.xy, 2u * local.z);
    if any(pair >= froxels.size) || pair.z >= live(pair.xy) {
        return;
    }
    let second = pair + vec3<u32>(0u, 0u, 1u);
    let has_second = second.z < froxels.size.z;
    var id = pair;
    if has_second && !froxel_injected(pair, frame.index, 1u) {
        id = second;
    }
#ifdef VOLFOG_INJECT_TEMPORAL
    // Both froxels of the pair within the live slices, each with its own history (the
    // one not injected takes the history alone, or this value where there is none).
    let column = history_column(pair.xy);
    let injected_at = history_at(column, id);
    let value = froxel_scattering(id, tile_light_count, tile_volume_count, froxel_taps(injected_at.w != 0.0));
    var pair_at = injected_at;
    if id.z != pair.z {
        pair_at = history_at(column, pair);
    }
    textureStore(scattering, pair, stabilise(pair_at, pair, value));
    if second.z < min(live(pair.xy), froxels.size.z) {
        var second_at = injected_at;
        if id.z != second.z {
            second_at = history_at(column, second);
        }
        textureStore(scattering, second, stabilise(second_at, second, value));
    }
#else
    let value = froxel_scattering(id, tile_light_count, tile_volume_count, froxel_taps(true));
    textureStore(scattering, pair, value);
    if has_second {
        textureStore(scattering, second, value);
    }
#endif
#else
    let id = first + local;
    if any(id >= froxels.size) || id.z >= live(id.xy) {
        return;
    }
#ifdef VOLFOG_INJECT_TEMPORAL
    let at = history_at(history_column(id.xy), id);
    textureStore(scattering, id, stabilise(at, id, froxel_scattering(id, tile_light_count, tile_volume_count, froxel_taps(at.w != 0.0))));
#else
    textureStore(scattering, id, froxel_scattering(id, tile_light_count, tile_volume_count, froxel_taps(true)));
#endif
#endif
}
