//! The shadow boundary in both eyes: a sheet of fog 1 m thick 3 m in front of the head, lit
//! by the sun overhead except where a slab shadows it (world x < 0.4 m), seen by eyes
//! 0.3 m apart (a wide baseline, so that a boundary in the wrong place in one eye
//! shows). In each eye's image the boundary is where a level row, its radiance divided
//! by each ray's path length through the sheet, crosses halfway between the shadowed
//! and the lit fog 1 m either side of the edge; from that column the eye's ray reaches
//! the sheet's middle at a world x.
//!
//! Both eyes read one shared volume, so the boundary they see is the same blurred edge
//! of it; each eye samples that edge with its own froxel columns, which the apply
//! interpolates bilinearly, so its crossing moves by at most half an eye froxel (its
//! width at the sheet, w_eye). The two eyes then agree within w_eye, and each lies
//! within w_eye / 2 + w_shared / 2 (where the shared grid's samples fall on the edge)
//! plus one shadow-map texel (the compare filter reads texel centres) of the slab's
//! edge.
//! The image columns of the two crossings differ by the geometry's disparity (the
//! columns where the eyes' cameras project one world point) within the same w_eye, in
//! pixels.

use super::*;
use crate::common::scene::Slab;
use volfog::cpu::stereo::centre_eye;
use volfog::uniforms::{LocalVolume, VolumeShape};

/// The slab's edge: world x (m).
const EDGE: f32 = 0.4;
/// The sheet's depth in front of the head (m).
const DEPTH: f32 = 3.0;
/// The baseline (m).
const IPD: f32 = 0.3;

#[test]
fn a_shadow_boundary_lands_at_one_world_position_in_both_eyes() {
    let gpu = gpu();
    let config = FogConfig {
        volume_size: glam::UVec3::new(64, 36, 48),
        ..super::config()
    };
    let head = Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0));
    let eyes = eyes(head, IPD);
    let slab = Slab {
        x: (-12.0, EDGE),
        z: (-10.0, 0.0),
        top: 7.0,
    };
    let (cascades, layers) = overhead_sun(&config, Some(slab));
    let shadow = shadow_map(gpu, &layers);
    let sheet = [LocalVolume::new(
        Mat4::from_scale_rotation_translation(
            Vec3::new(8.0, 1.5, 0.5),
            glam::Quat::IDENTITY,
            Vec3::new(0.0, 2.0, -DEPTH),
        ),
        VolumeShape::Box,
        0.2,
        0.05,
    )
    .unwrap()];
    let inputs = FrameInputs {
        medium: FogMedium {
            density: 0.0,
            noise_strength: 0.0,
            ..medium()
        },
        local_volumes: &sheet,
        cascades,
        ..FrameInputs::new(eyes[0].view_from_world, eyes[0].clip_from_view, 0.0)
    };
    let (fog, image) = stereo_frame(gpu, &config, &eyes, &inputs, &shadow);
    let centre = centre_eye(&eyes).unwrap();
    assert!(fog.centre_eye().is_some());

    let pixels = (IMAGE[0] * IMAGE[1]) as usize;
    let mut found = [(0.0f32, 0.0f32); 2];
    for (i, eye) in eyes.iter().enumerate() {
        // The row whose rays run level (view y = 0) through the sheet's middle.
        let clip = eye.clip_from_view * glam::Vec4::new(0.0, 0.0, -DEPTH, 1.0);
        let v = 0.5 - 0.5 * clip.y / clip.w;
        let row = ((v * IMAGE[1] as f32) - 0.5).round() as u32;
        // Each pixel's ray per metre of depth (view space): its tangent.
        let tangent_at = |column: f32| {
            let ndc_x = 2.0 * (column + 0.5) / IMAGE[0] as f32 - 1.0;
            let view = eye
                .clip_from_view
                .inverse()
                .project_point3(Vec3::new(ndc_x, 0.0, 0.5));
            view.x / -view.z
        };
        // The fog's radiance divided by the path length through the sheet
        // (sqrt(1 + tangent^2) per metre of thickness): the sun overhead meets every
        // level ray at 90 degrees, so lit and shadowed fog are each one level.
        let values: Vec<f32> = (0..IMAGE[0])
            .map(|x| {
                let t = tangent_at(x as f32);
                image[i * pixels + (row * IMAGE[0] + x) as usize].x / (1.0 + t * t).sqrt()
            })
            .collect();
        // The levels 1 m either side of the edge, well outside its blur.
        let column_of = |world_x: f32| {
            let clip = eye.clip_from_view
                * eye.view_from_world
                * glam::Vec4::new(world_x, 2.0, -DEPTH, 1.0);
            let ndc = clip.x / clip.w;
            (((ndc + 1.0) * 0.5 * IMAGE[0] as f32) - 0.5).round() as usize
        };
        let (lo, hi) = (values[column_of(EDGE - 1.0)], values[column_of(EDGE + 1.0)]);
        assert!(
            hi > 2.0 * lo + 1e-4,
            "eye {i}: the sun lights the sheet: {lo} {hi}"
        );
        let mid = 0.5 * (lo + hi);
        let k = (0..values.len() - 1)
            .find(|&k| values[k] < mid && values[k + 1] >= mid)
            .expect("the row crosses from shadow into light");
        let column = k as f32 + (mid - values[k]) / (values[k + 1] - values[k]);
        // Where the crossing's ray reaches the sheet's middle.
        let tangent = tangent_at(column);
        let world_x = eye
            .view_from_world
            .inverse()
            .transform_point3(Vec3::new(tangent * DEPTH, 0.0, -DEPTH))
            .x;
        found[i] = (column, world_x);
        eprintln!("eye {i}: boundary at column {column:.2}, world x {world_x:.3} m");
    }
    // The widths of one froxel at the sheet: an eye's and the shared grid's (its
    // frustum is the wider, its depth the larger by the apex offset).
    let tangents = volfog::cpu::stereo::frustum_tangents(eyes[0].clip_from_view);
    let w_eye = (tangents[1] - tangents[0]) * DEPTH / config.volume_size.x as f32;
    let wide = volfog::cpu::stereo::frustum_tangents(centre.clip_from_view);
    let w_shared = (wide[1] - wide[0]) * (DEPTH + centre.apex_offset) / config.volume_size.x as f32;
    let texel = 2.0 * 35.0 / (config.esm_resolution * 4) as f32;
    let (left, right) = (found[0], found[1]);
    eprintln!(
        "world x apart {:.4} m (bound {w_eye:.3}); each within {:.3} m of the edge",
        (left.1 - right.1).abs(),
        0.5 * w_eye + 0.5 * w_shared + texel
    );
    assert!((left.1 - right.1).abs() <= w_eye, "{left:?} {right:?}");
    for (column, x) in found {
        assert!(
            (x - EDGE).abs() <= 0.5 * w_eye + 0.5 * w_shared + texel,
            "{column} {x}"
        );
    }
    // The disparity in pixels against the geometry's: the columns where each eye's
    // camera projects the crossing's world point (the eyes' frusta are off-centre
    // mirror images, so the columns also differ by the frusta's offset).
    let focal = IMAGE[0] as f32 / (tangents[1] - tangents[0]);
    let point = Vec3::new(0.5 * (left.1 + right.1), 2.0, -DEPTH);
    let column = |eye: &StereoEye| {
        let clip = eye.clip_from_view * eye.view_from_world * point.extend(1.0);
        (clip.x / clip.w + 1.0) * 0.5 * IMAGE[0] as f32 - 0.5
    };
    let disparity = left.0 - right.0;
    let geometry = column(&eyes[0]) - column(&eyes[1]);
    let pixel_bound = w_eye * focal / DEPTH;
    eprintln!("disparity {disparity:.3} px, geometry {geometry:.3} px (bound {pixel_bound:.3} px)");
    assert!((disparity - geometry).abs() <= pixel_bound);
}
