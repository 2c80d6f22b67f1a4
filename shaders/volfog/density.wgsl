// volfog::density — extinction and emission of the participating medium at a point.
//
// Use:      #import volfog::density::{height_density, local_volume_blend, medium_extinction, medium_shape}
// Defines:  none
// Units:    positions in metres (world space), extinction in 1/m, emission in radiance
//           per metre (W / (sr m^3)).
// Reference: Wronski 2014, "Density estimation and volume lighting": procedural Perlin
//           noise animated by wind times a vertical (exponential) attenuation; "Controllable
//           density": analytical volumetric shapes injected into the volume. The height
//           profile b e^(-c (h - h0)) is Wenzel 2007's global volumetric fog density.
#define_import_path volfog::density

#import volfog::types::{FogMedium, LocalVolume, FogSample}
#import volfog::height_fog::{height_fog_light_optical_depth, height_fog_optical_depth_below}

// Exponents are clamped to this magnitude so the density stays finite in f32.
const DENSITY_MAX_EXPONENT: f32 = 80.0;

// Exponential height profile b * exp(-c * (h - h0)) at height h (m along the up axis).
fn height_density(h: f32, b: f32, c: f32, h0: f32) -> f32 {
    return b * exp(clamp(-c * (h - h0), -DENSITY_MAX_EXPONENT, DENSITY_MAX_EXPONENT));
}

// Shape codes of LocalVolume.shape (those of FogVolume.shape; a local volume has no
// plane).
const LOCAL_VOLUME_BOX: u32 = 0u;
const LOCAL_VOLUME_ELLIPSOID: u32 = 1u;
const LOCAL_VOLUME_CYLINDER: u32 = 3u;
const LOCAL_VOLUME_CONE: u32 = 4u;

// Distance-like measure of a point in a local volume's unit shape space: below 1
// inside, 1 on the surface, above 1 outside; along a line from the shape's core it
// grows linearly, so a linear fade over an edge band keeps its width.
//   box [-1, 1]^3:      max(|x|, |y|, |z|)
//   unit sphere:        |p|
//   cylinder (3):       max(|y|, |xz|), radius 1 around the y axis, |y| <= 1
//   cone (4):           max(|y|, |xz| + (y + 1) / 2), apex at y = 1 and a base of
//                       radius 1 at y = -1 (|xz| + (y + 1) / 2 = 1 on its side)
fn local_volume_measure(local: vec3<f32>, shape: u32) -> f32 {
    let a = abs(local);
    let radial = length(local.xz);
    if shape == LOCAL_VOLUME_ELLIPSOID {
        return length(local);
    } else if shape == LOCAL_VOLUME_CYLINDER {
        return max(a.y, radial);
    } else if shape == LOCAL_VOLUME_CONE {
        return max(a.y, radial + 0.5 * (local.y + 1.0));
    }
    return max(a.x, max(a.y, a.z));
}

// Soft membership in [0, 1] of a point given in a local volume's unit shape space:
// 1 inside, falling linearly to 0 over `edge` (fraction of the unit extent) at the
// boundary of the shape (see local_volume_measure).
fn local_volume_weight(local: vec3<f32>, shape: u32, edge: f32) -> f32 {
    return clamp((1.0 - local_volume_measure(local, shape)) / max(edge, 1e-4), 0.0, 1.0);
}

// Extinction (1/m) an additive local volume adds at a world position (negative clears
// fog); its density times its edge weight, whatever its blend mode.
fn local_volume_density(volume: LocalVolume, world: vec3<f32>) -> f32 {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    return volume.density * local_volume_weight(local, volume.shape, volume.edge);
}

// What an additive local volume adds at a world position: rgb the emitted radiance per
// metre (W / (sr m^3)), a the extinction (1/m, negative clears fog); one transform. (Its
// value times its edge weight, whatever its blend mode: local_volume_blend applies
// the mode.)
fn local_volume_sample(volume: LocalVolume, world: vec3<f32>) -> vec4<f32> {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    let w = local_volume_weight(local, volume.shape, volume.edge);
    return vec4<f32>(volume.emission, volume.density) * w;
}

// Blend modes of LocalVolume.blend. The medium m (rgb the emission per metre, a the
// extinction) goes through the local volumes in buffer order, each changing it where it
// holds by its value v = (emission, density) (times the density-texture factor of a
// textured volume), channel by channel:
//   add        m + v                    (the default; a negative density clears fog,
//                                       the sum is clamped at 0 at the end)
//   subtract   max(m - v, 0)            (clears fog: Godot's negative density, clamped
//                                       at once, so a later volume adds fog again)
//   multiply   m * density              (scales the extinction and the emission alike;
//                                       the volume's own emission is 0)
//   min        min(m, v)                (caps the extinction at density, the emission
//                                       at emission)
//   max        max(m, v)                (raises them to at least density, emission)
//   overwrite  v                        (replaces the medium: HDRP's overwrite)
// The edge weight w in [0, 1] (local_volume_weight) fades each mode in:
// m' = m + w (blend(m, v) - m), so where w = 0 (outside the volume) nothing changes
// and a volume culled from a block changes nothing there.
const LOCAL_VOLUME_ADD: u32 = 0u;
const LOCAL_VOLUME_SUBTRACT: u32 = 1u;
const LOCAL_VOLUME_MULTIPLY: u32 = 2u;
const LOCAL_VOLUME_MIN: u32 = 3u;
const LOCAL_VOLUME_MAX: u32 = 4u;
const LOCAL_VOLUME_OVERWRITE: u32 = 5u;

// The change blend(m, v) - m a local volume makes to the medium m = prior (rgb
// emission per metre, a extinction) where it holds fully, for its value v = own (rgb
// emission, a density) and its blend mode (LOCAL_VOLUME_ADD ...; an unknown code adds).
fn local_volume_blend_delta(prior: vec4<f32>, own: vec4<f32>, blend: u32) -> vec4<f32> {
    switch blend {
        case LOCAL_VOLUME_SUBTRACT: {
            // max(m - v, 0) - m.
            return -min(own, prior);
        }
        case LOCAL_VOLUME_MULTIPLY: {
            return prior * (own.a - 1.0);
        }
        case LOCAL_VOLUME_MIN: {
            return min(own - prior, vec4<f32>(0.0));
        }
        case LOCAL_VOLUME_MAX: {
            return max(own - prior, vec4<f32>(0.0));
        }
        case LOCAL_VOLUME_OVERWRITE: {
            return own - prior;
        }
        default: {
            return own;
        }
    }
}

// The medium (rgb emission per metre, a extinction) after a local volume at a world
// position, given the medium before it (prior): its blend mode faded in by its edge
// weight (see LOCAL_VOLUME_ADD).
fn local_volume_blend(prior: vec4<f32>, volume: LocalVolume, world: vec3<f32>) -> vec4<f32> {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    let w = local_volume_weight(local, volume.shape, volume.edge);
    return prior + w * local_volume_blend_delta(prior, vec4<f32>(volume.emission, volume.density), volume.blend);
}

// local_volume_blend with the density texture: texture_factor (the texture's red
// channel at local_volume_texture_coord, clamped to >= 0) scales a textured volume's
// value (its density and emission, or its factor under multiply); an untextured
// volume ignores it.
fn local_volume_blend_textured(prior: vec4<f32>, volume: LocalVolume, world: vec3<f32>, texture_factor: f32) -> vec4<f32> {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    let w = local_volume_weight(local, volume.shape, volume.edge);
    let factor = select(1.0, max(texture_factor, 0.0), volume.textured != 0u);
    return prior + w * local_volume_blend_delta(prior, vec4<f32>(volume.emission, volume.density) * factor, volume.blend);
}

// Texture coordinate of the density texture in a local volume at a world position:
// the unit shape's extent [-1, 1]^3 mapped to [0, 1]^3, plus the volume's
// texture_offset (sample with repeat addressing; Bevy's FogVolume convention).
fn local_volume_texture_coord(volume: LocalVolume, world: vec3<f32>) -> vec3<f32> {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    return local * 0.5 + 0.5 + volume.texture_offset;
}

// local_volume_sample with the density texture: texture_factor (the texture's red
// channel at local_volume_texture_coord, clamped to >= 0) scales a textured volume's
// density and emission; an untextured volume ignores it.
fn local_volume_sample_textured(volume: LocalVolume, world: vec3<f32>, texture_factor: f32) -> vec4<f32> {
    let factor = select(1.0, max(texture_factor, 0.0), volume.textured != 0u);
    return local_volume_sample(volume, world) * factor;
}

// Whether a local volume can add extinction anywhere in the world-space sphere
// (center, radius) (m). Conservative: the sphere's image in unit shape space lies in a
// ball of radius `radius` times the Frobenius norm of the transform's linear part, which
// is tested against the box [-1, 1]^3 that holds every shape.
fn local_volume_touches_sphere(volume: LocalVolume, center: vec3<f32>, radius: f32) -> bool {
    let m = volume.local_from_world;
    let local = (m * vec4<f32>(center, 1.0)).xyz;
    let scale = sqrt(dot(m[0].xyz, m[0].xyz) + dot(m[1].xyz, m[1].xyz) + dot(m[2].xyz, m[2].xyz));
    let outside = max(abs(local) - vec3<f32>(1.0), vec3<f32>(0.0));
    return length(outside) <= radius * scale;
}

// Shape of the global medium at a world position, the factor its density and its
// emission are scaled by: the height profile exp(-c (h - h0)) (0 above the medium's
// top_height) times the noise
// modulation max(1 + strength * noise, 0) (noise in [-1, 1]) times a density-texture
// factor (1 without a texture).
fn medium_shape(medium: FogMedium, world: vec3<f32>, noise: f32, texture_factor: f32) -> f32 {
    let h = dot(world, medium.up);
    let profile = select(height_density(h, 1.0, medium.height_falloff, medium.base_height), 0.0, h > medium.top_height);
    let modulation = max(1.0 + medium.noise_strength * noise, 0.0);
    return profile * modulation * max(texture_factor, 0.0);
}

// Global extinction (1/m) at a world position, given the medium, a noise value in
// [-1, 1] and a density-texture factor (1 without a texture); the caller blends the
// local volumes in (local_volume_blend) and clamps the result with max(0, .).
fn medium_extinction(medium: FogMedium, world: vec3<f32>, noise: f32, texture_factor: f32) -> f32 {
    return medium.density * medium_shape(medium, world, noise, texture_factor);
}

// The largest extinction (1/m) and emission per channel (W / (sr m^3)) a custom
// density's FogSample may give (volfog::limits::LOCAL_VOLUME_DENSITY's and EMISSION's
// maxima).
const FOG_SAMPLE_MAX_EXTINCTION: f32 = 1e3;
const FOG_SAMPLE_MAX_EMISSION: f32 = 1e6;

// x where it is above 0 (at most max_value), else 0: a negative value, and NaN where
// comparisons follow IEEE, read 0; +Inf reads max_value.
fn fog_sample_channel(x: f32, max_value: f32) -> f32 {
    return select(0.0, min(x, max_value), x > 0.0);
}

// A custom density's sample brought into range, channel by channel
// (fog_sample_channel): extinction in [0, 1e3], albedo in [0, 1], emission in [0, 1e6],
// so a function that returns nonsense cannot put NaN or Inf in the volume.
fn fog_sample_clamped(s: FogSample) -> FogSample {
    let a = s.albedo;
    let e = s.emission;
    let m = FOG_SAMPLE_MAX_EMISSION;
    return FogSample(
        vec3<f32>(fog_sample_channel(a.x, 1.0), fog_sample_channel(a.y, 1.0), fog_sample_channel(a.z, 1.0)),
        fog_sample_channel(s.extinction, FOG_SAMPLE_MAX_EXTINCTION),
        vec3<f32>(fog_sample_channel(e.x, m), fog_sample_channel(e.y, m), fog_sample_channel(e.z, m)),
    );
}

// The medium (rgb emission per metre, a extinction) with a custom density's sample
// (clamped: fog_sample_clamped) added to it: the two media superpose.
fn medium_with_sample(prior: vec4<f32>, s: FogSample) -> vec4<f32> {
    let c = fog_sample_clamped(s);
    return prior + vec4<f32>(c.emission, c.extinction);
}

// The albedo of the medium prior (of extinction prior.a, albedo `albedo`) with a custom
// density's sample (clamped) added: the mean of the two albedos weighted by their
// extinctions (sigma_s of the sum over its sigma_t); the medium's albedo where both are
// 0. Local volumes blended in afterwards keep it (sigma_s = albedo * sigma_t).
fn albedo_with_sample(prior: vec4<f32>, albedo: vec3<f32>, s: FogSample) -> vec3<f32> {
    let c = fog_sample_clamped(s);
    let own = max(prior.a, 0.0);
    let total = own + c.extinction;
    if total <= 0.0 {
        return albedo;
    }
    return (albedo * own + c.albedo * c.extinction) / total;
}

// Transmittance in (0, 1] of the medium's height profile (density, height falloff,
// base height, top; no noise, density texture or local volume) from a world position
// towards a light infinitely far along the unit direction towards (the sun): its light
// enters the medium at the top (volfog::height_fog::height_fog_light_optical_depth).
fn medium_light_transmittance(medium: FogMedium, world: vec3<f32>, towards: vec3<f32>) -> f32 {
    return exp(-height_fog_light_optical_depth(medium.density, medium.height_falloff,
        medium.base_height, medium.up, medium.top_height, world, towards));
}

// Transmittance in (0, 1] of the medium's height profile along the segment from a
// world position to a light's position (m): the closed form of the view-ray fog
// (volfog::height_fog::height_fog_optical_depth_below).
fn medium_segment_transmittance(medium: FogMedium, world: vec3<f32>, light: vec3<f32>) -> f32 {
    return exp(-height_fog_optical_depth_below(medium.density, medium.height_falloff,
        medium.base_height, medium.up, medium.top_height, world, light - world));
}
