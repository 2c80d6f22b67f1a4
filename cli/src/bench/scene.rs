//! The benchmark scene: a ground plane with two rows of pillars joined by a lintel, a
//! low sun whose four shadow cascades are ray cast on the CPU, eight coloured point and
//! spot lights, animated noise fog with a height falloff and one local fog volume; and
//! the depth maps of point and spot lights' shadow cameras, ray cast the same way. The
//! camera stands still so every frame costs the same.

use glam::{Mat4, Quat, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::pipeline::{FogConfig, FrameInputs};
use volfog::pipeline::{cascade_projection, cascade_splits};
use volfog::uniforms::{
    DirectionalLight, FogLight, FogMedium, LightCamera, LocalVolume, ShadowCascades, VolumeShape,
};

/// Vertical field of view of the camera (radians).
const FOV_Y: f32 = std::f32::consts::FRAC_PI_3; // 60 degrees
/// Aspect ratio of every screen the bench renders (720p, 1080p and 4K are all 16:9).
pub const ASPECT: f32 = 16.0 / 9.0;
/// Depth range (m) of each cascade beyond its bounding sphere, towards the sun, so that
/// occluders outside the camera frustum still cast shadows into it.
const CASCADE_MARGIN: f32 = 40.0;

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    /// Entry parameter of the ray origin + t dir in [0, t_max), if it hits.
    fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<f32> {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let near = t0.min(t1).max_element().max(0.0);
        let far = t0.max(t1).min_element().min(t_max);
        (near <= far).then_some(near)
    }
}

/// The scene and its camera.
#[derive(Debug, Clone)]
pub struct Scene {
    /// World -> view of the camera.
    pub view: Mat4,
    /// View -> clip (WebGPU depth range, standard depth).
    pub projection: Mat4,
    /// The medium.
    pub medium: FogMedium,
    /// The sun.
    pub sun: DirectionalLight,
    /// Ambient light.
    pub ambient: AmbientSh,
    /// Point and spot lights.
    pub lights: Vec<FogLight>,
    /// Local fog volumes.
    pub local_volumes: Vec<LocalVolume>,
    boxes: Vec<Aabb>,
}

impl Default for Scene {
    fn default() -> Self {
        Self::new()
    }
}

impl Scene {
    /// The benchmark scene.
    pub fn new() -> Self {
        let eye = Vec3::new(0.0, 2.0, 6.0);
        let pitch: f32 = -0.06;
        let view = glam::camera::rh::view::look_to_mat4(
            eye,
            Vec3::new(0.0, pitch.sin(), -pitch.cos()),
            Vec3::Y,
        );
        let projection = glam::camera::rh::proj::directx::perspective(FOV_Y, ASPECT, 0.1, 500.0);
        let mut boxes = Vec::new();
        for i in 0..6 {
            let z = -6.0 - 9.0 * i as f32;
            for x in [-5.0f32, 5.0] {
                boxes.push(Aabb {
                    min: Vec3::new(x - 0.6, 0.0, z - 0.6),
                    max: Vec3::new(x + 0.6, 8.0, z + 0.6),
                });
            }
            // A lintel across every other pair.
            if i % 2 == 1 {
                boxes.push(Aabb {
                    min: Vec3::new(-5.6, 8.0, z - 0.6),
                    max: Vec3::new(5.6, 9.0, z + 0.6),
                });
            }
        }
        let colors = [
            Vec3::new(40.0, 12.0, 6.0),
            Vec3::new(6.0, 20.0, 40.0),
            Vec3::new(10.0, 35.0, 12.0),
            Vec3::new(35.0, 8.0, 30.0),
        ];
        let mut lights = Vec::new();
        for i in 0..4 {
            let z = -10.0 - 12.0 * i as f32;
            let side = if i % 2 == 0 { -1.0 } else { 1.0 };
            lights.push(FogLight::point(
                Vec3::new(2.5 * side, 1.5, z),
                colors[i],
                9.0,
            ));
            lights.push(FogLight::spot(
                Vec3::new(-3.0 * side, 7.0, z - 4.0),
                Vec3::new(0.3 * side, -1.0, 0.1),
                colors[3 - i] * 3.0,
                14.0,
                0.25,
                0.45,
            ));
        }
        let local_volumes = vec![
            LocalVolume::new(
                Mat4::from_scale_rotation_translation(
                    Vec3::new(4.0, 1.5, 5.0),
                    Quat::from_rotation_y(0.3),
                    Vec3::new(1.0, 1.0, -24.0),
                ),
                VolumeShape::Box,
                0.12,
                0.4,
            )
            .expect("a valid local volume"),
        ];
        Self {
            view,
            projection,
            medium: FogMedium {
                density: 0.03,
                height_falloff: 0.12,
                noise_strength: 0.6,
                noise_scale: 0.2,
                phase_g: 0.5,
                ..FogMedium::default()
            },
            sun: DirectionalLight {
                direction: Vec3::new(0.45, 0.3, -0.84).normalize(),
                color: Vec3::new(4.0, 3.5, 2.8),
                ..DirectionalLight::default()
            },
            ambient: AmbientSh::sky_ground(
                Vec3::new(0.12, 0.16, 0.24),
                Vec3::new(0.04, 0.035, 0.03),
                Vec3::Y,
            ),
            lights,
            local_volumes,
            boxes,
        }
    }

    /// The frame inputs at `time` seconds with the given cascades.
    pub fn inputs(&self, time: f32, cascades: ShadowCascades) -> FrameInputs<'_> {
        FrameInputs {
            medium: self.medium,
            sun: self.sun,
            ambient: self.ambient,
            lights: &self.lights,
            local_volumes: &self.local_volumes,
            cascades,
            ..FrameInputs::new(self.view, self.projection, time)
        }
    }

    /// First hit (distance along a unit `dir`) of the ground plane y = 0 or a box.
    fn trace(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
        let inv = dir.recip();
        let mut best = if dir.y < 0.0 {
            Some(-origin.y / dir.y).filter(|t| *t < t_max)
        } else {
            None
        };
        for b in &self.boxes {
            if let Some(t) = b.hit(origin, inv, best.unwrap_or(t_max)) {
                best = Some(t);
            }
        }
        best
    }

    /// The scene's depth buffer (clip depth in [0, 1], 1 for the sky) at a resolution,
    /// row by row from the top.
    pub fn depth_buffer(&self, width: u32, height: u32) -> Vec<f32> {
        let world_from_view = self.view.inverse();
        let view_from_clip = self.projection.inverse();
        let clip_from_world = self.projection * self.view;
        let eye = world_from_view.w_axis.truncate();
        let pixel = |i: usize| {
            let (x, y) = (i as u32 % width, i as u32 / width);
            let ndc = Vec3::new(
                (x as f32 + 0.5) / width as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / height as f32 * 2.0,
                0.5,
            );
            let ray = view_from_clip.project_point3(ndc);
            let dir = world_from_view.transform_vector3(ray).normalize();
            match self.trace(eye, dir, 1.0e4) {
                Some(t) => clip_from_world
                    .project_point3(eye + dir * t)
                    .z
                    .clamp(0.0, 1.0),
                None => 1.0,
            }
        };
        parallel_map((width * height) as usize, pixel)
    }

    /// Shadow cascades of the sun fitted to the camera frustum between `config.near`
    /// and `config.far`, and the shadow-map depths of each cascade (`4 *
    /// config.esm_resolution` texels per side, row by row from the top).
    pub fn cascades(&self, config: &FogConfig) -> (ShadowCascades, Vec<Vec<f32>>) {
        let splits = cascade_splits(config.cascades, config.near, config.far, 0.75);
        let mut cascades = ShadowCascades {
            splits,
            count: config.cascades,
            exponent: config.esm_exponent,
            ..Default::default()
        };
        let world_from_view = self.view.inverse();
        let view_from_clip = self.projection.inverse();
        let size = config.esm_resolution * 4;
        let mut layers = Vec::new();
        let mut front = config.near;
        for i in 0..config.cascades as usize {
            let back = splits[i];
            let mut corners = Vec::with_capacity(8);
            for depth in [front, back] {
                for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                    let ray = view_from_clip.project_point3(Vec3::new(x, y, 0.5));
                    corners.push(world_from_view.transform_point3(ray * (depth / ray.z.abs())));
                }
            }
            let center = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
            let radius = corners
                .iter()
                .map(|c| c.distance(center))
                .fold(0.0f32, f32::max);
            let range = 2.0 * (radius + CASCADE_MARGIN);
            let light_from_world = cascade_projection(self.sun.direction, center, radius, range);
            cascades.light_from_world[i] = light_from_world;
            let world_from_light = light_from_world.inverse();
            let texel = |t: usize| {
                let (x, y) = (t as u32 % size, t as u32 / size);
                let ndc = Vec4::new(
                    (x as f32 + 0.5) / size as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / size as f32 * 2.0,
                    0.0,
                    1.0,
                );
                let origin = world_from_light.project_point3(ndc.truncate());
                let end = world_from_light.project_point3(Vec3::new(ndc.x, ndc.y, 1.0));
                // Orthographic: the depth is the fraction of the segment travelled.
                let length = origin.distance(end);
                self.trace(origin, (end - origin) / length, length)
                    .map_or(1.0, |t| t / length)
            };
            layers.push(parallel_map((size * size) as usize, texel));
            front = back;
        }
        (cascades, layers)
    }

    /// The depth maps of a light's shadow camera over the ground and the boxes: one
    /// layer for a spot camera, the six cube faces (+X, -X, +Y, -Y, +Z, -Z) for a point
    /// camera; `size` texels per side, row by row from the top, each the depth value of
    /// the camera's projection at the nearest hit (the far plane's where nothing is hit
    /// before it). The cameras of [`LightCamera::spot`] and [`LightCamera::point`] have
    /// standard depth (the far plane at 1).
    pub fn light_depth(&self, camera: &LightCamera, size: u32) -> Vec<Vec<f32>> {
        let views: Vec<Mat4> = match *camera {
            LightCamera::Spot {
                view_from_world, ..
            } => vec![view_from_world],
            LightCamera::Point {
                cube_from_world, ..
            } => (0..6)
                .map(|face| LightCamera::cube_face_view(face) * cube_from_world)
                .collect(),
        };
        let clip_from_view = camera.clip_from_view();
        let view_from_clip = clip_from_view.inverse();
        let depth_of = |view_depth: f32| {
            let clip = clip_from_view * Vec4::new(0.0, 0.0, -view_depth, 1.0);
            (clip.z / clip.w).clamp(0.0, 1.0)
        };
        let far = -view_from_clip.project_point3(Vec3::new(0.0, 0.0, 1.0)).z;
        views
            .into_iter()
            .map(|view_from_world| {
                let world_from_view = view_from_world.inverse();
                let origin = world_from_view.transform_point3(Vec3::ZERO);
                let texel = |t: usize| {
                    let (x, y) = (t as u32 % size, t as u32 / size);
                    let ndc = Vec3::new(
                        (x as f32 + 0.5) / size as f32 * 2.0 - 1.0,
                        1.0 - (y as f32 + 0.5) / size as f32 * 2.0,
                        0.5,
                    );
                    // The ray through the texel, one metre of view depth per unit.
                    let p = view_from_clip.project_point3(ndc);
                    let dir = world_from_view.transform_vector3(p / -p.z);
                    let per_depth = dir.length();
                    self.trace(origin, dir / per_depth, far * per_depth)
                        .map_or(1.0, |t| depth_of(t / per_depth))
                };
                parallel_map((size * size) as usize, texel)
            })
            .collect()
    }
}

/// `(0..count).map(f)` on every core.
fn parallel_map(count: usize, f: impl Fn(usize) -> f32 + Sync) -> Vec<f32> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = count.div_ceil(threads).max(1);
    let mut out = vec![0.0; count];
    std::thread::scope(|s| {
        for (c, part) in out.chunks_mut(chunk).enumerate() {
            let f = &f;
            s.spawn(move || {
                for (i, v) in part.iter_mut().enumerate() {
                    *v = f(c * chunk + i);
                }
            });
        }
    });
    out
}
