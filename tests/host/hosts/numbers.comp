// A compute shader of the kind a GLSL engine writes: it includes four volfog snippets
// (each guarded, so their shared definitions appear once) and evaluates them for a list
// of cases. The host test compiles it with glslang to SPIR-V, runs it on lavapipe and
// compares every output with volfog's CPU mirror. Matrices are GLSL's own: mat4 from
// columns, M * v.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "volfog_phase.glsl"
#include "volfog_height_fog.glsl"
#include "volfog_lightning.glsl"
#include "volfog_apply.glsl"

// CASE_VEC4 vec4 per case; see the field list in tests/host/foreign_numbers.rs.
#define CASE_VEC4 26
#define OUT_VEC4 9

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Cases { vec4 cases[]; };
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };

// A matrix given by its rows.
mat4 rows_at(uint base) {
    return transpose(mat4(cases[base], cases[base + 1], cases[base + 2], cases[base + 3]));
}

void main() {
    uint n = gl_GlobalInvocationID.x;
    if (n >= uint(cases.length()) / CASE_VEC4) {
        return;
    }
    uint c = n * CASE_VEC4;
    uint o = n * OUT_VEC4;

    float cos_theta = cases[c].x;
    float g = cases[c].y;
    float g2 = cases[c].z;
    float w = cases[c].w;
    vec3 dir = cases[c + 1].xyz;
    float x_in = cases[c + 1].w;
    vec3 toward = cases[c + 2].xyz;
    vec3 away = cases[c + 3].xyz;

    volfog_HeightFog fog;
    fog.color = cases[c + 4].xyz;
    fog.density = cases[c + 4].w;
    fog.up = cases[c + 5].xyz;
    fog.falloff = cases[c + 5].w;
    fog.sun_direction = cases[c + 6].xyz;
    fog.base_height = cases[c + 6].w;
    fog.sun_color = cases[c + 7].xyz;
    fog.sun_g = cases[c + 7].w;

    vec3 origin = cases[c + 8].xyz;
    float a = cases[c + 8].w;
    vec3 segment = cases[c + 9].xyz;
    float intensity = cases[c + 9].w;
    vec3 light = cases[c + 10].xyz;
    vec3 world = cases[c + 11].xyz;

    mat4 view_from_world = rows_at(c + 12);
    volfog_Froxels froxels;
    froxels.clip_from_view = rows_at(c + 16);
    froxels.view_from_clip = rows_at(c + 20);
    froxels.size = uvec3(cases[c + 24].xyz);
    froxels.near = cases[c + 24].w;
    froxels.far = cases[c + 25].x;
    froxels.curve = cases[c + 25].y;

    results[o] = vec4(
        volfog_phase_hg(cos_theta, g),
        volfog_phase_schlick(cos_theta, volfog_schlick_k(g)),
        volfog_phase_cornette_shanks(cos_theta, g),
        volfog_phase_rayleigh(cos_theta));
    results[o + 1] = vec4(
        volfog_phase_hg_two_lobe(cos_theta, g, g2, w),
        volfog_phase_isotropic(),
        volfog_exp_segment_average(x_in),
        volfog_height_fog_transmittance(fog.density, fog.falloff, fog.base_height, fog.up, origin, segment));
    results[o + 2] = vec4(
        volfog_phase_hg_zonal_sh(g),
        volfog_height_fog_optical_depth(fog.density, fog.falloff, fog.base_height, fog.up, origin, segment));
    results[o + 3] = volfog_phase_hg_sh_l1(dir, g);
    results[o + 4] = vec4(
        volfog_phase_two_color(cos_theta, toward, away),
        volfog_lightning_integral(a, light, origin, segment));
    results[o + 5] = volfog_height_fog(fog, origin, segment);
    results[o + 6] = vec4(
        volfog_volumetric_lightning(intensity, a, light, origin, segment),
        volfog_lightning_density(intensity, a, light, origin + 0.5 * segment),
        0.0,
        0.0);
    results[o + 7] = volfog_fog_coord_from_world(world, view_from_world, froxels);
    results[o + 8] = vec4(volfog_fog_view_position(world, view_from_world), 0.0);
}
