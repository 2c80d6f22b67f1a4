// Pass medium_shadow — the medium-shadow volume (volfog::medium_shadow): the optical
// depth towards the sun of the medium's extinction beyond its height profile, for
// inject@INJECT_MEDIUM_SHADOW (an extinction volume marched towards the light: Wronski
// 2014, "Future work"; Frostbite's volumetric shadow map).
//
// Dispatch: size.x x size.y x 1 workgroups of 1 x 1 x 64, one per column of the volume
// (one ray of sunlight), an invocation per slice, before inject and after the frame's
// uniforms and local volumes are written.
// Output: texel (i, j, k) = (tau, excess, 0, 1) at the texel's centre: excess the
//         mean over MEDIUM_SHADOW_SUBSAMPLES points evenly spread along the sunlight
//         through the texel's slice of the extinction of the medium (1/m: the height
//         profile with noise and
//         density texture, the custom density, the local volumes blended in, clamped at
//         0, as inject composes it) minus that of its bare height profile
//         (volfog::density::medium_extinction without noise or texture), each clamped
//         to [0, 1e4] first, tau the sum of excess * MediumShadow.step over the slices
//         before k plus half of slice k's (volfog::medium_shadow::medium_shadow_texel;
//         the sum runs over the workgroup, 64 slices at a time), clamped to +-6e4.
// Bindings (group 0), numbered as inject's:
//   1  uniform FogFrame (time)      2  uniform FogMedium
//   7  storage, read: array<LocalVolume> (FogMedium.local_volume_count elements used)
//   9  texture_3d<f32>: density texture; 10 sampler, linear, repeat
//      (VOLFOG_INJECT_DENSITY_TEXTURE only)
//  12  texture_3d<f32>: the baked noise texture; 13 sampler, linear, repeat
//      (VOLFOG_INJECT_NOISE_TEXTURE only)
//  31  uniform FogCustomParams (VOLFOG_INJECT_CUSTOM_DENSITY only)
//  34  storage, read: array<FogParticle>, the first FogMedium.particle_count elements
//      (VOLFOG_INJECT_PARTICLES only; each column gathers those that can reach it, 64
//      at a time, so none is dropped)
//  35  texture_storage_3d<rgba16float, write>: the medium-shadow volume
//  37  uniform MediumShadow: the volume's placement
// Defines: the medium's defines of the inject variant it serves, with their meaning
// there: VOLFOG_INJECT_NOISE_TEXTURE, VOLFOG_INJECT_NOISE_OCTAVES=N,
// VOLFOG_INJECT_DENSITY_TEXTURE, VOLFOG_INJECT_CUSTOM_DENSITY (composed with the
// user's volfog::custom_density module, never prebuilt), VOLFOG_INJECT_PARTICLES (the
// particles added to the medium clamped at 0, as inject adds them).

#import volfog::types::{FogFrame, FogMedium, LocalVolume, MediumShadow, FogSample}
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
#import volfog::noise::noise_animated_texture
#else
#import volfog::noise::noise_animated
#endif
#import volfog::density::{medium_shape, medium_extinction, local_volume_blend, local_volume_touches_sphere}
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
#import volfog::density::{local_volume_blend_textured, local_volume_texture_coord}
#endif
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
#import volfog::types::FogCustomParams
#import volfog::custom_density::volfog_custom_density
#endif
#ifdef VOLFOG_INJECT_PARTICLES
#import volfog::types::FogParticle
#import volfog::particles::{particle_density, particle_touches_sphere, particle_total}
#endif
#import volfog::density::medium_with_sample
#import volfog::medium_shadow::{medium_shadow_texel, MEDIUM_SHADOW_SUBSAMPLES}

@group(0) @binding(1) var<uniform> frame: FogFrame;
@group(0) @binding(2) var<uniform> fog_medium: FogMedium;
@group(0) @binding(7) var<storage, read> local_volumes: array<LocalVolume>;
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
@group(0) @binding(9) var density_texture: texture_3d<f32>;
@group(0) @binding(10) var density_sampler: sampler;
#endif
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
@group(0) @binding(12) var noise_texture: texture_3d<f32>;
@group(0) @binding(13) var noise_sampler: sampler;
#endif
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
@group(0) @binding(31) var<uniform> custom_params: FogCustomParams;
#endif
#ifdef VOLFOG_INJECT_PARTICLES
@group(0) @binding(34) var<storage, read> particles: array<FogParticle>;
// The particles of a chunk of 64 that can reach the column.
var<workgroup> column_particles: array<u32, 64>;
var<workgroup> column_particle_count: atomic<u32>;
#endif
@group(0) @binding(35) var medium_shadow_volume: texture_storage_3d<rgba16float, write>;
@group(0) @binding(37) var<uniform> medium_shadow: MediumShadow;

const NOISE_OCTAVES: u32 = #{VOLFOG_INJECT_NOISE_OCTAVES}u;
// Extinctions are clamped to [0, MAX_EXTINCTION] (1/m) before they are subtracted and
// optical depths to +-MAX_DEPTH (below the largest rgba16float value), so an
// exponential profile far below its base height (where the volume may reach
// underground) stays finite: no Inf, and no Inf - Inf, reaches the texels.
const MAX_EXTINCTION: f32 = 1e4;
const MAX_DEPTH: f32 = 6e4;

// The medium's extinction (1/m) at a world position beyond its bare height profile;
// `mask` bit i is set when local volume i can reach the column; `particle_extinction`
// is the particles' summed extinction there (1/m; 0 without them).
fn excess_extinction(world: vec3<f32>, mask: u32, volume_count: u32, particle_extinction: f32) -> f32 {
#ifdef VOLFOG_INJECT_NOISE_TEXTURE
    let noise = noise_animated_texture(noise_texture, noise_sampler, world, fog_medium.noise_scale, fog_medium.wind, frame.time, NOISE_OCTAVES);
#else
    let noise = noise_animated(world, fog_medium.noise_scale, fog_medium.wind, frame.time, NOISE_OCTAVES);
#endif
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
    let uvw = world * fog_medium.texture_scale + fog_medium.texture_offset - fog_medium.wind * frame.time * fog_medium.texture_scale;
    let texture_factor = select(1.0,
        textureSampleLevel(density_texture, density_sampler, uvw, 0.0).r, fog_medium.textured != 0u);
#else
    let texture_factor = 1.0;
#endif
    var medium = vec4<f32>(0.0, 0.0, 0.0, fog_medium.density * medium_shape(fog_medium, world, noise, texture_factor));
#ifdef VOLFOG_INJECT_CUSTOM_DENSITY
    medium = medium_with_sample(medium, volfog_custom_density(world, frame.time, custom_params));
#endif
    for (var i = 0u; i < volume_count; i++) {
        // Volumes past the first 32 are always evaluated.
        if i < 32u && (mask & (1u << i)) == 0u {
            continue;
        }
#ifdef VOLFOG_INJECT_DENSITY_TEXTURE
        let volume = local_volumes[i];
        var volume_factor = 1.0;
        if volume.textured != 0u {
            volume_factor = textureSampleLevel(density_texture, density_sampler,
                local_volume_texture_coord(volume, world), 0.0).r;
        }
        medium = local_volume_blend_textured(medium, volume, world, volume_factor);
#else
        medium = local_volume_blend(medium, local_volumes[i], world);
#endif
    }
    // The particles are added to the medium clamped at 0, as inject adds them.
    let total = medium_with_sample(max(medium, vec4<f32>(0.0)),
        particle_sum(particle_extinction)).a;
    return clamp(total, 0.0, MAX_EXTINCTION)
        - clamp(medium_extinction(fog_medium, world, 0.0, 1.0), 0.0, MAX_EXTINCTION);
}

// The particles' sum as a sample (their extinction; inject's particle_total, whose
// clamp the extinction passes through).
fn particle_sum(extinction: f32) -> FogSample {
#ifdef VOLFOG_INJECT_PARTICLES
    return particle_total(vec4<f32>(0.0, 0.0, 0.0, extinction), vec3<f32>(0.0));
#else
    return FogSample(vec3<f32>(0.0), extinction, vec3<f32>(0.0));
#endif
}

// Slices a workgroup handles at once: one invocation each.
const COLUMN: u32 = 64u;
// Each slice's optical depth (excess * step), then their running sums.
var<workgroup> column_depth: array<f32, 64>;
// Bit i: local volume i can reach the column (volumes past the first 32 always can).
var<workgroup> column_volumes: atomic<u32>;

@compute @workgroup_size(1, 1, 64)
fn medium_shadow_fill(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let size = medium_shadow.size;
    let column = (vec2<f32>(group.xy) + 0.5) / vec2<f32>(size.xy);
    let top = (medium_shadow.world_from_volume * vec4<f32>(column, 0.0, 1.0)).xyz;
    let bottom = (medium_shadow.world_from_volume * vec4<f32>(column, 1.0, 1.0)).xyz;
    if lane == 0u {
        atomicStore(&column_volumes, 0u);
    }
    workgroupBarrier();
    // The local volumes that can reach the column, one per invocation: each tested
    // against spheres that cover the column's segment (one a quarter of it, grown by a
    // texel's diagonal).
    let volume_count = min(fog_medium.local_volume_count, arrayLength(&local_volumes));
    let texel = length((medium_shadow.world_from_volume * vec4<f32>(1.0 / vec2<f32>(size.xy), 0.0, 0.0)).xyz);
    if lane < min(volume_count, 32u) {
        var touches = false;
        for (var q = 0u; q < 4u; q++) {
            let a = mix(top, bottom, f32(q) / 4.0);
            let b = mix(top, bottom, f32(q + 1u) / 4.0);
            touches = touches || local_volume_touches_sphere(local_volumes[lane], 0.5 * (a + b), 0.5 * distance(a, b) + texel);
        }
        if touches {
            atomicOr(&column_volumes, 1u << lane);
        }
    }
    workgroupBarrier();
    let mask = atomicLoad(&column_volumes);
    // COLUMN slices at a time: each invocation its slice's mean excess extinction from
    // MEDIUM_SHADOW_SUBSAMPLES points spread evenly along the sunlight through it, then
    // a running sum over the workgroup (Hillis and Steele's scan) for the optical depth
    // before it, carried from one group of slices to the next.
    var carry = 0.0;
    for (var base = 0u; base < size.z; base += COLUMN) {
        let k = base + lane;
        // The particles' extinction at this slice's points.
        var particle_extinction = vec4<f32>(0.0);
#ifdef VOLFOG_INJECT_PARTICLES
        let count = min(fog_medium.particle_count, arrayLength(&particles));
        for (var start = 0u; start < count; start += COLUMN) {
            if lane == 0u {
                atomicStore(&column_particle_count, 0u);
            }
            workgroupBarrier();
            let i = start + lane;
            if i < count {
                var touches = false;
                for (var q = 0u; q < 4u; q++) {
                    let a = mix(top, bottom, f32(q) / 4.0);
                    let b = mix(top, bottom, f32(q + 1u) / 4.0);
                    touches = touches || particle_touches_sphere(particles[i], 0.5 * (a + b), 0.5 * distance(a, b) + texel);
                }
                if touches {
                    column_particles[atomicAdd(&column_particle_count, 1u)] = i;
                }
            }
            workgroupBarrier();
            let listed = min(atomicLoad(&column_particle_count), COLUMN);
            for (var n = 0u; n < listed; n++) {
                let p = particles[column_particles[n]];
                for (var j = 0u; j < MEDIUM_SHADOW_SUBSAMPLES; j++) {
                    let w = (f32(k) + (f32(j) + 0.5) / f32(MEDIUM_SHADOW_SUBSAMPLES)) / f32(size.z);
                    particle_extinction[j] += particle_density(p, mix(top, bottom, w));
                }
            }
            workgroupBarrier();
        }
#endif
        var excess = 0.0;
        if k < size.z {
            for (var j = 0u; j < MEDIUM_SHADOW_SUBSAMPLES; j++) {
                let w = (f32(k) + (f32(j) + 0.5) / f32(MEDIUM_SHADOW_SUBSAMPLES)) / f32(size.z);
                excess += excess_extinction(mix(top, bottom, w), mask, volume_count, particle_extinction[j]);
            }
            excess /= f32(MEDIUM_SHADOW_SUBSAMPLES);
        }
        column_depth[lane] = excess * medium_shadow.step;
        workgroupBarrier();
        for (var offset = 1u; offset < COLUMN; offset *= 2u) {
            var before = 0.0;
            if lane >= offset {
                before = column_depth[lane - offset];
            }
            workgroupBarrier();
            column_depth[lane] += before;
            workgroupBarrier();
        }
        // The slices before k: the carry and this group's sum through k, less k's own.
        let prefix = carry + column_depth[lane] - excess * medium_shadow.step;
        let total = column_depth[COLUMN - 1u];
        workgroupBarrier();
        if k < size.z {
            let tau = clamp(medium_shadow_texel(prefix, excess, medium_shadow.step), -MAX_DEPTH, MAX_DEPTH);
            textureStore(medium_shadow_volume, vec3<u32>(group.xy, k), vec4<f32>(tau, excess, 0.0, 1.0));
        }
        carry = clamp(carry + total, -MAX_DEPTH, MAX_DEPTH);
    }
}
