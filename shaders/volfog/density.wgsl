// volfog::density — extinction and emission of the participating medium at a point.
//
// Use:      #import volfog::density::{height_density, local_volume_sample, medium_extinction, medium_shape}
// Defines:  none
// Units:    positions in metres (world space), extinction in 1/m, emission in radiance
//           per metre (W / (sr m^3)).
// Reference: Wronski 2014, "Density estimation and volume lighting": procedural Perlin
//           noise animated by wind times a vertical (exponential) attenuation; "Controllable
//           density": analytical volumetric shapes injected into the volume. The height
//           profile b e^(-c (h - h0)) is Wenzel 2007's global volumetric fog density.
#define_import_path volfog::density

#import volfog::types::{FogMedium, LocalVolume}
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

// Extinction (1/m) a local volume adds at a world position (negative clears fog).
fn local_volume_density(volume: LocalVolume, world: vec3<f32>) -> f32 {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    return volume.density * local_volume_weight(local, volume.shape, volume.edge);
}

// What a local volume adds at a world position: rgb the emitted radiance per metre
// (W / (sr m^3)), a the extinction (1/m, negative clears fog); one transform.
fn local_volume_sample(volume: LocalVolume, world: vec3<f32>) -> vec4<f32> {
    let local = (volume.local_from_world * vec4<f32>(world, 1.0)).xyz;
    let w = local_volume_weight(local, volume.shape, volume.edge);
    return vec4<f32>(volume.emission, volume.density) * w;
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
// [-1, 1] and a density-texture factor (1 without a texture); local volumes are added
// by the caller and the sum clamped with max(0, .).
fn medium_extinction(medium: FogMedium, world: vec3<f32>, noise: f32, texture_factor: f32) -> f32 {
    return medium.density * medium_shape(medium, world, noise, texture_factor);
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
