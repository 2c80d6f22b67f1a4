//! Shared test helpers: the GPU (failing loudly when there is none) and composition of
//! test kernels that import volfog modules.
#![allow(dead_code)]

use std::collections::HashMap;

use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog::gpu::Gpu;

/// The GPU every test uses; panics with the install command when no adapter exists.
pub fn gpu() -> Gpu {
    match Gpu::new() {
        Ok(gpu) => {
            eprintln!("adapter: {}", gpu.describe());
            gpu
        }
        Err(e) => panic!("{e}"),
    }
}

/// Composes a test shader that imports volfog modules; panics with naga_oil's report.
pub fn compose(source: &str, defs: &[(&str, ShaderDefValue)]) -> naga::Module {
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).expect("volfog modules compose");
    let shader_defs: HashMap<String, ShaderDefValue> =
        defs.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    match composer.make_naga_module(NagaModuleDescriptor {
        source,
        file_path: "test_kernel.wgsl",
        shader_defs,
        ..Default::default()
    }) {
        Ok(m) => m,
        Err(e) => panic!("{}", e.emit_to_string(&composer)),
    }
}

/// Runs a kernel (see `Gpu::run_kernel`) on f32 inputs and returns f32 outputs.
pub fn run_f32(gpu: &Gpu, source: &str, inputs: &[f32], outputs: usize, count: u32) -> Vec<f32> {
    let module = gpu.shader_from_naga("test kernel", compose(source, &[]));
    let bytes = gpu
        .run_kernel(
            &module,
            "main",
            bytemuck::cast_slice(inputs),
            (outputs * 4) as u64,
            count,
        )
        .expect("kernel runs");
    bytemuck::cast_slice(&bytes).to_vec()
}

/// A small deterministic generator for test inputs (64-bit LCG, top 24 bits).
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
    /// Log-uniform in [lo, hi) (both > 0).
    pub fn log(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f()).exp()
    }
    /// Uniform in the cube [-r, r)^3.
    pub fn vec(&mut self, r: f32) -> glam::Vec3 {
        glam::Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    /// A unit vector, uniform on the sphere (rejection from the cube).
    pub fn unit(&mut self) -> glam::Vec3 {
        loop {
            let v = self.vec(1.0);
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
    /// A random rotation.
    pub fn quat(&mut self) -> glam::Quat {
        glam::Quat::from_axis_angle(self.unit(), self.range(0.0, std::f32::consts::TAU))
    }
}

/// Relative error with a floor on the denominator.
pub fn rel_err(got: f32, want: f32, floor: f32) -> f32 {
    (got - want).abs() / want.abs().max(floor)
}

/// A small froxel scene for pipeline tests: a camera, a sun with an optional slab
/// occluder in its shadow map, and helpers to run `VolumetricFog` frames.
pub mod scene {
    use glam::{Mat4, UVec3, Vec3, Vec4};
    use volfog::cpu::esm::Layer;
    use volfog::gpu::Gpu;
    use volfog::pipeline::fog::{cascade_projection, cascade_splits};
    use volfog::pipeline::{FogConfig, FrameInputs, ShadowInputs, VolumetricFog};
    use volfog::uniforms::ShadowCascades;

    /// A horizontal slab occluder: x and z ranges (m), height of its top (m).
    #[derive(Debug, Clone, Copy)]
    pub struct Slab {
        pub x: (f32, f32),
        pub z: (f32, f32),
        pub top: f32,
    }

    pub fn projection() -> Mat4 {
        glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 0.1, 500.0)
    }

    /// Camera at (0, eye_height, 0) looking along -Z, pitched by `pitch` radians.
    pub fn view(eye_height: f32, pitch: f32) -> Mat4 {
        let dir = Vec3::new(0.0, pitch.sin(), -pitch.cos());
        glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, eye_height, 0.0), dir, Vec3::Y)
    }

    pub fn small_config() -> FogConfig {
        FogConfig {
            volume_size: UVec3::new(32, 18, 48),
            near: 0.5,
            far: 64.0,
            slice_curve: 3.0,
            esm_resolution: 128,
            cascades: 2,
            esm_exponent: 80.0,
            max_lights: 8,
            max_local_volumes: 4,
            jitter: false,
            temporal: false,
            ..FogConfig::default()
        }
    }

    /// Cascades for a sun straight overhead covering the camera's surroundings, and
    /// the matching shadow-map depths of an optional slab.
    pub fn overhead_sun(config: &FogConfig, slab: Option<Slab>) -> (ShadowCascades, Vec<Layer>) {
        let up = Vec3::Y;
        let mut cascades = ShadowCascades {
            splits: cascade_splits(config.cascades, config.near, config.far, 0.5),
            count: config.cascades,
            exponent: config.esm_exponent,
            ..Default::default()
        };
        let size = config.esm_resolution * 4;
        let mut layers = Vec::new();
        for i in 0..config.cascades as usize {
            let half = 10.0 * (i as f32 + 1.0) * 3.5;
            let m = cascade_projection(up, Vec3::new(0.0, 0.0, -half * 0.8), half, 60.0);
            cascades.light_from_world[i] = m;
            let inv = m.inverse();
            let texels = (0..size * size)
                .map(|t| {
                    let (x, y) = (t % size, t / size);
                    let u = (x as f32 + 0.5) / size as f32;
                    let v = (y as f32 + 0.5) / size as f32;
                    let world = inv.project_point3(Vec3::new(u * 2.0 - 1.0, 1.0 - v * 2.0, 0.5));
                    match slab {
                        Some(s)
                            if (s.x.0..s.x.1).contains(&world.x)
                                && (s.z.0..s.z.1).contains(&world.z) =>
                        {
                            m.project_point3(Vec3::new(world.x, s.top, world.z)).z
                        }
                        _ => 1.0,
                    }
                })
                .collect();
            layers.push(Layer {
                width: size,
                height: size,
                texels,
            });
        }
        (cascades, layers)
    }

    /// Runs `frames` frames (inputs from `inputs(frame)`) and returns the volumes read
    /// after the last one: (scattering texture, integrated volume).
    pub fn run_frames<'a>(
        gpu: &Gpu,
        fog: &mut VolumetricFog,
        shadow: Option<&wgpu::TextureView>,
        frames: u32,
        mut inputs: impl FnMut(u32) -> FrameInputs<'a>,
        mut each: impl FnMut(u32, &VolumetricFog),
    ) {
        for f in 0..frames {
            fog.prepare(&gpu.queue, &inputs(f)).expect("valid inputs");
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            fog.encode(
                &gpu.device,
                &mut encoder,
                &ShadowInputs { shadow_map: shadow },
            );
            gpu.queue.submit([encoder.finish()]);
            each(f, fog);
        }
    }

    pub fn read_volume(gpu: &Gpu, texture: &wgpu::Texture) -> Vec<Vec4> {
        gpu.read_texture_rgba16f(texture).expect("readback")
    }

    pub fn shadow_view(texture: &wgpu::Texture) -> wgpu::TextureView {
        texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        })
    }

    pub fn read_esm(gpu: &Gpu, fog: &VolumetricFog) -> Vec<Layer> {
        let t = fog.esm_texture();
        let raw = gpu.read_texture_raw(t, 4).expect("readback");
        let values: &[f32] = bytemuck::cast_slice(&raw);
        let s = t.size();
        values
            .chunks_exact((s.width * s.height) as usize)
            .map(|c| Layer {
                width: s.width,
                height: s.height,
                texels: c.to_vec(),
            })
            .collect()
    }

    pub fn index(size: UVec3, x: u32, y: u32, z: u32) -> usize {
        ((z * size.y + y) * size.x + x) as usize
    }
}
