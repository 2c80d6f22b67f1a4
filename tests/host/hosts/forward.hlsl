// The fragment shader of a forward-lit transparent surface in an HLSL engine (the way a
// Unity or Unreal custom node, or a C++ renderer's material, uses volfog): every volfog
// snippet is included, the engine declares its own resources, and each snippet function
// that takes resources or structs is called. The host test compiles it with Slang.
//
// Matrices: volfog's HLSL multiplies as mul(v, M), the rows of M holding the matrix's
// columns; the bytes of a column-major matrix declared row_major float4x4 (as the
// volfog structs do) are exactly that. An engine matrix built for mul(M, v) is passed
// as transpose(M).

#include "volfog_apply.hlsli"
#include "volfog_height_fog.hlsli"
#include "volfog_fog_volume.hlsli"
#include "volfog_lightning.hlsli"
#include "volfog_soft_particles.hlsli"
#include "volfog_phase.hlsli"

cbuffer FogParams : register(b0)
{
    volfog_Froxels froxels;      // bytes as in volfog_layout.h
    volfog_HeightFog tail;       // the far-plane tail, view space
    volfog_HeightFog height_fog; // analytic fog, world space
    volfog_FogVolume hull;       // one fog volume
    float4x4 view_from_world;    // engine convention: mul(view_from_world, p)
    float4 camera_position;      // world, metres
    float4 flash;                // lightning: xyz world position, w intensity
    float4 flash_attenuation;    // x: attenuation (1/m^2)
};

Texture3D<float4> fog_integrated : register(t0);
SamplerState fog_sampler : register(s0);
Texture2D<float> scene_depth : register(t1);

struct Varyings
{
    float4 position : SV_Position;
    float3 world : TEXCOORD0;
    float4 color : COLOR0;
    float particle_depth : TEXCOORD1; // view depth of the fragment, metres
};

float4 main(Varyings v) : SV_Target0
{
    float4x4 wgsl_view_from_world = transpose(view_from_world);
    float4 coord = volfog_fog_coord_from_world(v.world, wgsl_view_from_world, froxels);
    float4 froxel_fog = volfog_fog_sample(fog_integrated, fog_sampler, coord);
    float4 nearest = volfog_fog_load(fog_integrated, coord);
    float3 view_pos = volfog_fog_view_position(v.world, wgsl_view_from_world);
    float4 fog = volfog_fog_with_tail(lerp(froxel_fog, nearest, 0.5),
                                      volfog_fog_tail(froxels, tail, view_pos));

    float3 eye = camera_position.xyz;
    float4 analytic = volfog_height_fog(height_fog, eye, v.world - eye);
    float4 local_fog = volfog_fog_volume(hull, eye, v.world);
    fog = volfog_fog_over(volfog_fog_over(local_fog, analytic), fog);

    float glow = volfog_volumetric_lightning(flash.w, flash_attenuation.x, flash.xyz, eye, v.world - eye);
    float3 to_flash = normalize(flash.xyz - v.world);
    float3 to_eye = normalize(eye - v.world);
    float phase = volfog_phase_hg(dot(to_flash, -to_eye), 0.6);

    float depth = scene_depth.Load(int3(int2(v.position.xy), 0));
    float fade = volfog_soft_particle_fade(v.particle_depth, depth, 0.5);

    float3 lit = v.color.rgb + glow * phase;
    return float4(volfog_apply_fog(lit, fog), v.color.a * fade);
}
