//! The fog scene in Bevy: a colonnade with an arch under a low sun with four shadow
//! cascades, coloured point and spot lights, a local fog volume, and a glass sphere
//! whose material applies the fog through the `volfog` WESL package. Rendered
//! headless into an `Rgba16Float` image (no tonemapping: linear scene values) and
//! read back. Shared by the `fog_scene` example, its test and the benchmark.

#![allow(dead_code)]

use std::sync::{Arc, Mutex};

use bevy::app::PluginsState;
use bevy::asset::RenderAssetUsages;
use bevy::camera::{Exposure, Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::light::{
    CascadeShadowConfigBuilder, FogVolume, GlobalAmbientLight, VolumetricFog, VolumetricLight,
};
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderAdapter, RenderAdapterInfo, RenderDevice, RenderQueue};
use bevy::render::settings::{RenderCreation, WgpuSettings};
use bevy::render::{RenderApp, RenderPlugin};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use volfog_bevy::{
    BevyFogCompat, ExtractedFroxelFog, FogMediumSettings, FogViews, FogVolumeShape,
    FoggedGlassMaterial, FroxelFog, FroxelFogVolume, VolumetricFogPlugin,
};

/// The camera's exposure (EV100); light intensities below are chosen for it.
pub const EV100: f32 = 9.7;
/// Where the glass sphere sits (m) and its radius.
pub const GLASS_CENTER: Vec3 = Vec3::new(3.4, 1.9, -18.5);
pub const GLASS_RADIUS: f32 = 1.0;
/// The colonnade's row (z, m).
pub const ROW_Z: f32 = -25.0;
/// The camera: eye and target (m), vertical field of view (degrees).
pub const EYE: Vec3 = Vec3::new(-2.0, 1.8, -8.0);
pub const TARGET: Vec3 = Vec3::new(0.5, 2.8, -25.0);
pub const FOV_Y_DEGREES: f32 = 60.0;

/// Which fog the camera renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FogKind {
    /// No fog.
    None,
    /// volfog's froxel fog (`FroxelFog`).
    Froxel,
    /// Bevy's built-in ray-marched `VolumetricFog` in a `FogVolume` around the scene.
    BevyBuiltIn,
    /// The same components, rendered by volfog under `BevyFogCompat`.
    BevyCompat,
    /// Bevy's exponential `DistanceFog` ([`DISTANCE_FOG`]), drawn by Bevy's materials.
    BevyDistance,
    /// The same `DistanceFog`, rendered by volfog under `BevyFogCompat`.
    BevyDistanceCompat,
}

/// The distance fog of [`FogKind::BevyDistance`]: exponential, 0.03 / m, blue-grey.
pub fn distance_fog() -> DistanceFog {
    DistanceFog {
        color: Color::linear_rgb(0.5, 0.55, 0.62),
        falloff: FogFalloff::Exponential { density: 0.03 },
        ..default()
    }
}

/// How to build the scene.
#[derive(Clone, Debug)]
pub struct SceneOptions {
    /// Image size in pixels.
    pub width: u32,
    pub height: u32,
    /// The fog.
    pub fog: FogKind,
    /// Density noise on (off gives the closed-form height fog the tests compare with).
    pub noise: bool,
    /// Temporal reprojection on.
    pub temporal: bool,
    /// Record GPU time spans (timestamp queries and Bevy's `RenderDiagnosticsPlugin`).
    pub gpu_timings: bool,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self {
            width: 640,
            height: 360,
            fog: FogKind::Froxel,
            noise: true,
            temporal: true,
            gpu_timings: false,
        }
    }
}

impl SceneOptions {
    /// A still image of `fog` to compare: no noise, no temporal reprojection, no timings.
    pub fn still(width: u32, height: u32, fog: FogKind) -> Self {
        Self {
            width,
            height,
            fog,
            noise: false,
            temporal: false,
            gpu_timings: false,
        }
    }
}

/// An oriented box of the scene: centre, half extents and rotation (m).
#[derive(Clone, Copy, Debug)]
pub struct SceneBox {
    pub center: Vec3,
    pub half: Vec3,
    pub rotation: Quat,
}

impl SceneBox {
    fn aabb(min: Vec3, max: Vec3) -> Self {
        Self {
            center: 0.5 * (min + max),
            half: 0.5 * (max - min),
            rotation: Quat::IDENTITY,
        }
    }

    /// Distance along the ray (origin, unit dir) to the box, if it is hit.
    pub fn hit(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        let inv = self.rotation.inverse();
        let o = inv * (origin - self.center);
        let d = inv * dir;
        let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
        for i in 0..3 {
            if d[i].abs() < 1e-9 {
                if o[i].abs() > self.half[i] {
                    return None;
                }
                continue;
            }
            let a = (-self.half[i] - o[i]) / d[i];
            let b = (self.half[i] - o[i]) / d[i];
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        (t0 <= t1).then_some(t0)
    }
}

/// Unit direction from the scene towards the sun: 7 degrees up, slightly to the
/// right of the view, behind the colonnade.
pub fn sun_direction() -> Vec3 {
    let (elevation, azimuth) = (7f32.to_radians(), 3f32.to_radians());
    Vec3::new(
        azimuth.sin() * elevation.cos(),
        elevation.sin(),
        -azimuth.cos() * elevation.cos(),
    )
    .normalize()
}

/// Every opaque box of the scene (the ground is the plane y = 0).
pub fn boxes() -> Vec<SceneBox> {
    let mut boxes = Vec::new();
    let height = 7.0;
    let (inner, outer) = (2.4f32, 3.4f32);
    for k in -7i32..=7 {
        let x = 3.6 * k as f32;
        if x.abs() < outer + 0.5 {
            continue;
        }
        boxes.push(SceneBox::aabb(
            Vec3::new(x - 1.2, 0.0, ROW_Z - 0.8),
            Vec3::new(x + 1.2, 0.4, ROW_Z + 0.8),
        ));
        boxes.push(SceneBox::aabb(
            Vec3::new(x - 1.0, 0.4, ROW_Z - 0.55),
            Vec3::new(x + 1.0, height - 0.3, ROW_Z + 0.55),
        ));
        boxes.push(SceneBox::aabb(
            Vec3::new(x - 1.15, height - 0.3, ROW_Z - 0.75),
            Vec3::new(x + 1.15, height, ROW_Z + 0.75),
        ));
    }
    boxes.push(SceneBox::aabb(
        Vec3::new(-25.0, height, ROW_Z - 0.8),
        Vec3::new(25.0, height + 0.8, ROW_Z + 0.8),
    ));
    boxes.push(SceneBox::aabb(
        Vec3::new(-25.0, height + 0.8, ROW_Z - 0.5),
        Vec3::new(25.0, height + 4.0, ROW_Z + 0.5),
    ));
    let spring = 3.2;
    for side in [-1.0f32, 1.0] {
        let x = side * (inner + outer) * 0.5;
        boxes.push(SceneBox::aabb(
            Vec3::new(x - 0.5, 0.0, ROW_Z - 0.6),
            Vec3::new(x + 0.5, spring, ROW_Z + 0.6),
        ));
    }
    let pieces = 11;
    for k in 0..pieces {
        let a = std::f32::consts::PI * (k as f32 + 0.5) / pieces as f32;
        let r = (inner + outer) * 0.5;
        boxes.push(SceneBox {
            center: Vec3::new(r * a.cos(), spring + r * a.sin(), ROW_Z),
            half: Vec3::new(
                (outer - inner) * 0.5,
                outer * std::f32::consts::PI / pieces as f32 * 0.5 + 0.02,
                0.6,
            ),
            rotation: Quat::from_rotation_z(a),
        });
    }
    // The sphere's plinth.
    boxes.push(SceneBox::aabb(
        Vec3::new(GLASS_CENTER.x - 0.6, 0.0, GLASS_CENTER.z - 0.6),
        Vec3::new(GLASS_CENTER.x + 0.6, 0.8, GLASS_CENTER.z + 0.6),
    ));
    boxes
}

/// The fog settings of the scene's camera.
pub fn fog_settings(options: &SceneOptions) -> FroxelFog {
    FroxelFog {
        tile_size: 8,
        slices: 128,
        far: 128.0,
        medium: FogMediumSettings {
            density: 0.035,
            albedo: LinearRgba::rgb(0.9, 0.9, 0.9),
            height_falloff: 0.2,
            base_height: 0.0,
            phase_g: 0.7,
            noise_strength: if options.noise { 0.85 } else { 0.0 },
            noise_scale: 0.15,
            wind: if options.noise {
                Vec3::new(1.5, 0.2, -0.6)
            } else {
                Vec3::ZERO
            },
            ..default()
        },
        temporal: options.temporal,
        sun_scattering: 0.6,
        ..FroxelFog::default()
    }
}

/// Marks the scene's entities the tests change between frames.
#[derive(Component)]
pub struct SceneCamera;
#[derive(Component)]
pub struct GlassSphere;
#[derive(Component)]
pub struct Sun;

/// The scene camera's render target.
#[derive(Resource, Clone)]
pub struct Capture {
    pub image: Handle<Image>,
}

/// An `Rgba16Float` image a camera renders into and [`capture_images`] reads back.
pub fn render_target(images: &mut Assets<Image>, width: u32, height: u32) -> Handle<Image> {
    let mut target = Image::new_fill(
        Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        &[0; 8],
        TextureFormat::Rgba16Float,
        RenderAssetUsages::default(),
    );
    target.texture_descriptor.usage =
        TextureUsages::TEXTURE_BINDING | TextureUsages::COPY_SRC | TextureUsages::RENDER_ATTACHMENT;
    images.add(target)
}

/// A headless app that renders the scene into an `Rgba16Float` image.
pub fn app(options: &SceneOptions) -> App {
    build_app(options, None)
}

/// The scene's app: headless (`window` `None`: no window, no event loop; the camera
/// renders into the [`Capture`] image), or with a window of its own that the scene
/// camera renders into (run it with `App::run`).
pub fn build_app(options: &SceneOptions, window: Option<Window>) -> App {
    let mut app = App::new();
    // In a window the log is on: leave out the Vulkan validation layer, whose SPIR-V
    // validator (Debian 12's) does not know the WGSL source-language tag naga writes
    // into each module and logs an error per shader.
    let mut instance_flags = wgpu::InstanceFlags::from_build_config().with_env();
    if window.is_some() {
        instance_flags.remove(wgpu::InstanceFlags::VALIDATION);
    }
    let render = RenderPlugin {
        render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
            backends: Some(wgpu::Backends::VULKAN),
            instance_flags,
            features: if options.gpu_timings {
                wgpu::Features::TIMESTAMP_QUERY
                    | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                    | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES
            } else {
                wgpu::Features::empty()
            },
            ..Default::default()
        })),
        synchronous_pipeline_compilation: true,
        ..Default::default()
    };
    let plugins = DefaultPlugins.set(render);
    let headless = window.is_none();
    match window {
        Some(window) => app.add_plugins(plugins.set(WindowPlugin {
            primary_window: Some(window),
            ..Default::default()
        })),
        // Tests install their own log capture.
        None => app.add_plugins(
            plugins
                .disable::<bevy::log::LogPlugin>()
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    ..Default::default()
                })
                .disable::<WinitPlugin>(),
        ),
    };
    app.add_plugins(VolumetricFogPlugin)
        .insert_resource(GlobalAmbientLight {
            color: Color::linear_rgb(0.57, 0.71, 1.0),
            brightness: 140.0,
            ..Default::default()
        })
        .insert_resource(options.clone_resource())
        .add_systems(Startup, spawn);
    if options.gpu_timings {
        app.add_plugins(bevy::render::diagnostic::RenderDiagnosticsPlugin);
    }
    if matches!(
        options.fog,
        FogKind::BevyCompat | FogKind::BevyDistanceCompat
    ) {
        app.add_plugins(BevyFogCompat);
    }
    // Headless, the app is driven by `update`; with a window, `App::run` finishes
    // the plugins once the window (which the renderer needs) exists.
    if headless {
        while app.plugins_state() == PluginsState::Adding {
            bevy::tasks::tick_global_task_pools_on_main_thread();
        }
        app.finish();
        app.cleanup();
    }
    app
}

#[derive(Resource, Clone)]
struct Options(SceneOptions);

impl SceneOptions {
    fn clone_resource(&self) -> Options {
        Options(self.clone())
    }
}

fn spawn(
    mut commands: Commands,
    options: Res<Options>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut glass_materials: ResMut<Assets<FoggedGlassMaterial>>,
    mut images: ResMut<Assets<Image>>,
) {
    let options = &options.0;
    let image = render_target(&mut images, options.width, options.height);
    commands.insert_resource(Capture {
        image: image.clone(),
    });

    let stone = materials.add(StandardMaterial {
        base_color: Color::linear_rgb(0.62, 0.58, 0.52),
        perceptual_roughness: 0.9,
        reflectance: 0.2,
        ..Default::default()
    });
    let ground = materials.add(StandardMaterial {
        base_color: Color::linear_rgb(0.55, 0.52, 0.46),
        perceptual_roughness: 0.95,
        reflectance: 0.1,
        ..Default::default()
    });
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(600.0, 600.0))),
        MeshMaterial3d(ground),
    ));
    let cube = meshes.add(Cuboid::new(1.0, 1.0, 1.0));
    for b in boxes() {
        commands.spawn((
            Mesh3d(cube.clone()),
            MeshMaterial3d(stone.clone()),
            Transform::from_translation(b.center)
                .with_rotation(b.rotation)
                .with_scale(2.0 * b.half),
        ));
    }
    commands.spawn((
        Mesh3d(meshes.add(Sphere::new(GLASS_RADIUS).mesh().uv(48, 24))),
        MeshMaterial3d(glass_materials.add(FoggedGlassMaterial::default())),
        Transform::from_translation(GLASS_CENTER),
        GlassSphere,
    ));

    // The sun behind the colonnade, with four cascades over the first 80 m.
    let sun = sun_direction();
    commands.spawn((
        DirectionalLight {
            color: Color::linear_rgb(1.0, 0.75, 0.48),
            illuminance: 7800.0,
            shadow_maps_enabled: true,
            ..Default::default()
        },
        Transform::IDENTITY.looking_to(-sun, Vec3::Y),
        CascadeShadowConfigBuilder {
            num_cascades: 4,
            first_cascade_far_bound: 8.0,
            maximum_distance: 80.0,
            ..Default::default()
        }
        .build(),
        VolumetricLight,
        Sun,
    ));
    // Coloured lights: two lanterns on the pillars, two spots and a small red light
    // by the sphere. Intensities in lumens: 4 pi / exposure times the demo's
    // intensities at 1 m.
    let lumens = |i: f32| i * 4.0 * std::f32::consts::PI / Exposure { ev100: EV100 }.exposure();
    let front = ROW_Z + 0.75;
    for (position, color, intensity, range) in [
        (
            Vec3::new(-10.8, 2.6, front - 0.25),
            Color::linear_rgb(1.0, 0.43, 0.13),
            60.0,
            14.0,
        ),
        (
            Vec3::new(10.8, 2.4, front - 0.25),
            Color::linear_rgb(0.14, 0.57, 1.0),
            70.0,
            14.0,
        ),
        (
            GLASS_CENTER + Vec3::new(1.3, -1.2, 0.8),
            Color::linear_rgb(1.0, 0.17, 0.09),
            35.0,
            6.0,
        ),
    ] {
        commands.spawn((
            PointLight {
                color,
                intensity: lumens(intensity),
                range,
                radius: 0.05,
                ..Default::default()
            },
            Transform::from_translation(position),
        ));
    }
    for (position, dir, color, intensity, range, inner, outer) in [
        (
            Vec3::new(-7.2, 6.6, front),
            Vec3::new(0.0, -1.0, 0.25),
            Color::linear_rgb(1.0, 0.16, 0.86),
            110.0,
            14.0,
            0.3,
            0.5,
        ),
        (
            Vec3::new(-14.4, 6.6, front),
            Vec3::new(0.3, -1.0, 0.5),
            Color::linear_rgb(0.28, 1.0, 0.2),
            90.0,
            16.0,
            0.25,
            0.45,
        ),
    ] {
        commands.spawn((
            SpotLight {
                color,
                intensity: lumens(intensity),
                range,
                radius: 0.05,
                inner_angle: inner,
                outer_angle: outer,
                ..Default::default()
            },
            Transform::from_translation(position).looking_to(dir, Vec3::Y),
        ));
    }
    // A pocket of denser fog under the magenta spot.
    commands.spawn((
        FroxelFogVolume {
            shape: FogVolumeShape::Ellipsoid,
            density: 0.12,
            edge: 0.6,
            ..default()
        },
        Transform::from_xyz(-7.2, 2.0, ROW_Z + 3.0).with_scale(Vec3::new(4.4, 5.2, 4.4)),
    ));

    let mut camera = commands.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(Color::linear_rgb(0.35, 0.42, 0.55)),
            ..Default::default()
        },
        RenderTarget::Image(image.into()),
        Projection::Perspective(PerspectiveProjection {
            fov: FOV_Y_DEGREES.to_radians(),
            near: 0.1,
            ..Default::default()
        }),
        Transform::from_translation(EYE).looking_at(TARGET, Vec3::Y),
        Hdr,
        Msaa::Off,
        Tonemapping::None,
        Exposure { ev100: EV100 },
        SceneCamera,
    ));
    match options.fog {
        FogKind::None => {}
        FogKind::Froxel => {
            camera.insert(fog_settings(options));
        }
        FogKind::BevyBuiltIn | FogKind::BevyCompat => {
            camera.insert(VolumetricFog::default());
        }
        FogKind::BevyDistance | FogKind::BevyDistanceCompat => {
            camera.insert(distance_fog());
        }
    }
    if matches!(options.fog, FogKind::BevyBuiltIn | FogKind::BevyCompat) {
        // Bevy's fog lives in volumes: one box around the scene, with the extinction,
        // albedo and phase asymmetry of ours at the ground (Bevy's extinction is
        // density_factor * (absorption + scattering)).
        commands.spawn((
            FogVolume {
                density_factor: 0.035,
                absorption: 0.1,
                scattering: 0.9,
                scattering_asymmetry: 0.7,
                ..Default::default()
            },
            Transform::from_xyz(0.0, 10.0, -20.0).with_scale(Vec3::new(120.0, 20.0, 120.0)),
        ));
    }
}

/// A fog view's integrated volume read back, with the fog it was computed for.
pub struct Volume {
    pub texels: Vec<Vec4>,
    pub fog: ExtractedFroxelFog,
}

/// Reads the integrated volume (rgba16float) of the app's fog camera.
pub fn read_volume(app: &App) -> Volume {
    let world = app.sub_app(RenderApp).world();
    let fogs = world.resource::<FogViews>();
    let texture = fogs.primary().expect("a fog view").fog.integrated_texture();
    // Bevy's device, queue and adapter, with volfog's GPU test helpers.
    let gpu = volfog_testkit::gpu::Gpu {
        adapter: (**world.resource::<RenderAdapter>()).clone(),
        device: world.resource::<RenderDevice>().wgpu_device().clone(),
        queue: (**world.resource::<RenderQueue>()).clone(),
        info: (**world.resource::<RenderAdapterInfo>()).clone(),
    };
    let bytes = gpu
        .read_texture_raw(texture, 8)
        .expect("read the integrated volume");
    let texels = bytes
        .chunks_exact(8)
        .map(|p| {
            let h = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
            Vec4::new(h(0), h(1), h(2), h(3))
        })
        .collect();
    let mut views = world
        .try_query::<&ExtractedFroxelFog>()
        .expect("registered");
    let fog = views.iter(world).next().expect("an extracted fog").clone();
    Volume { texels, fog }
}

/// Runs frames until a read-back of the target arrives (after `warmup` frames), and
/// returns it as linear rgba.
pub fn capture(app: &mut App, warmup: u32) -> Vec<Vec4> {
    for _ in 0..warmup {
        app.update();
    }
    // The scene (and its target) exists after the first frame.
    let image = app.world().resource::<Capture>().image.clone();
    capture_images(app, &[image], 0).remove(0)
}

/// Runs frames until read-backs of every image arrive (after `warmup` frames, all from
/// the same frame's requests), and returns them as linear rgba.
pub fn capture_images(app: &mut App, images: &[Handle<Image>], warmup: u32) -> Vec<Vec<Vec4>> {
    for _ in 0..warmup {
        app.update();
    }
    let sinks: Vec<Arc<Mutex<Option<Vec<u8>>>>> = images
        .iter()
        .map(|image| {
            let sink = Arc::new(Mutex::new(None));
            let filled = sink.clone();
            app.world_mut()
                .spawn(Readback::texture(image.clone()))
                .observe(move |event: On<ReadbackComplete>, mut commands: Commands| {
                    *filled.lock().unwrap() = Some(event.data.clone());
                    commands.entity(event.entity).despawn();
                });
            sink
        })
        .collect();
    for _ in 0..20 {
        app.update();
        if sinks.iter().all(|s| s.lock().unwrap().is_some()) {
            return sinks
                .iter()
                .map(|s| {
                    s.lock()
                        .unwrap()
                        .take()
                        .unwrap()
                        .chunks_exact(8)
                        .map(|p| {
                            let h = |i: usize| {
                                half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32()
                            };
                            Vec4::new(h(0), h(1), h(2), h(3))
                        })
                        .collect()
                })
                .collect();
        }
    }
    panic!("no read-back of the render targets in 20 frames");
}

/// Per-pixel relative differences of two images (sum of rgb, against `b`), sorted.
pub fn relative_differences(a: &[Vec4], b: &[Vec4]) -> Vec<f32> {
    let mut d: Vec<f32> = a
        .iter()
        .zip(b)
        .map(|(a, b)| {
            let (a, b) = (a.truncate().element_sum(), b.truncate().element_sum());
            (a - b).abs() / b.abs().max(1e-3)
        })
        .collect();
    d.sort_by(f32::total_cmp);
    d
}

#[path = "png.rs"]
mod png;
// Not every file that includes the scene writes images.
#[allow(unused_imports)]
pub use png::write_png;
