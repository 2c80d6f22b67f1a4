// Pass esm_blur — separable box filter of the ESM, 2 * radius + 1 taps (11 by default),
// as two passes: esm_blur_x then esm_blur_y (Wronski 2014, bonus slide: "separable
// 11-pixel wide box filter (2 trivial passes)"). Each workgroup loads a row (or column)
// segment plus its apron into workgroup memory once.
//
// Dispatch: esm_blur_x: ceil(width / 64) x height x cascades workgroups of 64 x 1 x 1;
//           esm_blur_y: ceil(height / 64) x width x cascades workgroups of 64 x 1 x 1.
// Bindings (group 0):
//   0  texture_2d_array<f32>: source ESM (R32Float, textureLoad)
//   1  texture_storage_2d_array<r32float, write>: filtered ESM
// Edges clamp. Defines: VOLFOG_ESM_BLUR_RADIUS=N (1..=16, default 5),
// VOLFOG_ESM_LOG_SPACE (averages in the linear domain of log-space values: one streaming
// log-sum-exp over the window, volfog::esm::esm_sum_add4).

#import volfog::esm::{ESM_SUM_EMPTY, esm_sum_add4, esm_sum_mean}

@group(0) @binding(0) var unfiltered: texture_2d_array<f32>;
@group(0) @binding(1) var filtered: texture_storage_2d_array<r32float, write>;

const RADIUS: i32 = #{VOLFOG_ESM_BLUR_RADIUS};
const GROUP: i32 = 64;

var<workgroup> segment: array<f32, 96>;

// Loads the segment [start - RADIUS, start + GROUP + RADIUS) of line `fixed` along the
// axis (0: x, 1: y) into workgroup memory, then averages each output's window.
fn blur(axis: u32, lid: i32, start: i32, fixed: i32, layer: u32) {
    let size = vec2<i32>(textureDimensions(unfiltered));
    let length = select(size.x, size.y, axis == 1u);
    for (var i = lid; i < GROUP + 2 * RADIUS; i += GROUP) {
        let p = clamp(start - RADIUS + i, 0, length - 1);
        let coord = select(vec2<i32>(p, fixed), vec2<i32>(fixed, p), axis == 1u);
        segment[i] = textureLoad(unfiltered, coord, layer, 0).r;
    }
    workgroupBarrier();
    let p = start + lid;
    if p >= length {
        return;
    }
    // The window's 2 RADIUS + 1 values, four at a time (the last four overhang it).
    let last = lid + 2 * RADIUS;
    var sum = ESM_SUM_EMPTY;
    for (var k = 0; k <= 2 * RADIUS; k += 4) {
        let at = lid + k;
        let v = vec4<f32>(segment[at], segment[min(at + 1, last)], segment[min(at + 2, last)],
            segment[min(at + 3, last)]);
        sum = esm_sum_add4(sum, v, vec4<f32>(vec4<i32>(at) + vec4<i32>(0, 1, 2, 3) <= vec4<i32>(last)));
    }
    let mean = esm_sum_mean(sum, f32(2 * RADIUS + 1));
    let coord = select(vec2<i32>(p, fixed), vec2<i32>(fixed, p), axis == 1u);
    textureStore(filtered, coord, layer, vec4<f32>(mean, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(64, 1, 1)
fn esm_blur_x(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>) {
    blur(0u, i32(lid.x), i32(group.x) * GROUP, i32(group.y), group.z);
}

@compute @workgroup_size(64, 1, 1)
fn esm_blur_y(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>) {
    blur(1u, i32(lid.x), i32(group.x) * GROUP, i32(group.y), group.z);
}
