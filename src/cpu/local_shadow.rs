//! Mirror of `volfog::local_shadow` and of the `local_shadow_downsample` pass: shadows
//! and cookies of point and spot lights from the local-light ESM atlas.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::local_shadow::local_shadow_cube;
//! // A point 2 m along -Y of the light falls in the middle of face 3 (-Y), 2 m deep.
//! let c = local_shadow_cube(Vec3::new(0.0, -2.0, 0.0));
//! assert_eq!((c.face, c.depth), (3, 2.0));
//! assert_eq!(c.uv, glam::Vec2::splat(0.5));
//! ```

use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};

use super::esm::{
    ESM_SUM_EMPTY, Layer, esm_encode, esm_occluder, esm_sum_add4, esm_sum_mean, esm_visibility,
};
use super::frustum::frustum_depth_from_terms;
use super::shadow::{shadow_depth_increasing, shadow_pcf, shadow_receiver_depth};
use crate::uniforms::{
    LOCAL_SHADOW_NONE, LOCAL_SHADOW_POINT, LOCAL_SHADOW_SPOT, LightProjection, LocalShadowSource,
};

/// Where a direction from a point light falls on its cube map (WGSL `CubeCoord`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubeCoord {
    /// Coordinate on the face, [0, 1]^2, v down.
    pub uv: Vec2,
    /// Face: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
    pub face: u32,
    /// Distance along the face's axis.
    pub depth: f32,
}

/// The cube face, its coordinate and the depth along its axis of `v` (cube-map space,
/// from the light to the point).
pub fn local_shadow_cube(v: Vec3) -> CubeCoord {
    let a = v.abs();
    let (face, depth, st) = if a.x >= a.y && a.x >= a.z {
        let positive = v.x >= 0.0;
        (
            if positive { 0 } else { 1 },
            a.x,
            Vec2::new(if positive { -v.z } else { v.z }, -v.y),
        )
    } else if a.y >= a.z {
        let positive = v.y >= 0.0;
        (
            if positive { 2 } else { 3 },
            a.y,
            Vec2::new(v.x, if positive { v.z } else { -v.z }),
        )
    } else {
        let positive = v.z >= 0.0;
        (
            if positive { 4 } else { 5 },
            a.z,
            Vec2::new(if positive { v.x } else { -v.x }, -v.y),
        )
    };
    CubeCoord {
        uv: 0.5 * st / depth.max(1e-30) + 0.5,
        face,
        depth,
    }
}

/// Texture coordinate (xy, v down) and depth along the axis (z) of a world position in
/// a spot light's shadow camera.
pub fn local_shadow_spot(light_from_world: Mat4, world: Vec3) -> Vec3 {
    let clip = light_from_world * world.extend(1.0);
    let w = if clip.w.abs() < 1e-30 { 1e-30 } else { clip.w };
    Vec3::new(clip.x / w * 0.5 + 0.5, 0.5 - clip.y / w * 0.5, clip.w)
}

/// In front of the light and inside its shadow camera's frustum.
pub fn local_shadow_spot_inside(coord: Vec3) -> bool {
    coord.z > 0.0 && coord.x >= 0.0 && coord.y >= 0.0 && coord.x <= 1.0 && coord.y <= 1.0
}

/// Linear depth in [0, 1] the atlas stores for a shadow-map depth value.
pub fn local_shadow_linear_depth(depth_terms: Vec4, d: f32, depth_range: f32) -> f32 {
    (frustum_depth_from_terms(depth_terms, d) / depth_range).clamp(0.0, 1.0)
}

/// Occluder value of one shadow-map depth.
pub fn local_shadow_encode(
    depth_terms: Vec4,
    d: f32,
    depth_range: f32,
    exponent: f32,
    log_space: bool,
) -> f32 {
    esm_encode(
        local_shadow_linear_depth(depth_terms, d, depth_range),
        exponent,
        log_space,
    )
}

/// Visibility in [0, 1] of a light at a world position through its ESM in the atlas
/// (`atlas[layer]`, filtered as the passes filter it).
pub fn local_shadow_visibility(
    atlas: &[Layer],
    p: &LightProjection,
    world: Vec3,
    log_space: bool,
) -> f32 {
    if p.layer == LOCAL_SHADOW_NONE {
        return 1.0;
    }
    let (uv, layer, depth) = if p.kind == LOCAL_SHADOW_POINT {
        let c = local_shadow_cube(p.light_from_world.transform_point3(world));
        (c.uv, p.layer + c.face, c.depth)
    } else {
        let s = local_shadow_spot(p.light_from_world, world);
        if !local_shadow_spot_inside(s) {
            return 1.0;
        }
        (s.truncate(), p.layer, s.z)
    };
    let receiver = ((depth - p.bias) / p.depth_range).clamp(0.0, 1.0);
    let occluder = esm_occluder(&atlas[layer as usize], uv, log_space);
    esm_visibility(occluder, receiver, p.exponent, log_space)
}

/// Visibility in [0, 1] of a light at a world position by the compare filter
/// (`local_shadow_compare`): a 2 x 2 percentage-closer compare against its own depth
/// map, `spot_maps[layer]` or, for a point light, `point_maps[layer + face]`.
pub fn local_shadow_compare(
    spot_maps: &[Layer],
    point_maps: &[Layer],
    p: &LightProjection,
    world: Vec3,
) -> f32 {
    if p.layer == LOCAL_SHADOW_NONE {
        return 1.0;
    }
    let increasing = shadow_depth_increasing(p.depth_terms);
    let (map, uv, depth) = if p.kind == LOCAL_SHADOW_POINT {
        let c = local_shadow_cube(p.light_from_world.transform_point3(world));
        (&point_maps[(p.layer + c.face) as usize], c.uv, c.depth)
    } else {
        let s = local_shadow_spot(p.light_from_world, world);
        if !local_shadow_spot_inside(s) {
            return 1.0;
        }
        (&spot_maps[p.layer as usize], s.truncate(), s.z)
    };
    let receiver = shadow_receiver_depth(p.depth_terms, (depth - p.bias).max(0.0));
    shadow_pcf(map, uv, receiver, increasing)
}

/// One layer of an rgba image (a cookie), row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorLayer {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels (linear rgba).
    pub texels: Vec<Vec4>,
}

impl ColorLayer {
    /// Texel with clamp to edge.
    pub fn at(&self, x: i32, y: i32) -> Vec4 {
        let x = x.clamp(0, self.width as i32 - 1) as u32;
        let y = y.clamp(0, self.height as i32 - 1) as u32;
        self.texels[(y * self.width + x) as usize]
    }

    /// Bilinear sample at uv with clamp to edge (a linear sampler's result, before the
    /// GPU's fixed-point weights).
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        let texel = uv * Vec2::new(self.width as f32, self.height as f32) - 0.5;
        let base = texel.floor();
        let f = texel - base;
        let (x, y) = (base.x as i32, base.y as i32);
        let top = self.at(x, y).lerp(self.at(x + 1, y), f.x);
        let bottom = self.at(x, y + 1).lerp(self.at(x + 1, y + 1), f.x);
        top.lerp(bottom, f.y)
    }
}

/// Colour a spot light's cookie gives its light at a world position (`cookies[layer]`);
/// 0 outside its frustum, 1 without a cookie or for a point light.
pub fn light_cookie(cookies: &[ColorLayer], p: &LightProjection, world: Vec3) -> Vec3 {
    if p.cookie == LOCAL_SHADOW_NONE || p.kind != LOCAL_SHADOW_SPOT {
        return Vec3::ONE;
    }
    let s = local_shadow_spot(p.light_from_world, world);
    if !local_shadow_spot_inside(s) {
        return Vec3::ZERO;
    }
    cookies[p.cookie as usize].sample(s.truncate()).truncate()
}

/// The `local_shadow_downsample` pass for one source: each atlas texel is the mean
/// occluder value of a `factor x factor` block of the depth layer (`factor` = depth
/// width / `size`), summed 2 x 2 texels at a time with [`esm_sum_add4`] as the pass's
/// gathers do (texels past the block's edge, where `factor` is odd, left out).
pub fn downsample(depth: &Layer, source: &LocalShadowSource, size: u32, log_space: bool) -> Layer {
    let factor = (depth.width / size).max(1);
    let rows = factor.div_ceil(2);
    let encode = |d: f32| {
        local_shadow_encode(
            source.depth_terms,
            d,
            source.depth_range,
            source.exponent,
            log_space,
        )
    };
    let mut texels = Vec::with_capacity((size * size) as usize);
    for y in 0..size {
        for x in 0..size {
            let (origin, last) = (
                UVec2::new(x, y) * factor,
                UVec2::new(x, y) * factor + factor - 1,
            );
            let mut sum = ESM_SUM_EMPTY;
            for j in 0..rows {
                for i in 0..rows {
                    let a = origin + 2 * UVec2::new(i, j);
                    let b = (a + 1).min(last);
                    let at = |x: u32, y: u32| encode(depth.at(x as i32, y as i32));
                    // In the order of the pass's gather.
                    let v = Vec4::new(at(a.x, b.y), at(b.x, b.y), at(b.x, a.y), at(a.x, a.y));
                    let inside = Vec2::new(
                        f32::from(u8::from(a.x < last.x)),
                        f32::from(u8::from(a.y < last.y)),
                    );
                    let weight = Vec4::new(inside.y, inside.x * inside.y, inside.x, 1.0);
                    sum = esm_sum_add4(sum, v, weight, log_space);
                }
            }
            texels.push(esm_sum_mean(sum, (factor * factor) as f32, log_space));
        }
    }
    Layer {
        width: size,
        height: size,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uniforms::{FogLight, LightCamera};

    /// Every face's view and projection puts a point where `local_shadow_cube` says,
    /// at the depth it says: the cube layout the atlas assumes is the one
    /// `LightCamera::cube_face_view` renders.
    #[test]
    fn cube_faces_match_their_cameras() {
        let light = FogLight::point(Vec3::new(1.0, 2.0, 3.0), Vec3::ONE, 20.0);
        let LightCamera::Point {
            cube_from_world,
            clip_from_view,
        } = LightCamera::point(&light, 0.1).unwrap()
        else {
            unreachable!()
        };
        let mut rng = crate::cpu::TestRng(7);
        let mut faces = [0; 6];
        for _ in 0..2000 {
            let v = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            if v.length() < 0.1 {
                continue;
            }
            let world = light.position + 5.0 * v;
            let c = local_shadow_cube(cube_from_world.transform_point3(world));
            faces[c.face as usize] += 1;
            let clip = clip_from_view
                * LightCamera::cube_face_view(c.face)
                * cube_from_world
                * world.extend(1.0);
            let uv = Vec2::new(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
            assert!(
                (uv - c.uv).abs().max_element() < 1e-5,
                "{v} face {}",
                c.face
            );
            assert!((clip.w - c.depth).abs() < 1e-4 * c.depth.max(1.0));
        }
        assert!(faces.iter().all(|&n| n > 200), "{faces:?}");
    }

    /// The linear depth of a rendered depth value is its view depth over the range,
    /// for standard, reversed and infinite reversed projections.
    #[test]
    fn linear_depth_undoes_every_depth_convention() {
        use glam::camera::rh::proj::directx;
        let (near, far) = (0.2f32, 25.0f32);
        let projections = [
            directx::perspective(1.0, 1.0, near, far),
            directx::perspective(1.0, 1.0, far, near),
            directx::perspective_infinite_reverse(1.0, 1.0, near),
        ];
        for proj in projections {
            let camera = LightCamera::Spot {
                view_from_world: Mat4::IDENTITY,
                clip_from_view: proj,
            };
            let terms = camera.depth_terms().unwrap();
            for z in [0.5f32, 3.0, 12.0, 24.0] {
                let clip = proj * Vec4::new(0.0, 0.0, -z, 1.0);
                let d = clip.z / clip.w;
                let linear = local_shadow_linear_depth(terms, d, far);
                assert!((linear - z / far).abs() < 2e-4, "{proj} {z}: {linear}");
            }
        }
    }

    /// A block of one depth downsamples to that depth's occluder value, linear and
    /// log space alike; a block with a far half is the mean of the two values.
    #[test]
    fn downsample_averages_occluders_of_linear_depths() {
        let source = LocalShadowSource {
            depth_terms: Vec4::new(0.0, -1.0, 0.0, 1.0), // view depth 1 m for any d
            depth_range: 4.0,
            exponent: 20.0,
            ..Default::default()
        };
        let depth = Layer {
            width: 8,
            height: 8,
            texels: vec![0.5; 64],
        };
        for log_space in [false, true] {
            let atlas = downsample(&depth, &source, 2, log_space);
            let want = esm_encode(0.25, 20.0, log_space);
            assert!(
                atlas
                    .texels
                    .iter()
                    .all(|v| (v - want).abs() <= 1e-5 * want.abs())
            );
        }
        // Depth terms of view depth = d (m): half the block at 1 m, half at 3 m.
        let source = LocalShadowSource {
            depth_terms: Vec4::new(-1.0, 0.0, 0.0, 1.0),
            ..source
        };
        let depth = Layer {
            width: 2,
            height: 2,
            texels: vec![1.0, 3.0, 1.0, 3.0],
        };
        let linear = downsample(&depth, &source, 1, false).texels[0];
        let log = downsample(&depth, &source, 1, true).texels[0];
        let mean = 0.5 * ((20.0f32 * 0.25).exp() + (20.0f32 * 0.75).exp());
        assert!((linear - mean).abs() < 1e-5 * mean);
        assert!((log - mean.ln()).abs() < 1e-5);
    }

    /// An odd factor: each atlas texel is the mean of its own 3 x 3 block, whatever
    /// lies beyond it (the pass's 2 x 2 quads overhang the block and leave that out).
    #[test]
    fn downsample_by_an_odd_factor_keeps_to_each_block() {
        let source = LocalShadowSource {
            depth_terms: Vec4::new(-1.0, 0.0, 0.0, 1.0), // view depth = d (m)
            depth_range: 8.0,
            exponent: 30.0,
            ..Default::default()
        };
        let depth = Layer {
            width: 6,
            height: 6,
            texels: (0..36).map(|i| 0.5 + ((i * 7) % 13) as f32 * 0.5).collect(),
        };
        for log_space in [false, true] {
            let atlas = downsample(&depth, &source, 2, log_space);
            for (t, got) in atlas.texels.iter().enumerate() {
                let (bx, by) = (t % 2 * 3, t / 2 * 3);
                let block: Vec<f64> = (0..9)
                    .map(|k| f64::from(depth.texels[(by + k / 3) * 6 + bx + k % 3]) / 8.0 * 30.0)
                    .collect();
                let mean = block.iter().map(|z| z.exp()).sum::<f64>() / 9.0;
                let want = if log_space { mean.ln() } else { mean };
                assert!(
                    (f64::from(*got) - want).abs() <= 1e-5 * want.abs(),
                    "log space {log_space}, texel {t}: {got} against {want}"
                );
            }
        }
    }
}
