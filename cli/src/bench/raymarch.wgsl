// Bench pass raymarch — the per-pixel reference of the froxel pipeline: for every pixel,
// march the view ray through the same medium and lights as the inject pass and
// integrate them with the same step as the scan pass. This is how renderers without a
// froxel volume draw volumetric fog; `volfog bench` times it against the froxel
// pipeline.
//
// Draw: 3 vertices, no vertex buffers (one fullscreen triangle). The fragment writes
// (in-scatter, transmittance) like the apply pass; blend it onto the colour target with
// volfog's FOG_BLEND (colour: src + dst * src_alpha, alpha: dst) to get color * T + L.
// Ray: from the near plane (Froxels.near, view depth in metres) to the scene depth or
// Froxels.far, whichever is closer, in RAYMARCH_STEPS equal steps sampled at their
// midpoints. Sample: density as in inject (medium_extinction with animated noise, plus
// local volumes), light as in inject (sun with its ESM shadow, ambient L1 SH, every
// point/spot light whose range reaches the sample), no jitter, HG phase, no density
// texture. Step: volfog::scan::scan_step.
// Bindings (group 0): the inject layout with the scene depth in place of the
// scattering volume:
//   0  uniform Froxels (camera projection, near, far)   1  uniform FogFrame
//   2  uniform FogMedium     3  uniform FogLighting     4  uniform ShadowCascades
//   5  texture_2d_array<f32>: filtered ESM, one layer per cascade (R32Float, textureLoad)
//   6  storage, read: array<FogLight>                   7  storage, read: array<LocalVolume>
//   8  texture_2d<f32>, unfilterable: the scene depth buffer, same size as the target
// Shader defs: RAYMARCH_STEPS (u32, steps per pixel), NOISE_OCTAVES (u32, 1..=8),
//   LIGHT_CAPACITY and VOLUME_CAPACITY (u32, >= 1: elements in the bound buffers).

#import volfog::types::{Froxels, FogFrame, FogMedium, FogLighting, ShadowCascades, FogLight, LocalVolume}
#import volfog::froxel::{ndc_from_uv, view_from_ndc}
#import volfog::noise::noise_animated
#import volfog::density::{medium_extinction, local_volume_density}
#import volfog::esm::esm_shadow
#import volfog::lights::{light_touches_sphere, fog_light_inscatter, sun_inscatter, ambient_inscatter}
#import volfog::scan::{scan_step, SCAN_START}
#import volfog::fullscreen::fullscreen_position

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var<uniform> frame: FogFrame;
@group(0) @binding(2) var<uniform> fog_medium: FogMedium;
@group(0) @binding(3) var<uniform> fog_lighting: FogLighting;
@group(0) @binding(4) var<uniform> shadow_cascades: ShadowCascades;
@group(0) @binding(5) var esm_array: texture_2d_array<f32>;
@group(0) @binding(6) var<storage, read> lights: array<FogLight>;
@group(0) @binding(7) var<storage, read> local_volumes: array<LocalVolume>;
@group(0) @binding(8) var scene_depth: texture_2d<f32>;

const STEPS: u32 = #{RAYMARCH_STEPS}u;
const NOISE_OCTAVES: u32 = #{NOISE_OCTAVES}u;
const LIGHT_CAPACITY: u32 = #{LIGHT_CAPACITY}u;
const VOLUME_CAPACITY: u32 = #{VOLUME_CAPACITY}u;

@vertex
fn raymarch_vs(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(index);
}

@fragment
fn raymarch_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(scene_depth));
    let uv = frag.xy / size;
    let ndc = ndc_from_uv(uv);
    let depth = textureLoad(scene_depth, vec2<i32>(frag.xy), 0).r;
    let scene = abs(view_from_ndc(vec3<f32>(ndc, depth), froxels.view_from_clip).z);
    let end = min(scene, froxels.far);
    if end <= froxels.near {
        return SCAN_START;
    }
    // A point of the pixel's ray (any depth inside the clip volume) and the path length
    // per metre of view depth.
    let ray = view_from_ndc(vec3<f32>(ndc, 0.5), froxels.view_from_clip);
    let ray_depth = max(abs(ray.z), 1e-30);
    let scale = length(ray) / ray_depth;
    let view_dir = normalize((frame.world_from_view * vec4<f32>(ray, 0.0)).xyz);
    let g = fog_medium.phase_g;
    let ambient = ambient_inscatter(fog_lighting.ambient_r, fog_lighting.ambient_g, fog_lighting.ambient_b, view_dir, g);
    // The counts are bounded by the buffer capacities given as shader defs (not by
    // arrayLength, which Mesa 22.3's lavapipe miscompiles in this fragment shader).
    let light_count = min(fog_lighting.light_count, LIGHT_CAPACITY);
    let volume_count = min(fog_medium.local_volume_count, VOLUME_CAPACITY);

    let dz = (end - froxels.near) / f32(STEPS);
    let ds = dz * scale;
    var acc = SCAN_START;
    for (var i = 0u; i < STEPS; i++) {
        let z = froxels.near + (f32(i) + 0.5) * dz;
        let view = ray * (z / ray_depth);
        let world = (frame.world_from_view * vec4<f32>(view, 1.0)).xyz;

        let noise = noise_animated(world, fog_medium.noise_scale, fog_medium.wind, frame.time, NOISE_OCTAVES);
        var sigma_t = medium_extinction(fog_medium, world, noise, 1.0);
        for (var v = 0u; v < volume_count; v++) {
            sigma_t += local_volume_density(local_volumes[v], world);
        }
        sigma_t = max(sigma_t, 0.0);

        let shadow = esm_shadow(esm_array, shadow_cascades, world, z);
        var light = sun_inscatter(fog_lighting.sun, shadow, view_dir, g) + ambient;
        for (var l = 0u; l < light_count; l++) {
            if light_touches_sphere(lights[l], world, 0.0) {
                light += fog_light_inscatter(lights[l], world, view_dir, g);
            }
        }
        acc = scan_step(acc, vec4<f32>(fog_medium.albedo * sigma_t * light, sigma_t), ds);
    }
    return acc;
}
