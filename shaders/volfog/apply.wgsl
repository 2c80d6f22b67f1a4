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
//           continuous there. fog_tail_shafts is the same tail with the sun's light
//           shadowed by the epipolar pass (volfog::epipolar, the far field).
// MSAA:     a resolved depth buffer averages the depths of a silhouette's samples, and
//           fog looked up at that average draws an outline around objects. Following
//           Wenzel 2007 ("Scene depth based rendering and MSAA: Fog"), the pass that
//           lays out depth also writes each sample's fog amount, fog_layout = vec2(view
//           depth, 1 - T), into a two-channel multisampled target (rg16float) whose
//           resolve averages both; the fullscreen pass then takes the fog's colour at
//           the resolved depth and the amount from the resolve (fog_resolved). The fog
//           colour changes slowly across a silhouette, the amount does not.
// Reference: Wronski 2014, "Applying effect": color * transmittance + in-scattering;
//           Wenzel 2007, eq. 2, for the tail.
#define_import_path volfog::apply

#import volfog::types::{Froxels, HeightFog}
#import volfog::froxel::{ndc_from_uv, slice_coord, uv_from_ndc, view_from_ndc}
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

// View-space position (m) of the point at screen uv (v down) and view depth depth (m),
// for a perspective projection with inverse view_from_clip.
fn fog_view_from_depth(uv: vec2<f32>, depth: f32, view_from_clip: mat4x4<f32>) -> vec3<f32> {
    // Any depth strictly inside the clip volume lies on the ray; 0.5 stays finite for
    // standard, reversed and infinite projections.
    let p = view_from_ndc(vec3<f32>(ndc_from_uv(uv), 0.5), view_from_clip);
    return p * (depth / max(abs(p.z), 1e-30));
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

// fog_tail with the sun's light shadowed: the far field of epipolar sun shafts
// (volfog::epipolar). shafts is the lit fraction F in [0, 1] per colour channel, the
// shaft texture's rgb at the pixel (marched in the same HeightFog, view space, from the far plane
// to the point): the tail's constant colour fills the whole segment, its sun lobe the
// fraction F of it: vec4((color + sun_color * HG * F) * (1 - T), T). F = 1 (nothing
// shadows) gives fog_tail exactly; at the far plane both are empty.
fn fog_tail_shafts(froxels: Froxels, tail: HeightFog, view_pos: vec3<f32>, shafts: vec3<f32>) -> vec4<f32> {
    var shadowed = tail;
    shadowed.sun_color = tail.sun_color * clamp(shafts, vec3<f32>(0.0), vec3<f32>(1.0));
    return fog_tail(froxels, shadowed, view_pos);
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

// Below this fog amount (1 - T) at the resolved depth, fog_resolved keeps the colour
// of this amount (the in-scatter of thinner fog is mostly rounding).
const FOG_RESOLVED_MIN_AMOUNT: f32 = 1e-4;

// The layout of one sample for the MSAA path: vec2(its view depth in m, the fog
// amount 1 - T of the sample's fog). Write it to a two-channel multisampled target
// while laying out depth and let the resolve average it; the resolved r channel is
// also the linear depth volfog::water::water_scene_depth reads.
fn fog_layout(fog: vec4<f32>, view_depth: f32) -> vec2<f32> {
    return vec2<f32>(view_depth, 1.0 - fog.a);
}

// Fog of a pixel from its resolved layout: fog is the fog at the resolved view depth,
// amount the resolved fog amount. The colour (in-scatter per unit amount) comes from
// fog, the amount from the resolve: vec4(fog.rgb * amount / (1 - fog.a), 1 - amount).
// Where no silhouette crosses the pixel this is fog itself.
fn fog_resolved(fog: vec4<f32>, amount: f32) -> vec4<f32> {
    let a = clamp(amount, 0.0, 1.0);
    let scale = a / max(1.0 - fog.a, FOG_RESOLVED_MIN_AMOUNT);
    return vec4<f32>(fog.rgb * scale, 1.0 - a);
}
