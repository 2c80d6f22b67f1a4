//! Shadowed point and spot lights, cookies and emission in the froxel volume: the
//! atlas and the inject pass against the CPU mirror, and each against an independent
//! answer (the ESM leak bound of a closed room, the lit wedge behind a slot, a
//! cookie's stripes, the closed form of an emitting medium, the chords of cylinders
//! and cones).
//!
//! The scenes' shadow maps are ray traced on the CPU from their occluders (boxes) and
//! written as depth textures, so the geometry the fog should see is known exactly.

mod atlas;
mod budget;
mod cookie;
mod emission;
mod kept;
mod room;
mod shapes;
mod slot;

use crate::common::gpu;
use crate::common::scene::{index, read_volume, run_frames};
use glam::{Mat4, UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::esm::{Layer, blur};
use volfog::cpu::fog_volume::ray_unit_box;
use volfog::cpu::inject::{InjectInputs, LocalShadowInputs, froxel_scattering};
use volfog::cpu::local_shadow::{ColorLayer, downsample};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, FrameInputs, LocalShadowConfig, ShadowedLight, VolumetricFog};
use volfog::uniforms::{
    DirectionalLight, FogLight, FogMedium, LOCAL_SHADOW_NONE, LightCamera, LightProjection,
    LocalShadowSource, LocalVolume,
};
use volfog_testkit::selfcheck::depth_array_texture;

/// A solid box occluder: the unit box [-1, 1]^3 under `world_from_local`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Occluder {
    pub(super) local_from_world: Mat4,
}

impl Occluder {
    /// An axis-aligned box from `min` to `max` (m).
    pub(super) fn aabb(min: Vec3, max: Vec3) -> Self {
        let world_from_local =
            Mat4::from_translation(0.5 * (min + max)) * Mat4::from_scale(0.5 * (max - min));
        Self {
            local_from_world: world_from_local.inverse(),
        }
    }

    /// The line parameter where `origin + t dir` first enters the box at t >= 0.
    fn hit(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        let ro = self.local_from_world.transform_point3(origin);
        let rd = self.local_from_world.transform_vector3(dir);
        let t = ray_unit_box(ro, rd);
        (t.x <= t.y && t.y > 0.0).then_some(t.x.max(0.0))
    }
}

/// Pillars of staggered depths under a ceiling around `pillar_lights`, so every map
/// holds near and far depths.
pub(super) fn pillars() -> Vec<Occluder> {
    let mut o = vec![Occluder::aabb(
        Vec3::new(-6.0, 5.0, -16.0),
        Vec3::new(6.0, 5.3, -2.0),
    )];
    for k in 0..5 {
        let x = -4.0 + 2.0 * k as f32;
        o.push(Occluder::aabb(
            Vec3::new(x, 0.0, -9.0 - 0.7 * k as f32),
            Vec3::new(x + 0.5, 4.0, -8.5 - 0.7 * k as f32),
        ));
    }
    o
}

/// Three spot lights of different colours shining down past the `pillars` and a point
/// light among them.
pub(super) fn pillar_lights() -> [FogLight; 4] {
    [
        FogLight::spot(
            Vec3::new(-3.0, 4.5, -4.0),
            Vec3::new(0.2, -0.6, -1.0).normalize(),
            Vec3::new(30.0, 20.0, 10.0),
            16.0,
            0.35,
            0.6,
        ),
        FogLight::spot(
            Vec3::new(3.0, 4.5, -5.0),
            Vec3::new(-0.3, -0.5, -1.0).normalize(),
            Vec3::new(10.0, 20.0, 30.0),
            14.0,
            0.3,
            0.5,
        ),
        FogLight::spot(
            Vec3::new(0.0, 4.8, -12.0),
            Vec3::new(0.0, -1.0, 0.1).normalize(),
            Vec3::new(20.0, 30.0, 20.0),
            10.0,
            0.4,
            0.7,
        ),
        FogLight::point(Vec3::new(0.5, 2.0, -11.0), Vec3::new(40.0, 30.0, 20.0), 9.0),
    ]
}

/// The nearest hit of a ray among the occluders (m along a unit `dir`), or infinity.
pub(super) fn trace(occluders: &[Occluder], origin: Vec3, dir: Vec3) -> f32 {
    occluders
        .iter()
        .filter_map(|o| o.hit(origin, dir))
        .fold(f32::INFINITY, f32::min)
}

/// The depth map of one view of a light: for each texel centre, the depth value of the
/// nearest occluder along its ray (the far plane's value where nothing is hit).
pub(super) fn render_depth(
    occluders: &[Occluder],
    world_from_view: Mat4,
    clip_from_view: Mat4,
    size: u32,
) -> Vec<f32> {
    let view_from_clip = clip_from_view.inverse();
    let origin = world_from_view.transform_point3(Vec3::ZERO);
    // The depth value at view depth z, and the far plane's (the one of the larger
    // view depth of depth 0 and 1).
    let depth_of = |z: f32| {
        let clip = clip_from_view * Vec4::new(0.0, 0.0, -z, 1.0);
        clip.z / clip.w
    };
    let at = |d: f32| {
        let p = view_from_clip * Vec4::new(0.0, 0.0, d, 1.0);
        -p.z / p.w
    };
    let far_value = if at(1.0) > at(0.0) || at(0.0) < 0.0 {
        1.0
    } else {
        0.0
    };
    let mut out = Vec::with_capacity((size * size) as usize);
    for j in 0..size {
        for i in 0..size {
            let ndc = glam::Vec2::new(
                2.0 * (i as f32 + 0.5) / size as f32 - 1.0,
                1.0 - 2.0 * (j as f32 + 0.5) / size as f32,
            );
            let p = view_from_clip * Vec4::new(ndc.x, ndc.y, 0.5, 1.0);
            // The view direction through the texel with view depth 1 per unit of t.
            let view_dir = p.truncate() / -p.z;
            let dir = world_from_view.transform_vector3(view_dir);
            let len = dir.length();
            let t = trace(occluders, origin, dir / len) / len;
            out.push(if t.is_finite() {
                depth_of(t)
            } else {
                far_value
            });
        }
    }
    out
}

/// The depth maps of a light's camera: one layer for a spot light, six faces for a
/// point light.
pub(super) fn render_camera(
    occluders: &[Occluder],
    camera: &LightCamera,
    size: u32,
) -> Vec<Vec<f32>> {
    match *camera {
        LightCamera::Spot {
            view_from_world,
            clip_from_view,
        } => vec![render_depth(
            occluders,
            view_from_world.inverse(),
            clip_from_view,
            size,
        )],
        LightCamera::Point {
            cube_from_world,
            clip_from_view,
        } => (0..6)
            .map(|face| {
                let view_from_world = LightCamera::cube_face_view(face) * cube_from_world;
                render_depth(occluders, view_from_world.inverse(), clip_from_view, size)
            })
            .collect(),
    }
}

/// A depth array texture of the layers.
pub(super) fn depth_texture(layers: &[Vec<f32>], size: u32) -> wgpu::Texture {
    let slices: Vec<&[f32]> = layers.iter().map(Vec::as_slice).collect();
    depth_array_texture(gpu(), size, size, &slices).expect("the depth maps are written")
}

/// The fog's local-light atlas read back, one `Layer` per atlas layer.
pub(super) fn read_atlas(fog: &VolumetricFog) -> Vec<Layer> {
    let t = fog.local_shadow_atlas().expect("an atlas");
    let raw = gpu().read_texture_raw(t, 4).expect("readback");
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

/// The configuration of these tests: a small volume, no jitter, no temporal
/// reprojection (the scattering volume is inject's output), no culling.
/// The configuration of the scenes with the ESM filter (the atlas).
pub(super) fn config(local: LocalShadowConfig, log_space: bool) -> FogConfig {
    FogConfig {
        shadow_filter: ShadowFilter::Esm,
        volume_size: UVec3::new(48, 27, 64),
        near: 0.5,
        far: 24.0,
        slice_curve: 2.0,
        esm_resolution: 16,
        cascades: 1,
        esm_log_space: log_space,
        max_lights: 8,
        max_local_volumes: 4,
        jitter: false,
        temporal: false,
        depth_cull: false,
        local_shadows: Some(local),
        ..FogConfig::default()
    }
}

/// The configuration of the scenes with the compare filter of `taps` taps (four times
/// as many per froxel, as there is no temporal blend) and jittered taps.
pub(super) fn compare_config(local: LocalShadowConfig, taps: u32) -> FogConfig {
    FogConfig {
        shadow_filter: ShadowFilter::Compare { taps },
        jitter: true,
        ..config(local, false)
    }
}

/// Homogeneous, isotropic, white fog of extinction `density` without noise.
pub(super) fn medium(density: f32) -> FogMedium {
    FogMedium {
        albedo: Vec3::ONE,
        density,
        height_falloff: 0.0,
        noise_strength: 0.0,
        phase_g: 0.0,
        ..FogMedium::default()
    }
}

/// The camera of these scenes: at `eye` looking at `target`, 70 degrees, 16:9.
pub(super) fn camera(eye: Vec3, target: Vec3) -> (Mat4, Mat4) {
    (
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
        glam::camera::rh::proj::directx::perspective(70f32.to_radians(), 16.0 / 9.0, 0.1, 100.0),
    )
}

/// Frame inputs with only the point and spot lights (no sun, no ambient).
pub(super) fn inputs<'a>(
    view: (Mat4, Mat4),
    medium: FogMedium,
    lights: &'a [FogLight],
    shadowed: &'a [ShadowedLight],
    volumes: &'a [LocalVolume],
) -> FrameInputs<'a> {
    FrameInputs {
        medium,
        sun: DirectionalLight {
            color: Vec3::ZERO,
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::constant(Vec3::ZERO),
        lights,
        shadowed_lights: shadowed,
        local_volumes: volumes,
        ..FrameInputs::new(view.0, view.1, 0.0)
    }
}

/// Runs one frame and returns the scattering volume (inject's output).
pub(super) fn run(fog: &mut VolumetricFog, inputs: &FrameInputs<'_>) -> Vec<Vec4> {
    let gpu = gpu();
    let mut out = Vec::new();
    run_frames(
        gpu,
        fog,
        1,
        |_| inputs.clone(),
        |_, fog| {
            out = read_volume(gpu, fog.scattering_texture());
        },
    );
    out
}

/// What the CPU mirror reads of the lights' shadows: the atlas (the ESM filter) or the
/// depth maps themselves (the compare filter).
pub(super) struct CpuShadows {
    pub(super) atlas: Vec<Layer>,
    pub(super) spot: Vec<Layer>,
    pub(super) point: Vec<Layer>,
}

/// The CPU shadows of a frame. With the ESM filter each shadowed light's maps are
/// downsampled and blurred as the passes do, atlas layers handed out from 0 in the
/// order of `shadowed` within the budget; with the compare filter the maps are read
/// as they are, a light's projection pointing at its own map. Returns them with the
/// projections (what `VolumetricFog::prepare` should build).
pub(super) fn cpu_atlas(
    config: &FogConfig,
    lights: &[FogLight],
    shadowed: &[ShadowedLight],
    spot_maps: &[Vec<f32>],
    point_maps: &[Vec<f32>],
    map_size: u32,
) -> (CpuShadows, Vec<LightProjection>) {
    let local = config.local_shadows.expect("local shadows");
    let compare = config.shadow_filter.compares();
    let layers = |maps: &[Vec<f32>]| -> Vec<Layer> {
        maps.iter()
            .map(|texels| Layer {
                width: map_size,
                height: map_size,
                texels: texels.clone(),
            })
            .collect()
    };
    let log_space = config.esm_log_space;
    let radius = config.esm_blur_radius as i32;
    let (mut atlas, mut projections) = (Vec::new(), Vec::new());
    let (mut spots, mut points) = (0, 0);
    for s in shadowed {
        let light = &lights[s.light as usize];
        let point = matches!(s.camera, LightCamera::Point { .. });
        let granted = s.shadow.is_some()
            && if point {
                points < local.point_shadows
            } else {
                spots < local.spot_shadows
            };
        let mut layer = LOCAL_SHADOW_NONE;
        if granted && compare {
            let per_map = if point { 6 } else { 1 };
            layer = per_map * s.shadow.unwrap();
            if point {
                points += 1;
            } else {
                spots += 1;
            }
        } else if granted {
            layer = atlas.len() as u32;
            let map = s.shadow.unwrap() as usize;
            let faces: Vec<&Vec<f32>> = if point {
                points += 1;
                point_maps[6 * map..6 * map + 6].iter().collect()
            } else {
                spots += 1;
                vec![&spot_maps[map]]
            };
            for depth in faces {
                let source = LocalShadowSource {
                    depth_terms: s.camera.depth_terms().unwrap(),
                    depth_range: light.range,
                    exponent: local.exponent,
                    ..Default::default()
                };
                let depth = Layer {
                    width: map_size,
                    height: map_size,
                    texels: depth.clone(),
                };
                let down = downsample(&depth, &source, local.resolution, log_space);
                atlas.push(blur(
                    &blur(&down, radius, 0, log_space),
                    radius,
                    1,
                    log_space,
                ));
            }
        }
        projections.push(
            LightProjection::new(
                light,
                &s.camera,
                layer,
                s.cookie.unwrap_or(LOCAL_SHADOW_NONE),
                local.exponent,
                s.bias,
            )
            .unwrap(),
        );
    }
    let shadows = CpuShadows {
        atlas,
        spot: if compare {
            layers(spot_maps)
        } else {
            Vec::new()
        },
        point: if compare {
            layers(point_maps)
        } else {
            Vec::new()
        },
    };
    (shadows, projections)
}

/// The CPU mirror of a frame's scattering volume.
pub(super) fn cpu_volume(
    config: &FogConfig,
    inputs: &FrameInputs<'_>,
    shadows: &CpuShadows,
    projections: &[LightProjection],
    cookies: &[ColorLayer],
) -> Vec<Vec4> {
    let u = crate::common::scene::expected_uniforms(config, inputs, 0);
    let mut lights = inputs.lights.to_vec();
    for l in &mut lights {
        l.projection = LOCAL_SHADOW_NONE;
    }
    for (i, s) in inputs.shadowed_lights.iter().enumerate() {
        lights[s.light as usize].projection = i as u32;
    }
    let cpu = InjectInputs {
        froxels: &u.froxels,
        frame: &u.frame,
        medium: &u.medium,
        lighting: &u.lighting,
        cascades: &u.cascades,
        esm: &[],
        shadow_taps: &u.shadow_taps,
        lights: &lights,
        local_volumes: inputs.local_volumes,
        options: config.inject_options(),
        density_texture: None,
        noise_texture: None,
        clouds: None,
        local_shadows: Some(LocalShadowInputs {
            projections,
            atlas: &shadows.atlas,
            spot_maps: &shadows.spot,
            point_maps: &shadows.point,
            cookies,
        }),
        scene_depth: None,
        medium_shadow: None,
    };
    let size = config.volume_size;
    let mut out = vec![Vec4::ZERO; (size.x * size.y * size.z) as usize];
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                out[index(size, x, y, z)] = froxel_scattering(&cpu, UVec3::new(x, y, z));
            }
        }
    }
    out
}

/// The worst error of a GPU volume against the CPU mirror, relative to the largest
/// in-scattering channel of each froxel (floor `floor`).
pub(super) fn worst_relative(got: &[Vec4], want: &[Vec4], floor: f32) -> f32 {
    got.iter()
        .zip(want)
        .map(|(g, w)| {
            assert!(g.is_finite(), "a non-finite froxel");
            (*g - *w).truncate().abs().max_element() / w.truncate().max_element().max(floor)
        })
        .fold(0.0, f32::max)
}

/// The world position of every froxel centre, in the volume's order.
pub(super) fn froxel_positions(config: &FogConfig, inputs: &FrameInputs<'_>) -> Vec<Vec3> {
    let u = crate::common::scene::expected_uniforms(config, inputs, 0);
    let size = config.volume_size;
    let mut out = Vec::with_capacity((size.x * size.y * size.z) as usize);
    for z in 0..size.z {
        for y in 0..size.y {
            for x in 0..size.x {
                let (world, _) = volfog::cpu::inject::froxel_world_position(
                    &u.froxels,
                    &u.frame,
                    UVec3::new(x, y, z),
                    false,
                );
                out.push(world);
            }
        }
    }
    out
}

/// A froxel column's centre ray: the camera position and the world direction per
/// metre of view depth, with the path length per metre of view depth.
pub(super) fn column_ray(
    config: &FogConfig,
    inputs: &FrameInputs<'_>,
    x: u32,
    y: u32,
) -> (Vec3, Vec3) {
    let size = config.volume_size;
    let uv = glam::Vec2::new(
        (x as f32 + 0.5) / size.x as f32,
        (y as f32 + 0.5) / size.y as f32,
    );
    let ndc = volfog::cpu::froxel::ndc_from_uv(uv);
    let view = volfog::cpu::froxel::view_from_ndc(ndc.extend(0.5), inputs.clip_from_view.inverse());
    let world_from_view = inputs.view_from_world.inverse();
    (
        world_from_view.transform_point3(Vec3::ZERO),
        world_from_view.transform_vector3(view / view.z.abs()),
    )
}

/// The view depth (m) at the back of each slice.
pub(super) fn slice_backs(config: &FogConfig) -> Vec<f32> {
    let slices = config.volume_size.z;
    (1..=slices)
        .map(|k| {
            volfog::cpu::froxel::slice_depth(
                k as f32 / slices as f32,
                config.near,
                config.far,
                config.slice_curve,
            )
        })
        .collect()
}

/// Runs one frame and returns the integrated volume (rgb in-scatter, a transmittance).
pub(super) fn run_integrated(fog: &mut VolumetricFog, inputs: &FrameInputs<'_>) -> Vec<Vec4> {
    let gpu = gpu();
    let mut out = Vec::new();
    run_frames(
        gpu,
        fog,
        1,
        |_| inputs.clone(),
        |_, fog| {
            out = read_volume(gpu, fog.integrated_texture());
        },
    );
    out
}

/// The projections with their shadows taken away (what the frame would be without
/// them; cookies kept).
pub(super) fn unshadowed(projections: &[LightProjection]) -> Vec<LightProjection> {
    projections
        .iter()
        .map(|p| LightProjection {
            layer: LOCAL_SHADOW_NONE,
            ..*p
        })
        .collect()
}

/// The chord (m) of froxel column (x, y)'s centre ray through a volume's unit shape,
/// within the froxel volume's view depths, and the thickest slice it enters or leaves
/// through (the error a slice at each end can make). `chord_of` is the shape's
/// analytic chord in local space (`ray_unit_box`, `ray_unit_cylinder`, ...).
pub(super) fn column_chord(
    config: &FogConfig,
    inputs: &FrameInputs<'_>,
    local_from_world: Mat4,
    chord_of: fn(Vec3, Vec3) -> glam::Vec2,
    (x, y): (u32, u32),
) -> (f32, f32) {
    let (eye, dir) = column_ray(config, inputs, x, y);
    let t = chord_of(
        local_from_world.transform_point3(eye),
        local_from_world.transform_vector3(dir),
    );
    let (a, b) = (t.x.max(config.near), t.y.min(config.far));
    let thickest = slice_backs(config)
        .windows(2)
        .filter(|w| w[1] >= a && w[0] <= b)
        .map(|w| (w[1] - w[0]) * dir.length())
        .fold(0.0f32, f32::max);
    ((b - a).max(0.0) * dir.length(), thickest)
}

/// One shadowed light in a scene, run through the fog: the GPU volume, the CPU
/// mirror's, the mirror's without the shadow, and the froxel positions.
pub(super) struct OneLight {
    pub(super) maps: Vec<Vec<f32>>,
    pub(super) got: Vec<Vec4>,
    pub(super) want: Vec<Vec4>,
    pub(super) open: Vec<Vec4>,
    pub(super) positions: Vec<Vec3>,
}

/// Renders `light`'s depth maps of `map` texels from `camera`, sets them, runs a frame
/// of homogeneous fog seen from `view` and computes its mirrors.
pub(super) fn one_light(
    config: &FogConfig,
    light: FogLight,
    camera: LightCamera,
    occluders: &[Occluder],
    map: u32,
    view: (Mat4, Mat4),
) -> OneLight {
    let device = &gpu().device;
    let maps = render_camera(occluders, &camera, map);
    let mut fog = VolumetricFog::new(device, config).unwrap();
    let point = matches!(camera, LightCamera::Point { .. });
    let texture = depth_texture(&maps, map);
    if point {
        fog.set_point_shadow_maps(device, &texture).unwrap();
    } else {
        fog.set_spot_shadow_maps(device, &texture).unwrap();
    }
    let lights = [light];
    let shadowed = [ShadowedLight::new(0, camera).with_shadow(0)];
    let frame = inputs(view, medium(0.05), &lights, &shadowed, &[]);
    let got = run(&mut fog, &frame);
    let (spot_maps, point_maps) = if point {
        (&[][..], &maps[..])
    } else {
        (&maps[..], &[][..])
    };
    let (atlas, projections) = cpu_atlas(config, &lights, &shadowed, spot_maps, point_maps, map);
    OneLight {
        want: cpu_volume(config, &frame, &atlas, &projections, &[]),
        open: cpu_volume(config, &frame, &atlas, &unshadowed(&projections), &[]),
        positions: froxel_positions(config, &frame),
        maps,
        got,
    }
}
