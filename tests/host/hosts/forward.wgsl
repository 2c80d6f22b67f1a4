// The shaders of a forward-lit transparent surface in a WebGPU engine that does not use
// naga_oil: volfog_all.wgsl is pasted in front of this file (WGSL has no #include), the
// engine declares its own resources, and each snippet function that takes resources or
// structs is called. The host test creates the pipeline in Dawn.

struct FogParams {
    froxels: volfog_Froxels,
    tail: volfog_HeightFog,
    height_fog: volfog_HeightFog,
    hull: volfog_FogVolume,
    view_from_world: mat4x4<f32>,
    camera_position: vec4<f32>,
    flash: vec4<f32>,
    flash_attenuation: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: FogParams;
@group(0) @binding(1) var fog_integrated: texture_3d<f32>;
@group(0) @binding(2) var fog_sampler: sampler;
// A depth buffer bound as unfilterable-float, as volfog's apply pass binds it (WebGPU
// compatibility mode has no textureLoad of depth textures).
@group(0) @binding(3) var scene_depth: texture_2d<f32>;

struct Varyings {
    @builtin(position) position: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) particle_depth: f32,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> Varyings {
    var v: Varyings;
    v.position = vec4<f32>(position, 1.0);
    v.world = position;
    v.color = vec4<f32>(1.0);
    v.particle_depth = 1.0;
    return v;
}

@fragment
fn fs_main(v: Varyings) -> @location(0) vec4<f32> {
    let coord = volfog_fog_coord_from_world(v.world, params.view_from_world, params.froxels);
    let froxel_fog = volfog_fog_sample(fog_integrated, fog_sampler, coord);
    let nearest = volfog_fog_load(fog_integrated, coord);
    let view_pos = volfog_fog_view_position(v.world, params.view_from_world);
    var fog = volfog_fog_with_tail(mix(froxel_fog, nearest, vec4<f32>(0.5)),
                                   volfog_fog_tail(params.froxels, params.tail, view_pos));

    let eye = params.camera_position.xyz;
    let analytic = volfog_height_fog(params.height_fog, eye, v.world - eye);
    let local_fog = volfog_fog_volume(params.hull, eye, v.world);
    fog = volfog_fog_over(volfog_fog_over(local_fog, analytic), fog);

    let glow = volfog_volumetric_lightning(params.flash.w, params.flash_attenuation.x,
                                           params.flash.xyz, eye, v.world - eye);
    let to_flash = normalize(params.flash.xyz - v.world);
    let to_eye = normalize(eye - v.world);
    let phase = volfog_phase_hg(dot(to_flash, -to_eye), 0.6);

    let depth = textureLoad(scene_depth, vec2<i32>(v.position.xy), 0).r;
    let fade = volfog_soft_particle_fade(v.particle_depth, depth, 0.5);

    let lit = v.color.rgb + glow * phase;
    return vec4<f32>(volfog_apply_fog(lit, fog), v.color.a * fade);
}
