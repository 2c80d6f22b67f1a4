//! The test scenes (hull mesh, the boxes it is made of, opaque boxes, camera) and what
//! their geometry says about every pixel.

use super::{Camera, DENSITY, FOG_COLOR, HEIGHT, WIDTH};
use glam::{Vec2, Vec3};
use volfog::cpu::hull::{HullMesh, box_interval, boxes_chord};
use volfog::pipeline::hull::HullSumFormat;
use volfog::uniforms::FogHull;

/// A test scene: a hull (mesh and the boxes it is made of), opaque boxes, a camera.
pub(super) struct Case {
    pub(super) name: &'static str,
    pub(super) camera: Camera,
    pub(super) mesh: HullMesh,
    pub(super) boxes: Vec<(Vec3, Vec3)>,
    pub(super) occluders: Vec<(Vec3, Vec3)>,
    /// Least number of compared pixels that must show each feature: two hull parts
    /// on one ray, the scene point in fog, a crossing closer than the near plane.
    pub(super) min_concave: usize,
    pub(super) min_scene_in_fog: usize,
    pub(super) min_before_near: usize,
}

/// What the geometry says about one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Exact {
    /// Chord length in front of the scene (m).
    pub(super) chord: f32,
    /// Distance of the opaque surface (infinite for the background).
    pub(super) scene: f32,
    /// Depth-buffer value.
    pub(super) depth: f32,
    /// The camera lies inside the hull.
    pub(super) camera_inside: bool,
    /// The scene point lies inside the hull.
    pub(super) scene_inside: bool,
    /// A hull crossing in front of the scene lies closer than the near plane.
    pub(super) before_near: bool,
    /// Fog intervals (merged over the boxes) starting in front of the scene, and
    /// whether an occluder is hit: pixels whose neighbours differ are on a silhouette.
    pub(super) signature: (usize, bool),
}

impl Case {
    fn exact(&self, x: u32, y: u32) -> Exact {
        let (eye, dir) = (self.camera.eye, self.camera.ray(x, y));
        let hit = self
            .occluders
            .iter()
            .filter_map(|(min, max)| box_interval(eye, dir, *min, *max).map(|(t, _)| t))
            .fold(f32::INFINITY, f32::min);
        let (scene, depth) = if hit.is_finite() {
            (hit, self.camera.depth(eye + dir * hit))
        } else {
            (f32::INFINITY, 1.0)
        };
        let mut intervals: Vec<(f32, f32)> = self
            .boxes
            .iter()
            .filter_map(|(min, max)| box_interval(eye, dir, *min, *max))
            .collect();
        intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut merged: Vec<(f32, f32)> = Vec::new();
        for (enter, exit) in intervals {
            match merged.last_mut() {
                Some(last) if enter <= last.1 + 1e-5 => last.1 = last.1.max(exit),
                _ => merged.push((enter, exit)),
            }
        }
        let inside = |p: Vec3| {
            self.boxes
                .iter()
                .any(|(min, max)| p.cmpgt(*min).all() && p.cmplt(*max).all())
        };
        Exact {
            chord: boxes_chord(eye, dir, &self.boxes, scene),
            scene,
            depth,
            camera_inside: inside(eye),
            scene_inside: hit.is_finite() && inside(eye + dir * hit),
            before_near: merged.iter().any(|&(enter, exit)| {
                (enter > 0.0 && enter < self.camera.near.min(scene))
                    || exit < self.camera.near.min(scene)
            }),
            signature: (
                merged.iter().filter(|(enter, _)| *enter < scene).count(),
                hit.is_finite(),
            ),
        }
    }

    /// Every pixel's exact values and whether it is at least 1 px from a silhouette.
    pub(super) fn exact_image(&self) -> (Vec<Exact>, Vec<bool>) {
        let exact: Vec<Exact> = (0..HEIGHT)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .map(|(x, y)| self.exact(x, y))
            .collect();
        let at = |x: i32, y: i32| {
            let (x, y) = (x.clamp(0, WIDTH as i32 - 1), y.clamp(0, HEIGHT as i32 - 1));
            exact[(y as u32 * WIDTH + x as u32) as usize].signature
        };
        let interior = (0..HEIGHT as i32)
            .flat_map(|y| (0..WIDTH as i32).map(move |x| (x, y)))
            .map(|(x, y)| (-1..=1).all(|dy| (-1..=1).all(|dx| at(x + dx, y + dy) == at(x, y))))
            .collect();
        (exact, interior)
    }

    pub(super) fn hull(&self, format: HullSumFormat) -> FogHull {
        let hull = FogHull::new(self.camera.proj, self.camera.view, FOG_COLOR, DENSITY).unwrap();
        match format {
            HullSumFormat::Full => hull,
            HullSumFormat::Half => {
                // The U's rays cross its surface up to 4 times.
                let (reference, quantum) = self.mesh.depth_range(self.camera.eye, 4);
                hull.with_depth_range(reference, quantum).unwrap()
            }
        }
    }
}

/// The U of the concave cases: outline in xy (pillars x in [-1.5, -0.5] and
/// [0.5, 1.5] for y in [-0.5, 1.5], bar y in [-1.5, -0.5]), z in [-0.75, 0.75].
fn u_shape() -> (HullMesh, Vec<(Vec3, Vec3)>) {
    let outline = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 3.0),
        (2.0, 3.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 3.0),
        (0.0, 3.0),
    ]
    .map(|(x, y)| Vec2::new(x - 1.5, y - 1.5));
    let z = 0.75;
    let boxes = vec![
        (Vec3::new(-1.5, -1.5, -z), Vec3::new(1.5, -0.5, z)),
        (Vec3::new(-1.5, -0.5, -z), Vec3::new(-0.5, 1.5, z)),
        (Vec3::new(0.5, -0.5, -z), Vec3::new(1.5, 1.5, z)),
    ];
    (HullMesh::prism(&outline, -z, z), boxes)
}

pub(super) fn cases() -> Vec<Case> {
    let (u_mesh, u_boxes) = u_shape();
    let (box_min, box_max) = (Vec3::new(-1.0, -0.75, -1.0), Vec3::new(1.0, 0.75, 1.0));
    let (room_min, room_max) = (Vec3::new(-2.0, -1.0, -2.0), Vec3::new(2.0, 1.0, 2.0));
    vec![
        Case {
            name: "(a) convex box",
            camera: Camera::new(Vec3::new(2.0, 1.5, 3.0), Vec3::ZERO, 0.1),
            mesh: HullMesh::cuboid(box_min, box_max),
            boxes: vec![(box_min, box_max)],
            occluders: vec![],
            min_concave: 0,
            min_scene_in_fog: 0,
            min_before_near: 0,
        },
        Case {
            name: "(b) concave U",
            camera: Camera::new(Vec3::new(5.0, 1.0, 1.5), Vec3::new(0.0, 0.3, 0.0), 0.1),
            mesh: u_mesh.clone(),
            boxes: u_boxes.clone(),
            occluders: vec![],
            min_concave: 200,
            min_scene_in_fog: 0,
            min_before_near: 0,
        },
        Case {
            name: "(c) objects inside the U",
            camera: Camera::new(Vec3::new(4.0, 2.0, 1.5), Vec3::new(0.0, -0.2, 0.0), 0.1),
            mesh: u_mesh.clone(),
            boxes: u_boxes.clone(),
            occluders: vec![
                // Straddles the left pillar's inner wall (x = -0.5).
                (Vec3::new(-1.0, -0.2, -0.4), Vec3::new(0.0, 0.6, 0.4)),
                // Wholly inside the right pillar and the bar.
                (Vec3::new(0.6, -1.4, -0.6), Vec3::new(1.4, 0.2, 0.6)),
            ],
            min_concave: 20,
            min_scene_in_fog: 100,
            min_before_near: 0,
        },
        Case {
            name: "(d) camera inside a box",
            camera: Camera::new(Vec3::new(1.9, 0.2, 0.5), Vec3::new(1.0, -0.2, -3.0), 0.5),
            mesh: HullMesh::cuboid(room_min, room_max),
            boxes: vec![(room_min, room_max)],
            occluders: vec![(Vec3::new(1.2, -0.6, -1.4), Vec3::new(1.8, 0.1, -0.9))],
            min_concave: 0,
            min_scene_in_fog: 200,
            min_before_near: 200,
        },
        Case {
            name: "(d) camera inside the U",
            camera: Camera::new(Vec3::new(-0.7, 0.5, 0.0), Vec3::new(1.0, 0.3, 0.2), 0.5),
            mesh: u_mesh,
            boxes: u_boxes,
            occluders: vec![],
            min_concave: 1000,
            min_scene_in_fog: 0,
            min_before_near: 1000,
        },
    ]
}
