// volfog::types — uniform structures shared by the passes and the forward snippet.
//
// Use:      #import volfog::types::Froxels
// Defines:  none
// Layout:   every struct here has a Rust twin in `volfog::uniforms` (encase); a test
//           compares their member offsets and sizes with naga's layout.
// Units:    metres, view space right-handed (camera looks down -Z), clip space as in
//           WebGPU (x, y in [-1, 1] with y up, depth in [0, 1]).
#define_import_path volfog::types

// Placement of a camera-aligned froxel volume (Wronski 2014, "Volume texture layout").
// x and y follow the screen (uv in [0, 1], v down), z follows view depth through the
// slice distribution of volfog::froxel.
struct Froxels {
    // Projection of the camera the volume is aligned with (view -> clip).
    clip_from_view: mat4x4<f32>,
    // Inverse of clip_from_view (clip -> view).
    view_from_clip: mat4x4<f32>,
    // Volume size in froxels: screen x, screen y, depth slices; each >= 1.
    size: vec3<u32>,
    // View depth of the front of the first slice, metres, > 0.
    near: f32,
    // View depth of the back of the last slice, metres, > near.
    far: f32,
    // Slice distribution curve, >= 0: 0 gives equal thickness, ln(far / near) gives a
    // constant thickness-to-depth ratio (exponential slices).
    curve: f32,
}

// Per-frame camera and temporal state of the froxel pipeline.
struct FogFrame {
    // View -> world transform of the current camera.
    world_from_view: mat4x4<f32>,
    // World -> clip (projection * view) of the current camera; the temporal pass
    // records it with the history it writes.
    clip_from_world: mat4x4<f32>,
    // Camera position in world space (m).
    camera_position: vec3<f32>,
    // Seconds since start, drives noise animation and density scrolling.
    time: f32,
    // Sample offset inside each froxel this frame, froxel units in [-0.5, 0.5]^3
    // (a Halton 2, 3, 5 sequence; used when VOLFOG_INJECT_JITTER is set).
    jitter: vec3<f32>,
    // Weight of the reprojected history in [0, 1) (0.9 by default).
    history_weight: f32,
    // Frames prepared before this one.
    index: u32,
    // 0 to ignore the history this frame (after a camera cut), else 1.
    history_enabled: u32,
    // 1 to amortise injection over two frames: inject writes only the froxels of one
    // colour of a 3D checkerboard (volfog::froxel::froxel_injected) and temporal fills
    // the others from the history; 0 to inject every froxel.
    checkerboard: u32,
}

// What a history volume holds, written by the temporal pass beside the volume it
// stabilises (so reprojection always uses the camera the history was rendered with,
// whichever frames were submitted). Zeroed memory reads as "no history".
struct HistoryState {
    // World -> clip of the frame whose volume it is.
    clip_from_world: mat4x4<f32>,
    // 1 once a volume was written, 0 before.
    valid: u32,
}

// The participating medium (Wronski 2014, "Density estimation and volume lighting").
// Extinction sigma_t(p) = density * exp(-height_falloff * (dot(p, up) - base_height))
//                         * (1 + noise_strength * noise(p)) + local volumes, clamped >= 0;
// scattering sigma_s = albedo * sigma_t.
struct FogMedium {
    // Single-scattering albedo sigma_s / sigma_t per channel, [0, 1].
    albedo: vec3<f32>,
    // Extinction at base_height (1/m), >= 0.
    density: f32,
    // Unit up axis of the height gradient.
    up: vec3<f32>,
    // Height falloff c (1/m), >= 0; 0 disables the gradient.
    height_falloff: f32,
    // Wind velocity (m/s) that advects the noise and the density texture.
    wind: vec3<f32>,
    // Height (m along up) where the extinction equals density.
    base_height: f32,
    // World -> density texture coordinate scale (1/m), VOLFOG_INJECT_DENSITY_TEXTURE only.
    texture_scale: vec3<f32>,
    // Noise amplitude in [0, 1]: the density is modulated by 1 + strength * noise.
    noise_strength: f32,
    // Density texture coordinate offset, VOLFOG_INJECT_DENSITY_TEXTURE only.
    texture_offset: vec3<f32>,
    // Noise frequency (1/m), > 0.
    noise_scale: f32,
    // Henyey-Greenstein mean cosine of the medium, (-1, 1).
    phase_g: f32,
    // Number of local volumes in the local volume buffer.
    local_volume_count: u32,
    // Radiance the medium emits per metre of path (linear rgb, W / (sr m^3)) where its
    // extinction equals density; it follows the extinction's shape (height profile,
    // noise, density texture) and is integrated by the scan with the in-scattering.
    // [0, 1e6]; 0 for a medium that only scatters.
    emission: vec3<f32>,
    // Height (m along up) where the medium ends: its extinction and emission are 0
    // above it, and light from the sun enters the medium there
    // (volfog::height_fog::height_fog_light_optical_depth). 1e9 for a medium without
    // a top.
    top_height: f32,
    // 1: the density texture scales the medium in world space, at
    // world * texture_scale + texture_offset (VOLFOG_INJECT_DENSITY_TEXTURE only);
    // 0: it does not (the texture then only shapes the textured local volumes).
    textured: u32,
    // Number of particles in inject's particle buffer (VOLFOG_INJECT_PARTICLES only;
    // set by the runtime, 0 elsewhere).
    particle_count: u32,
}

// A local fog volume blended into the medium (added, subtracted, multiplied, min,
// max or overwritten; see volfog::density::local_volume_blend): a box, ellipsoid,
// cylinder or cone with an arbitrary transform and a soft edge, which may glow.
struct LocalVolume {
    // World -> unit shape space: the box [-1, 1]^3, the unit sphere, the cylinder of
    // radius 1 around the y axis for |y| <= 1, or the cone with its apex at y = 1 and a
    // base of radius 1 at y = -1 (see volfog::density::local_volume_weight).
    local_from_world: mat4x4<f32>,
    // Radiance emitted per metre of path inside (linear rgb, W / (sr m^3)), faded with
    // the edge like the density, [0, 1e6].
    emission: vec3<f32>,
    // The volume's extinction inside (1/m), which its blend combines with the medium's:
    // added (negative values clear fog), subtracted, the min, the max or the value
    // itself; under LOCAL_VOLUME_MULTIPLY the factor that scales the medium's
    // extinction and emission.
    density: f32,
    // Width of the edge falloff as a fraction of the unit extent, (0, 1].
    edge: f32,
    // 0 box, 1 ellipsoid, 3 cylinder, 4 cone (the codes of FogVolume.shape).
    shape: u32,
    // How the volume combines with the medium before it (the global medium, then the
    // volumes before it in the buffer): 0 add, 1 subtract, 2 multiply, 3 min, 4 max,
    // 5 overwrite (volfog::density::LOCAL_VOLUME_ADD ...).
    blend: u32,
    // Added to the density texture's coordinate in this volume (texture units: the unit
    // shape's extent spans [0, 1]); move it to scroll the pattern through the volume.
    texture_offset: vec3<f32>,
    // 1: the volume's density and emission are multiplied by the density texture's red
    // channel at volfog::density::local_volume_texture_coord (in passes that read a
    // density texture, e.g. inject@VOLFOG_INJECT_DENSITY_TEXTURE); 0: they are not.
    textured: u32,
}

// What a custom density function (VOLFOG_INJECT_CUSTOM_DENSITY: the user's
// `fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) ->
// FogSample`) gives at a point: a medium of its own, added to the global medium before
// the local volumes blend (volfog::density::medium_with_sample).
struct FogSample {
    // Single-scattering albedo per channel, [0, 1].
    albedo: vec3<f32>,
    // Extinction (1/m), [0, 1e3].
    extinction: f32,
    // Radiance emitted per metre of path (linear rgb, W / (sr m^3)), [0, 1e6].
    emission: vec3<f32>,
}

// The parameters of a custom density function: eight vec4 the application sets each
// frame (FrameInputs::custom_params), read by the function as it pleases (inject's
// binding 31 under VOLFOG_INJECT_CUSTOM_DENSITY).
struct FogCustomParams {
    values: array<vec4<f32>, 8>,
}

// The main directional light (sun or moon).
struct DirectionalLight {
    // Unit direction from the scene towards the light.
    direction: vec3<f32>,
    // Multiplier of this light's contribution to the fog, >= 0 ("affects fog").
    fog_intensity: f32,
    // Illuminance colour (linear rgb) reaching the medium when unshadowed.
    color: vec3<f32>,
    // Two-colour phase (AC4, VOLFOG_INJECT_TWO_COLOR_PHASE): tint looking towards the light.
    toward_tint: vec3<f32>,
    // Two-colour phase: tint looking away from the light.
    away_tint: vec3<f32>,
}

// A point, spot or directional light affecting the fog (storage buffer element).
struct FogLight {
    // World position (m).
    position: vec3<f32>,
    // Range (m) beyond which the light has no effect, > 0.
    range: f32,
    // Intensity colour (linear rgb): illuminance at 1 m is color / 1 m^2.
    color: vec3<f32>,
    // Multiplier of this light's contribution to the fog, >= 0.
    fog_intensity: f32,
    // Spot axis (unit, pointing away from the light); for a directional light the way
    // its light travels; ignored for point lights.
    direction: vec3<f32>,
    // Source radius (m), > 0: the inverse square law is clamped at this distance.
    radius: f32,
    // Cosine of the spot's outer half-angle; <= -1 for a point light.
    cos_outer: f32,
    // Cosine of the spot's inner half-angle (full intensity inside), >= cos_outer.
    cos_inner: f32,
    // Index of the light's LightProjection (its shadow and cookie) in the projection
    // buffer of inject@INJECT_LOCAL_SHADOWS, or 0xffffffff (LOCAL_SHADOW_NONE): none.
    projection: u32,
    // Bits of volfog::lights: FOG_LIGHT_DIRECTIONAL (a light at infinity: colour is its
    // illuminance, position, range, radius and cone are ignored), FOG_LIGHT_SPOT_SQUARED
    // (Filament's squared linear cone falloff instead of the smoothstep); 0 for none.
    flags: u32,
}

// Placement of the medium-shadow volume (volfog::medium_shadow; Wronski 2014's
// extension list, Frostbite's volumetric shadow map): a box aligned with the sun, its
// texels x and y across the sunlight and z along it, from the side facing the sun
// (w = 0) to the far side (w = 1). Texel (i, j, k) holds at its centre, in r, the
// optical depth (dimensionless) from the box's sun-side face to it of the medium's
// extinction beyond the height profile (noise, density texture, custom density, local
// volumes: what medium_light_transmittance leaves out) and, in g, that excess
// extinction itself (1/m, negative where the medium is thinner than its profile).
struct MediumShadow {
    // World -> volume coordinate uvw in [0, 1]^3 (affine).
    volume_from_world: mat4x4<f32>,
    // Volume coordinate -> world (the inverse).
    world_from_volume: mat4x4<f32>,
    // Texels per axis, each 2..=512.
    size: vec3<u32>,
    // Length (m) of one texel along the sunlight (the box's depth / size.z), > 0.
    step: f32,
    // Midpoint samples of the march towards a point, spot or directional light, 1..=64.
    march_steps: u32,
    // Length (m) marched towards a directional light (the box's diagonal), > 0.
    march_length: f32,
}

// A rectangle or disk (ellipse) emitter lighting the fog, its in-scattering integrated
// over its area (volfog::area_lights). One-sided: it emits on the side of
// cross(axis_x, axis_y). Storage-buffer element, 80-byte stride.
struct AreaLight {
    // Centre of the emitter (m).
    center: vec3<f32>,
    // AREA_LIGHT_RECT (0) or AREA_LIGHT_DISK (1) of volfog::area_lights.
    shape: u32,
    // Unit axis in the emitter's plane: the rectangle's width, the disk's first semi-axis.
    axis_x: vec3<f32>,
    // Half the rectangle's width along axis_x, or the disk's radius along it (m), > 0.
    half_x: f32,
    // Unit axis in the emitter's plane, orthogonal to axis_x.
    axis_y: vec3<f32>,
    // Half the rectangle's height along axis_y, or the disk's radius along it (m), > 0.
    half_y: f32,
    // Emitted radiance, W / (m^2 sr) per channel, >= 0.
    radiance: vec3<f32>,
    // Contribution to the fog, >= 0.
    fog_intensity: f32,
    // Range (m) from the centre: a smooth window saturate(1 - (d / range)^4)^2 as for
    // point lights; 0 marks an unused slot (it touches nothing).
    range: f32,
}

// A particle in the fog (volfog::particles): a sphere of smoke, dust or glowing gas
// whose extinction and emission fall off from its centre, added to the medium after
// the local volumes. Storage-buffer element, 48-byte stride.
struct FogParticle {
    // Centre (m, world space), finite.
    position: vec3<f32>,
    // Radius R (m), > 0: nothing beyond it.
    radius: f32,
    // Single-scattering albedo per channel, [0, 1].
    albedo: vec3<f32>,
    // Extinction at the centre (1/m), [0, 1e3].
    extinction: f32,
    // Radiance emitted per metre of path at the centre (linear rgb, W / (sr m^3)),
    // [0, 1e6]; it follows the extinction's profile.
    emission: vec3<f32>,
    // Falloff f in [0, 1]: the profile (1 - f) + f (1 - r^2 / R^2)^2 for r < R, from a
    // uniform sphere (0) to a smooth one (1) whose density and slope vanish at R.
    falloff: f32,
}

// The projection of a point or spot light (volfog::local_shadow): its exponential
// shadow map in the local-light ESM atlas and, for a spot light, its cookie.
struct LightProjection {
    // World -> light space. A spot light: the clip space of its shadow camera (a
    // perspective projection times its view; x, y and w are used, w being the depth
    // along the spot's axis in m). A point light: the space of its cube shadow map
    // (rigid; the light at the origin, the axes those of the cube's faces).
    light_from_world: mat4x4<f32>,
    // Distance (m) the atlas's linear depths are divided by (the shadow's far plane),
    // > 0: depths along the light's axis (spot) or the face's axis (point) in
    // [0, depth_range] map to [0, 1].
    depth_range: f32,
    // ESM exponent applied to linear depths in [0, 1]; <= 88 unless the atlas holds
    // log-space values (VOLFOG_ESM_LOG_SPACE).
    exponent: f32,
    // Receivers are tested this far (m) nearer the light, >= 0 (against acne where
    // the medium meets the shadow caster).
    bias: f32,
    // 0 spot light (one atlas layer), 1 point light (six layers: the cube's faces
    // +X, -X, +Y, -Y, +Z, -Z).
    kind: u32,
    // The light's first atlas layer, or 0xffffffff (LOCAL_SHADOW_NONE): unshadowed.
    layer: u32,
    // Layer of the cookie array that a spot light projects, or 0xffffffff: none.
    cookie: u32,
    // View depth (m) of a depth value d of the light's shadow maps: -(x d + y) / (z d + w),
    // the depth rows of the inverse of its shadow camera's projection (standard,
    // reversed or infinite depth; LocalShadowSource.depth_terms). The compare filter
    // (VOLFOG_INJECT_SHADOW_COMPARE) maps receivers into the maps' depth with it.
    depth_terms: vec4<f32>,
}

// One map of the local-light ESM atlas, filled from a shadow depth map by the
// local_shadow_downsample pass.
struct LocalShadowSource {
    // View depth (m) of a depth value d: -(x d + y) / (z d + w), the depth rows of the
    // inverse of the shadow camera's projection (standard, reversed or infinite depth).
    depth_terms: vec4<f32>,
    // Distance (m) the linear depth is divided by, > 0 (LightProjection.depth_range).
    depth_range: f32,
    // ESM exponent (LightProjection.exponent).
    exponent: f32,
    // Layer of the source depth array to read.
    source_layer: u32,
    // Atlas layer to write.
    atlas_layer: u32,
    // Which depth array: 0 the spot lights' shadow maps, 1 the point lights' cube maps
    // (six layers a cube).
    source: u32,
}

// Lighting of the medium: the sun, ambient light as L1 SH and the local light count.
struct FogLighting {
    sun: DirectionalLight,
    // L1 SH of the incoming ambient radiance per channel (order Y00, Y1-1, Y10, Y11);
    // a constant ambient radiance a has only the first coefficient, a * sqrt(4 pi).
    ambient_r: vec4<f32>,
    ambient_g: vec4<f32>,
    ambient_b: vec4<f32>,
    // Number of valid entries in the light buffer.
    light_count: u32,
    // 1: the light reaching a froxel is attenuated by the medium's height profile
    // between the froxel and the light (the sun: up to the medium's top; point and spot
    // lights: along the segment to the light); 0: lights reach every froxel
    // unattenuated. Noise, density textures and local volumes are not on these paths.
    transmittance: u32,
}

// Cascaded shadow maps of the directional light and their exponential shadow maps.
struct ShadowCascades {
    // World -> light clip space of each cascade (x, y in [-1, 1], depth in [0, 1]).
    light_from_world: array<mat4x4<f32>, 4>,
    // Far view depth (m) of each cascade; a froxel uses the first cascade whose split
    // exceeds its depth.
    splits: vec4<f32>,
    // Number of cascades in use, 1..=4 (0: no shadows).
    count: u32,
    // ESM exponent c applied to depths in [0, 1]; c <= 88 keeps exp(c) finite in f32
    // (larger values need VOLFOG_ESM_LOG_SPACE).
    exponent: f32,
}

// Where the shadow filter of the fog tests the lights' visibility within a froxel this
// frame (VOLFOG_INJECT_SHADOW_COMPARE): depth compares against the full-resolution shadow
// maps at `count` points spread over the froxel (`fresh` where the froxel has no
// history), which the temporal blend accumulates into the visibility averaged over the
// froxel's volume.
struct ShadowTaps {
    // Offsets from the froxel's centre in froxel units, xyz in [-0.5, 0.5) (w unused).
    // Tap 0 is the froxel's own sample (FogFrame.jitter); tap t is it moved by t times
    // the R3 low-discrepancy step (modulo the froxel), so each tap cycles through the
    // froxel over the frames and the taps of one frame spread over it.
    offsets: array<vec4<f32>, 16>,
    // The world-space view ray of a screen position per metre of view depth, affine in
    // its normalised device coordinates (a perspective projection's rays are):
    // ray_origin + ray_x * ndc.x + ray_y * ndc.y. A tap lies at the camera plus its
    // ray times its view depth, so the taps need no matrix.
    ray_origin: vec3<f32>,
    // Taps of a froxel, 1..=16: FogConfig's taps (1..=4) with temporal reprojection,
    // `fresh` without it.
    count: u32,
    // d ray / d ndc.x (per metre of view depth).
    ray_x: vec3<f32>,
    // Taps of a froxel whose history the fused temporal blend (VOLFOG_INJECT_TEMPORAL)
    // does not find (the first frame, disocclusions), count..=16.
    fresh: u32,
    // d ray / d ndc.y (per metre of view depth).
    ray_y: vec3<f32>,
    // 1: the sun's shadow map holds reversed depth (1 at the light's near plane); the
    // cascades' light_from_world still give standard depth.
    sun_reversed_z: u32,
    // The camera's depth terms: view depth (m) of a scene-depth value d is
    // -(x d + y) / (z d + w) (FrustumRays.depth_terms).
    camera_depth_terms: vec4<f32>,
    // 1: the scene's depth is bound (with depth culling), and the taps of each froxel
    // are moved into its part in front of the opaque surface that depth holds at their
    // screen position (volfog::shadow::shadow_tap_visible_depth: the fog the camera
    // sees ends at that surface; a tap inside an object would read the object's own
    // shadow). 0: the taps stay where they are.
    use_scene_depth: u32,
}

// The short-lived lights of a frame (VOLFOG_SCAN_TRANSIENT_LIGHTS of the scan): point,
// spot and directional lights that light only the frame they are in (a muzzle flash, a
// lightning strike). The scan adds their in-scattering to every live froxel of the
// volume it integrates, after the temporal blend, so none of it reaches the history.
struct TransientLighting {
    // Camera position in world space (m).
    camera_position: vec3<f32>,
    // Number of valid entries in the transient light buffer.
    count: u32,
    // The world-space view ray of a screen position per metre of view depth, affine in
    // its normalised device coordinates, as in ShadowTaps: ray_origin + ray_x * ndc.x +
    // ray_y * ndc.y. A froxel's centre lies at the camera plus its column's ray times
    // its view depth.
    ray_origin: vec3<f32>,
    // 1: each transient light is attenuated by the medium's height profile on its way
    // to the froxel, as FogLighting.transmittance; 0: unattenuated.
    transmittance: u32,
    // d ray / d ndc.x (per metre of view depth).
    ray_x: vec3<f32>,
    // d ray / d ndc.y (per metre of view depth).
    ray_y: vec3<f32>,
}

// The camera of a frame, for shaders that start from world positions (the fog group's
// binding 4).
struct FogView {
    // World -> view transform (m): rigid, the camera looks down -Z.
    view_from_world: mat4x4<f32>,
}

// Closed-form global height fog (Wenzel 2007, eq. 2; volfog::height_fog). Extinction
// f(p) = density * exp(-falloff * (dot(p, up) - base_height)), lit by a constant
// radiance plus an optional Henyey-Greenstein sun lobe (sun_color = 0 disables it).
struct HeightFog {
    // In-scattered radiance of the fog (linear rgb), [0, 1e9].
    color: vec3<f32>,
    // Extinction on the plane dot(p, up) = base_height, 1/m, [0, 1e3].
    density: f32,
    // Unit axis the density falls along (any direction, e.g. +Y or +Z).
    up: vec3<f32>,
    // Falloff c along up, 1/m, [-1e3, 1e3]; > 0 thins upwards, 0 is uniform fog.
    falloff: f32,
    // Unit direction from the scene towards the sun.
    sun_direction: vec3<f32>,
    // Height h0 (m along up) where the extinction equals density, |h0| <= 1e9.
    base_height: f32,
    // Sun light scattered by the fog (linear rgb, radiance * sr), [0, 1e9]; the lobe
    // adds sun_color * HG(dot(view_dir, sun_direction), sun_g) to color.
    sun_color: vec3<f32>,
    // HG mean cosine of the sun lobe, [-0.999, 0.999].
    sun_g: f32,
    // Height (m along up) where the fog ends: no medium above it, and the sun's light
    // enters the fog there. 1e9 (volfog's "no top") for fog without a top.
    top_height: f32,
    // 1: the sun lobe is attenuated by the fog between each point and the sun
    // (volfog::height_fog::height_fog_lit_integral); 0: the sun reaches every point
    // unattenuated (the lobe scales 1 - T).
    sun_transmittance: u32,
}

// An analytic fog volume (Wenzel 2007, "Fog Volumes"; volfog::fog_volume): the unit box
// [-1, 1]^3 (shape 0), the unit sphere (shape 1), the half-space y <= 0 below a plane
// (shape 2), the unit cylinder (3) or the unit cone (4) in local space, ray traced per
// pixel and filled with exponential-gradient fog
// f(p) = density * exp(-falloff * (dot(p - center, gradient) - offset)), lit by a
// constant radiance.
struct FogVolume {
    // World -> local transform (affine): the volume's shape in local space.
    local_from_world: mat4x4<f32>,
    // In-scattered radiance of the fog (linear rgb), [0, 1e9].
    color: vec3<f32>,
    // Extinction on the gradient's reference plane, 1/m, [0, 1e3].
    density: f32,
    // Unit world-space direction the density falls along.
    gradient: vec3<f32>,
    // Falloff c along gradient, 1/m, [-1e3, 1e3]; 0 is uniform fog.
    falloff: f32,
    // World position of the local origin (the volume centre), m.
    center: vec3<f32>,
    // Offset (m) of the reference plane from center along gradient.
    offset: f32,
    // 0 box, 1 ellipsoid, 2 plane, 3 cylinder (radius 1 around the y axis, |y| <= 1),
    // 4 cone (apex at y = 1, base of radius 1 at y = -1); any other value is treated as
    // a box.
    shape: u32,
}

// Water below a plane (Wenzel 2007, "River shading", "Ocean shading"; volfog::water):
// uniform extinction, light falling in straight down and fading with depth.
struct Water {
    // Unit normal of the surface, pointing out of the water.
    normal: vec3<f32>,
    // The surface is the plane dot(p, normal) = height (m), |height| <= 1e9; the water
    // is below it.
    height: f32,
    // Radiance just below the surface of the light falling in (linear rgb), [0, 1e9].
    light: vec3<f32>,
    // Extinction of the water along the view ray, 1/m, [0, 1e3].
    extinction: f32,
    // Single-scattering albedo per channel, [0, 1].
    albedo: vec3<f32>,
    // HG mean cosine of the scattering of the light falling in, [-0.999, 0.999].
    g: f32,
    // Attenuation of the light with depth per channel, 1/m, [0, 1e3]: 0 gives the
    // uniform river model, > 0 the ocean model.
    attenuation: vec3<f32>,
    // View depth (m) over which the surface fades in at the shore, [0, 1e9].
    shore_fade: f32,
}

// A single-scattering atmosphere (Nishita et al. 1993; Wenzel 2007, eq. 1;
// volfog::sky): Rayleigh and Mie scattering with exponential height profiles over a
// spherical planet, the camera on the ground, the world's up axis +Y.
struct SkyAtmosphere {
    // Unit direction towards the sun (world space).
    sun_direction: vec3<f32>,
    // Planet radius, m, [1e3, 1e8].
    planet_radius: f32,
    // Rayleigh scattering coefficients at the ground per channel, 1/m, [0, 1e-2].
    rayleigh: vec3<f32>,
    // Radius of the top of the atmosphere, m, above planet_radius (at most 2x).
    atmosphere_radius: f32,
    // Solar irradiance (linear rgb), [0, 1e9].
    sun_intensity: vec3<f32>,
    // Camera altitude above the ground, m, [0, atmosphere_radius - planet_radius).
    camera_height: f32,
    // Rayleigh scale height, m, [1, 1e6].
    rayleigh_height: f32,
    // Mie scattering coefficient at the ground, 1/m, [0, 1e-2].
    mie: f32,
    // Mie scale height, m, [1, 1e6].
    mie_height: f32,
    // Mie extinction over Mie scattering, [1, 10] (1.11 for haze).
    mie_extinction_ratio: f32,
    // Cornette-Shanks mean cosine of Mie scattering, [0, 0.999].
    mie_g: f32,
    // Quadrature points along the view ray and towards the sun, [1, 256].
    view_samples: u32,
    light_samples: u32,
    // First texture row the sky_solve dispatch fills (the solve spread over frames).
    first_row: u32,
}

// Rays through the screen's corners for fullscreen passes (Wenzel 2007, "Recovering
// World Space Position from Depth"; volfog::frustum).
struct FrustumRays {
    // World-space vectors from the camera to the points at view depth 1 m through the
    // corners uv (0, 0), (1, 0), (0, 1), (1, 1) (xyz; w 0).
    corners: array<vec4<f32>, 4>,
    // Camera position in world space (xyz), m; w the view depth of the far plane (at
    // most 1e30): depth-buffer values at or beyond it are the sky.
    camera: vec4<f32>,
    // View depth from a depth-buffer value d: -(x d + y) / (z d + w), the depth rows of
    // the inverse projection.
    depth_terms: vec4<f32>,
}

// A cloud layer (Wenzel 2007, "Clouds", "Cloud Shadows", "Distance Clouds";
// volfog::clouds): a horizontal slab whose density is a wind-scrolled 2D map.
struct CloudLayer {
    // Unit direction towards the sun.
    sun_direction: vec3<f32>,
    // Height of the layer's base (m along +Y).
    base_height: f32,
    // Sun radiance scattered by the clouds (linear rgb, radiance * sr), [0, 1e9].
    sun_color: vec3<f32>,
    // Thickness of the layer, m, (0, 1e5].
    thickness: f32,
    // Sky light on the clouds (linear rgb radiance), [0, 1e9].
    sky_color: vec3<f32>,
    // Extinction at map density 1, 1/m, [0, 10].
    extinction: f32,
    // Wind: how far the map moves per second (m/s, world x and z).
    wind: vec2<f32>,
    // Metres of world per repeat of the map, (0, 1e7].
    map_size: f32,
    // Time, s.
    time: f32,
    // Samples along the view ray and towards the sun (distance clouds), [1, 64].
    view_samples: u32,
    sun_samples: u32,
    // Henyey-Greenstein mean cosine of the sun's scattering, [-0.999, 0.999].
    g: f32,
    // Rim light strength (the silver lining of thin cloud edges), [0, 1e3].
    rim: f32,
}

// A fog hull (Boyd 2001): a closed mesh filled with homogeneous fog, drawn by the
// hull_thickness pass and composited by hull_composite (see volfog::hull).
struct FogHull {
    // World -> clip (projection * view) of the camera; the view must be rigid
    // (rotation and translation) so that distances stay in metres.
    clip_from_world: mat4x4<f32>,
    // Inverse of the projection (clip -> view), to turn scene depths into distances.
    view_from_clip: mat4x4<f32>,
    // Camera position in world space (m).
    camera_position: vec3<f32>,
    // Reference distance (m), >= 0: a lower bound of the distance from the camera of
    // every point of the hull (0 is always valid); hull terms are stored relative to it.
    reference: f32,
    // In-scattered colour (linear rgb, >= 0): the colour of infinitely thick fog.
    color: vec3<f32>,
    // Extinction inside the hull (1/m), >= 0.
    density: f32,
    // Step (m) of the split of each term into a multiple of it and a remainder for
    // rgba16float targets: a power of two with (crossings / 2) * depth extent <= 2048
    // * quantum; 0 keeps terms whole (rgba32float targets).
    quantum: f32,
}

// One frame of epipolar sun shafts (Yusov 2012; volfog::epipolar): the camera, the
// shadow cascade the shafts are marched in, the epipolar sampling and the phase of the
// sun's light. The medium is a HeightFog in view space (uniform fog: falloff 0).
struct EpipolarFrame {
    // Inverse of the camera's projection (clip -> view); standard, reversed or
    // infinite perspective.
    view_from_clip: mat4x4<f32>,
    // Camera view -> light clip space of the shadow cascade (orthographic: a
    // directional light; x, y in [-1, 1], depth in [0, 1], smaller is nearer the light).
    light_from_view: mat4x4<f32>,
    // The epipole: the sun's position in normalised device coordinates (the anti-sun
    // point when the sun is behind the camera); may lie far outside [-1, 1].
    light_screen: vec2<f32>,
    // Size of the full-resolution target, pixels.
    screen_size: vec2<f32>,
    // Rayleigh in-scatter colour (linear rgb, radiance * sr per unit extinction),
    // [0, 1e9]: adds rayleigh * phase_rayleigh(cos) to the sun lobe of the medium.
    rayleigh: vec3<f32>,
    // View depth (m) where the march starts: 0 alone, the froxel far plane as the far
    // field of a froxel volume.
    start_depth: f32,
    // Epipolar slices (lines from the epipole to the screen border), [4, 4096].
    slices: u32,
    // Samples per slice, a multiple of 128 in [128, 2048].
    samples: u32,
    // Initial step between ray-marching samples: 8, 16, 32 or 64.
    initial_step: u32,
    // Side of the shadow map in texels: a power of two in [64, 4096].
    shadow_size: u32,
    // Array layer of the cascade in the shadow map.
    cascade: u32,
    // Downscale factor of the screen-space resolve: 1, 2 or 4.
    downscale: u32,
    // Steps of the per-pixel march that corrects pixels the interpolation cannot
    // serve, [1, 4096].
    fix_steps: u32,
    // Phase of the sun lobe: 0 Henyey-Greenstein, 1 Cornette-Shanks.
    phase_model: u32,
    // Relative view-depth difference that counts as a depth break, (0, 10].
    depth_threshold: f32,
    // Longest view depth (m) a ray is marched to (sky pixels stop here), > start_depth.
    max_depth: f32,
    // Steps of the per-pixel brute-force reference march, [1, 65536].
    reference_steps: u32,
    // Added to every shadow depth before the lit test (light depth units, [0, 1]):
    // the usual shadow-map bias against acne where a ray ends on a receiver.
    depth_bias: f32,
}
