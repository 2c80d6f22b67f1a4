// Pass sky_horizon — the sky's scattering averaged along the horizon (the lowest row of
// the sky texture's directions), for fog that matches the sky there (Wenzel 2007,
// "Combining Sky Light and Fog": the fog colour is this average with the per-pixel
// phase, volfog::sky::sky_radiance).
//
// Dispatch: 1 workgroup (64 invocations, two azimuths each) after the sun moves.
// Bindings (group 0):
//   0  uniform SkyAtmosphere
//   1  storage, read_write: SkyHorizon (32 bytes: Rayleigh rgb, Mie rgb; w 0)

#import volfog::types::SkyAtmosphere
#import volfog::sky::{sky_single_scattering, sky_texel_direction, SKY_TEXTURE_WIDTH}

struct SkyHorizon {
    rayleigh: vec4<f32>,
    mie: vec4<f32>,
}

@group(0) @binding(0) var<uniform> sky_atmosphere: SkyAtmosphere;
@group(0) @binding(1) var<storage, read_write> sky_horizon_average: SkyHorizon;

var<workgroup> partial_r: array<vec3<f32>, 64>;
var<workgroup> partial_m: array<vec3<f32>, 64>;

@compute @workgroup_size(64, 1, 1)
fn sky_horizon(@builtin(local_invocation_index) i: u32) {
    var r = vec3<f32>(0.0);
    var m = vec3<f32>(0.0);
    for (var x = i; x < SKY_TEXTURE_WIDTH; x += 64u) {
        let s = sky_single_scattering(sky_atmosphere, sky_texel_direction(vec2<u32>(x, 0u)));
        r += s.rayleigh;
        m += s.mie;
    }
    partial_r[i] = r;
    partial_m[i] = m;
    workgroupBarrier();
    for (var stride = 32u; stride > 0u; stride = stride >> 1u) {
        if i < stride {
            partial_r[i] += partial_r[i + stride];
            partial_m[i] += partial_m[i + stride];
        }
        workgroupBarrier();
    }
    if i == 0u {
        let n = f32(SKY_TEXTURE_WIDTH);
        sky_horizon_average.rayleigh = vec4<f32>(partial_r[0] / n, 0.0);
        sky_horizon_average.mie = vec4<f32>(partial_m[0] / n, 0.0);
    }
}
