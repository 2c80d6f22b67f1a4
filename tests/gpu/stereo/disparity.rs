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
//! The edge's width (25 % to 75 %) in each eye is at most the mono fog's (the left
//! eye's camera) plus w_shared: the shared volume's trilinear look-up spreads it by one
//! froxel of its grid at most.
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
    let mut widths = [0.0f32; 2];
    for (i, eye) in eyes.iter().enumerate() {
        let edge = find_edge(eye, &image[i * pixels..(i + 1) * pixels]);
        found[i] = (edge.column, edge.world_x[1]);
        widths[i] = edge.world_x[2] - edge.world_x[0];
        eprintln!(
            "eye {i}: boundary at column {:.2}, world x {:.3} m, 25-75 % over {:.3} m",
            edge.column, edge.world_x[1], widths[i]
        );
    }
    // The mono fog of the left eye's camera: how much the shared volume widens the edge.
    let (_, mono_image) = mono_frame(gpu, &config, &inputs, &shadow);
    let mono = find_edge(&eyes[0], &mono_image);
    let mono_width = mono.world_x[2] - mono.world_x[0];
    eprintln!(
        "mono (left eye's camera): boundary at world x {:.3} m, 25-75 % over {mono_width:.3} m",
        mono.world_x[1]
    );
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
    // The trilinear look-up of the shared volume spreads the edge by at most one shared
    // froxel beyond what the eye's own grid does.
    for width in widths {
        assert!(
            width <= mono_width + w_shared,
            "{width} {mono_width} {w_shared}"
        );
    }
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

/// Where a level row of an eye's image crosses from the shadowed into the lit fog.
struct Edge {
    /// The image column (pixels, fractional) of the halfway crossing.
    column: f32,
    /// World x (m) where the rays of the 25 %, 50 % and 75 % crossings reach the
    /// sheet's middle.
    world_x: [f32; 3],
}

/// The crossing in `image` (one eye's pixels, rows of `IMAGE[0]`) seen by `eye`: the
/// level row's radiance divided by each ray's path length through the sheet
/// (sqrt(1 + tangent^2) per metre of thickness; the sun overhead meets every level ray
/// at 90 degrees, so lit and shadowed fog are each one level), against the levels 1 m
/// either side of the edge, well outside its blur.
fn find_edge(eye: &StereoEye, image: &[Vec4]) -> Edge {
    // The row whose rays run level (view y = 0) through the sheet's middle.
    let clip = eye.clip_from_view * Vec4::new(0.0, 0.0, -DEPTH, 1.0);
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
    let values: Vec<f32> = (0..IMAGE[0])
        .map(|x| {
            let t = tangent_at(x as f32);
            image[(row * IMAGE[0] + x) as usize].x / (1.0 + t * t).sqrt()
        })
        .collect();
    let column_of = |world_x: f32| {
        let clip = eye.clip_from_view * eye.view_from_world * Vec4::new(world_x, 2.0, -DEPTH, 1.0);
        let ndc = clip.x / clip.w;
        (((ndc + 1.0) * 0.5 * IMAGE[0] as f32) - 0.5).round() as usize
    };
    let (lo, hi) = (values[column_of(EDGE - 1.0)], values[column_of(EDGE + 1.0)]);
    assert!(hi > 2.0 * lo + 1e-4, "the sun lights the sheet: {lo} {hi}");
    let crossing = |share: f32| {
        let level = lo + share * (hi - lo);
        let k = (0..values.len() - 1)
            .find(|&k| values[k] < level && values[k + 1] >= level)
            .expect("the row crosses from shadow into light");
        k as f32 + (level - values[k]) / (values[k + 1] - values[k])
    };
    // Where a column's ray reaches the sheet's middle.
    let world_x = |column: f32| {
        eye.view_from_world
            .inverse()
            .transform_point3(Vec3::new(tangent_at(column) * DEPTH, 0.0, -DEPTH))
            .x
    };
    Edge {
        column: crossing(0.5),
        world_x: [0.25, 0.5, 0.75].map(|share| world_x(crossing(share))),
    }
}
