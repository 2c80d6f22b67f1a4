//! The test scene of the epipolar unit tests: a camera, an orthographic sun and a shadow
//! map of random boxes, with the suns they are tested under.

use glam::{Mat4, Vec2, Vec3};

use super::INVALID;
use super::height_map::ShadowLayer;
use super::lines::{line, sample_position};
use crate::cpu::TestRng as Rng;
use crate::uniforms::{EpipolarFrame, EpipolarSampling, EpipolarView};

/// A scene: a camera looking along -Z-ish at 5 m, an orthographic light of 200 m x
/// 200 m x 400 m around a point 60 m ahead, and a 256 x 256 shadow map.
pub(super) struct Scene {
    pub(super) frame: EpipolarFrame,
    pub(super) view_from_world: Mat4,
    pub(super) shadow: Vec<f32>,
}

impl Scene {
    pub(super) fn new(sun: Vec3, rng: &mut Rng, boxes: u32) -> Self {
        let size = 256;
        let eye = Vec3::new(0.0, 5.0, 0.0);
        let forward = Vec3::new(0.2, -0.05, -1.0).normalize();
        let view_from_world = glam::camera::rh::view::look_to_mat4(eye, forward, Vec3::Y);
        let up = if sun.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
        let center = eye + forward * 60.0;
        let light_from_world =
            glam::camera::rh::proj::directx::orthographic(-100.0, 100.0, -100.0, 100.0, 0.0, 400.0)
                * glam::camera::rh::view::look_to_mat4(center + sun * 200.0, -sun, up);
        let view = EpipolarView {
            view_from_world,
            clip_from_view: glam::camera::rh::proj::directx::perspective(
                1.0,
                16.0 / 9.0,
                0.1,
                500.0,
            ),
            light_from_world,
            cascade: 0,
            rayleigh: Vec3::ZERO,
            phase: Default::default(),
            start_depth: 0.0,
            max_depth: 1000.0,
            depth_bias: 0.0,
        };
        let sampling = EpipolarSampling::new(1280, 720, size);
        let frame = EpipolarFrame::new(&sampling, &view, sun).unwrap();
        let mut shadow = vec![1.0f32; (size * size) as usize];
        for _ in 0..boxes {
            let (w, h) = (rng.int(2, 60), rng.int(2, 60));
            let (x0, y0) = (rng.int(0, size - 1), rng.int(0, size - 1));
            let depth = rng.range(0.35, 0.65);
            for y in y0..(y0 + h).min(size) {
                for x in x0..(x0 + w).min(size) {
                    let d = &mut shadow[(y * size + x) as usize];
                    *d = d.min(depth);
                }
            }
        }
        Self {
            frame,
            view_from_world,
            shadow,
        }
    }

    pub(super) fn layer(&self) -> ShadowLayer<'_> {
        ShadowLayer {
            size: self.frame.shadow_size,
            depths: &self.shadow,
        }
    }

    /// A random valid sample `(slice, ndc)` of the frame.
    pub(super) fn sample(&self, rng: &mut Rng) -> (u32, Vec2) {
        loop {
            let j = rng.int(0, self.frame.slices - 1);
            let line = line(&self.frame, j);
            // One in eight at the entry (the epipole when it is on the screen, where
            // rays run along the sun and project to less than a texel).
            let k = if rng.unit() < 0.125 {
                0
            } else {
                rng.int(0, self.frame.samples - 1)
            };
            let p = sample_position(line, self.frame.samples, k);
            if p.x != INVALID {
                return (j, p);
            }
        }
    }
}

pub(super) fn suns() -> Vec<Vec3> {
    [
        Vec3::new(0.3, 0.8, -0.5),  // ahead, the epipole on or near the screen
        Vec3::new(-0.4, 0.5, 0.75), // behind the camera
        Vec3::new(0.9, 0.3, 0.1),   // to the side, the epipole far off the screen
        Vec3::new(0.05, 0.99, -0.1),
        Vec3::new(0.2, 0.25, -0.95), // low, straight ahead
    ]
    .map(Vec3::normalize)
    .to_vec()
}
