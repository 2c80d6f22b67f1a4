//! Mirror of `volfog::stereo` and of the scan's `VOLFOG_SCAN_RESAMPLE` variant: stereo
//! fog injects one volume for both eyes, aligned with a centre eye whose frustum
//! encloses both eyes' frusta ([`centre_eye`]), and each eye scans its own froxel grid,
//! reading that shared volume trilinearly at the world position of each of its froxels'
//! centres ([`resample_scan_volume`]).
//!
//! What the shared volume cannot hold per eye: the phase function's view direction is
//! the centre eye's (the angle between the two directions to a point at distance `d`
//! is at most `|eye - apex| / d` radians), and detail finer than one froxel of the
//! shared grid is smoothed by the trilinear look-up (a shadow edge spreads over about
//! one froxel of it).
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use volfog::cpu::stereo::{StereoEye, centre_eye};
//!
//! // Eyes 64 mm apart looking down -Z with 90-degree symmetric frusta.
//! let proj = glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
//! let eye = |x: f32| StereoEye {
//!     view_from_world: Mat4::from_translation(Vec3::new(-x, -1.6, 0.0)),
//!     clip_from_view: proj,
//! };
//! let centre = centre_eye(&[eye(-0.032), eye(0.032)]).unwrap();
//! // The apex lies 32 mm behind the midpoint (tan 45 degrees = 1).
//! let apex = centre.view_from_world.inverse().w_axis.truncate();
//! assert!((apex - Vec3::new(0.0, 1.6, 0.032)).length() < 1e-5);
//! assert!((centre.apex_offset - 0.032).abs() < 1e-5);
//! ```

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::apply::Volume;
use super::froxel::{ndc_from_uv, ray_scale, slice_coord, slice_depth, slice_walk, uv_from_ndc};
use super::inject::HALF_MAX;
use super::scan::{SCAN_START, scan_step};
use crate::limits::{InvalidValue, check};
use crate::options::ScanStep;
use crate::uniforms::{Froxels, TransientLighting};

/// One eye's camera, as an XR runtime gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StereoEye {
    /// World -> view transform of the eye (right-handed, looking down -Z).
    pub view_from_world: Mat4,
    /// The eye's perspective projection (view -> clip, WebGPU depth range; off-centre
    /// frusta as XR runtimes give them are fine).
    pub clip_from_view: Mat4,
}

/// The centre eye of a pair: the camera the shared volume is aligned with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentreEye {
    /// World -> view of the centre eye: the eyes' orientation, its apex behind them.
    pub view_from_world: Mat4,
    /// Its off-centre projection (WebGPU depth range, near plane 1 m: only its
    /// frustum's side planes matter, the slices come from the froxel placement).
    pub clip_from_view: Mat4,
    /// How far (m) the apex lies behind the eyes along the view axis: an eye's view
    /// depth z is the centre eye's view depth z + `apex_offset`.
    pub apex_offset: f32,
    /// The largest distance (m) of an eye from the apex: the phase function's view
    /// direction at distance d from an eye is off by at most `eye_distance / d`
    /// radians.
    pub eye_distance: f32,
}

/// The tangents (left, right, bottom, top: x / -z and y / -z) of a perspective
/// projection's side planes.
pub fn frustum_tangents(clip_from_view: Mat4) -> [f32; 4] {
    let view_from_clip = clip_from_view.inverse();
    let at = |x: f32, y: f32| {
        let p = view_from_clip * Vec4::new(x, y, 0.5, 1.0);
        let p = p.truncate() / p.w;
        Vec2::new(p.x, p.y) / -p.z
    };
    [
        at(-1.0, 0.0).x,
        at(1.0, 0.0).x,
        at(0.0, -1.0).y,
        at(0.0, 1.0).y,
    ]
}

/// An off-centre perspective projection (WebGPU depth range) with the given side-plane
/// tangents, near plane `near` and far plane `far` (m).
pub fn off_centre_projection(tangents: [f32; 4], near: f32, far: f32) -> Mat4 {
    let [l, r, b, t] = tangents;
    Mat4::from_cols(
        Vec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
        Vec4::new(
            (r + l) / (r - l),
            (t + b) / (t - b),
            far / (near - far),
            -1.0,
        ),
        Vec4::new(0.0, 0.0, near * far / (near - far), 0.0),
    )
}

/// The centre eye whose frustum encloses both eyes' frusta (each whole, from its
/// apex): the widest of the eyes' side-plane tangents, its apex the nearest point
/// behind the eyes from which planes of those tangents enclose both eyes. Errors (naming
/// the field) on non-finite or singular matrices, a projection that is not a
/// perspective one, and eyes whose orientations differ by more than 1e-3 (canted
/// displays are not supported).
pub fn centre_eye(eyes: &[StereoEye; 2]) -> Result<CentreEye, InvalidValue> {
    let views = [
        "StereoEye.view_from_world (left)",
        "StereoEye.view_from_world (right)",
    ];
    let projections = [
        "StereoEye.clip_from_view (left)",
        "StereoEye.clip_from_view (right)",
    ];
    for (i, eye) in eyes.iter().enumerate() {
        check(
            eye.view_from_world.is_finite() && eye.view_from_world.determinant().abs() > 1e-12,
            views[i],
            eye.view_from_world,
            "a finite, invertible transform",
        )?;
        crate::uniforms::froxels::check_perspective(projections[i], eye.clip_from_view)?;
    }
    let [left, right] = eyes;
    let world_from_left = left.view_from_world.inverse();
    // The right eye in the left eye's view space: the same orientation, an offset.
    let right_in_left = left.view_from_world * right.view_from_world.inverse();
    let rotation = glam::Mat3::from_mat4(right_in_left);
    check(
        (rotation - glam::Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|v| v.abs() <= 1e-3),
        views[1],
        right.view_from_world,
        "the left eye's orientation (within 1e-3), offset by a translation",
    )?;
    let origins = [Vec3::ZERO, right_in_left.w_axis.truncate()];
    let [tl, tr] = [left, right].map(|e| frustum_tangents(e.clip_from_view));
    let tangents = [
        tl[0].min(tr[0]),
        tl[1].max(tr[1]),
        tl[2].min(tr[2]),
        tl[3].max(tr[3]),
    ];
    // Apex a (left-eye view space, depth -a.z along the view axis). An eye at o lies in
    // the frustum of tangents (lo, hi) on an axis iff lo (a_z - o_z) <= o_x - a_x <=
    // hi (a_z - o_z); then so does its whole frustum, whose tangents lie within.
    let axis = |i: usize, lo: f32, hi: f32| {
        let min_lo = origins
            .iter()
            .map(|o| o[i] + lo * o.z)
            .fold(f32::INFINITY, f32::min);
        let max_hi = origins
            .iter()
            .map(|o| o[i] + hi * o.z)
            .fold(f32::NEG_INFINITY, f32::max);
        (min_lo, max_hi)
    };
    let (x_lo, x_hi) = axis(0, tangents[0], tangents[1]);
    let (y_lo, y_hi) = axis(1, tangents[2], tangents[3]);
    let behind = origins
        .iter()
        .map(|o| o.z)
        .fold(f32::NEG_INFINITY, f32::max);
    let a_z = ((x_hi - x_lo) / (tangents[1] - tangents[0]))
        .max((y_hi - y_lo) / (tangents[3] - tangents[2]))
        .max(behind);
    // a_x between hi-bound and lo-bound: the midpoint.
    let a_x = 0.5 * ((x_hi - tangents[1] * a_z) + (x_lo - tangents[0] * a_z));
    let a_y = 0.5 * ((y_hi - tangents[3] * a_z) + (y_lo - tangents[2] * a_z));
    let apex = Vec3::new(a_x, a_y, a_z);
    let world_from_centre = world_from_left * Mat4::from_translation(apex);
    let eye_distance = origins
        .iter()
        .map(|o| (*o - apex).length())
        .fold(0.0, f32::max);
    Ok(CentreEye {
        view_from_world: world_from_centre.inverse(),
        clip_from_view: off_centre_projection(tangents, 1.0, 1.0e4),
        apex_offset: a_z - origins.iter().map(|o| o.z).fold(f32::INFINITY, f32::min),
        eye_distance,
    })
}

/// `stereo_resample_column`: the centre eye's clip coordinates along an eye's column,
/// `[c0, c1]` with the point at eye view depth z landing at `c0 z + c1`.
pub fn stereo_resample_column(origin: Vec3, ray: Vec3, centre_clip_from_world: Mat4) -> [Vec4; 2] {
    [
        centre_clip_from_world * ray.extend(0.0),
        centre_clip_from_world * origin.extend(1.0),
    ]
}

/// `stereo_resample_uvw`: the shared volume's texture coordinates (clamped to [0, 1])
/// of the point at eye view depth `z` (m) of a column.
pub fn stereo_resample_uvw(column: [Vec4; 2], z: f32, centre: &Froxels) -> Vec3 {
    let clip = column[0] * z + column[1];
    let w = clip.w.max(1e-6);
    let uv = uv_from_ndc(Vec2::new(clip.x, clip.y) / w);
    let t = slice_coord(w, centre.near, centre.far, centre.curve);
    uv.extend(t).clamp(Vec3::ZERO, Vec3::ONE)
}

/// The scan's `VOLFOG_SCAN_RESAMPLE` variant over a whole eye volume (x fastest, then
/// y, then slices): `eye` the eye's froxel placement, `rays` its `TransientLighting`
/// (camera position and column rays), `shared` the shared volume with its froxel
/// placement and its camera's `clip_from_world`.
pub fn resample_scan_volume(
    eye: &Froxels,
    rays: &TransientLighting,
    step: ScanStep,
    shared: &Volume,
    shared_froxels: &Froxels,
    shared_clip_from_world: Mat4,
) -> Vec<Vec4> {
    let [sx, sy, sz] = eye.size.to_array();
    let mut out = vec![Vec4::ZERO; (sx * sy * sz) as usize];
    let (a, b) = slice_walk(sz, eye.near, eye.far, eye.curve);
    for y in 0..sy {
        for x in 0..sx {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / eye.size.truncate().as_vec2();
            let scale = ray_scale(uv, eye.view_from_clip);
            let ndc = ndc_from_uv(uv);
            let ray = rays.ray_origin + rays.ray_x * ndc.x + rays.ray_y * ndc.y;
            let column = stereo_resample_column(rays.camera_position, ray, shared_clip_from_world);
            let mut middle = slice_depth(0.5 / sz as f32, eye.near, eye.far, eye.curve) - eye.near;
            let (mut front, mut acc) = (0.0, SCAN_START);
            for k in 0..sz {
                let back = front * a + b;
                let uvw = stereo_resample_uvw(column, eye.near + middle, shared_froxels);
                middle = middle * a + b;
                acc = scan_step(acc, shared.sample(uvw), (back - front) * scale, step);
                out[((k * sy + y) * sx + x) as usize] = acc.min(Vec4::splat(HALF_MAX));
                front = back;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eye(x: f32, proj: Mat4, turn: f32) -> StereoEye {
        let world_from_view = Mat4::from_rotation_translation(
            glam::Quat::from_rotation_y(turn),
            Vec3::new(3.0, 1.6, 2.0),
        ) * Mat4::from_translation(Vec3::new(x, 0.0, 0.0));
        StereoEye {
            view_from_world: world_from_view.inverse(),
            clip_from_view: proj,
        }
    }

    /// Every point of both eyes' frusta (from their apexes) projects inside the centre
    /// eye's frustum, and the widest planes touch: the enclosure is tight.
    #[test]
    fn the_centre_frustum_encloses_both_eyes_tightly() {
        // Off-centre XR-like frusta, mirrored between the eyes.
        let left_proj = off_centre_projection([-1.05, 0.85, -0.95, 0.9], 0.1, 100.0);
        let right_proj = off_centre_projection([-0.85, 1.05, -0.95, 0.9], 0.1, 100.0);
        let eyes = [eye(-0.032, left_proj, 0.4), eye(0.032, right_proj, 0.4)];
        let c = centre_eye(&eyes).unwrap();
        let clip_from_world = c.clip_from_view * c.view_from_world;
        let mut widest = 0.0f32;
        for e in &eyes {
            let world_from_clip = (e.clip_from_view * e.view_from_world).inverse();
            for (x, y) in [
                (-1.0, -1.0),
                (1.0, 1.0),
                (-1.0, 1.0),
                (1.0, -1.0),
                (0.0, 0.0),
            ] {
                for depth in [0.0, 0.5, 0.9, 0.999] {
                    let p = world_from_clip * Vec4::new(x, y, depth, 1.0);
                    let q = clip_from_world * (p / p.w);
                    assert!(q.w > 0.0);
                    let ndc = Vec2::new(q.x, q.y) / q.w;
                    assert!(ndc.abs().max_element() <= 1.0 + 1e-4, "{ndc}");
                    widest = widest.max(ndc.x.abs());
                }
            }
        }
        assert!(widest > 0.999, "the outer planes are shared: {widest}");
        // Symmetric 90-degree tangents 1.05/0.85 from eyes 64 mm apart: the apex lies
        // 64 mm / (1.05 + 1.05) behind them.
        assert!(
            (c.apex_offset - 0.064 / 2.1).abs() < 1e-5,
            "{}",
            c.apex_offset
        );
    }

    #[test]
    fn canted_and_broken_eyes_are_rejected_naming_the_field() {
        let proj = glam::camera::rh::proj::directx::perspective(1.6, 1.0, 0.1, 100.0);
        let canted = [eye(-0.032, proj, 0.0), eye(0.032, proj, 0.1)];
        assert_eq!(
            centre_eye(&canted).unwrap_err().field,
            "StereoEye.view_from_world (right)"
        );
        let mut nan = [eye(-0.032, proj, 0.0), eye(0.032, proj, 0.0)];
        nan[0].clip_from_view.x_axis.x = f32::NAN;
        assert_eq!(
            centre_eye(&nan).unwrap_err().field,
            "StereoEye.clip_from_view (left)"
        );
        nan[0].clip_from_view = proj;
        nan[1].view_from_world.w_axis.y = f32::INFINITY;
        assert_eq!(
            centre_eye(&nan).unwrap_err().field,
            "StereoEye.view_from_world (right)"
        );
    }

    /// A point's resampled coordinates are where the centre eye's froxel placement puts
    /// it: the column's clip coordinates at depth z are the point's, and a froxel
    /// centre of a grid aligned with the centre eye lands on its texel centre.
    #[test]
    fn a_shared_froxel_centre_resamples_onto_its_own_texel() {
        let proj = glam::camera::rh::proj::directx::perspective(1.2, 1.5, 0.1, 100.0);
        let froxels = Froxels::new(proj, glam::UVec3::new(16, 9, 32), 0.5, 64.0, 3.0).unwrap();
        let world_from_view = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
        let rays = crate::cpu::shadow::shadow_tap_rays(froxels.view_from_clip, world_from_view);
        let clip_from_world = proj * world_from_view.inverse();
        for (x, y, k) in [(0u32, 0u32, 0u32), (7, 4, 13), (15, 8, 31)] {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(16.0, 9.0);
            let ndc = ndc_from_uv(uv);
            let ray = rays[0] + rays[1] * ndc.x + rays[2] * ndc.y;
            let column =
                stereo_resample_column(world_from_view.w_axis.truncate(), ray, clip_from_world);
            let z = slice_depth((k as f32 + 0.5) / 32.0, 0.5, 64.0, 3.0);
            let uvw = stereo_resample_uvw(column, z, &froxels);
            let want = (Vec3::new(x as f32, y as f32, k as f32) + 0.5) / Vec3::new(16.0, 9.0, 32.0);
            assert!((uvw - want).abs().max_element() < 1e-4, "{uvw} {want}");
        }
    }
}
