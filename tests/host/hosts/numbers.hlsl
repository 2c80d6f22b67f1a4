// A compute shader of the kind an HLSL engine writes: it includes four volfog snippets
// (each guarded, so their shared definitions appear once) and evaluates them for a list
// of cases. The host test compiles it with Slang to SPIR-V, runs it on lavapipe and
// compares every output with volfog's CPU mirror.
//
// Matrices: volfog's HLSL multiplies as mul(v, M), with the rows of M holding the
// matrix's columns (the bytes of a column-major matrix read as row_major float4x4).
// A matrix built for mul(M, v) is passed as transpose(M), as done here.

#include "volfog_phase.hlsli"
#include "volfog_height_fog.hlsli"
#include "volfog_lightning.hlsli"
#include "volfog_apply.hlsli"

// CASE_FLOAT4 float4 per case; see the field list in tests/host/foreign_numbers.rs.
#define CASE_FLOAT4 26
#define OUT_FLOAT4 9

[[vk::binding(0, 0)]] StructuredBuffer<float4> cases : register(t0);
[[vk::binding(1, 0)]] RWStructuredBuffer<float4> results : register(u0);

// A matrix given by its rows (mul(M, v) convention).
float4x4 rows_at(uint base)
{
    return float4x4(cases[base], cases[base + 1], cases[base + 2], cases[base + 3]);
}

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID)
{
    uint count, stride;
    cases.GetDimensions(count, stride);
    uint n = id.x;
    if (n >= count / CASE_FLOAT4)
        return;
    uint c = n * CASE_FLOAT4;
    uint o = n * OUT_FLOAT4;

    float cos_theta = cases[c].x;
    float g = cases[c].y;
    float g2 = cases[c].z;
    float w = cases[c].w;
    float3 dir = cases[c + 1].xyz;
    float x_in = cases[c + 1].w;
    float3 toward = cases[c + 2].xyz;
    float3 away = cases[c + 3].xyz;

    volfog_HeightFog fog;
    fog.color = cases[c + 4].xyz;
    fog.density = cases[c + 4].w;
    fog.up = cases[c + 5].xyz;
    fog.falloff = cases[c + 5].w;
    fog.sun_direction = cases[c + 6].xyz;
    fog.base_height = cases[c + 6].w;
    fog.sun_color = cases[c + 7].xyz;
    fog.sun_g = cases[c + 7].w;

    float3 origin = cases[c + 8].xyz;
    float a = cases[c + 8].w;
    float3 segment = cases[c + 9].xyz;
    float intensity = cases[c + 9].w;
    float3 light = cases[c + 10].xyz;
    float3 world = cases[c + 11].xyz;

    float4x4 view_from_world = rows_at(c + 12);
    volfog_Froxels froxels;
    froxels.clip_from_view = transpose(rows_at(c + 16));
    froxels.view_from_clip = transpose(rows_at(c + 20));
    froxels.size = uint3(cases[c + 24].xyz);
    froxels.near = cases[c + 24].w;
    froxels.far = cases[c + 25].x;
    froxels.curve = cases[c + 25].y;

    results[o] = float4(
        volfog_phase_hg(cos_theta, g),
        volfog_phase_schlick(cos_theta, volfog_schlick_k(g)),
        volfog_phase_cornette_shanks(cos_theta, g),
        volfog_phase_rayleigh(cos_theta));
    results[o + 1] = float4(
        volfog_phase_hg_two_lobe(cos_theta, g, g2, w),
        volfog_phase_isotropic(),
        volfog_exp_segment_average(x_in),
        volfog_height_fog_transmittance(fog.density, fog.falloff, fog.base_height, fog.up, origin, segment));
    results[o + 2] = float4(
        volfog_phase_hg_zonal_sh(g),
        volfog_height_fog_optical_depth(fog.density, fog.falloff, fog.base_height, fog.up, origin, segment));
    results[o + 3] = volfog_phase_hg_sh_l1(dir, g);
    results[o + 4] = float4(
        volfog_phase_two_color(cos_theta, toward, away),
        volfog_lightning_integral(a, light, origin, segment));
    results[o + 5] = volfog_height_fog(fog, origin, segment);
    results[o + 6] = float4(
        volfog_volumetric_lightning(intensity, a, light, origin, segment),
        volfog_lightning_density(intensity, a, light, origin + 0.5 * segment),
        0.0,
        0.0);
    results[o + 7] = volfog_fog_coord_from_world(world, transpose(view_from_world), froxels);
    results[o + 8] = float4(volfog_fog_view_position(world, transpose(view_from_world)), 0.0);
}
