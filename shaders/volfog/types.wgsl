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
    // World -> clip (projection * view) of the previous frame, for reprojection.
    prev_clip_from_world: mat4x4<f32>,
    // Camera position in world space (m).
    camera_position: vec3<f32>,
    // Seconds since start, drives noise animation and density scrolling.
    time: f32,
    // Sample offset inside each froxel this frame, froxel units in [-0.5, 0.5]^3
    // (a Halton 2, 3, 5 sequence; used when VOLFOG_INJECT_JITTER is set).
    jitter: vec3<f32>,
    // Weight of the reprojected history in [0, 1) (0.9 by default).
    history_weight: f32,
    // 1 when the history volume holds a previous frame, 0 on the first frame.
    history_valid: u32,
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
}

// A local fog volume added to (or, with negative density, removed from) the medium:
// a box or ellipsoid with an arbitrary transform and a soft edge.
struct LocalVolume {
    // World -> unit shape space: the box [-1, 1]^3 or the unit sphere.
    local_from_world: mat4x4<f32>,
    // Extinction added inside (1/m); negative values clear fog (e.g. indoors).
    density: f32,
    // Width of the edge falloff as a fraction of the unit extent, (0, 1].
    edge: f32,
    // 0 box, 1 ellipsoid.
    shape: u32,
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

// A point or spot light affecting the fog (storage buffer element).
struct FogLight {
    // World position (m).
    position: vec3<f32>,
    // Range (m) beyond which the light has no effect, > 0.
    range: f32,
    // Intensity colour (linear rgb): illuminance at 1 m is color / 1 m^2.
    color: vec3<f32>,
    // Multiplier of this light's contribution to the fog, >= 0.
    fog_intensity: f32,
    // Spot axis (unit, pointing away from the light); ignored for point lights.
    direction: vec3<f32>,
    // Source radius (m), > 0: the inverse square law is clamped at this distance.
    radius: f32,
    // Cosine of the spot's outer half-angle; <= -1 for a point light.
    cos_outer: f32,
    // Cosine of the spot's inner half-angle (full intensity inside), >= cos_outer.
    cos_inner: f32,
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
