// Bench pass write_volume — the floor of the inject pass: writes a constant to every
// texel of a write-only rgba16float 3D volume, one invocation per texel in 4 x 4 x 4
// workgroups, as inject dispatches.
//
// Dispatch: ceil(size.x / 4) x ceil(size.y / 4) x ceil(size.z / 4) workgroups.
// Bindings (group 0):
//   0  texture_storage_3d<rgba16float, write>: the volume

@group(0) @binding(0) var destination: texture_storage_3d<rgba16float, write>;

@compute @workgroup_size(4, 4, 4)
fn write_volume(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id >= textureDimensions(destination)) {
        return;
    }
    textureStore(destination, id, vec4<f32>(0.25, 0.5, 0.75, 0.01));
}
