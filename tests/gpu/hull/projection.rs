//! The CPU formulas of the hull passes' projection: the scene distance from a view
//! depth against the depth-buffer path, and the near clamp.

use glam::Vec4;
use volfog::cpu::hull::HULL_MIN_W;

/// The scene distance from a view depth (the resolved layout's path) equals the one
/// from the depth-buffer value of the same point, on the CPU, for standard and
/// reversed projections.
#[test]
fn scene_distance_from_view_depth_equals_the_depth_buffer_path() {
    use volfog::cpu::hull::{hull_scene_distance, hull_scene_distance_from_view_depth};
    for proj in [
        glam::camera::rh::proj::directx::perspective(1.0, 1.6, 0.1, 300.0),
        glam::camera::rh::proj::directx::perspective(1.0, 1.6, 300.0, 0.1),
    ] {
        let view_from_clip = proj.inverse();
        for (u, v, z) in [
            (0.5, 0.5, 2.0f32),
            (0.05, 0.9, 40.0),
            (0.97, 0.1, 250.0),
            (0.3, 0.7, 0.3),
        ] {
            let uv = glam::Vec2::new(u, v);
            let ndc = volfog::cpu::froxel::ndc_from_uv(uv);
            let p = view_from_clip.project_point3(ndc.extend(0.5));
            let view = p * (z / p.z.abs());
            let clip = proj * view.extend(1.0);
            let from_depth = hull_scene_distance(ndc.extend(clip.z / clip.w), view_from_clip);
            let from_view = hull_scene_distance_from_view_depth(uv, z, view_from_clip);
            assert!(
                (from_view - view.length()).abs() <= 1e-5 * view.length(),
                "{from_view} vs {}",
                view.length()
            );
            assert!(
                (from_view - from_depth).abs() <= 1e-4 * view.length(),
                "{from_view} vs {from_depth}"
            );
        }
    }
}

#[test]
fn near_clamp_keeps_faces_in_front_of_the_near_plane() {
    // The clip depth w - HULL_MIN_W lies in [0, w] for every w >= HULL_MIN_W: a face at
    // 0.2 m with a 0.5 m near plane is not clipped, one behind the camera is.
    let proj = glam::camera::rh::proj::directx::perspective(1.0, 1.0, 0.5, 100.0);
    for (view_z, kept) in [(-0.2, true), (-50.0, true), (-500.0, true), (0.5, false)] {
        let clip = volfog::cpu::hull::hull_clip_position(proj * Vec4::new(0.1, 0.0, view_z, 1.0));
        let inside = clip.z >= 0.0 && clip.z <= clip.w;
        assert_eq!(inside, kept, "view z {view_z}");
    }
    // Only hull surfaces within HULL_MIN_W of the camera plane are lost.
    let clip =
        volfog::cpu::hull::hull_clip_position(proj * Vec4::new(0.0, 0.0, -HULL_MIN_W * 2.0, 1.0));
    assert!(clip.z >= 0.0 && clip.z <= clip.w);
}
