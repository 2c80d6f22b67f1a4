// volfog::medium_shadow — shadows the medium casts on itself: the light of the sun and
// of point, spot and directional lights dimmed by the medium's extinction beyond its
// height profile (noise, density texture, custom density, local volumes) on its way.
//
// Use:      #import volfog::medium_shadow::{medium_shadow_sun, medium_shadow_segment, medium_shadow_texel}
// Defines:  none
// Data:     the medium-shadow volume (types::MediumShadow): an rgba16float 3D texture
//           aligned with the sun, r the optical depth from its sun-side face to each
//           texel centre, g the excess extinction at the centre (1/m), written by the
//           medium_shadow pass; sampled with a linear, clamp-to-edge sampler.
// Method:   the light's transmittance to a point is exp(-tau_profile - tau_excess). The
//           height profile's tau_profile has a closed form
//           (volfog::density::medium_light_transmittance); the rest varies in space
//           without one, so it is tabulated: each column of the volume follows one ray of
//           sunlight and accumulates its excess extinction slice by slice (the
//           volumetric shadow map of Frostbite, an extension Wronski 2014 lists under
//           "Future work": an extinction volume marched towards the light). A point or
//           spot light marches the tabulated excess extinction along its segment with
//           MediumShadow.march_steps midpoint samples. Where the medium is thinner than
//           its profile (noise below 0, subtractive volumes) the excess is negative; the
//           caller clamps the product of the two factors at 1.
// Range:    outside the volume across the sunlight the excess is taken as 0; beyond
//           its far face a point reads the far face's optical depth.
// Units:    metres, extinction 1/m, optical depth dimensionless.
#define_import_path volfog::medium_shadow

#import volfog::types::MediumShadow

// Points per texel along the sunlight at which the medium_shadow pass evaluates the
// extinction; the texel holds their mean, so a boundary inside a slice shifts the
// tabulated optical depth by at most sigma * step / (2 MEDIUM_SHADOW_SUBSAMPLES)
// instead of sigma * step / 2.
const MEDIUM_SHADOW_SUBSAMPLES: u32 = 4u;

// The optical depth stored at the centre of slice k of a column: the column's optical
// depth before the slice (prefix, through slices 0..k) plus half the slice's own
// mean excess extinction (1/m) over its length step (m). The medium_shadow pass writes it;
// trilinear filtering between slice centres then integrates the excess piecewise
// linearly.
fn medium_shadow_texel(prefix: f32, excess: f32, step: f32) -> f32 {
    return prefix + 0.5 * excess * step;
}

// The volume coordinate uvw of a world position (m).
fn medium_shadow_coord(params: MediumShadow, world: vec3<f32>) -> vec3<f32> {
    return (params.volume_from_world * vec4<f32>(world, 1.0)).xyz;
}

// Factor in (0, +inf) by which the medium beyond its height profile dims the sunlight
// reaching a world position: exp(-tau) of the excess optical depth between the
// volume's sun-side face and the point (1 outside the volume across the sunlight).
fn medium_shadow_sun(volume: texture_3d<f32>, linear: sampler, params: MediumShadow, world: vec3<f32>) -> f32 {
    let uvw = medium_shadow_coord(params, world);
    if any((uvw.xy < vec2<f32>(0.0)) | (uvw.xy > vec2<f32>(1.0))) {
        return 1.0;
    }
    let tau = textureSampleLevel(volume, linear, uvw, 0.0).r;
    return exp(-clamp(tau, -80.0, 80.0));
}

// Factor in (0, +inf) by which the medium beyond its height profile dims the light
// travelling from `light` (m) to `world` (m): exp(-tau) of the excess extinction
// sampled at params.march_steps midpoints of the segment (0 outside the volume).
fn medium_shadow_segment(volume: texture_3d<f32>, linear: sampler, params: MediumShadow, world: vec3<f32>, light: vec3<f32>) -> f32 {
    let steps = max(params.march_steps, 1u);
    let delta = (light - world) / f32(steps);
    var tau = 0.0;
    for (var i = 0u; i < steps; i++) {
        let uvw = medium_shadow_coord(params, world + delta * (f32(i) + 0.5));
        if all((uvw >= vec3<f32>(0.0)) & (uvw <= vec3<f32>(1.0))) {
            tau += textureSampleLevel(volume, linear, uvw, 0.0).g;
        }
    }
    return exp(-clamp(tau * length(delta), -80.0, 80.0));
}
