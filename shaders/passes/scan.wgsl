// Pass scan — integrates every froxel column of the scattering volume front to back.
//
// Dispatch: ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups of 8 x 8; under
//   VOLFOG_SCAN_RESAMPLE ceil(size.x / 8) x ceil(size.y / 4) x 1 workgroups of 8 x 4 x 2
//   (invocation z is the eye: both eyes in one dispatch).
// Bindings (group 0):
//   0  uniform Froxels
//   1  texture_3d<f32>: scattering volume, rgb = sigma_s * L_in, a = sigma_t (read with
//      textureLoad, no sampler)
//   2  texture_storage_3d<rgba16float, write>: integrated volume, rgb = in-scattered
//      radiance from the near plane to the back of each slice, a = transmittance
//   3  texture_2d<u32>: live slices per column from froxel_cull (VOLFOG_FROXEL_CULL only);
//      slices behind them are not read, and their texels hold the value at the last
//      live slice (nothing reads them; they stay defined)
//   4  uniform FogMedium; 5 uniform TransientLighting; 6 storage, read: array<FogLight>,
//      the transient lights (4-6 VOLFOG_SCAN_TRANSIENT_LIGHTS only)
//   VOLFOG_SCAN_RESAMPLE only: bindings 0, 2, 3 are the left eye's; 5 uniform
//      TransientLighting, the left eye's camera position and column rays (its light
//      count is not read); 7 sampler, filtering, clamp to edge; 8 uniform FogFrame and
//      9 uniform Froxels of the shared volume (binding 1, sampled trilinearly: bound as
//      filterable float); 10 uniform Froxels, 11 integrated volume, 12 uniform
//      TransientLighting and 13 live slices (VOLFOG_FROXEL_CULL only) of the right eye
// Defines: VOLFOG_SCAN_WRONSKI_STEP (see volfog::scan), VOLFOG_FROXEL_CULL,
//   VOLFOG_SCAN_TRANSIENT_LIGHTS: short-lived lights (a muzzle flash, a lightning
//   strike) light this frame only. Each live froxel's scattering gains
//   sigma_s * sum_i fog_light_inscatter(light_i) (times fog_light_transmittance where
//   TransientLighting.transmittance is 1), sigma_s = FogMedium.albedo * sigma_t of the
//   volume read, at the froxel's centre (no jitter, no shadow, no cookie), before it is
//   integrated. The scan reads the stabilised volume and writes the integrated one, so
//   the history never holds these lights, and every froxel gets them whether or not
//   inject amortises its work over two frames.
//   VOLFOG_SCAN_RESAMPLE (not with VOLFOG_SCAN_TRANSIENT_LIGHTS): stereo fog, both eyes.
//   Binding 1 is the volume shared by both eyes (volfog::stereo), aligned with the
//   centre eye of bindings 8 and 9; each eye's froxel scattering is read trilinearly at
//   the world position of its centre (no jitter) on that eye's column ray,
//   stereo_resample_uvw, then integrated along that eye's ray as above into that eye's
//   volume. A wave holds the same 8 x 4 columns of both eyes, which step through the
//   slices together and read the same region of the shared volume, so the volume is
//   fetched from memory once for both eyes rather than once per eye.
// Reference: Wronski 2014, "Solving scattering equation" (RayMarchThroughVolume).

#import volfog::types::Froxels
#import volfog::froxel::{slice_walk, ray_scale}
#import volfog::scan::{scan_step, SCAN_START}
#ifdef VOLFOG_SCAN_TRANSIENT_LIGHTS
#import volfog::types::{FogMedium, FogLight, TransientLighting}
#import volfog::froxel::{ndc_from_uv, slice_depth}
#import volfog::lights::{light_touches_sphere, fog_light_inscatter, fog_light_transmittance}
#endif
#ifdef VOLFOG_SCAN_RESAMPLE
#import volfog::types::{FogFrame, TransientLighting}
#import volfog::froxel::{ndc_from_uv, slice_depth}
#import volfog::stereo::{stereo_resample_column, stereo_resample_uvw}
#endif

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var scattering: texture_3d<f32>;
@group(0) @binding(2) var integrated: texture_storage_3d<rgba16float, write>;
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(3) var live_slices: texture_2d<u32>;
#endif
#ifdef VOLFOG_SCAN_TRANSIENT_LIGHTS
@group(0) @binding(4) var<uniform> fog_medium: FogMedium;
@group(0) @binding(5) var<uniform> transient: TransientLighting;
@group(0) @binding(6) var<storage, read> transient_lights: array<FogLight>;

// Radiance scattered towards the eye per unit sigma_s by the transient lights at a
// world position seen along the unit view_dir. A point or spot light is skipped beyond
// its range (where its light is 0), and its transmittance is not evaluated outside its
// cone.
fn transient_inscatter(world: vec3<f32>, view_dir: vec3<f32>) -> vec3<f32> {
    let count = min(transient.count, arrayLength(&transient_lights));
    var light = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        let source = transient_lights[i];
        if !light_touches_sphere(source, world, 0.0) {
            continue;
        }
        var inscatter = fog_light_inscatter(source, world, view_dir, fog_medium.phase_g);
        if transient.transmittance != 0u && max(inscatter.r, max(inscatter.g, inscatter.b)) > 0.0 {
            inscatter *= fog_light_transmittance(fog_medium, source, world);
        }
        light += inscatter;
    }
    return light;
}

// A froxel's scattering read from the volume with the transient lights' in-scattering
// added at its centre `world`: sigma_s = FogMedium.albedo * sigma_t, clamped as inject
// clamps its output.
fn with_transient_lights(read: vec4<f32>, world: vec3<f32>, view_dir: vec3<f32>) -> vec4<f32> {
    let sigma_s = fog_medium.albedo * max(read.a, 0.0);
    return min(vec4<f32>(read.rgb + sigma_s * transient_inscatter(world, view_dir), read.a),
        vec4<f32>(65504.0));
}
#endif
#ifdef VOLFOG_SCAN_RESAMPLE
@group(0) @binding(5) var<uniform> left_eye: TransientLighting;
@group(0) @binding(7) var shared_sampler: sampler;
@group(0) @binding(8) var<uniform> shared_frame: FogFrame;
@group(0) @binding(9) var<uniform> shared_froxels: Froxels;
@group(0) @binding(10) var<uniform> right_froxels: Froxels;
@group(0) @binding(11) var right_integrated: texture_storage_3d<rgba16float, write>;
@group(0) @binding(12) var<uniform> right_eye: TransientLighting;
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(13) var right_live_slices: texture_2d<u32>;
#endif

// The froxel placement of the eye (right: the right eye, else the left).
fn eye_froxels(right: bool) -> Froxels {
    if right {
        return right_froxels;
    }
    return froxels;
}

// The camera position and column rays of the eye.
fn eye_rays(right: bool) -> TransientLighting {
    if right {
        return right_eye;
    }
    return left_eye;
}

// Writes a texel of the eye's integrated volume.
fn store_eye(right: bool, texel: vec3<u32>, value: vec4<f32>) {
    if right {
        textureStore(right_integrated, texel, value);
    } else {
        textureStore(integrated, texel, value);
    }
}
#endif

#ifdef VOLFOG_SCAN_RESAMPLE
@compute @workgroup_size(8, 4, 2)
#else
@compute @workgroup_size(8, 8, 1)
#endif
fn scan(@builtin(global_invocation_id) id: vec3<u32>) {
#ifdef VOLFOG_SCAN_RESAMPLE
    // Invocation z is the eye (one workgroup in z): 0 left, 1 right.
    let right = id.z == 1u;
    let froxels = eye_froxels(right);
    let eye = eye_rays(right);
#endif
    if id.x >= froxels.size.x || id.y >= froxels.size.y {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(froxels.size.xy);
    // Path length per metre of view depth along this column's centre ray.
    let scale = ray_scale(uv, froxels.view_from_clip);
    let slices = froxels.size.z;
#ifdef VOLFOG_FROXEL_CULL
#ifdef VOLFOG_SCAN_RESAMPLE
    let live_left = textureLoad(live_slices, id.xy, 0).r;
    let live = min(select(live_left, textureLoad(right_live_slices, id.xy, 0).r, right), slices);
#else
    let live = min(textureLoad(live_slices, id.xy, 0).r, slices);
#endif
#else
    let live = slices;
#endif
    var acc = SCAN_START;
    // front and back: the slice's boundaries as depths beyond near, walked
    // (volfog::froxel::slice_walk: no exp and no branch per slice).
    let walk = slice_walk(slices, froxels.near, froxels.far, froxels.curve);
    var front = 0.0;
#ifdef VOLFOG_SCAN_TRANSIENT_LIGHTS
    // The column's world-space ray per metre of view depth and the depth of slice 0's
    // centre beyond near, walked like the boundaries (the walk holds at any offset).
    let ndc = ndc_from_uv(uv);
    let ray = transient.ray_origin + transient.ray_x * ndc.x + transient.ray_y * ndc.y;
    let view_dir = normalize(ray);
    var middle = slice_depth(0.5 / f32(slices), froxels.near, froxels.far, froxels.curve) - froxels.near;
#endif
#ifdef VOLFOG_SCAN_RESAMPLE
    // The column's world-space ray per metre of this eye's view depth, in the shared
    // volume's clip space, and the depth of slice 0's centre beyond near, walked like the
    // boundaries.
    let ndc = ndc_from_uv(uv);
    let ray = eye.ray_origin + eye.ray_x * ndc.x + eye.ray_y * ndc.y;
    let column = stereo_resample_column(eye.camera_position, ray, shared_frame.clip_from_world);
    var middle = slice_depth(0.5 / f32(slices), froxels.near, froxels.far, froxels.curve) - froxels.near;
#endif
    for (var k = 0u; k < live; k++) {
        let back = front * walk.x + walk.y;
#ifdef VOLFOG_SCAN_TRANSIENT_LIGHTS
        let world = transient.camera_position + ray * (froxels.near + middle);
        let medium = with_transient_lights(textureLoad(scattering, vec3<u32>(id.xy, k), 0), world, view_dir);
        middle = middle * walk.x + walk.y;
#else
#ifdef VOLFOG_SCAN_RESAMPLE
        let uvw = stereo_resample_uvw(column, froxels.near + middle, shared_froxels);
        let medium = textureSampleLevel(scattering, shared_sampler, uvw, 0.0);
        middle = middle * walk.x + walk.y;
#else
        let medium = textureLoad(scattering, vec3<u32>(id.xy, k), 0);
#endif
#endif
        acc = scan_step(acc, medium, (back - front) * scale);
        // Clamped to the largest finite rgba16float value so no texel becomes Inf.
#ifdef VOLFOG_SCAN_RESAMPLE
        store_eye(right, vec3<u32>(id.xy, k), min(acc, vec4<f32>(65504.0)));
#else
        textureStore(integrated, vec3<u32>(id.xy, k), min(acc, vec4<f32>(65504.0)));
#endif
        front = back;
    }
#ifdef VOLFOG_FROXEL_CULL
    let held = min(acc, vec4<f32>(65504.0));
    for (var k = live; k < slices; k++) {
#ifdef VOLFOG_SCAN_RESAMPLE
        store_eye(right, vec3<u32>(id.xy, k), held);
#else
        textureStore(integrated, vec3<u32>(id.xy, k), held);
#endif
    }
#endif
}
