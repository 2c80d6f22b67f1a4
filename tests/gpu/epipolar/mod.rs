//! Epipolar sun shafts (Yusov 2012): the coordinate texture against the CPU mirror for
//! epipoles inside, on the edge of and outside the screen; refinement never
//! interpolating across a depth break; the min/max tree march against the march over
//! every section; the final image against the per-pixel brute-force reference; and the
//! far field of `VolumetricFog` against the analytic tail. Here: the test scene (boxes
//! ray traced into a depth buffer and a shadow map), one run of the shafts, readbacks.

mod coordinates;
mod errors;
mod far_field;
mod image;
mod march;
mod per_pixel;

pub(crate) use far_field::apply_over_depth;

use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};
use volfog::pipeline::cascade_projection;
use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
use volfog::uniforms::{EpipolarFrame, EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
use volfog_testkit::Gpu;
use volfog_testkit::selfcheck::depth_texture;

/// An axis-aligned box (min, max), m.
type Aabb = (Vec3, Vec3);

/// The test scene: a ground plane, three pillars and a bar across them, a low sun ahead
/// of the camera; depth buffer and shadow map ray traced from the same boxes.
/// `transmittance` gives the medium a top 14 m up and attenuates the sun's light by the
/// fog between each point and the sun (`HeightFog::sun_transmittance`).
struct Scene {
    width: u32,
    height: u32,
    view_from_world: Mat4,
    clip_from_view: Mat4,
    sun: Vec3,
    light_from_world: Mat4,
    shadow_size: u32,
    shadow: Vec<f32>,
    depth: Vec<f32>,
    transmittance: bool,
}

const FAR: f32 = 400.0;
const MAX_DEPTH: f32 = 150.0;

fn occluders() -> Vec<Aabb> {
    // Four pillars and a lintel high over the two middle ones.
    let mut boxes = vec![(Vec3::new(-4.0, 16.0, -32.0), Vec3::new(4.0, 17.0, -30.0))];
    for x in [-9.0f32, -3.0, 3.0, 9.0] {
        let top = if x.abs() < 5.0 { 16.0 } else { 12.0 };
        boxes.push((
            Vec3::new(x - 0.8, 0.0, -32.0),
            Vec3::new(x + 0.8, top, -30.0),
        ));
    }
    boxes
}

/// Nearest hit t > 0 of origin + t dir with the boxes and the ground (y = 0).
fn trace(origin: Vec3, dir: Vec3, boxes: &[Aabb]) -> Option<f32> {
    let mut best = f32::INFINITY;
    if dir.y < 0.0 && origin.y > 0.0 {
        best = -origin.y / dir.y;
    }
    for (lo, hi) in boxes {
        let inv = dir.recip();
        let a = (*lo - origin) * inv;
        let b = (*hi - origin) * inv;
        let near = a.min(b).max_element();
        let far = a.max(b).min_element();
        if near <= far && far > 0.0 && near > 0.0 && near < best {
            best = near;
        }
    }
    best.is_finite().then_some(best)
}

fn sun_direction() -> Vec3 {
    Vec3::new(0.15, 0.22, -1.0).normalize()
}

impl Scene {
    fn new(width: u32, height: u32, shadow_size: u32, boxes: &[Aabb], sun: Vec3) -> Self {
        let eye = Vec3::new(0.0, 2.0, 6.0);
        let view_from_world =
            glam::camera::rh::view::look_at_mat4(eye, Vec3::new(0.0, 5.0, -30.0), Vec3::Y);
        let clip_from_view = glam::camera::rh::proj::directx::perspective(
            1.0,
            width as f32 / height as f32,
            0.1,
            FAR,
        );
        let light_from_world = cascade_projection(sun, Vec3::new(0.0, 0.0, -40.0), 70.0, 200.0);
        let light_inv = light_from_world.inverse();
        let shadow = (0..shadow_size * shadow_size)
            .map(|t| {
                let (x, y) = (t % shadow_size, t / shadow_size);
                let u = (x as f32 + 0.5) / shadow_size as f32;
                let v = (y as f32 + 0.5) / shadow_size as f32;
                let start = light_inv.project_point3(Vec3::new(2.0 * u - 1.0, 1.0 - 2.0 * v, 0.0));
                match trace(start, -sun, boxes) {
                    Some(t) => light_from_world
                        .project_point3(start - sun * t)
                        .z
                        .clamp(0.0, 1.0),
                    None => 1.0,
                }
            })
            .collect();
        let world_from_view = view_from_world.inverse();
        let view_from_clip = clip_from_view.inverse();
        let depth = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let ndc = Vec2::new(
                    (x as f32 + 0.5) / width as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / height as f32 * 2.0,
                );
                let p = view_from_clip.project_point3(ndc.extend(0.5));
                let dir = world_from_view.transform_vector3(p).normalize();
                match trace(eye, dir, boxes) {
                    Some(t) => {
                        let view = view_from_world.transform_point3(eye + dir * t);
                        clip_from_view.project_point3(view).z.min(1.0)
                    }
                    None => 1.0,
                }
            })
            .collect();
        Self {
            width,
            height,
            view_from_world,
            clip_from_view,
            sun,
            light_from_world,
            shadow_size,
            shadow,
            depth,
            transmittance: false,
        }
    }

    /// The scene with the sun's transmittance on or off (see [`Scene::medium`]).
    fn with_transmittance(self, on: bool) -> Self {
        Self {
            transmittance: on,
            ..self
        }
    }

    /// The medium (world space): exponential fog, 0.02 / m at the ground thinning e
    /// times every 25 m; with `transmittance` ending 14 m up (above the pillars' shafts,
    /// below the lintel's top) and attenuating the sun's light on its way.
    fn medium(&self) -> HeightFog {
        let fog = HeightFog::new(Vec3::new(0.02, 0.025, 0.03), 0.02, Vec3::Y, 0.04, 0.0)
            .unwrap()
            .with_sun(self.sun, Vec3::new(3.0, 2.8, 2.5), 0.5)
            .unwrap();
        if self.transmittance {
            fog.with_top(14.0).unwrap().with_sun_transmittance(true)
        } else {
            fog
        }
    }

    fn view(&self, start_depth: f32) -> EpipolarView {
        EpipolarView {
            view_from_world: self.view_from_world,
            clip_from_view: self.clip_from_view,
            light_from_world: self.light_from_world,
            cascade: 0,
            rayleigh: Vec3::new(0.05, 0.1, 0.2),
            phase: EpipolarPhase::HenyeyGreenstein,
            start_depth,
            max_depth: MAX_DEPTH,
            depth_bias: 0.001,
        }
    }

    /// The view depth (m) the coordinate pass reads at a screen point (nearest pixel).
    fn view_depth_at(&self, ndc: Vec2) -> f32 {
        let uv = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
        let x = ((uv.x * self.width as f32).floor() as i64).clamp(0, self.width as i64 - 1);
        let y = ((uv.y * self.height as f32).floor() as i64).clamp(0, self.height as i64 - 1);
        let d = self.depth[(y * self.width as i64 + x) as usize];
        let v = volfog::cpu::froxel::view_from_ndc(ndc.extend(d), self.clip_from_view.inverse());
        v.z.abs().min(MAX_DEPTH)
    }

    fn sampling(&self) -> EpipolarSampling {
        EpipolarSampling {
            slices: 256,
            samples: 256,
            reference_steps: 1024,
            ..EpipolarSampling::new(self.width, self.height, self.shadow_size)
        }
    }

    fn textures(&self, gpu: &Gpu) -> (wgpu::Texture, wgpu::Texture) {
        let depth = depth_texture(gpu, self.width, self.height, &self.depth).unwrap();
        let shadow = depth_texture(gpu, self.shadow_size, self.shadow_size, &self.shadow).unwrap();
        (depth, shadow)
    }
}

/// Runs the shafts once and returns the object (for its textures) and the frame.
fn run(
    gpu: &Gpu,
    scene: &Scene,
    sampling: EpipolarSampling,
    mode: EpipolarMode,
    frame: Option<EpipolarFrame>,
) -> (EpipolarShafts, EpipolarFrame) {
    let mut shafts = EpipolarShafts::new(&gpu.device, sampling).unwrap();
    let (depth, shadow) = scene.textures(gpu);
    shafts.set_inputs(&gpu.device, &depth, &shadow).unwrap();
    let medium = scene.medium();
    let frame = match frame {
        Some(f) => {
            shafts
                .prepare_frame(
                    &gpu.queue,
                    &f,
                    &EpipolarFrame::medium(&medium, scene.view_from_world),
                )
                .unwrap();
            f
        }
        None => shafts
            .prepare(&gpu.queue, &scene.view(0.0), &medium)
            .unwrap(),
    };
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    shafts.encode(&mut encoder, mode).unwrap();
    gpu.queue.submit([encoder.finish()]);
    (shafts, frame)
}

fn read_vec4(gpu: &Gpu, t: &wgpu::Texture) -> Vec<Vec4> {
    let raw = gpu.read_texture_raw(t, 16).unwrap();
    bytemuck::cast_slice::<u8, f32>(&raw)
        .chunks_exact(4)
        .map(Vec4::from_slice)
        .collect()
}

/// The rgb of an rgba32float texture (the marched lit fractions).
fn read_rgb(gpu: &Gpu, t: &wgpu::Texture) -> Vec<Vec3> {
    read_vec4(gpu, t).into_iter().map(Vec4::truncate).collect()
}

fn read_uvec2(gpu: &Gpu, t: &wgpu::Texture) -> Vec<UVec2> {
    bytemuck::cast_slice::<u8, u32>(&gpu.read_texture_raw(t, 4).unwrap())
        .iter()
        .map(|&p| UVec2::new(p & 0xffff, p >> 16))
        .collect()
}
