//! Mirror of `volfog::shadow` (the compare filter) and of the tap offsets the runtime
//! uploads with each frame ([`shadow_taps`]).
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use volfog::cpu::esm::Layer;
//! use volfog::cpu::shadow::{shadow_pcf, shadow_taps};
//!
//! // An occluder at depth 0.3 over the left half of a 4 x 4 map, nothing on the right.
//! let texels = (0..16).map(|i| if i % 4 < 2 { 0.3 } else { 1.0 }).collect();
//! let map = Layer { width: 4, height: 4, texels };
//! assert_eq!(shadow_pcf(&map, Vec2::new(0.2, 0.5), 0.5, true), 0.0); // behind it
//! assert_eq!(shadow_pcf(&map, Vec2::new(0.8, 0.5), 0.5, true), 1.0); // beside it
//! assert_eq!(shadow_pcf(&map, Vec2::new(0.5, 0.5), 0.5, true), 0.5); // on its edge
//! // One tap per froxel with history, four without; tap 0 is the froxel's sample.
//! let taps = shadow_taps(Vec3::new(0.25, -0.1, 0.0), 1, false, [Vec3::NEG_Z, Vec3::X, Vec3::Y]);
//! assert_eq!((taps.count, taps.fresh), (1, 4));
//! assert_eq!(taps.offsets[0].truncate(), Vec3::new(0.25, -0.1, 0.0));
//! ```

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::esm::{Layer, esm_shadow_coord};
use super::froxel::{ndc_from_uv, slice_depth, view_from_ndc};
use crate::limits::MAX_SHADOW_TAPS;
use crate::uniforms::{Froxels, ShadowTaps};

/// The R3 low-discrepancy step (the inverse powers 1, 2, 3 of the root > 1 of
/// x^4 = x + 1, Roberts 2018, "The unreasonable effectiveness of quasirandom
/// sequences"): tap t of a frame sits `t` steps from tap 0, modulo the froxel.
pub const SHADOW_TAP_STEP: Vec3 = Vec3::new(0.819_172_5, 0.671_043_6, 0.549_700_5);

/// Offset (froxel units, [-0.5, 0.5)^3) of tap `tap` of a frame whose froxel sample
/// lies at `jitter` (`FogFrame::jitter`, [-0.5, 0.5)^3): the sample itself for tap 0,
/// else moved by `tap` R3 steps and wrapped into the froxel.
pub fn shadow_tap_offset(jitter: Vec3, tap: u32) -> Vec3 {
    if tap == 0 {
        return jitter;
    }
    let moved = jitter + 0.5 + SHADOW_TAP_STEP * tap as f32;
    // fract, kept below 1 where rounding reaches it.
    let wrapped = (moved - moved.floor()).min(Vec3::splat(1.0 - f32::EPSILON));
    wrapped - 0.5
}

/// The world-space view rays of a camera per metre of view depth, affine in the
/// normalised device coordinates: `(ray at ndc 0, 0; d ray / d ndc.x; d ray / d
/// ndc.y)`, from its inverse projection and its view -> world transform (what
/// `froxel_view_position` scales by the view depth, taken at three points; a
/// perspective projection's rays are affine in ndc).
pub fn shadow_tap_rays(view_from_clip: glam::Mat4, world_from_view: glam::Mat4) -> [Vec3; 3] {
    let ray = |x: f32, y: f32| {
        let v = view_from_ndc(Vec3::new(x, y, 0.5), view_from_clip);
        world_from_view.transform_vector3(v / v.z.abs().max(1e-30))
    };
    let origin = ray(0.0, 0.0);
    [origin, ray(1.0, 0.0) - origin, ray(0.0, 1.0) - origin]
}

/// The taps of a frame whose froxel sample lies at `jitter`: `count` (1..=4) per froxel
/// with history, `4 count` (at most 16) without, `sun_reversed_z` when the sun's map
/// holds reversed depth, the camera's `rays` ([`shadow_tap_rays`]). Each tap cycles
/// through the froxel as the jitter does (a rotation of the jitter's Halton points),
/// and one frame's taps spread over it.
pub fn shadow_taps(jitter: Vec3, count: u32, sun_reversed_z: bool, rays: [Vec3; 3]) -> ShadowTaps {
    let default = ShadowTaps::default();
    let count = count.clamp(1, MAX_SHADOW_TAPS / 4);
    let mut offsets = [Vec4::ZERO; MAX_SHADOW_TAPS as usize];
    for (t, o) in offsets.iter_mut().enumerate() {
        *o = shadow_tap_offset(jitter, t as u32).extend(0.0);
    }
    ShadowTaps {
        offsets,
        ray_origin: rays[0],
        count,
        ray_x: rays[1],
        fresh: 4 * count,
        ray_y: rays[2],
        sun_reversed_z: u32::from(sun_reversed_z),
        camera_depth_terms: default.camera_depth_terms,
        use_scene_depth: 0,
    }
}

/// The view depth (m) at which a shadow tap samples the fog the camera sees
/// (`shadow_tap_visible_depth`): a tap at screen uv (v down) and view depth
/// `view_depth` in a froxel spanning view depths `near..far` (m) is moved into the part
/// of the span in front of the surface `scene_depth` (device depths, interpolated
/// bilinearly between texel centres, clamp to edge) holds at uv,
/// `near + (view_depth - near) clamp((surface - near) / (far - near), 0, 1)`, the
/// surface's view depth from the camera's `depth_terms`.
pub fn shadow_tap_visible_depth(
    scene_depth: &Layer,
    uv: Vec2,
    view_depth: f32,
    near: f32,
    far: f32,
    depth_terms: Vec4,
) -> f32 {
    let size = Vec2::new(scene_depth.width as f32, scene_depth.height as f32);
    let texel = uv.clamp(Vec2::ZERO, Vec2::ONE) * size - 0.5;
    let base = texel.floor();
    let f = texel - base;
    let (x, y) = (base.x as i32, base.y as i32);
    let top = lerp(scene_depth.at(x, y), scene_depth.at(x + 1, y), f.x);
    let bottom = lerp(scene_depth.at(x, y + 1), scene_depth.at(x + 1, y + 1), f.x);
    let device = lerp(top, bottom, f.y);
    let surface = super::frustum::frustum_depth_from_terms(depth_terms, device);
    let visible = ((surface - near) / (far - near).max(1e-6)).clamp(0.0, 1.0);
    near + (view_depth - near) * visible
}

/// `a + (b - a) t`, as WGSL's `mix`.
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// World position and view depth (m) of the point at `offset` (froxel units) in froxel
/// `id` through the taps' affine rays (`shadow_tap` of the inject pass): the camera at
/// `camera`, plus the ray of the point's screen position times its view depth.
pub fn shadow_tap_world(
    froxels: &Froxels,
    taps: &ShadowTaps,
    camera: Vec3,
    id: glam::UVec3,
    offset: Vec3,
) -> (Vec3, f32) {
    let cell = (id.as_vec3() + 0.5 + offset) / froxels.size.as_vec3();
    let ndc = ndc_from_uv(cell.truncate());
    let depth = slice_depth(cell.z, froxels.near, froxels.far, froxels.curve);
    let ray = taps.ray_origin + taps.ray_x * ndc.x + taps.ray_y * ndc.y;
    (camera + ray * depth, depth)
}

/// The 2 x 2 percentage-closer compare of a receiver at depth `receiver` around uv
/// (`shadow_pcf`): each texel lights it when it holds a depth >= receiver
/// (`increasing`, standard depth) or <= receiver (reversed), weighted bilinearly;
/// clamp to edge.
pub fn shadow_pcf(map: &Layer, uv: Vec2, receiver: f32, increasing: bool) -> f32 {
    let size = Vec2::new(map.width as f32, map.height as f32);
    let texel = uv * size - 0.5;
    let base = texel.floor();
    let f = texel - base;
    let (x, y) = (base.x as i32, base.y as i32);
    let lit = |d: f32| {
        let nearer = if increasing {
            d < receiver
        } else {
            d > receiver
        };
        if nearer { 0.0 } else { 1.0 }
    };
    lit(map.at(x, y)) * (1.0 - f.x) * (1.0 - f.y)
        + lit(map.at(x + 1, y)) * f.x * (1.0 - f.y)
        + lit(map.at(x, y + 1)) * (1.0 - f.x) * f.y
        + lit(map.at(x + 1, y + 1)) * f.x * f.y
}

/// Visibility of the directional light at a world position through one cascade of its
/// shadow map (`shadow_cascade_compare`): 1 outside the cascade's map and beyond its
/// far plane; `reversed` when the map holds 1 - depth.
pub fn shadow_cascade_compare(
    map: &Layer,
    light_from_world: Mat4,
    world: Vec3,
    reversed: bool,
) -> f32 {
    let coord = esm_shadow_coord(light_from_world, world);
    if coord.x < 0.0 || coord.y < 0.0 || coord.x > 1.0 || coord.y > 1.0 || coord.z > 1.0 {
        return 1.0;
    }
    let depth = coord.z.clamp(0.0, 1.0);
    let receiver = if reversed { 1.0 - depth } else { depth };
    shadow_pcf(map, coord.truncate(), receiver, !reversed)
}

/// Depth value in [0, 1] a perspective shadow camera with these depth terms stores
/// for view depth `view_depth` (m) (`shadow_receiver_depth`).
pub fn shadow_receiver_depth(depth_terms: Vec4, view_depth: f32) -> f32 {
    let den = depth_terms.x + depth_terms.z * view_depth;
    let den = if den.abs() < 1e-30 { 1e-30 } else { den };
    (-(depth_terms.y + depth_terms.w * view_depth) / den).clamp(0.0, 1.0)
}

/// Whether the depth values of a camera with these depth terms grow with view depth
/// (`shadow_depth_increasing`).
pub fn shadow_depth_increasing(depth_terms: Vec4) -> bool {
    depth_terms.w * depth_terms.x - depth_terms.z * depth_terms.y < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::froxel::froxel_jitter;

    #[test]
    fn taps_stay_in_the_froxel_and_tap_zero_is_the_sample() {
        for frame in 0..64 {
            let jitter = froxel_jitter(frame);
            let taps = shadow_taps(jitter, 4, false, [Vec3::NEG_Z, Vec3::X, Vec3::Y]);
            assert_eq!(taps.offsets[0].truncate(), jitter);
            taps.validate().unwrap();
        }
    }

    #[test]
    fn each_tap_covers_the_froxel_over_sixteen_frames() {
        // Over the jitter's 16-frame cycle every tap visits each half of the froxel
        // along each axis 6 to 10 times: a rotation of the 16 Halton points (16 strata
        // in base 2, 9 then 7 more points in base 3, 15 then 1 in base 5) modulo 1.
        for tap in 0..16 {
            for axis in 0..3 {
                let low = (0..16)
                    .filter(|&f| shadow_tap_offset(froxel_jitter(f), tap)[axis] < 0.0)
                    .count();
                assert!(
                    (6..=10).contains(&low),
                    "tap {tap} axis {axis}: {low} of 16 below 0"
                );
            }
        }
    }

    #[test]
    fn tap_rays_place_points_as_the_froxel_mapping_does() {
        // An off-centre (jittered) perspective with reversed depth, a rotated camera.
        let projection = glam::Mat4::from_translation(Vec3::new(0.003, -0.002, 0.0))
            * glam::camera::rh::proj::directx::perspective(1.1, 1.6, 40.0, 0.2);
        let world_from_view = glam::Mat4::from_rotation_translation(
            glam::Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.3, 0.1),
            Vec3::new(3.0, 2.0, -1.0),
        );
        let froxels =
            Froxels::new(projection, glam::UVec3::new(16, 9, 32), 0.5, 64.0, 3.0).unwrap();
        let taps = shadow_taps(
            Vec3::ZERO,
            1,
            false,
            shadow_tap_rays(froxels.view_from_clip, world_from_view),
        );
        let camera = world_from_view.transform_point3(Vec3::ZERO);
        for (id, offset) in [
            (glam::UVec3::new(0, 0, 0), Vec3::splat(-0.5)),
            (glam::UVec3::new(15, 8, 31), Vec3::splat(0.49)),
            (glam::UVec3::new(7, 3, 12), Vec3::new(0.2, -0.4, 0.1)),
        ] {
            let view = crate::cpu::froxel::froxel_view_position(
                id,
                offset,
                froxels.size,
                froxels.view_from_clip,
                froxels.near,
                froxels.far,
                froxels.curve,
            );
            let want = world_from_view.transform_point3(view);
            let (got, depth) = shadow_tap_world(&froxels, &taps, camera, id, offset);
            assert!(
                (got - want).length() < 1e-4 * want.distance(camera).max(1.0),
                "{id}: {got} vs {want}"
            );
            assert!(
                (depth - view.z.abs()).abs() < 1e-4 * depth,
                "{depth} vs {}",
                view.z
            );
        }
    }

    #[test]
    fn receiver_depths_invert_the_depth_terms() {
        // Standard and reversed perspective projections, near 0.5 m, far 40 m.
        let standard = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.5, 40.0);
        let reversed = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 40.0, 0.5);
        for (projection, increasing) in [(standard, true), (reversed, false)] {
            let terms = crate::uniforms::frustum::depth_terms("projection", projection).unwrap();
            assert_eq!(shadow_depth_increasing(terms), increasing);
            for z in [0.5f32, 1.0, 7.3, 39.9] {
                let d = projection.project_point3(Vec3::new(0.0, 0.0, -z)).z;
                let got = shadow_receiver_depth(terms, z);
                assert!((got - d).abs() < 2e-6, "z {z}: {got} vs {d}");
            }
            // Beyond the far plane and before the near plane: the planes' depths.
            let far = if increasing { 1.0 } else { 0.0 };
            assert_eq!(shadow_receiver_depth(terms, 100.0), far);
            assert_eq!(shadow_receiver_depth(terms, 0.1), 1.0 - far);
        }
    }

    #[test]
    fn pcf_weights_the_four_texels_bilinearly() {
        // Texel (1, 1) of a 4 x 4 map is nearer the light than the receiver.
        let mut texels = vec![1.0; 16];
        texels[5] = 0.2;
        let map = Layer {
            width: 4,
            height: 4,
            texels,
        };
        // At the centre of texel (1, 1): shadowed; half a texel right: half lit; at
        // the corner shared with texels (2, 1), (1, 2), (2, 2): three quarters lit.
        let at = |x: f32, y: f32| shadow_pcf(&map, Vec2::new(x, y) / 4.0, 0.5, true);
        assert_eq!(at(1.5, 1.5), 0.0);
        assert_eq!(at(2.0, 1.5), 0.5);
        assert_eq!(at(2.0, 2.0), 0.75);
        // Reversed depth: the same map read as reversed lights where d <= receiver.
        assert_eq!(shadow_pcf(&map, Vec2::splat(1.5) / 4.0, 0.5, false), 1.0);
    }
}
