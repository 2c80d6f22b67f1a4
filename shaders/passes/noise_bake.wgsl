// Pass noise_bake — bakes one period of the tileable Perlin noise into a 3D texture,
// once, for the texture form of the fog's noise (volfog::noise::noise_fbm_texture).
//
// Dispatch: ceil(width / 4) x ceil(height / 4) x ceil(depth / 4) workgroups of 4 x 4 x 4,
// once, into a NOISE_TEXTURE_SIZE^3 texture (64^3, 2 MiB).
// Output: texel i = (perlin_noise_tiled(i / NOISE_TEXTURE_TEXELS_PER_UNIT,
//         NOISE_TEXTURE_PERIOD), 0, 0, 1): the noise at lattice points 1/4 unit apart over
//         one 16-unit period, in [-1, 1], so a linear sampler with repeat addressing
//         continues it seamlessly across the tiles.
// Bindings (group 0):
//   0  texture_storage_3d<rgba16float, write>: the noise texture (later sampled as
//      texture_3d<f32> with a linear, repeat sampler)
// Defines: none.
// Reference: Perlin 2002, "Improving Noise" (the noise baked); Wronski 2014, "Density
// estimation and volume lighting" (the fog density it modulates).

#import volfog::noise::{perlin_noise_tiled, NOISE_TEXTURE_PERIOD, NOISE_TEXTURE_TEXELS_PER_UNIT}

@group(0) @binding(0) var noise_texture: texture_storage_3d<rgba16float, write>;

@compute @workgroup_size(4, 4, 4)
fn noise_bake(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id >= textureDimensions(noise_texture)) {
        return;
    }
    let q = vec3<f32>(id) / f32(NOISE_TEXTURE_TEXELS_PER_UNIT);
    let n = perlin_noise_tiled(q, NOISE_TEXTURE_PERIOD);
    textureStore(noise_texture, id, vec4<f32>(n, 0.0, 0.0, 1.0));
}
