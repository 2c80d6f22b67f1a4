// Demo scene shading: the lit opaque pass (sun with cascaded shadow maps, point and
// spot lights, hemisphere ambient), the sky, and a semi-transparent surface fogged
// through the forward snippet (volfog::apply with volfog::bindings at group 1).
//
// Bindings (group 0): 0 Scene, 1 lights (array<FogLight>), 2 ShadowCascades,
//                     3 shadow map (depth 2D array, one layer per cascade),
//                     4 comparison sampler.
//           (group 1): the volfog::bindings fog group (transparent pass only).
// Outputs: linear radiance in rgb; alpha carries the sun visibility of the opaque
// surface (1 for the sky) for the demo's probe output; the fullscreen apply and the
// transparent pass keep the destination alpha.

#import volfog::types::{FogLight, ShadowCascades}
#import volfog::lights::{light_attenuation, spot_factor}
#import volfog::esm::{esm_cascade, esm_shadow_coord}
#import volfog::bindings
#import volfog::apply::{fog_coord_from_view, fog_sample, apply_fog}

struct Scene {
    clip_from_world: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    world_from_clip: mat4x4<f32>,
    // World-space size (m) of one shadow-map texel per cascade.
    shadow_texel: vec4<f32>,
    camera_position: vec3<f32>,
    // Multiplies every surface and sky radiance (0 renders black surfaces: the probe
    // that isolates the fog's in-scattering).
    surface_scale: f32,
    sun_direction: vec3<f32>,
    light_count: u32,
    sun_color: vec3<f32>,
    sun_disk: f32,
    sky_zenith: vec3<f32>,
    sky_horizon: vec3<f32>,
    glass_alpha: f32,
    ambient_ground: vec3<f32>,
    // Constant depth bias of the shadow-map comparison (light clip depth units).
    shadow_bias: f32,
}

@group(0) @binding(0) var<uniform> scene: Scene;
@group(0) @binding(1) var<storage, read> lights: array<FogLight>;
@group(0) @binding(2) var<uniform> cascades: ShadowCascades;
@group(0) @binding(3) var shadow_map: texture_depth_2d_array;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;

const PI: f32 = 3.14159265;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) kind: f32,
}

@vertex
fn scene_vs(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) kind: f32,
) -> VertexOut {
    var out: VertexOut;
    out.clip = scene.clip_from_world * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.color = color;
    out.kind = kind;
    return out;
}

// Sun visibility from the cascaded shadow map: 3x3 PCF with hardware comparison,
// normal offset of 1.5 texels and a small constant bias.
fn sun_visibility(world: vec3<f32>, normal: vec3<f32>, view_depth: f32) -> f32 {
    let i = esm_cascade(view_depth, cascades.splits, cascades.count);
    if i >= cascades.count {
        return 1.0;
    }
    let texel = scene.shadow_texel[i];
    let p = world + normal * (1.5 * texel);
    let coord = esm_shadow_coord(cascades.light_from_world[i], p);
    if any(coord.xy < vec2<f32>(0.0)) || any(coord.xy > vec2<f32>(1.0)) || coord.z > 1.0 {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(shadow_map));
    var sum = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let uv = coord.xy + vec2<f32>(f32(x), f32(y)) / size;
            sum += textureSampleCompareLevel(shadow_map, shadow_sampler, uv, i, coord.z - scene.shadow_bias);
        }
    }
    return sum / 9.0;
}

// Irradiance from the hemisphere ambient for a surface normal.
fn ambient_irradiance(normal: vec3<f32>) -> vec3<f32> {
    return PI * mix(scene.ambient_ground, scene.sky_horizon, 0.5 + 0.5 * normal.y);
}

// Irradiance from the point and spot lights (same falloff as in the fog).
fn local_irradiance(world: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < scene.light_count; k++) {
        let light = lights[k];
        let offset = light.position - world;
        let distance = length(offset);
        let l = offset / max(distance, 1e-6);
        let attenuation = light_attenuation(distance, light.range, light.radius);
        let spot = spot_factor(dot(-l, light.direction), light.cos_outer, light.cos_inner);
        e += light.color * (attenuation * spot * max(dot(normal, l), 0.0));
    }
    return e;
}

// A 1 m checkerboard on the ground (kind 1).
fn checker(world: vec3<f32>) -> f32 {
    let c = floor(world.x) + floor(world.z);
    return select(0.65, 1.0, c - 2.0 * floor(c * 0.5) < 0.5);
}

struct Shaded {
    radiance: vec3<f32>,
    sun_visibility: f32,
}

fn shade(in: VertexOut, view_depth: f32) -> Shaded {
    let n = normalize(in.normal);
    if in.kind > 1.5 {
        // Emissive (kind 2): the light markers.
        return Shaded(in.color * scene.surface_scale, 1.0);
    }
    var albedo = in.color;
    if in.kind > 0.5 {
        albedo *= checker(in.world);
    }
    let vis = sun_visibility(in.world, n, view_depth);
    let sun = scene.sun_color * (vis * max(dot(n, scene.sun_direction), 0.0));
    let e = sun + ambient_irradiance(n) + local_irradiance(in.world, n);
    return Shaded(albedo / PI * e * scene.surface_scale, vis);
}

@fragment
fn opaque_fs(in: VertexOut) -> @location(0) vec4<f32> {
    let view_depth = -(scene.view_from_world * vec4<f32>(in.world, 1.0)).z;
    let s = shade(in, view_depth);
    return vec4<f32>(s.radiance, s.sun_visibility);
}

// The sky behind everything: a fullscreen triangle at the far plane.
struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn sky_vs(@builtin(vertex_index) index: u32) -> SkyOut {
    let xy = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u)) * 2.0 - 1.0;
    var out: SkyOut;
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

@fragment
fn sky_fs(in: SkyOut) -> @location(0) vec4<f32> {
    let far = scene.world_from_clip * vec4<f32>(in.ndc, 1.0, 1.0);
    let near = scene.world_from_clip * vec4<f32>(in.ndc, 0.0, 1.0);
    let dir = normalize(far.xyz / far.w - near.xyz / near.w);
    let up = clamp(dir.y, 0.0, 1.0);
    var sky = mix(scene.sky_horizon, scene.sky_zenith, pow(up, 0.5));
    let mu = dot(dir, scene.sun_direction);
    sky += scene.sun_color * (0.02 * pow(max(mu, 0.0), 64.0));
    sky += scene.sun_color * (scene.sun_disk * smoothstep(0.9996, 0.9998, mu));
    if dir.y < 0.0 {
        sky = scene.ambient_ground;
    }
    return vec4<f32>(sky * scene.surface_scale, 1.0);
}

// The semi-transparent surface: shaded like the opaque pass plus a Fresnel-like rim,
// then fogged with the forward snippet at its own depth.
@fragment
fn transparent_fs(in: VertexOut) -> @location(0) vec4<f32> {
    let view_pos = (scene.view_from_world * vec4<f32>(in.world, 1.0)).xyz;
    let s = shade(in, -view_pos.z);
    let n = normalize(in.normal);
    let v = normalize(scene.camera_position - in.world);
    let rim = pow(1.0 - clamp(abs(dot(n, v)), 0.0, 1.0), 3.0);
    let h = normalize(v + scene.sun_direction);
    let specular = scene.sun_color * (s.sun_visibility * pow(max(dot(n, h), 0.0), 96.0) * 4.0);
    let lit = s.radiance + (specular + rim * scene.sky_horizon) * scene.surface_scale;
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler,
                         fog_coord_from_view(view_pos, bindings::fog_froxels));
    let alpha = clamp(scene.glass_alpha + 0.5 * rim, 0.0, 1.0);
    return vec4<f32>(apply_fog(lit, fog), alpha);
}
