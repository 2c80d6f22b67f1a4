// Pass sky_draw — the sky behind everything: the solved sky texture with the phase
// applied per pixel (volfog::sky::sky_sample), on a fullscreen triangle.
//
// Draw: 3 vertices with sky_draw_vs, no vertex buffers, onto the colour target before
// the opaque geometry (or with a depth test that keeps it behind). The fragment writes
// the sky's radiance (rgb) and alpha 1.
// Bindings (group 0):
//   0  uniform FrustumRays (volfog::frustum)
//   1  uniform SkyAtmosphere
//   2  texture_2d_array<f32>: the sky texture sky_solve wrote
//   3  sampler: linear, repeat in u, clamp-to-edge in v

#import volfog::types::{FrustumRays, SkyAtmosphere}
#import volfog::frustum::frustum_vertex
#import volfog::sky::sky_sample

@group(0) @binding(0) var<uniform> frustum_rays: FrustumRays;
@group(0) @binding(1) var<uniform> sky_atmosphere: SkyAtmosphere;
@group(0) @binding(2) var sky_texture: texture_2d_array<f32>;
@group(0) @binding(3) var sky_texture_sampler: sampler;

struct SkyVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) ray: vec3<f32>,
}

@vertex
fn sky_draw_vs(@builtin(vertex_index) index: u32) -> SkyVertex {
    let v = frustum_vertex(frustum_rays, index);
    return SkyVertex(v.clip, v.ray);
}

@fragment
fn sky_draw_fs(in: SkyVertex) -> @location(0) vec4<f32> {
    let dir = normalize(in.ray);
    return vec4<f32>(sky_sample(sky_texture, sky_texture_sampler, dir, sky_atmosphere), 1.0);
}
