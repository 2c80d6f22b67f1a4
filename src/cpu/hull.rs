//! Mirror of `volfog::hull`: fog hulls (Boyd 2001), the signed per-fragment terms
//! whose per-pixel sum is the fog thickness, the fog of that thickness, plus closed
//! meshes to draw as hulls and exact chord lengths through boxes.
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::hull::{box_chord, hull_contribution, hull_fog, hull_thickness};
//!
//! // A ray along -z through the box [-1, 1]^3 seen from z = 5: entry at 4, exit at 6.
//! let (origin, dir) = (Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z);
//! let chord = box_chord(origin, dir, Vec3::splat(-1.0), Vec3::ONE, f32::INFINITY);
//! assert_eq!(chord, 2.0);
//! // The entry (front face) and exit (back face) terms sum to the same thickness ...
//! let term = |d: f32, scene: f32, front: bool| hull_contribution(d, scene, 3.0, 0.25, front);
//! let sum = term(4.0, 1e30, true) + term(6.1, 1e30, false);
//! assert!((hull_thickness(sum) - 2.1).abs() < 1e-6);
//! // ... and an opaque surface at 5 m inside the box cuts it to 1 m.
//! let sum = term(4.0, 5.0, true) + term(6.1, 5.0, false);
//! assert_eq!(hull_thickness(sum), 1.0);
//! let fog = hull_fog(1.0, 0.5, Vec3::ONE);
//! assert!((fog.w - (-0.5f32).exp()).abs() < 1e-7);
//! ```

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Clip w below which the hull is clipped (WGSL `HULL_MIN_W`).
pub const HULL_MIN_W: f32 = 1e-3;

/// The clip position a hull vertex is drawn at: depth `w - HULL_MIN_W`, so that only
/// the plane `w = HULL_MIN_W` clips the hull.
pub fn hull_clip_position(clip: Vec4) -> Vec4 {
    Vec4::new(clip.x, clip.y, clip.w - HULL_MIN_W, clip.w)
}

/// Distance (m) from the camera to the scene point at normalised device coordinates
/// `ndc` (depth-buffer value in z); at least 1e30 for a point at infinity.
pub fn hull_scene_distance(ndc: Vec3, view_from_clip: Mat4) -> f32 {
    let p = view_from_clip * ndc.extend(1.0);
    if p.w.abs() * 1e30 <= p.truncate().length() {
        return 1e30;
    }
    (p.truncate() / p.w).length().min(1e30)
}

/// Distance (m) from the camera to the scene point at screen `uv` and `view_depth` (m,
/// the resolved MSAA fog layout's r channel); at most 1e30.
pub fn hull_scene_distance_from_view_depth(uv: Vec2, view_depth: f32, view_from_clip: Mat4) -> f32 {
    (view_depth.max(0.0) * super::froxel::ray_scale(uv, view_from_clip)).min(1e30)
}

/// The signed term of one hull fragment (exit +, entry -): the distance clamped to
/// the scene and taken relative to the reference, split into a multiple of
/// `quantum` (x) and the remainder (w) when `quantum > 0`; y the crossing (+-1), z
/// the crossing if it lies behind the scene.
pub fn hull_contribution(
    face_distance: f32,
    scene_distance: f32,
    reference: f32,
    quantum: f32,
    entry: bool,
) -> Vec4 {
    let side = if entry { -1.0 } else { 1.0 };
    let v = face_distance.min(scene_distance).max(reference) - reference;
    let whole = if quantum > 0.0 {
        (v / quantum).floor() * quantum
    } else {
        v
    };
    let behind = if face_distance >= scene_distance {
        1.0
    } else {
        0.0
    };
    side * Vec4::new(whole, 1.0, behind, v - whole)
}

/// Fog thickness (m) in front of the scene from a hull sum (x + w), >= 0.
pub fn hull_thickness(sum: Vec4) -> f32 {
    (sum.x + sum.w).max(0.0)
}

/// Whether the view ray of a hull sum starts inside the hull.
pub fn hull_camera_inside(sum: Vec4) -> bool {
    sum.y > 0.5
}

/// Whether the scene point of a hull sum lies inside the hull.
pub fn hull_scene_inside(sum: Vec4) -> bool {
    sum.z > 0.5
}

/// Fog over `thickness` (m) of extinction `density` (1/m) and in-scattered `color`:
/// rgb = color * (1 - T), w = T = exp(-density * thickness).
pub fn hull_fog(thickness: f32, density: f32, color: Vec3) -> Vec4 {
    let t = (-density.max(0.0) * thickness.max(0.0)).exp();
    (color * (1.0 - t)).extend(t)
}

/// A reference distance for a hull inside the box `[min, max]` seen from `camera`:
/// the distance from the camera to the box, 0 when the camera is inside it. It is a
/// lower bound of the distance of every hull point, and tight enough for an
/// rgba16float target to keep the terms within the hull's own extent.
pub fn reference_distance(camera: Vec3, min: Vec3, max: Vec3) -> f32 {
    (min - camera).max(camera - max).max(Vec3::ZERO).length()
}

/// Reference distance and quantum of a hull inside the box `[min, max]` seen from
/// `camera` whose view rays cross its surface at most `crossings` times: the
/// reference is [`reference_distance`]; the quantum the least power of two with
/// `crossings / 2 * extent <= 2048 * quantum` (extent: the farthest corner's
/// distance minus the reference), clamped to `2^-20..=2^20` m, so that the whole
/// multiples add exactly in fp16.
pub fn depth_range(camera: Vec3, min: Vec3, max: Vec3, crossings: u32) -> (f32, f32) {
    let reference = reference_distance(camera, min, max);
    let far = (0..8)
        .map(|i| {
            let corner = Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            );
            corner.distance(camera)
        })
        .fold(0.0, f32::max);
    let span = (far - reference) * (crossings / 2).max(1) as f32 / 2048.0;
    let quantum = 2f32.powi(span.max(1e-30).log2().ceil().clamp(-20.0, 20.0) as i32);
    (reference, quantum)
}

/// The interval of ray distances `(enter, exit)` inside the box `[min, max]` along
/// the ray `origin + t * dir` (dir of unit length), `t >= 0`, or `None` when the ray
/// misses it.
pub fn box_interval(origin: Vec3, dir: Vec3, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let (mut enter, mut exit) = (0.0f32, f32::INFINITY);
    for axis in 0..3 {
        let (o, d) = (origin[axis], dir[axis]);
        if d == 0.0 {
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let (a, b) = ((min[axis] - o) / d, (max[axis] - o) / d);
        enter = enter.max(a.min(b));
        exit = exit.min(a.max(b));
    }
    (exit > enter).then_some((enter, exit))
}

/// Length of the ray `origin + t * dir` (dir of unit length) inside the box
/// `[min, max]` for `t` in `[0, max_distance]`.
pub fn box_chord(origin: Vec3, dir: Vec3, min: Vec3, max: Vec3, max_distance: f32) -> f32 {
    box_interval(origin, dir, min, max)
        .map(|(enter, exit)| (exit.min(max_distance) - enter.min(max_distance)).max(0.0))
        .unwrap_or(0.0)
}

/// Length of the ray inside a union of boxes whose interiors do not overlap (a
/// shape made of boxes, such as a U) for `t` in `[0, max_distance]`.
pub fn boxes_chord(origin: Vec3, dir: Vec3, boxes: &[(Vec3, Vec3)], max_distance: f32) -> f32 {
    boxes
        .iter()
        .map(|(min, max)| box_chord(origin, dir, *min, *max, max_distance))
        .sum()
}

/// A closed triangle mesh to draw as a fog hull: faces wound counter-clockwise seen
/// from outside, no holes, no T-junctions.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HullMesh {
    /// World positions (m).
    pub positions: Vec<Vec3>,
    /// Triangle list, three indices per face.
    pub indices: Vec<u32>,
}

impl HullMesh {
    /// The box `[min, max]` (12 triangles).
    pub fn cuboid(min: Vec3, max: Vec3) -> Self {
        let outline = [
            Vec2::new(min.x, min.y),
            Vec2::new(max.x, min.y),
            Vec2::new(max.x, max.y),
            Vec2::new(min.x, max.y),
        ];
        Self::prism(&outline, min.z, max.z)
    }

    /// The prism of a simple polygon in the xy plane (counter-clockwise seen from +z,
    /// concave allowed) extruded from `z0` to `z1 > z0`; the caps are triangulated
    /// by ear clipping.
    pub fn prism(outline: &[Vec2], z0: f32, z1: f32) -> Self {
        let n = outline.len() as u32;
        let mut positions: Vec<Vec3> = outline.iter().map(|p| p.extend(z0)).collect();
        positions.extend(outline.iter().map(|p| p.extend(z1)));
        let mut indices = Vec::new();
        for [a, b, c] in triangulate(outline) {
            // Top cap faces +z, bottom cap -z.
            indices.extend([a + n, b + n, c + n]);
            indices.extend([a, c, b]);
        }
        for i in 0..n {
            let j = (i + 1) % n;
            // The outward normal of edge i -> j lies to its right.
            indices.extend([i, j, j + n, i, j + n, i + n]);
        }
        Self { positions, indices }
    }

    /// The bounding box (min, max) of the positions.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// [`depth_range`] of the mesh's bounding box.
    pub fn depth_range(&self, camera: Vec3, crossings: u32) -> (f32, f32) {
        let (min, max) = self.bounds();
        depth_range(camera, min, max, crossings)
    }
}

/// Ear-clipping triangulation of a simple counter-clockwise polygon.
fn triangulate(outline: &[Vec2]) -> Vec<[u32; 3]> {
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut remaining: Vec<u32> = (0..outline.len() as u32).collect();
    let mut triangles = Vec::new();
    while remaining.len() > 3 {
        let m = remaining.len();
        let ear = (0..m).find(|&k| {
            let (ia, ib, ic) = (
                remaining[(k + m - 1) % m],
                remaining[k],
                remaining[(k + 1) % m],
            );
            let (a, b, c) = (
                outline[ia as usize],
                outline[ib as usize],
                outline[ic as usize],
            );
            cross(a, b, c) > 0.0
                && remaining.iter().all(|&i| {
                    let p = outline[i as usize];
                    i == ia
                        || i == ib
                        || i == ic
                        || cross(a, b, p) < 0.0
                        || cross(b, c, p) < 0.0
                        || cross(c, a, p) < 0.0
                })
        });
        // A simple polygon always has an ear; a degenerate one stops here.
        let Some(k) = ear else { break };
        triangles.push([
            remaining[(k + m - 1) % m],
            remaining[k],
            remaining[(k + 1) % m],
        ]);
        remaining.remove(k);
    }
    if remaining.len() == 3 {
        triangles.push([remaining[0], remaining[1], remaining[2]]);
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume of a closed mesh (positive when wound outwards).
    fn volume(mesh: &HullMesh) -> f32 {
        mesh.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn meshes_are_closed_and_outward() {
        let cube = HullMesh::cuboid(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 2.5));
        assert_eq!(cube.indices.len(), 36);
        assert!((volume(&cube) - 3.0).abs() < 1e-5);
        let u = [
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.0),
            Vec2::new(3.0, 3.0),
            Vec2::new(2.0, 3.0),
            Vec2::new(2.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 3.0),
            Vec2::new(0.0, 3.0),
        ];
        let mesh = HullMesh::prism(&u, -1.0, 1.0);
        assert_eq!(mesh.indices.len(), (2 * 6 + 16) * 3);
        assert!((volume(&mesh) - 14.0).abs() < 1e-4);
        // Every directed edge appears once and its reverse once: closed and oriented.
        let mut edges = std::collections::HashMap::new();
        for t in mesh.indices.chunks_exact(3) {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }
    }

    #[test]
    fn chords_and_references() {
        let (min, max) = (Vec3::splat(-1.0), Vec3::ONE);
        let dir = Vec3::new(1.0, 1.0, 0.0).normalize();
        let chord = box_chord(Vec3::new(-2.0, -2.0, 0.0), dir, min, max, f32::INFINITY);
        assert!((chord - 8f32.sqrt()).abs() < 1e-5);
        // From inside: the distance to the exit only.
        assert!((box_chord(Vec3::ZERO, Vec3::X, min, max, 5.0) - 1.0).abs() < 1e-6);
        assert_eq!(
            box_chord(Vec3::new(0.0, 2.0, 0.0), Vec3::X, min, max, 5.0),
            0.0
        );
        assert_eq!(reference_distance(Vec3::ZERO, min, max), 0.0);
        assert!((reference_distance(Vec3::new(4.0, 5.0, 0.0), min, max) - 5.0).abs() < 1e-6);
        // Seen from 2 m in front of the box: extent sqrt(4^2 + 2 * 1^2) - 2 = 2.24 m;
        // 4 crossings: 2 * 2.24 m / 2048 = 0.0022 m rounds up to 2^-8.
        let (reference, quantum) = depth_range(Vec3::new(0.0, 0.0, 3.0), min, max, 4);
        assert!((reference - 2.0).abs() < 1e-6);
        assert_eq!(quantum, 2f32.powi(-8));
    }

    #[test]
    fn terms_sum_to_the_chord_in_front_of_the_scene() {
        // A concave hull crossed at 2 (in), 3 (out), 5 (in), 7 (out); the scene at 6.
        let crossings = [(2.0, true), (3.0, false), (5.0, true), (7.0, false)];
        let sum = |scene: f32, reference: f32, from: usize| {
            crossings[from..]
                .iter()
                .map(|&(d, front)| hull_contribution(d, scene, reference, 0.25, front))
                .sum::<Vec4>()
        };
        let s = sum(6.0, 1.5, 0);
        assert_eq!((hull_thickness(s), s.y, s.z), (2.0, 0.0, 1.0));
        assert!(hull_scene_inside(s) && !hull_camera_inside(s));
        // The scene in front of the hull: no fog.
        assert_eq!(hull_thickness(sum(1.0, 1.5, 0)), 0.0);
        // Camera inside the first part (the entry at 2 lies behind it): 3 + 1.
        let s = sum(6.0, 0.0, 1);
        assert_eq!((hull_thickness(s), s.y), (4.0, 1.0));
        assert!(hull_camera_inside(s));
    }
}
