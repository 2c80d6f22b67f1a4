//! A small froxel scene for pipeline tests: a camera, a sun straight overhead with an
//! optional slab occluder in its shadow map, and helpers to run `VolumetricFog` frames.

use glam::{Mat4, UVec3, Vec3, Vec4};
use volfog::cpu::esm::Layer;
use volfog::cpu::froxel::froxel_jitter_amortised;
use volfog::cpu::shadow::SHADOW_TAP_STEP;
use volfog::options::ShadowFilter;
use volfog::pipeline::{
    FogConfig, FrameInputs, FrameUniforms, VolumetricFog, cascade_projection, cascade_splits,
};
use volfog::uniforms::{
    FogFrame, FogLight, FogLighting, FogMedium, FogView, Froxels, LocalVolume, ShadowCascades,
    ShadowTaps, TransientLighting, VolumeShape,
};

use crate::gpu::Gpu;

/// A horizontal slab occluder: x and z ranges (m), height of its top (m).
#[derive(Debug, Clone, Copy)]
pub struct Slab {
    /// x range (m).
    pub x: (f32, f32),
    /// z range (m).
    pub z: (f32, f32),
    /// Height of the top face (m).
    pub top: f32,
}

/// The slab the scene's sun shadows: under it, x in [-12, 8] m, z in [-40, -8] m.
pub const SLAB: Slab = Slab {
    x: (-12.0, 8.0),
    z: (-40.0, -8.0),
    top: 7.0,
};

/// The scene's lights in front of the camera: a warm point light, a blue spot light
/// pointing down and a bright point light 200 m away (outside every froxel's range).
pub fn lights() -> [FogLight; 3] {
    [
        FogLight::point(
            Vec3::new(-2.0, 2.0, -12.0),
            Vec3::new(30.0, 20.0, 10.0),
            12.0,
        ),
        FogLight::spot(
            Vec3::new(3.0, 6.0, -20.0),
            Vec3::new(0.0, -1.0, 0.2),
            Vec3::new(10.0, 40.0, 60.0),
            20.0,
            0.3,
            0.5,
        ),
        FogLight::point(Vec3::new(200.0, 0.0, 0.0), Vec3::splat(1000.0), 5.0),
    ]
}

/// The scene's local volumes: a denser rotated box and a thinning ellipsoid.
pub fn local_volumes() -> [LocalVolume; 2] {
    [
        LocalVolume::new(
            Mat4::from_scale_rotation_translation(
                Vec3::new(4.0, 2.0, 3.0),
                glam::Quat::from_rotation_y(0.4),
                Vec3::new(1.0, 1.0, -15.0),
            ),
            VolumeShape::Box,
            0.2,
            0.3,
        )
        .expect("a valid volume"),
        LocalVolume::new(
            Mat4::from_scale_rotation_translation(
                Vec3::splat(5.0),
                glam::Quat::IDENTITY,
                Vec3::new(-3.0, 3.0, -25.0),
            ),
            VolumeShape::Ellipsoid,
            -0.02,
            0.5,
        )
        .expect("a valid volume"),
    ]
}

/// The scene's medium: 0.03/m at the ground, falling with height, noisy, forward
/// scattering.
pub fn medium() -> FogMedium {
    FogMedium {
        density: 0.03,
        height_falloff: 0.08,
        noise_strength: 0.8,
        noise_scale: 0.3,
        phase_g: 0.5,
        ..FogMedium::default()
    }
}

/// The scene's projection: 60 degrees vertical, 16:9, standard depth, 0.1..500 m.
pub fn projection() -> Mat4 {
    glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 0.1, 500.0)
}

/// Camera at (0, eye_height, 0) looking along -Z, pitched by `pitch` radians.
pub fn view(eye_height: f32, pitch: f32) -> Mat4 {
    let dir = Vec3::new(0.0, pitch.sin(), -pitch.cos());
    glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, eye_height, 0.0), dir, Vec3::Y)
}

/// A small configuration (32 x 18 x 48, two cascades, no jitter, no temporal) that
/// runs quickly on a software adapter.
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
        // The procedural noise, which the CPU mirror evaluates without a texture.
        noise_texture: false,
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

/// Runs `frames` frames (inputs from `inputs(frame)`, one submit each) and calls
/// `each(frame, fog)` after each submit.
pub fn run_frames<'a>(
    gpu: &Gpu,
    fog: &mut VolumetricFog,
    frames: u32,
    mut inputs: impl FnMut(u32) -> FrameInputs<'a>,
    mut each: impl FnMut(u32, &VolumetricFog),
) {
    for f in 0..frames {
        fog.prepare(&gpu.queue, &inputs(f)).expect("valid inputs");
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).expect("a prepared frame");
        gpu.queue.submit([encoder.finish()]);
        each(f, fog);
    }
}

/// Reads an rgba16float volume back.
pub fn read_volume(gpu: &Gpu, texture: &wgpu::Texture) -> Vec<Vec4> {
    gpu.read_texture_rgba16f(texture).expect("readback")
}

/// Reads the fog's filtered ESM back, one layer per cascade.
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

/// The index of froxel (x, y, z) in a volume read back (x fastest).
pub fn index(size: UVec3, x: u32, y: u32, z: u32) -> usize {
    ((z * size.y + y) * size.x + x) as usize
}

/// A Depth32Float shadow map holding `layers` (one array layer each), as
/// `VolumetricFog::set_shadow_map` takes it.
pub fn shadow_map(gpu: &Gpu, layers: &[Layer]) -> wgpu::Texture {
    let slices: Vec<&[f32]> = layers.iter().map(|l| l.texels.as_slice()).collect();
    crate::selfcheck::depth_array_texture(gpu, layers[0].width, layers[0].height, &slices)
        .expect("the shadow map is written")
}

/// The uniforms of frame `index` (frames prepared before it) of `inputs`, written here
/// from what each member means, not by the code `VolumetricFog::prepare` runs: the
/// CPU references of the pipeline tests start from these.
pub fn expected_uniforms(
    config: &FogConfig,
    inputs: &FrameInputs<'_>,
    index: u32,
) -> FrameUniforms {
    let view_from_world = inputs.view_from_world;
    let world_from_view = view_from_world.inverse();
    FrameUniforms {
        froxels: Froxels {
            clip_from_view: inputs.clip_from_view,
            view_from_clip: inputs.clip_from_view.inverse(),
            size: config.volume_size,
            near: config.near,
            far: config.far,
            curve: config.slice_curve,
        },
        frame: FogFrame {
            world_from_view,
            clip_from_world: inputs.clip_from_view * view_from_world,
            camera_position: world_from_view.transform_point3(Vec3::ZERO),
            time: inputs.time,
            jitter: if config.jitter {
                froxel_jitter_amortised(index, u32::from(config.amortize))
            } else {
                Vec3::ZERO
            },
            history_weight: config.history_weight,
            index,
            history_enabled: if inputs.reset_history { 0 } else { 1 },
            checkerboard: u32::from(config.amortize),
        },
        medium: FogMedium {
            local_volume_count: inputs.local_volumes.len() as u32,
            particle_count: inputs.particles.len() as u32,
            ..inputs.medium
        },
        lighting: FogLighting {
            sun: inputs.sun,
            ambient_r: inputs.ambient.rgb[0],
            ambient_g: inputs.ambient.rgb[1],
            ambient_b: inputs.ambient.rgb[2],
            light_count: inputs.lights.len() as u32,
            transmittance: u32::from(config.light_transmittance),
        },
        cascades: inputs.cascades,
        tail: inputs
            .tail
            .with_sun_transmittance(config.light_transmittance)
            .to_view_space(view_from_world),
        view: FogView { view_from_world },
        shadow_taps: expected_shadow_taps(config, index, inputs),
        transient: expected_transient(config, inputs),
    }
}

/// The transient lights' uniform: the camera, the view rays per metre of view depth
/// as the compare filter's taps hold them, the light count, the transmittance switch.
fn expected_transient(config: &FogConfig, inputs: &FrameInputs<'_>) -> TransientLighting {
    let taps = expected_shadow_taps(config, 0, inputs);
    TransientLighting {
        camera_position: inputs
            .view_from_world
            .inverse()
            .transform_point3(Vec3::ZERO),
        count: inputs.transient_lights.len() as u32,
        ray_origin: taps.ray_origin,
        transmittance: u32::from(config.light_transmittance),
        ray_x: taps.ray_x,
        ray_y: taps.ray_y,
    }
}

/// The compare filter's taps of frame `index`: tap 0 at the froxel's sample (the
/// frame's jitter), tap t moved t R3 steps from it modulo the froxel; `taps` per
/// froxel with history and 4 taps without (every froxel without temporal blending).
fn expected_shadow_taps(config: &FogConfig, index: u32, inputs: &FrameInputs<'_>) -> ShadowTaps {
    let jitter = if config.jitter {
        froxel_jitter_amortised(index, u32::from(config.amortize))
    } else {
        Vec3::ZERO
    };
    let taps = match config.shadow_filter {
        ShadowFilter::Compare { taps } => taps,
        ShadowFilter::Esm => 1,
    };
    let mut offsets = [Vec4::ZERO; 16];
    for (t, o) in offsets.iter_mut().enumerate() {
        let moved = jitter + 0.5 + SHADOW_TAP_STEP * t as f32;
        let wrapped = Vec3::new(
            moved.x.rem_euclid(1.0),
            moved.y.rem_euclid(1.0),
            moved.z.rem_euclid(1.0),
        );
        *o = if t == 0 {
            jitter
        } else {
            wrapped.min(Vec3::splat(1.0 - f32::EPSILON)) - 0.5
        }
        .extend(0.0);
    }
    // The view ray per metre of view depth through ndc (x, y): the inverse projection
    // of the point at depth 0.5, scaled to a view depth of 1, in world space.
    let world_from_view = inputs.view_from_world.inverse();
    let view_from_clip = inputs.clip_from_view.inverse();
    let ray = |x: f32, y: f32| {
        let v = view_from_clip.project_point3(Vec3::new(x, y, 0.5));
        world_from_view.transform_vector3(v / -v.z)
    };
    ShadowTaps {
        offsets,
        ray_origin: ray(0.0, 0.0),
        count: if config.temporal { taps } else { 4 * taps },
        ray_x: ray(1.0, 0.0) - ray(0.0, 0.0),
        fresh: 4 * taps,
        ray_y: ray(0.0, 1.0) - ray(0.0, 0.0),
        sun_reversed_z: u32::from(config.shadow_reversed_z),
        // The view depth of a device depth d is -p.z / p.w of the inverse projection's
        // (0, 0, d, 1): its depth rows.
        camera_depth_terms: Vec4::new(
            view_from_clip.z_axis.z,
            view_from_clip.w_axis.z,
            view_from_clip.z_axis.w,
            view_from_clip.w_axis.w,
        ),
        // Set by a frame with a scene depth (depth culling).
        use_scene_depth: 0,
    }
}

/// The fraction of its froxels that a fog with depth culling processed in the prepared
/// frame (the sum of its live slices over the volume); `None` without culling.
pub fn live_fraction(gpu: &Gpu, fog: &VolumetricFog) -> Result<Option<f64>, crate::GpuError> {
    let Some(texture) = fog.live_slices_texture() else {
        return Ok(None);
    };
    let raw = gpu.read_texture_raw(texture, 4)?;
    let live: u64 = bytemuck::cast_slice::<u8, u32>(&raw)
        .iter()
        .map(|v| u64::from(*v))
        .sum();
    let size = fog.config().volume_size;
    Ok(Some(
        live as f64 / (f64::from(size.x) * f64::from(size.y) * f64::from(size.z)),
    ))
}
