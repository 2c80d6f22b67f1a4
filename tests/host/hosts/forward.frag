// The fragment shader of a forward-lit transparent surface in a GLSL engine: every
// volfog snippet is included, the engine declares its own resources, and each snippet
// function that takes resources or structs is called. volfog's GLSL passes a texture
// and its sampler as one combined sampler. The host test compiles it with glslang and,
// with the includes pasted in (OpenGL has no #include), links it in Mesa's GL driver.
#version 450 core
#extension GL_GOOGLE_include_directive : require

#include "volfog_apply.glsl"
#include "volfog_height_fog.glsl"
#include "volfog_fog_volume.glsl"
#include "volfog_lightning.glsl"
#include "volfog_soft_particles.glsl"
#include "volfog_phase.glsl"

layout(std140, binding = 0) uniform FogParams {
    volfog_Froxels froxels;      // bytes as in volfog_layout.h
    volfog_HeightFog tail;       // the far-plane tail, view space
    volfog_HeightFog height_fog; // analytic fog, world space
    volfog_FogVolume hull;       // one fog volume
    mat4 view_from_world;
    vec4 camera_position;        // world, metres
    vec4 flash;                  // lightning: xyz world position, w intensity
    vec4 flash_attenuation;      // x: attenuation (1/m^2)
};

layout(binding = 0) uniform sampler3D fog_integrated;
layout(binding = 1) uniform sampler2D scene_depth;

layout(location = 0) in vec3 world;
layout(location = 1) in vec4 color;
layout(location = 2) in float particle_depth; // view depth of the fragment, metres
layout(location = 0) out vec4 frag_color;

void main() {
    vec4 coord = volfog_fog_coord_from_world(world, view_from_world, froxels);
    vec4 froxel_fog = volfog_fog_sample(fog_integrated, coord);
    vec4 nearest = volfog_fog_load(fog_integrated, coord);
    vec3 view_pos = volfog_fog_view_position(world, view_from_world);
    vec4 fog = volfog_fog_with_tail(mix(froxel_fog, nearest, 0.5),
                                    volfog_fog_tail(froxels, tail, view_pos));

    vec3 eye = camera_position.xyz;
    vec4 analytic = volfog_height_fog(height_fog, eye, world - eye);
    vec4 local_fog = volfog_fog_volume(hull, eye, world);
    fog = volfog_fog_over(volfog_fog_over(local_fog, analytic), fog);

    float glow = volfog_volumetric_lightning(flash.w, flash_attenuation.x, flash.xyz, eye, world - eye);
    vec3 to_flash = normalize(flash.xyz - world);
    vec3 to_eye = normalize(eye - world);
    float phase = volfog_phase_hg(dot(to_flash, -to_eye), 0.6);

    float depth = texelFetch(scene_depth, ivec2(gl_FragCoord.xy), 0).r;
    float fade = volfog_soft_particle_fade(particle_depth, depth, 0.5);

    vec3 lit = color.rgb + glow * phase;
    frag_color = vec4(volfog_apply_fog(lit, fog), color.a * fade);
}
