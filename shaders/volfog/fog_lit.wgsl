// volfog::fog_lit — particles and translucent surfaces lit by the fog's own light at
// their position: the incoming light with its shadows, phase-weighted, read back from
// the volume inject fills.
//
// Use:      #import volfog::fog_lit::{fog_lit_coord_from_view, fog_lit_light}
//           let source = textureSampleLevel(lit_volume, linear_sampler,
//               fog_lit_coord_from_view(view_pos, froxels), 0.0);
//           let light = fog_lit_light(source, medium_albedo, fallback);
//           color = particle_albedo * light + particle_emission;  // then apply the fog
//           as for any surface (volfog::apply).
// Defines:  none; nothing is bound: pass the lit volume (VolumetricFog::lit_texture, a
//           texture_3d<f32>, rgba16float, filterable) and a linear clamp-to-edge sampler.
// Data:     the lit volume holds per froxel rgb = sigma_s L_in and a = sigma_t, where
//           L_in = integral of phase(view, w) L(w) dw is the light the medium at the
//           froxel scatters towards the camera per unit sigma_s: the sun with its
//           shadows (cascades, clouds), the ambient light, point, spot and area lights
//           with their shadows and cookies, each through the medium's transmittance
//           when the fog computes it. rgb / (albedo a) gives L_in back.
// Approximation:
//           - The light is the medium's: its Henyey-Greenstein phase towards the
//             camera, as if the particle scattered as the fog does.
//           - The texture's trilinear filter gives the ratio of filtered rgb to
//             filtered a: the extinction-weighted mean of L_in over the froxels around
//             the point, so shadow edges are as sharp as the froxels.
//           - The medium's emission (and that of glowing local volumes and particles)
//             counts as light: emission / (albedo sigma_t) is added.
//           - Where the froxels around the point hold no extinction (a below
//             FOG_LIT_MIN_EXTINCTION: clear air, or behind the depth-culled slices) the
//             fog carries no light there, and `fallback` is returned; so is it per
//             channel where `albedo` is 0.
//           - `albedo` is the medium's (FogMedium.albedo); where particles or a custom
//             density change the albedo locally, the result is off by their ratio.
// Units:    view positions in metres, radiance linear (W / (m^2 sr)).
// Reference: Wronski 2014, "Volumetric fog", extensions: the fog's lighting volume used
//           to light and shadow particles.
#define_import_path volfog::fog_lit

#import volfog::types::Froxels
#import volfog::froxel::{slice_coord, uv_from_ndc}

// Extinction (1/m) below which the lit volume carries no light: rgba16float holds
// values above 6.1e-5 to 2^-11 relative (below, its subnormals lose precision).
const FOG_LIT_MIN_EXTINCTION: f32 = 1e-4;

// Texture coordinate in the lit volume of the point at screen uv (v down) and view
// depth `depth` (m): texel k of the depth axis holds the froxel sampled at the middle
// of slice k; depths in front of the first or behind the last middle read those.
fn fog_lit_coord(uv: vec2<f32>, depth: f32, froxels: Froxels) -> vec3<f32> {
    let n = f32(froxels.size.z);
    let t = slice_coord(depth, froxels.near, froxels.far, froxels.curve);
    return vec3<f32>(uv, clamp(t, 0.5 / n, 1.0 - 0.5 / n));
}

// Texture coordinate in the lit volume of a view-space position (m).
fn fog_lit_coord_from_view(view_pos: vec3<f32>, froxels: Froxels) -> vec3<f32> {
    let clip = froxels.clip_from_view * vec4<f32>(view_pos, 1.0);
    let ndc = clip.xy / select(clip.w, 1e-30, abs(clip.w) < 1e-30);
    return fog_lit_coord(uv_from_ndc(ndc), abs(view_pos.z), froxels);
}

// The fog's light at a point from the lit volume's sample there (rgb sigma_s L_in, a
// sigma_t) and the medium's albedo: L_in per channel (W / (m^2 sr), the phase-weighted
// incoming radiance), or `fallback` where the sample holds no extinction or the
// albedo's channel is 0.
fn fog_lit_light(source: vec4<f32>, albedo: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    if source.a < FOG_LIT_MIN_EXTINCTION {
        return fallback;
    }
    let scattering = albedo * source.a;
    let light = max(source.rgb, vec3<f32>(0.0)) / max(scattering, vec3<f32>(1e-30));
    // Per channel, light where the albedo is above 0, else the fallback (weights of
    // exactly 0 and 1, so either is returned unchanged; no vector select, which HLSL
    // writes as a deprecated vector ?:).
    let scatters = vec3<f32>(albedo > vec3<f32>(0.0));
    return light * scatters + fallback * (1.0 - scatters);
}
