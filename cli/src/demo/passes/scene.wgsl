// Demo scene shading: the lit opaque pass (sun with cascaded shadow maps, point and
// spot lights, the lamp with its cube shadow map, hemisphere ambient), the sky, a semi-transparent surface fogged
// through the forward snippet (volfog::apply with volfog::bindings at group 1), and
// the pool: submerged surfaces lit through the water and seen through its fog
// (volfog::water), and its surface.
//
// Bindings (group 0): 0 Scene, 1 lights (array<FogLight>), 2 ShadowCascades,
//                     3 shadow map (depth 2D array, one layer per cascade),
//                     4 comparison sampler, 5 the sky texture (volfog::sky), 6 its
//                     sampler, 7 the lamp's cube shadow map (depth 2D array, faces
//                     +X, -X, +Y, -Y, +Z, -Z), 8 world -> clip of its six faces.
//           (group 1): the volfog::bindings fog group (transparent pass only).
// Outputs: linear radiance in rgb; alpha carries the sun visibility of the opaque
// surface (1 for the sky) for the demo's probe output; the fullscreen apply and the
// transparent pass keep the destination alpha.

#import volfog::types::{FogLight, HeightFog, ShadowCascades, SkyAtmosphere, Water}
#import volfog::sky::sky_sample
#import volfog::height_fog::height_fog
#import volfog::water::{water_fog, water_light}
#import volfog::lights::{light_attenuation, fog_light_spot}
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
    water: Water,
    // The medium as analytic height fog: from under water, the air beyond the surface.
    air: HeightFog,
    // The pool's footprint (x, z); pool_min.w 1 turns the water on.
    pool_min: vec4<f32>,
    pool_max: vec4<f32>,
    // The sky's atmosphere; the sky texture (binding 5) is solved for it.
    atmosphere: SkyAtmosphere,
    // The lamp: its position and its index in the lights (shadowed by binding 7).
    lamp_position: vec3<f32>,
    lamp_index: u32,
}

@group(0) @binding(0) var<uniform> scene: Scene;
@group(0) @binding(1) var<storage, read> lights: array<FogLight>;
@group(0) @binding(2) var<uniform> cascades: ShadowCascades;
@group(0) @binding(3) var shadow_map: texture_depth_2d_array;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;
@group(0) @binding(5) var sky_texture: texture_2d_array<f32>;
@group(0) @binding(6) var sky_texture_sampler: sampler;
@group(0) @binding(7) var lamp_map: texture_depth_2d_array;
@group(0) @binding(8) var<uniform> lamp_faces: array<mat4x4<f32>, 6>;

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

// The lamp's visibility from its cube shadow map: the face along the major axis of
// the direction from the lamp, 3x3 PCF with hardware comparison, the receiver moved
// 1.5 texels along its normal and half a texel towards the lamp.
fn lamp_visibility(world: vec3<f32>, normal: vec3<f32>) -> f32 {
    let to = world - scene.lamp_position;
    let size = f32(textureDimensions(lamp_map).x);
    let texel = 2.0 * length(to) / size;
    let p = world + normal * (1.5 * texel) - normalize(to) * (0.5 * texel);
    let d = p - scene.lamp_position;
    let a = abs(d);
    var face = select(5u, 4u, d.z > 0.0);
    if a.x >= a.y && a.x >= a.z {
        face = select(1u, 0u, d.x > 0.0);
    } else if a.y >= a.z {
        face = select(3u, 2u, d.y > 0.0);
    }
    let clip = lamp_faces[face] * vec4<f32>(p, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    var sum = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let offset = vec2<f32>(f32(x), f32(y)) / size;
            sum += textureSampleCompareLevel(lamp_map, shadow_sampler, uv + offset, face, ndc.z);
        }
    }
    return sum / 9.0;
}

// Irradiance from the hemisphere ambient for a surface normal.
fn ambient_irradiance(normal: vec3<f32>) -> vec3<f32> {
    return PI * mix(scene.ambient_ground, scene.sky_horizon, 0.5 + 0.5 * normal.y);
}

// Irradiance from the point and spot lights (same falloff as in the fog), the lamp
// shadowed by its cube shadow map.
fn local_irradiance(world: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    for (var k = 0u; k < scene.light_count; k++) {
        let light = lights[k];
        let offset = light.position - world;
        let distance = length(offset);
        let l = offset / max(distance, 1e-6);
        let attenuation = light_attenuation(distance, light.range, light.radius);
        let spot = fog_light_spot(light, dot(-l, light.direction));
        var lit = attenuation * spot * max(dot(normal, l), 0.0);
        if k == scene.lamp_index && lit > 0.0 {
            lit *= lamp_visibility(world, normal);
        }
        e += light.color * lit;
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
    if in_pool(in.world) {
        // Under water the light falls straight down and fades with depth
        // (volfog::water's model); the low sun's direct light does not reach here.
        let down = water_light(scene.water, in.world) * (0.5 + 0.5 * dot(n, scene.water.normal));
        let e = down + ambient_irradiance(n) + local_irradiance(in.world, n);
        return Shaded(albedo / PI * e * scene.surface_scale, 1.0);
    }
    let vis = sun_visibility(in.world, n, view_depth);
    let sun = scene.sun_color * (vis * max(dot(n, scene.sun_direction), 0.0));
    let e = sun + ambient_irradiance(n) + local_irradiance(in.world, n);
    return Shaded(albedo / PI * e * scene.surface_scale, vis);
}

// In the pool's water: within the basin's footprint and below the surface (the
// basin's walls bound the water, which volfog::water treats as a half-space).
fn in_pool(p: vec3<f32>) -> bool {
    // 1 cm of slack: the basin's inner faces lie on the footprint's edges.
    let inside = p.x >= scene.pool_min.x - 0.01 && p.x <= scene.pool_max.x + 0.01
        && p.z >= scene.pool_min.z - 0.01 && p.z <= scene.pool_max.z + 0.01;
    return scene.pool_min.w > 0.5 && inside && dot(p, scene.water.normal) <= scene.water.height;
}

// Radiance of a surface at p as the camera sees it through the water: a view ray
// from or into the water is fogged over its underwater part (and, from under water,
// by the air beyond the surface). Elsewhere unchanged.
fn through_water(radiance: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    var c = radiance;
    let eye = scene.camera_position;
    if in_pool(eye) && !in_pool(p) {
        // From under water: the air between the surface and p first (the froxel
        // volume starts at the camera, so it is not applied to this view).
        let d0 = scene.water.height - dot(eye, scene.water.normal);
        let d1 = scene.water.height - dot(p, scene.water.normal);
        let exit = eye + (p - eye) * clamp(d0 / max(d0 - d1, 1e-6), 0.0, 1.0);
        c = apply_fog(c, height_fog(scene.air, exit, p - exit));
    }
    if in_pool(p) || in_pool(eye) {
        c = apply_fog(c, water_fog(scene.water, eye, p));
    }
    return c;
}

@fragment
fn opaque_fs(in: VertexOut) -> @location(0) vec4<f32> {
    let view_depth = -(scene.view_from_world * vec4<f32>(in.world, 1.0)).z;
    let s = shade(in, view_depth);
    return vec4<f32>(through_water(s.radiance, in.world), s.sun_visibility);
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
    // Nishita single scattering from the solved texture, the phase per pixel
    // (volfog::sky), and the sun's disc.
    var sky = sky_sample(sky_texture, sky_texture_sampler, dir, scene.atmosphere);
    let mu = dot(dir, scene.sun_direction);
    sky += scene.sun_color * (scene.sun_disk * smoothstep(0.9996, 0.9998, mu));
    if dir.y < 0.0 {
        sky = scene.ambient_ground;
    }
    // From under water the sky lies beyond the surface: 1 km along the ray.
    let far_point = scene.camera_position + dir * 1000.0;
    return vec4<f32>(through_water(sky * scene.surface_scale, far_point), 1.0);
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

// The pool's water surface: a Fresnel-weighted reflection of the sky and the sun seen
// from above, blended over the submerged scene (already fogged by the water in the
// opaque pass) and fogged by the air; seen from below, the underside fogged by the
// water between it and the camera.
@fragment
fn water_fs(in: VertexOut) -> @location(0) vec4<f32> {
    let v = normalize(scene.camera_position - in.world);
    let up = scene.water.normal;
    let cos_v = clamp(abs(dot(up, v)), 0.0, 1.0);
    let fresnel = 0.02 + 0.98 * pow(1.0 - cos_v, 5.0);
    let view_pos = (scene.view_from_world * vec4<f32>(in.world, 1.0)).xyz;
    if in_pool(scene.camera_position) {
        let under = scene.sky_horizon * scene.surface_scale;
        return vec4<f32>(apply_fog(under, water_fog(scene.water, scene.camera_position, in.world)), 0.15);
    }
    let r = reflect(-v, up);
    let sky = mix(scene.sky_horizon, scene.sky_zenith, sqrt(clamp(r.y, 0.0, 1.0)));
    let glint = scene.sun_color * (0.5 * pow(max(dot(r, scene.sun_direction), 0.0), 400.0));
    let lit = (sky + glint) * scene.surface_scale;
    let fog = fog_sample(bindings::fog_integrated, bindings::fog_sampler,
                         fog_coord_from_view(view_pos, bindings::fog_froxels));
    return vec4<f32>(apply_fog(lit, fog), fresnel);
}
