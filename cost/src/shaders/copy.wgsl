// Bench pass copy_volume — the bandwidth floor of the scan pass: reads every texel of
// a 3D volume with textureLoad and writes it unchanged to a write-only storage volume,
// with the scan's access pattern (one invocation per column, front to back).
//
// Dispatch: ceil(size.x / 8) x ceil(size.y / 8) x 1 workgroups of 8 x 8, as the scan.
// Bindings (group 0):
//   0  texture_3d<f32>: the source volume (rgba16float, textureLoad, no sampler)
//   1  texture_storage_3d<rgba16float, write>: the destination, same size

@group(0) @binding(0) var source: texture_3d<f32>;
@group(0) @binding(1) var destination: texture_storage_3d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn copy_volume(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(source);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    for (var k = 0u; k < size.z; k++) {
        let texel = vec3<u32>(id.xy, k);
        textureStore(destination, texel, textureLoad(source, texel, 0));
    }
}
