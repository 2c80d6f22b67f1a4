// Pass apply — fogs a lit colour target with the integrated volume, using the depth
// buffer: one fullscreen triangle.
//
// Draw: 3 vertices with the fullscreen pass's vertex shader (fullscreen_vs), no vertex
// buffers. The fragment writes (in-scatter, transmittance); blend it onto the colour
// target with
//   colour: src * One + dst * SrcAlpha      alpha: src * Zero + dst * One
// which gives color * T + L (Wronski 2014, "Applying effect") without reading the colour.
// Bindings:
//   group 0 (VOLFOG_FOG_GROUP): the fog group of volfog::bindings (0 Froxels,
//     1 integrated volume, 2 sampler unless VOLFOG_BINDINGS_NO_SAMPLER, 3 HeightFog
//     tail in view space)
//   group 1, binding 0: texture_2d<f32>, unfilterable: the scene depth buffer (a depth
//     texture bound as unfilterable float, as WebGPU allows; read with textureLoad),
//     same size as the colour target; under VOLFOG_APPLY_RESOLVED the resolved MSAA
//     fog layout instead (volfog::apply::fog_layout: r view depth in m, g fog amount).
// Defines: VOLFOG_BINDINGS_NO_SAMPLER — manual trilinear filtering, no sampler binding.
//          VOLFOG_APPLY_RESOLVED — a multisampled scene (Wenzel 2007): the fog colour
//          at the resolved view depth, the fog amount averaged over the samples.
//          VOLFOG_APPLY_EPIPOLAR — the far field: beyond the far plane the tail's sun
//          light is shadowed by epipolar sun shafts (Yusov 2012); group 1 binding 1 is
//          the shaft texture (rgba16float, rgb the lit fraction; EpipolarShafts marched
//          from the far plane in the tail's medium), read with textureLoad.
//          VOLFOG_APPLY_NO_TAIL — no analytic tail beyond the far plane: the volume's
//          fog alone, for frames whose tail (group 0 binding 3) has density 0, where it
//          draws the same image without paying for fog_tail on every pixel (hardware
//          that runs both sides of a branch pays for it even where no pixel is beyond
//          the far plane). Not with VOLFOG_APPLY_EPIPOLAR, whose shafts shadow the tail.
//          VOLFOG_APPLY_MULTIVIEW — both eyes of stereo fog in one multiview render pass
//          (a two-layer colour target, view mask 0b11): the fragment reads
//          @builtin(view_index) (0 left, 1 right); group 0 (VOLFOG_STEREO_FOG_GROUP) is
//          the stereo fog group of volfog::stereo_bindings (both eyes' fog), group 1
//          binding 0 a texture_2d_array<f32> of the eyes' scene depths (layer i the
//          depth of view i, unfilterable, read with textureLoad). The target needs
//          multiview (wgpu Features::MULTIVIEW; SPIR-V MultiView, HLSL SM 6.1
//          SV_ViewID, MSL 2.2 amplification_id, GLSL GL_EXT_multiview). Not with
//          VOLFOG_APPLY_RESOLVED or VOLFOG_APPLY_EPIPOLAR.

#ifdef VOLFOG_APPLY_MULTIVIEW
#import volfog::stereo_bindings
#import volfog::stereo_apply::{stereo_eye_froxels, stereo_eye_tail, stereo_fog_load, stereo_fog_sample}
#else
#import volfog::bindings
#endif
#import volfog::apply::{fog_coord, fog_sample, fog_load, fog_tail, fog_tail_shafts, fog_with_tail, fog_view_from_depth, fog_resolved}
#import volfog::froxel::{ndc_from_uv, view_from_ndc}

#ifdef VOLFOG_APPLY_MULTIVIEW
@group(1) @binding(0) var scene_depth: texture_2d_array<f32>;
#else
@group(1) @binding(0) var scene_depth: texture_2d<f32>;
#endif
#ifdef VOLFOG_APPLY_EPIPOLAR
@group(1) @binding(1) var epipolar_shafts: texture_2d<f32>;
#endif

@fragment
fn apply_fs(
    @builtin(position) frag: vec4<f32>,
#ifdef VOLFOG_APPLY_MULTIVIEW
    @builtin(view_index) view_index: u32,
#endif
) -> @location(0) vec4<f32> {
    // The pixel's texel is loaded before anything else is computed: a CPU rasterizer
    // (llvmpipe) keeps the values computed before a texture fetch alive across it,
    // which cost this pass about 5 % there.
#ifdef VOLFOG_APPLY_RESOLVED
    let resolved = textureLoad(scene_depth, vec2<i32>(frag.xy), 0);
#else
#ifdef VOLFOG_APPLY_MULTIVIEW
    let depth = textureLoad(scene_depth, vec2<i32>(frag.xy), i32(view_index), 0).r;
#else
    let depth = textureLoad(scene_depth, vec2<i32>(frag.xy), 0).r;
#endif
#endif
    let uv = frag.xy / vec2<f32>(textureDimensions(scene_depth));
#ifdef VOLFOG_APPLY_MULTIVIEW
    let froxels = stereo_eye_froxels(
        view_index, stereo_bindings::stereo_left_froxels, stereo_bindings::stereo_right_froxels);
#else
    let froxels = bindings::fog_froxels;
#endif
#ifdef VOLFOG_APPLY_RESOLVED
    let view = fog_view_from_depth(uv, resolved.r, froxels.view_from_clip);
#else
    let view = view_from_ndc(vec3<f32>(ndc_from_uv(uv), depth), froxels.view_from_clip);
#endif
    let coord = fog_coord(uv, abs(view.z), froxels);
#ifdef VOLFOG_APPLY_MULTIVIEW
#ifdef VOLFOG_BINDINGS_NO_SAMPLER
    let fog = stereo_fog_load(
        view_index, stereo_bindings::stereo_left_integrated,
        stereo_bindings::stereo_right_integrated, coord);
#else
    let fog = stereo_fog_sample(
        view_index, stereo_bindings::stereo_left_integrated,
        stereo_bindings::stereo_right_integrated, stereo_bindings::stereo_sampler, coord);
#endif
#else
#ifdef VOLFOG_BINDINGS_NO_SAMPLER
    let fog = fog_load(bindings::fog_integrated, coord);
#else
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler, coord);
#endif
#endif
#ifdef VOLFOG_APPLY_NO_TAIL
    let total = fog;
#else
#ifdef VOLFOG_APPLY_EPIPOLAR
    let shafts = textureLoad(epipolar_shafts, vec2<i32>(frag.xy), 0).rgb;
    let tail = fog_tail_shafts(froxels, bindings::fog_far_tail, view, shafts);
#else
#ifdef VOLFOG_APPLY_MULTIVIEW
    let far_tail = stereo_eye_tail(
        view_index, stereo_bindings::stereo_left_tail, stereo_bindings::stereo_right_tail);
    let tail = fog_tail(froxels, far_tail, view);
#else
    let tail = fog_tail(froxels, bindings::fog_far_tail, view);
#endif
#endif
    let total = fog_with_tail(fog, tail);
#endif
#ifdef VOLFOG_APPLY_RESOLVED
    return fog_resolved(total, resolved.g);
#else
    return total;
#endif
}
