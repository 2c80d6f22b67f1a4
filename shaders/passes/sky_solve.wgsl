// Pass sky_solve — the sky texture of volfog::sky: eq. 1 of Wenzel 2007 per texel.
//
// Dispatch: ceil(SKY_TEXTURE_WIDTH / 8) x ceil(rows / 8) x 1 workgroups to fill rows
// [first_row, first_row + rows) (SkyAtmosphere.first_row); the whole texture at once
// with first_row 0 and rows SKY_TEXTURE_HEIGHT, or a band per frame (the seed spread
// its solve over frames).
// Bindings (group 0):
//   0  uniform SkyAtmosphere
//   1  texture_storage_2d_array<rgba16float, write>: SKY_TEXTURE_WIDTH x
//      SKY_TEXTURE_HEIGHT, 2 layers (0 Rayleigh, 1 Mie; rgb, a = 1)

#import volfog::types::SkyAtmosphere
#import volfog::sky::{sky_single_scattering, sky_texel_direction, SKY_TEXTURE_WIDTH, SKY_TEXTURE_HEIGHT}

@group(0) @binding(0) var<uniform> sky_atmosphere: SkyAtmosphere;
@group(0) @binding(1) var sky_texture: texture_storage_2d_array<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn sky_solve(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = vec2<u32>(id.x, id.y + sky_atmosphere.first_row);
    if texel.x >= SKY_TEXTURE_WIDTH || texel.y >= SKY_TEXTURE_HEIGHT {
        return;
    }
    let s = sky_single_scattering(sky_atmosphere, sky_texel_direction(texel));
    textureStore(sky_texture, vec2<i32>(texel), 0, vec4<f32>(s.rayleigh, 1.0));
    textureStore(sky_texture, vec2<i32>(texel), 1, vec4<f32>(s.mie, 1.0));
}
