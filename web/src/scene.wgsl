// The web demo's scene: the sun's depth-only shadow pass and the lit pass (diffuse sun
// through a 3x3 PCF shadow lookup, the point and spot lights unshadowed, sky-ground
// ambient). The fog is not here: VolumetricFog applies it to the lit image.

struct Scene {
    clip_from_world: mat4x4<f32>,
    light_from_world: mat4x4<f32>,
    // xyz towards the sun, w unused.
    sun_direction: vec4<f32>,
    sun_color: vec4<f32>,
    sky: vec4<f32>,
    ground: vec4<f32>,
    // xyz position (m), w range (m).
    light_positions: array<vec4<f32>, 2>,
    light_colors: array<vec4<f32>, 2>,
    // The spot light: xyz direction it points, w cosine of the cone's edge.
    spot: vec4<f32>,
}

@group(0) @binding(0) var<uniform> scene: Scene;

struct Varyings {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
}

@vertex
fn shadow_vertex(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return scene.light_from_world * vec4(position, 1.0);
}

@vertex
fn lit_vertex(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
) -> Varyings {
    var out: Varyings;
    out.clip = scene.clip_from_world * vec4(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.albedo = albedo;
    return out;
}

@group(1) @binding(0) var shadow_map: texture_depth_2d_array;
@group(1) @binding(1) var shadow_sampler: sampler_comparison;

// Fraction of the sun reaching `world`: 3x3 comparison taps around its texel.
fn sun_visibility(world: vec3<f32>, normal: vec3<f32>) -> f32 {
    let light = scene.light_from_world * vec4(world + normal * 0.05, 1.0);
    let uv = vec2(light.x * 0.5 + 0.5, 0.5 - light.y * 0.5);
    let texel = 1.0 / vec2<f32>(textureDimensions(shadow_map).xy);
    var lit = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let offset = vec2(f32(x), f32(y)) * texel;
            lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + offset, 0, light.z - 0.002);
        }
    }
    return lit / 9.0;
}

@fragment
fn lit_fragment(in: Varyings) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let sun = scene.sun_direction.xyz;
    var radiance = scene.sun_color.rgb * max(dot(n, sun), 0.0) * sun_visibility(in.world, n);
    radiance += mix(scene.ground.rgb, scene.sky.rgb, n.y * 0.5 + 0.5);
    for (var i = 0; i < 2; i++) {
        let to_light = scene.light_positions[i].xyz - in.world;
        let d = length(to_light);
        let l = to_light / max(d, 1e-4);
        let range = scene.light_positions[i].w;
        let window = saturate(1.0 - pow(d / range, 4.0));
        var cone = 1.0;
        if i == 1 {
            cone = smoothstep(scene.spot.w, scene.spot.w + 0.1, dot(-l, scene.spot.xyz));
        }
        radiance += scene.light_colors[i].rgb * max(dot(n, l), 0.0) * window * window * cone
            / max(d * d, 0.01);
    }
    return vec4(in.albedo * radiance / 3.14159265, 1.0);
}
