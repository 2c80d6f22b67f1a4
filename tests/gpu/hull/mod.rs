//! Fog hulls (Boyd 2001) on the GPU: the `hull_thickness` pass against the exact chord
//! length of the same shapes along every pixel's view ray (a convex box, a concave U,
//! opaque objects inside the hull, the camera inside the hull closer to a wall than the
//! near plane), its inside/outside counts against the geometry, and `hull_composite`
//! against the CPU formula. Pixels within 1 px of a silhouette (where the hull or an
//! occluder starts or stops covering the pixel) are left out of the comparisons. Here:
//! the image, the fog and the camera.

mod projection;
mod render;
mod scene;
mod thickness;

use glam::{Mat4, Vec2, Vec3};

const WIDTH: u32 = 96;
const HEIGHT: u32 = 72;
const FOV_Y: f32 = std::f32::consts::FRAC_PI_3; // 60 degrees
const FAR: f32 = 100.0;
const DENSITY: f32 = 0.6;
const FOG_COLOR: Vec3 = Vec3::new(0.7, 0.75, 0.8);

/// A camera looking from `eye` at `target` with the given near plane.
struct Camera {
    eye: Vec3,
    near: f32,
    view: Mat4,
    proj: Mat4,
}

impl Camera {
    fn new(eye: Vec3, target: Vec3, near: f32) -> Self {
        Self {
            eye,
            near,
            view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
            proj: glam::camera::rh::proj::directx::perspective(
                FOV_Y,
                WIDTH as f32 / HEIGHT as f32,
                near,
                FAR,
            ),
        }
    }

    /// Unit world direction of the view ray through the centre of pixel (x, y), from
    /// the field of view alone (not from the matrices the GPU uses).
    fn ray(&self, x: u32, y: u32) -> Vec3 {
        let tan = (FOV_Y * 0.5).tan();
        let ndc = Vec2::new(
            (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
            1.0 - (y as f32 + 0.5) / HEIGHT as f32 * 2.0,
        );
        let view_dir = Vec3::new(
            ndc.x * tan * WIDTH as f32 / HEIGHT as f32,
            ndc.y * tan,
            -1.0,
        );
        self.view.inverse().transform_vector3(view_dir).normalize()
    }

    /// Depth-buffer value of a world point.
    fn depth(&self, world: Vec3) -> f32 {
        let clip = self.proj * self.view * world.extend(1.0);
        clip.z / clip.w
    }
}
