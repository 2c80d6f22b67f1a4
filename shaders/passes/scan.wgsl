// Pass scan — integrates every froxel column of the scattering volume front to back.
//
// Dispatch: ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups of 8 x 8.
// Bindings (group 0):
//   0  uniform Froxels
//   1  texture_3d<f32>: scattering volume, rgb = sigma_s * L_in, a = sigma_t (read with
//      textureLoad, no sampler)
//   2  texture_storage_3d<rgba16float, write>: integrated volume, rgb = in-scattered
//      radiance from the near plane to the back of each slice, a = transmittance
//   3  texture_2d<u32>: live slices per column from froxel_cull (VOLFOG_FROXEL_CULL only);
//      slices behind them are not read, and their texels hold the value at the last
//      live slice (nothing reads them; they stay defined)
// Defines: VOLFOG_SCAN_WRONSKI_STEP (see volfog::scan), VOLFOG_FROXEL_CULL.
// Reference: Wronski 2014, "Solving scattering equation" (RayMarchThroughVolume).

#import volfog::types::Froxels
#import volfog::froxel::{slice_walk, ray_scale}
#import volfog::scan::{scan_step, SCAN_START}

@group(0) @binding(0) var<uniform> froxels: Froxels;
@group(0) @binding(1) var scattering: texture_3d<f32>;
@group(0) @binding(2) var integrated: texture_storage_3d<rgba16float, write>;
#ifdef VOLFOG_FROXEL_CULL
@group(0) @binding(3) var live_slices: texture_2d<u32>;
#endif

@compute @workgroup_size(8, 8, 1)
fn scan(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= froxels.size.x || id.y >= froxels.size.y {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(froxels.size.xy);
    // Path length per metre of view depth along this column's centre ray.
    let scale = ray_scale(uv, froxels.view_from_clip);
    let slices = froxels.size.z;
#ifdef VOLFOG_FROXEL_CULL
    let live = min(textureLoad(live_slices, id.xy, 0).r, slices);
#else
    let live = slices;
#endif
    var acc = SCAN_START;
    // front and back: the slice's boundaries as depths beyond near, walked
    // (volfog::froxel::slice_walk: no exp and no branch per slice).
    let walk = slice_walk(slices, froxels.near, froxels.far, froxels.curve);
    var front = 0.0;
    for (var k = 0u; k < live; k++) {
        let back = front * walk.x + walk.y;
        let medium = textureLoad(scattering, vec3<u32>(id.xy, k), 0);
        acc = scan_step(acc, medium, (back - front) * scale);
        // Clamped to the largest finite rgba16float value so no texel becomes Inf.
        textureStore(integrated, vec3<u32>(id.xy, k), min(acc, vec4<f32>(65504.0)));
        front = back;
    }
#ifdef VOLFOG_FROXEL_CULL
    let held = min(acc, vec4<f32>(65504.0));
    for (var k = live; k < slices; k++) {
        textureStore(integrated, vec3<u32>(id.xy, k), held);
    }
#endif
}
