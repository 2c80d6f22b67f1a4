// volfog::clouds — a cloud layer from a wind-scrolled 2D density map: cloud shadows on
// the scene and in the fog, distance clouds marched towards the sun, and the layer lit
// per pixel with gradient and rim lighting, soft-clipped at the scene's depth.
//
// Use:      #import volfog::clouds::{cloud_shadow, distance_clouds, cloud_layer}
//           color *= cloud_shadow(map, map_sampler, layer, world_pos);   // lit scene
//           sun_visibility *= cloud_shadow(...);                         // froxel sun term
//           color = apply_fog(color, distance_clouds(map, map_sampler, layer, eye, dir, dist));
//           color = apply_fog(color, cloud_layer(map, map_sampler, layer, eye, dir, dist));
// Defines:  none
// Layer:    a horizontal slab from base_height to base_height + thickness (+Y up) of
//           extinction layer.extinction * m(x, z), m the map's red channel in [0, 1] at
//           uv = fract(((x, z) - wind * time) / map_size) (sample with a linear,
//           repeat sampler: the sky scrolls with the wind).
// Shadow:   the sun's ray from p crosses the slab over thickness / sun.y metres; its
//           transmittance exp(-extinction m t / sun.y) takes m where that ray meets
//           the slab's middle (one look-up, the seed's single fullscreen pass). 1 above
//           the slab's middle and for a sun below CLOUD_MIN_SUN_HEIGHT (no shadow
//           direction; the sun term is 0 there anyway).
// Distance clouds: view_samples points along the view ray's part in the slab (and in
//           front of the scene), each with sun_samples points towards the sun inside
//           the slab; per step the in-scattered light is (sun_color T_sun
//           HG(dot(dir, sun), g) + sky_color) (1 - e^(-sigma ds)), attenuated by the
//           transmittance in front of it (albedo 1). A uniform map gives the slant-path
//           transmittance exp(-sigma thickness / |dir.y|) exactly.
// Cloud layer: the slab lit once per pixel at the middle of the visible part of the
//           view ray: gradient lighting (Wang 2003: a normal from the map's gradient,
//           wrapped diffuse 0.5 + 0.5 n.sun), rim lighting of thin cloud (rim (1 - m)^2
//           HG forward lobe), opacity 1 - e^(-sigma m length); the part of the slab
//           behind the scene is cut as a soft particle is (volfog::soft_particles: the
//           share of the slab's ray segment in front of the scene).
// Output:   vec4(in-scattered radiance rgb, transmittance a), as volfog::apply.
// Reference: Wenzel 2007, "Real-time Atmospheric Effects in Games Revisited", "Clouds
//           Rendering Using Per-Pixel Depth", "Cloud Shadows", "Distance Clouds";
//           Wang 2003, "Realistic and Fast Cloud Rendering in Computer Games".
#define_import_path volfog::clouds

#import volfog::types::CloudLayer
#import volfog::phase::phase_hg
#import volfog::soft_particles::soft_particle_box_fade

// Below this sun height (sun_direction.y) clouds cast no shadow.
const CLOUD_MIN_SUN_HEIGHT: f32 = 0.01;
// View rays are cut at this distance (m): a ray grazing the slab crosses it far away.
const CLOUD_MAX_DISTANCE: f32 = 1e5;
// No clouds: no in-scattering, full transmittance.
const CLOUD_NONE: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, 1.0);

// Map coordinates of world (x, z), scrolled by the wind, wrapped into [0, 1): the
// repeat sampler gives the same value, and small coordinates keep the sampler's
// sub-texel precision far from the origin.
fn cloud_map_uv(layer: CloudLayer, xz: vec2<f32>) -> vec2<f32> {
    return fract((xz - layer.wind * layer.time) / max(layer.map_size, 1e-6));
}

// Map density in [0, 1] at world (x, z).
fn cloud_density(map: texture_2d<f32>, map_sampler: sampler, layer: CloudLayer, xz: vec2<f32>) -> f32 {
    return clamp(textureSampleLevel(map, map_sampler, cloud_map_uv(layer, xz), 0.0).r, 0.0, 1.0);
}

// Transmittance of the sun's light at world position p through the cloud layer.
fn cloud_shadow(map: texture_2d<f32>, map_sampler: sampler, layer: CloudLayer, p: vec3<f32>) -> f32 {
    let sun = layer.sun_direction;
    let middle = layer.base_height + 0.5 * layer.thickness;
    let rise = middle - p.y;
    if sun.y < CLOUD_MIN_SUN_HEIGHT || rise <= 0.0 {
        return 1.0;
    }
    let xz = p.xz + sun.xz * (min(rise, CLOUD_MAX_DISTANCE) / sun.y);
    let m = cloud_density(map, map_sampler, layer, xz);
    return exp(-min(layer.extinction * m * layer.thickness / sun.y, 80.0));
}

// Ray parameters [t0, t1] (m along the unit direction dir from eye) of the slab,
// cut to [0, min(max_distance, CLOUD_MAX_DISTANCE)]; t0 >= t1 when the ray misses it.
fn cloud_slab(layer: CloudLayer, eye: vec3<f32>, dir: vec3<f32>, max_distance: f32) -> vec2<f32> {
    let far = min(max_distance, CLOUD_MAX_DISTANCE);
    let bottom = layer.base_height;
    let top = layer.base_height + layer.thickness;
    if abs(dir.y) < 1e-6 {
        let inside = eye.y >= bottom && eye.y <= top;
        return select(vec2<f32>(1.0, 0.0), vec2<f32>(0.0, far), inside);
    }
    let ta = (bottom - eye.y) / dir.y;
    let tb = (top - eye.y) / dir.y;
    return vec2<f32>(clamp(min(ta, tb), 0.0, far), clamp(max(ta, tb), 0.0, far));
}

// Distance clouds along the unit view direction dir from eye, up to max_distance (m,
// the scene's distance along the ray): vec4(in-scatter rgb, transmittance).
fn distance_clouds(map: texture_2d<f32>, map_sampler: sampler, layer: CloudLayer,
                   eye: vec3<f32>, dir: vec3<f32>, max_distance: f32) -> vec4<f32> {
    let t = cloud_slab(layer, eye, dir, max_distance);
    if t.y <= t.x {
        return CLOUD_NONE;
    }
    let n = clamp(layer.view_samples, 1u, 64u);
    let m = clamp(layer.sun_samples, 1u, 64u);
    let sun = layer.sun_direction;
    let ds = (t.y - t.x) / f32(n);
    let lobe = phase_hg(clamp(dot(dir, sun), -1.0, 1.0), clamp(layer.g, -0.999, 0.999));
    let top = layer.base_height + layer.thickness;
    var transmittance = 1.0;
    var inscatter = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let p = eye + dir * (t.x + (f32(i) + 0.5) * ds);
        let sigma = layer.extinction * cloud_density(map, map_sampler, layer, p.xz);
        // Towards the sun, to the top of the slab.
        var sun_light = 0.0;
        if sun.y >= CLOUD_MIN_SUN_HEIGHT {
            let dl = min(max(top - p.y, 0.0) / sun.y, CLOUD_MAX_DISTANCE) / f32(m);
            var depth = 0.0;
            for (var j = 0u; j < m; j++) {
                let q = p + sun * ((f32(j) + 0.5) * dl);
                depth += layer.extinction * cloud_density(map, map_sampler, layer, q.xz) * dl;
            }
            sun_light = exp(-min(depth, 80.0));
        }
        let step_t = exp(-min(sigma * ds, 80.0));
        inscatter += transmittance * (1.0 - step_t) * (layer.sun_color * (sun_light * lobe) + layer.sky_color);
        transmittance *= step_t;
    }
    return vec4<f32>(inscatter, transmittance);
}

// The cloud layer lit per pixel along the unit view direction dir from eye, the scene
// max_distance (m) along the ray: vec4(in-scatter rgb, transmittance), soft-clipped
// where the slab passes behind the scene.
fn cloud_layer(map: texture_2d<f32>, map_sampler: sampler, layer: CloudLayer,
               eye: vec3<f32>, dir: vec3<f32>, max_distance: f32) -> vec4<f32> {
    let whole = cloud_slab(layer, eye, dir, CLOUD_MAX_DISTANCE);
    if whole.y <= whole.x {
        return CLOUD_NONE;
    }
    let fade = soft_particle_box_fade(whole.x, whole.y, max_distance);
    let t_mid = 0.5 * (whole.x + min(whole.y, max(max_distance, whole.x)));
    let p = eye + dir * t_mid;
    let m = cloud_density(map, map_sampler, layer, p.xz);
    // Gradient of the map (per metre) by central differences one texel apart.
    let texel = max(layer.map_size, 1e-6) / f32(textureDimensions(map).x);
    let gx = cloud_density(map, map_sampler, layer, p.xz + vec2<f32>(texel, 0.0))
        - cloud_density(map, map_sampler, layer, p.xz - vec2<f32>(texel, 0.0));
    let gz = cloud_density(map, map_sampler, layer, p.xz + vec2<f32>(0.0, texel))
        - cloud_density(map, map_sampler, layer, p.xz - vec2<f32>(0.0, texel));
    let grad = vec2<f32>(gx, gz) / (2.0 * texel);
    let normal = normalize(vec3<f32>(-grad.x * layer.thickness, 1.0, -grad.y * layer.thickness));
    let sun = layer.sun_direction;
    let diffuse = 0.5 + 0.5 * dot(normal, sun);
    let lobe = phase_hg(clamp(dot(dir, sun), -1.0, 1.0), clamp(layer.g, -0.999, 0.999));
    let rim = layer.rim * (1.0 - m) * (1.0 - m) * lobe;
    let color = layer.sun_color * (diffuse + rim) + layer.sky_color;
    let opacity = (1.0 - exp(-min(layer.extinction * m * (whole.y - whole.x), 80.0))) * fade;
    return vec4<f32>(color * opacity, 1.0 - opacity);
}
