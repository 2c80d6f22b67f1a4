// volfog::apply — fog from the integrated volume for any shaded point: forward
// shaders, transparent layers and the fullscreen apply pass.
//
// Use:      #import volfog::apply::{fog_coord_from_view, fog_sample, fog_tail, fog_with_tail, apply_fog}
//           let fog = fog_sample(volume, volume_sampler, fog_coord_from_view(p, froxels));
//           color = apply_fog(color, fog_with_tail(fog, fog_tail(froxels, tail, p)));
//           From a world position w: p = fog_view_position(w, view_from_world), or
//           fog_coord_from_world(w, view_from_world, froxels).
// Defines:  none (the bindings live in volfog::bindings).
// Data:     the integrated volume (the scan pass output) holds, in texel (x, y, k), the
//           in-scattered radiance (rgb) and transmittance (a) from the near plane to the
//           back of slice k. A fog coordinate is a vec4: xyz the texture coordinate to
//           sample, w the weight of that sample against "no fog" (below 1 only in front
//           of the first slice's back face, where fog fades in linearly from the near
//           plane). Depth is interpolated linearly between slice backs, xy bilinearly:
//           the quadrilinear look-up of Wronski 2014, "Applying effect".
//           Beyond the far plane the volume holds its value at far; the analytic
//           height-fog tail (fog_tail, a HeightFog given in VIEW space) continues the
//           fog from the far plane to the shaded point, so distant geometry has no
//           hard fog edge. At the far plane the tail is empty, so the result is
//           continuous there.
// Reference: Wronski 2014, "Applying effect": color * transmittance + in-scattering;
//           Wenzel 2007, eq. 2, for the tail.
#define_import_path volfog::apply

#import volfog::types::{Froxels, HeightFog}
#import volfog::froxel::{slice_coord, uv_from_ndc, view_from_ndc}
#import volfog::height_fog::height_fog

// Fog coordinate of the point at screen uv (v down) and view depth depth (m).
// Depths beyond far read the value at far.
fn fog_coord(uv: vec2<f32>, depth: f32, froxels: Froxels) -> vec4<f32> {
    let n = f32(froxels.size.z);
    let slices = slice_coord(depth, froxels.near, froxels.far, froxels.curve) * n;
    // The back of slice k sits at slices = k + 1, stored at the texel centre (k + 0.5) / n.
    let w = clamp((slices - 0.5) / n, 0.5 / n, 1.0 - 0.5 / n);
    return vec4<f32>(uv, w, clamp(slices, 0.0, 1.0));
}

// Fog coordinate of a view-space position (m).
fn fog_coord_from_view(view_pos: vec3<f32>, froxels: Froxels) -> vec4<f32> {
    let clip = froxels.clip_from_view * vec4<f32>(view_pos, 1.0);
    let ndc = clip.xy / select(clip.w, 1e-30, abs(clip.w) < 1e-30);
    return fog_coord(uv_from_ndc(ndc), abs(view_pos.z), froxels);
}

// View-space position (m) of a world-space position (m), with the camera's
// world -> view transform (FogView.view_from_world).
fn fog_view_position(world_pos: vec3<f32>, view_from_world: mat4x4<f32>) -> vec3<f32> {
    return (view_from_world * vec4<f32>(world_pos, 1.0)).xyz;
}

// Fog coordinate of a world-space position (m).
fn fog_coord_from_world(world_pos: vec3<f32>, view_from_world: mat4x4<f32>, froxels: Froxels) -> vec4<f32> {
    return fog_coord_from_view(fog_view_position(world_pos, view_from_world), froxels);
}

// Fog coordinate of a point in normalised device coordinates: x, y in [-1, 1] (y up)
// and the depth-buffer value (standard, reversed or infinite projections).
fn fog_coord_from_ndc(ndc: vec3<f32>, froxels: Froxels) -> vec4<f32> {
    let view = view_from_ndc(ndc, froxels.view_from_clip);
    return fog_coord(uv_from_ndc(ndc.xy), abs(view.z), froxels);
}

// Fog (rgb in-scatter, a transmittance) at a fog coordinate, filtered by the sampler
// (use linear filtering, clamp-to-edge addressing).
fn fog_sample(volume: texture_3d<f32>, volume_sampler: sampler, coord: vec4<f32>) -> vec4<f32> {
    let fog = textureSampleLevel(volume, volume_sampler, coord.xyz, 0.0);
    return mix(vec4<f32>(0.0, 0.0, 0.0, 1.0), fog, coord.w);
}

// Fog at a fog coordinate without a sampler: eight texel loads filtered trilinearly in
// the shader, clamp-to-edge (same result as fog_sample with a linear sampler).
fn fog_load(volume: texture_3d<f32>, coord: vec4<f32>) -> vec4<f32> {
    let size = vec3<i32>(textureDimensions(volume));
    let texel = coord.xyz * vec3<f32>(size) - 0.5;
    let base = floor(texel);
    let f = texel - base;
    let lo = clamp(vec3<i32>(base), vec3<i32>(0), size - 1);
    let hi = clamp(vec3<i32>(base) + 1, vec3<i32>(0), size - 1);
    let c000 = textureLoad(volume, vec3<i32>(lo.x, lo.y, lo.z), 0);
    let c100 = textureLoad(volume, vec3<i32>(hi.x, lo.y, lo.z), 0);
    let c010 = textureLoad(volume, vec3<i32>(lo.x, hi.y, lo.z), 0);
    let c110 = textureLoad(volume, vec3<i32>(hi.x, hi.y, lo.z), 0);
    let c001 = textureLoad(volume, vec3<i32>(lo.x, lo.y, hi.z), 0);
    let c101 = textureLoad(volume, vec3<i32>(hi.x, lo.y, hi.z), 0);
    let c011 = textureLoad(volume, vec3<i32>(lo.x, hi.y, hi.z), 0);
    let c111 = textureLoad(volume, vec3<i32>(hi.x, hi.y, hi.z), 0);
    let y0 = mix(mix(c000, c100, f.x), mix(c010, c110, f.x), f.y);
    let y1 = mix(mix(c001, c101, f.x), mix(c011, c111, f.x), f.y);
    return mix(vec4<f32>(0.0, 0.0, 0.0, 1.0), mix(y0, y1, f.z), coord.w);
}

// Analytic fog between the far plane and a view-space position (m) beyond it, with
// the height fog given in view space; no fog (0, 0, 0, 1) for points within the volume.
fn fog_tail(froxels: Froxels, tail: HeightFog, view_pos: vec3<f32>) -> vec4<f32> {
    let depth = abs(view_pos.z);
    if depth <= froxels.far {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let start = view_pos * (froxels.far / depth);
    return height_fog(tail, start, view_pos - start);
}

// The volume's fog followed by the fog behind it (the tail): in-scatter of the tail
// attenuated by the volume, transmittances multiplied.
fn fog_with_tail(fog: vec4<f32>, tail: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(fog.rgb + fog.a * tail.rgb, fog.a * tail.a);
}

// A lit colour seen through fog: color * transmittance + in-scattering.
fn apply_fog(color: vec3<f32>, fog: vec4<f32>) -> vec3<f32> {
    return color * fog.a + fog.rgb;
}
