// Pass epipolar_refine — places the ray-marching samples (Yusov 2012, 6.2): samples
// initial_step apart (denser next to the epipole) plus the samples on both sides of
// every depth break; every other sample gets the two ray-marching samples of its run
// to interpolate from. Depth-break flags are packed 32 to a word in workgroup memory
// and searched with firstLeadingBit / firstTrailingBit.
//
// Dispatch: samples / 128 x slices workgroups, after epipolar_coords.
// Bindings (group 0):
//   0 uniform EpipolarFrame
//   1 texture_2d<f32>, unfilterable: the coordinate texture (epipolar_coords)
//   2 storage texture r32uint (samples x slices), write: the interpolation sources of
//     each sample, packed by epipolar_pack_sources (equal for ray-marching samples and
//     for samples off the screen)

#import volfog::types::EpipolarFrame
#import volfog::epipolar::{epipolar_continuous, epipolar_section, epipolar_sources, epipolar_pack_sources, EPIPOLAR_GROUP, EPIPOLAR_INVALID_DEPTH}

@group(0) @binding(0) var<uniform> epipolar_frame: EpipolarFrame;
@group(0) @binding(1) var coords: texture_2d<f32>;
@group(0) @binding(2) var source_pairs: texture_storage_2d<r32uint, write>;

var<workgroup> packed_flags: array<atomic<u32>, 4>;

@compute @workgroup_size(128, 1, 1)
fn epipolar_refine(@builtin(local_invocation_index) local: u32, @builtin(workgroup_id) group: vec3<u32>) {
    if local < 4u {
        atomicStore(&packed_flags[local], 0u);
    }
    workgroupBarrier();
    let base = group.x * EPIPOLAR_GROUP;
    let k = base + local;
    let slice = i32(group.y);
    let valid = k < epipolar_frame.samples;
    var z0 = EPIPOLAR_INVALID_DEPTH;
    var z1 = EPIPOLAR_INVALID_DEPTH;
    if valid {
        z0 = textureLoad(coords, vec2<i32>(i32(k), slice), 0).z;
    }
    if k + 1u < epipolar_frame.samples {
        z1 = textureLoad(coords, vec2<i32>(i32(k) + 1, slice), 0).z;
    }
    if epipolar_continuous(z0, z1, epipolar_frame.depth_threshold) {
        atomicOr(&packed_flags[local / 32u], 1u << (local % 32u));
    }
    workgroupBarrier();
    let flags = vec4<u32>(
        atomicLoad(&packed_flags[0]),
        atomicLoad(&packed_flags[1]),
        atomicLoad(&packed_flags[2]),
        atomicLoad(&packed_flags[3]),
    );
    if !valid {
        return;
    }
    let section = epipolar_section(epipolar_frame.initial_step, epipolar_frame.samples, k);
    let local_sources = epipolar_sources(flags, local, section.x - base, section.y - base);
    textureStore(source_pairs, vec2<i32>(i32(k), slice), vec4<u32>(epipolar_pack_sources(local_sources + base), 0u, 0u, 0u));
}
