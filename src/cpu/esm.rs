//! Mirror of `volfog::esm` and of the ESM passes: encoding, 4x downsampling, the
//! separable box blur and the visibility lookup, in linear or log space.
//!
//! ```
//! use volfog::cpu::esm::{esm_encode, esm_visibility};
//! let c = 80.0;
//! let occluder = esm_encode(0.5, c, false);
//! assert_eq!(esm_visibility(occluder, 0.4, c, false), 1.0); // in front: lit
//! assert!(esm_visibility(occluder, 0.5 + 3.0 / c, c, false) < 0.05); // 3 / c behind: shadowed
//! ```

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::uniforms::ShadowCascades;

/// Occluder value of one depth.
pub fn esm_encode(depth: f32, exponent: f32, log_space: bool) -> f32 {
    if log_space {
        exponent * depth
    } else {
        (exponent * depth).exp()
    }
}

/// The empty running sum of `volfog::esm` (`ESM_SUM_EMPTY`): x the largest value added
/// (log space), y the sum.
pub const ESM_SUM_EMPTY: Vec2 = Vec2::new(-1.0e30, 0.0);

/// Adds the values of `v` to a running sum, each with weight 1 (added) or 0 (left
/// out) (`esm_sum_add4`): in log space a streaming log-sum-exp, in linear space the
/// plain sum.
pub fn esm_sum_add4(sum: Vec2, v: Vec4, weight: Vec4, log_space: bool) -> Vec2 {
    if log_space {
        let masked = v - (1.0 - weight) * 1.0e30;
        let peak = sum.x.max(masked.max_element());
        let terms = weight * (masked - peak).exp();
        Vec2::new(peak, sum.y * (sum.x - peak).exp() + terms.element_sum())
    } else {
        Vec2::new(sum.x, sum.y + v.dot(weight))
    }
}

/// Mean of the `n >= 1` values added to a running sum (`esm_sum_mean`).
pub fn esm_sum_mean(sum: Vec2, n: f32, log_space: bool) -> f32 {
    if log_space {
        sum.x + (sum.y / n).ln()
    } else {
        sum.y / n
    }
}

/// Visibility of a receiver.
pub fn esm_visibility(occluder: f32, receiver: f32, exponent: f32, log_space: bool) -> f32 {
    if log_space {
        (occluder - exponent * receiver)
            .min(0.0)
            .exp()
            .clamp(0.0, 1.0)
    } else {
        (occluder * (-exponent * receiver).exp()).clamp(0.0, 1.0)
    }
}

/// One layer of a 2D float image, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels.
    pub texels: Vec<f32>,
}

impl Layer {
    /// Texel with clamp to edge.
    pub fn at(&self, x: i32, y: i32) -> f32 {
        let x = x.clamp(0, self.width as i32 - 1) as u32;
        let y = y.clamp(0, self.height as i32 - 1) as u32;
        self.texels[(y * self.width + x) as usize]
    }
}

/// The downsample pass: each output texel is the mean of the encoded 4x4 block, its
/// four gathers added to the running sum in the pass's order.
pub fn downsample(depth: &Layer, exponent: f32, log_space: bool) -> Layer {
    let (w, h) = (depth.width / 4, depth.height / 4);
    let mut texels = Vec::with_capacity((w * h) as usize);
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            let quad = |ox: i32, oy: i32| {
                let (bx, by) = (4 * x + ox, 4 * y + oy);
                let v = Vec4::new(
                    depth.at(bx, by + 1),
                    depth.at(bx + 1, by + 1),
                    depth.at(bx + 1, by),
                    depth.at(bx, by),
                );
                Vec4::from_array(v.to_array().map(|d| esm_encode(d, exponent, log_space)))
            };
            let sum = [(0, 0), (2, 0), (0, 2), (2, 2)]
                .into_iter()
                .fold(ESM_SUM_EMPTY, |sum, (ox, oy)| {
                    esm_sum_add4(sum, quad(ox, oy), Vec4::ONE, log_space)
                });
            texels.push(esm_sum_mean(sum, 16.0, log_space));
        }
    }
    Layer {
        width: w,
        height: h,
        texels,
    }
}

/// One pass of the box blur along x (`axis = 0`) or y, `2 radius + 1` taps, clamped.
pub fn blur(layer: &Layer, radius: i32, axis: u32, log_space: bool) -> Layer {
    let mut texels = Vec::with_capacity(layer.texels.len());
    for y in 0..layer.height as i32 {
        for x in 0..layer.width as i32 {
            let tap = |k: i32| {
                if axis == 0 {
                    layer.at(x - radius + k, y)
                } else {
                    layer.at(x, y - radius + k)
                }
            };
            // Four taps at a time, as the pass sums them (the last four overhang).
            let mut sum = ESM_SUM_EMPTY;
            for k in (0..=2 * radius).step_by(4) {
                let v =
                    Vec4::from_array(std::array::from_fn(|i| tap((k + i as i32).min(2 * radius))));
                let weight = Vec4::from_array(std::array::from_fn(|i| {
                    f32::from(u8::from(k + i as i32 <= 2 * radius))
                }));
                sum = esm_sum_add4(sum, v, weight, log_space);
            }
            texels.push(esm_sum_mean(sum, (2 * radius + 1) as f32, log_space));
        }
    }
    Layer {
        width: layer.width,
        height: layer.height,
        texels,
    }
}

/// Bilinear occluder lookup at uv (clamp to edge).
pub fn esm_occluder(layer: &Layer, uv: Vec2, log_space: bool) -> f32 {
    let texel = uv * Vec2::new(layer.width as f32, layer.height as f32) - 0.5;
    let base = texel.floor();
    let f = texel - base;
    let (x, y) = (base.x as i32, base.y as i32);
    let v = Vec4::new(
        layer.at(x, y),
        layer.at(x + 1, y),
        layer.at(x, y + 1),
        layer.at(x + 1, y + 1),
    );
    let w = Vec4::new(
        (1.0 - f.x) * (1.0 - f.y),
        f.x * (1.0 - f.y),
        (1.0 - f.x) * f.y,
        f.x * f.y,
    );
    if log_space {
        let m = v.max_element();
        m + (v - m).exp().dot(w).max(1e-30).ln()
    } else {
        v.dot(w)
    }
}

/// Cascade index of a view depth.
pub fn esm_cascade(view_depth: f32, splits: Vec4, count: u32) -> u32 {
    let mut i = 0;
    while i < count && view_depth >= splits[i as usize] {
        i += 1;
    }
    i
}

/// Shadow-map uv (v down) and depth of a world position.
pub fn esm_shadow_coord(light_from_world: Mat4, world: Vec3) -> Vec3 {
    let ndc = light_from_world.project_point3(world);
    Vec3::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5, ndc.z)
}

/// Visibility of the directional light at a world position in one cascade (its
/// matrix and ESM layer); 1 outside the cascade's shadow map.
pub fn esm_shadow_cascade(
    layer: &Layer,
    light_from_world: Mat4,
    exponent: f32,
    world: Vec3,
    log_space: bool,
) -> f32 {
    let coord = esm_shadow_coord(light_from_world, world);
    if coord.x < 0.0 || coord.y < 0.0 || coord.x > 1.0 || coord.y > 1.0 || coord.z > 1.0 {
        return 1.0;
    }
    let occluder = esm_occluder(layer, Vec2::new(coord.x, coord.y), log_space);
    esm_visibility(occluder, coord.z.clamp(0.0, 1.0), exponent, log_space)
}

/// Visibility of the directional light at a world position and view depth.
pub fn esm_shadow(
    layers: &[Layer],
    cascades: &ShadowCascades,
    world: Vec3,
    view_depth: f32,
    log_space: bool,
) -> f32 {
    let i = esm_cascade(view_depth, cascades.splits, cascades.count);
    if i >= cascades.count {
        return 1.0;
    }
    esm_shadow_cascade(
        &layers[i as usize],
        cascades.light_from_world[i as usize],
        cascades.exponent,
        world,
        log_space,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The running sum gives the mean of its values, in any order and with any of
    /// them left out, against the mean taken in f64: log(mean(exp(v))) in log space
    /// (values up to 300, where exp overflows f32), mean(v) in linear space.
    #[test]
    fn running_sum_is_the_mean_of_the_values_added() {
        let values: Vec<f32> = (0..23)
            .map(|i| ((i * 37) % 23) as f32 * 13.0 + 0.5)
            .collect();
        for log_space in [false, true] {
            for (order, keep) in [(false, 1), (true, 1), (false, 3)] {
                let mut v = values.clone();
                if order {
                    v.reverse();
                }
                let mut sum = ESM_SUM_EMPTY;
                let mut kept = Vec::new();
                for (q, chunk) in v.chunks(4).enumerate() {
                    let quad = Vec4::from_array(std::array::from_fn(|i| {
                        chunk.get(i).copied().unwrap_or(1e9)
                    }));
                    let valid: [bool; 4] =
                        std::array::from_fn(|i| i < chunk.len() && (q * 4 + i) % keep == 0);
                    kept.extend((0..4).filter(|&i| valid[i]).map(|i| f64::from(quad[i])));
                    let weight = Vec4::from_array(valid.map(|k| f32::from(u8::from(k))));
                    sum = esm_sum_add4(sum, quad, weight, log_space);
                }
                let n = kept.len() as f64;
                let (got, want) = if log_space {
                    let peak = kept.iter().copied().fold(f64::MIN, f64::max);
                    let mean = kept.iter().map(|x| (x - peak).exp()).sum::<f64>() / n;
                    (esm_sum_mean(sum, n as f32, true), peak + mean.ln())
                } else {
                    (
                        esm_sum_mean(sum, n as f32, false),
                        kept.iter().sum::<f64>() / n,
                    )
                };
                assert!(
                    (f64::from(got) - want).abs() <= 1e-6 * want.abs(),
                    "log space {log_space}, reversed {order}, every {keep}: {got} against {want}"
                );
            }
        }
    }
}
