// Your own density for volfog: a glowing swirl of fog around a portal.
//
// volfog composes this module into its inject pass (FogConfig::custom_density, or
// `volfog export --custom-density examples/portal_swirl.wgsl`) and adds the sample it
// returns at each froxel's position to the medium, before the local volumes blend.
// The parameters are FrameInputs::custom_params:
//   values[0]  the portal's centre (xyz, m) and radius (w, m)
//   values[1]  peak extinction (x, 1/m), swirl speed (y, rad/s), number of arms (z)
//   values[2]  the glow at the peak (rgb, radiance per metre)
#import volfog::types::{FogSample, FogCustomParams}
#import volfog::noise::noise_animated

fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {
    let centre = params.values[0].xyz;
    let radius = max(params.values[0].w, 1e-3);
    let peak = params.values[1].x;
    let d = (world - centre) / radius;
    let r = length(d.xz);
    // Arms turning about the portal's axis (y), wound tighter towards the middle.
    let arms = 0.5 + 0.5 * sin(params.values[1].z * atan2(d.z, d.x) - params.values[1].y * time + 4.0 * r);
    let falloff = exp(-r * r - abs(d.y));
    let turbulence = max(1.0 + 0.4 * noise_animated(world, 0.8, vec3<f32>(0.0, 0.5, 0.0), time, 2u), 0.0);
    let extinction = peak * falloff * arms * turbulence;
    let glow = params.values[2].rgb * (extinction / max(peak, 1e-6));
    return FogSample(vec3<f32>(0.9), extinction, glow);
}
