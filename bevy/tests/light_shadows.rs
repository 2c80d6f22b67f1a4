//! Bevy's own point and spot light shadow maps in the fog: a closed room (six walls,
//! floor and ceiling as Bevy meshes that cast shadows) with a shadowed point lamp and a
//! shadowed spot light inside, the camera outside, in homogeneous fog. Bevy renders the
//! lights' shadow maps; the plugin hands them to the fog with the layers and cameras
//! Bevy used. With shadows, the fog outside the room gets none of the lamp's light
//! beyond the ESM leak band (volfog's bound: under 5 % once the fog is `bias + 3 range /
//! exponent` behind the farthest wall depth within the atlas texel's footprint); the same
//! scene with the light's shadows off lights the fog outside as the CPU mirror does.
//!
//! The scene also holds light-less shadowed decoys (two point lights and a spot light,
//! spawned before and after the room's lights, and a sun with four cascades) so that
//! the room's lights are not the first of Bevy's cube and spot layers: the fog finds
//! them only through Bevy's own light order.

#[path = "light_shadows/room.rs"]
mod room;

use bevy::app::PluginsState;
use bevy::asset::RenderAssetUsages;
use bevy::camera::{Exposure, RenderTarget, visibility::RenderLayers};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::light::{DirectionalLightShadowMap, GlobalAmbientLight, PointLightShadowMap};
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat, TextureUsages};
use bevy::render::renderer::{RenderAdapter, RenderAdapterInfo, RenderDevice, RenderQueue};
use bevy::render::settings::{RenderCreation, WgpuSettings};
use bevy::render::sync_world::RenderEntity;
use bevy::render::{RenderApp, RenderPlugin};
use room::{Measure, ROOM_MAX, ROOM_MIN, WALL};
use volfog::glam as vg;
use volfog::pipeline::LocalShadowStats;
use volfog_bevy::{
    ExtractedFroxelFog, FogMediumSettings, FogViews, FroxelFog, VolumetricFogPlugin,
};

const W: u32 = 320;
const H: u32 = 180;
/// Bevy's shadow map sizes here: the atlas is a quarter of them (128 texels, k = 4).
const MAP: u32 = 512;
/// The lamp's and the spot's light at 1 m in the fog (before the medium), range (m).
const CANDELA: f32 = 1000.0;
const RANGE: f32 = 12.0;
const LAMP: Vec3 = Vec3::new(0.4, 1.6, -8.3);
const SPOT: Vec3 = Vec3::new(0.0, 1.5, -8.0);
const DENSITY: f32 = 0.05;

#[derive(Component)]
struct Lamp;
#[derive(Component)]
struct Spot;

/// One frame's scattering volume (inject's output: rgb in-scattering) with its fog.
struct Frame {
    texels: Vec<vg::Vec4>,
    fog: ExtractedFroxelFog,
    stats: LocalShadowStats,
}

fn fog_settings() -> FroxelFog {
    FroxelFog {
        tile_size: 8,
        slices: 64,
        near: 0.5,
        far: 24.0,
        slice_curve: 2.0,
        medium: FogMediumSettings {
            density: DENSITY,
            albedo: LinearRgba::rgb(1.0, 1.0, 1.0),
            height_falloff: 0.0,
            phase_g: 0.0,
            noise_strength: 0.0,
            ..default()
        },
        temporal: false,
        tail: false,
        ..default()
    }
}

fn app() -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(RenderPlugin {
                render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                    backends: Some(wgpu::Backends::VULKAN),
                    ..default()
                })),
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .disable::<bevy::log::LogPlugin>()
            // Headless: no window and no event loop.
            .set(bevy::window::WindowPlugin {
                primary_window: None,
                exit_condition: bevy::window::ExitCondition::DontExit,
                ..default()
            })
            .disable::<bevy::winit::WinitPlugin>(),
    )
    .add_plugins(VolumetricFogPlugin)
    .insert_resource(GlobalAmbientLight {
        brightness: 0.0,
        ..default()
    })
    .insert_resource(PointLightShadowMap { size: MAP as usize })
    .insert_resource(DirectionalLightShadowMap { size: MAP as usize })
    .add_systems(Startup, spawn);
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    app
}

fn lumens(candela: f32) -> f32 {
    candela * 4.0 * std::f32::consts::PI / Exposure::default().exposure()
}

fn spawn(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut images: ResMut<Assets<Image>>,
) {
    let mut target = Image::new_fill(
        Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        &[0; 8],
        TextureFormat::Rgba16Float,
        RenderAssetUsages::default(),
    );
    target.texture_descriptor.usage =
        TextureUsages::TEXTURE_BINDING | TextureUsages::COPY_SRC | TextureUsages::RENDER_ATTACHMENT;
    // The camera outside the room, looking at it. It does not draw the room (layer 1),
    // so its depth culls no froxel; the lights see layers 0 and 1.
    commands.spawn((
        Camera3d::default(),
        RenderTarget::Image(images.add(target).into()),
        Projection::Perspective(PerspectiveProjection {
            fov: 70f32.to_radians(),
            near: 0.1,
            ..default()
        }),
        Transform::from_xyz(0.5, 1.7, -0.5).looking_at(Vec3::new(0.0, 1.5, -9.0), Vec3::Y),
        Msaa::Off,
        Tonemapping::None,
        fog_settings(),
    ));
    let lit = RenderLayers::from_layers(&[0, 1]);
    let stone = materials.add(StandardMaterial::default());
    for (min, max) in room::walls(ROOM_MIN, ROOM_MAX, WALL) {
        let (min, max) = (
            Vec3::from_array(min.to_array()),
            Vec3::from_array(max.to_array()),
        );
        commands.spawn((
            Mesh3d(meshes.add(Cuboid::from_corners(min, max))),
            MeshMaterial3d(stone.clone()),
            Transform::from_translation(0.5 * (min + max)),
            RenderLayers::layer(1),
        ));
    }
    // A sun without light whose four cascades come first in the directional texture.
    commands.spawn((
        DirectionalLight {
            illuminance: 0.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::default().looking_to(Vec3::new(0.2, -1.0, -0.3), Vec3::Y),
    ));
    let decoy_point = |commands: &mut Commands, x: f32| {
        commands.spawn((
            PointLight {
                intensity: 0.0,
                range: 1.0,
                shadow_maps_enabled: true,
                ..default()
            },
            Transform::from_xyz(x, 1.0, -3.0),
            lit.clone(),
        ));
    };
    let decoy_spot = |commands: &mut Commands, x: f32| {
        commands.spawn((
            SpotLight {
                intensity: 0.0,
                range: 1.0,
                shadow_maps_enabled: true,
                ..default()
            },
            Transform::from_xyz(x, 1.0, -3.0).looking_to(Vec3::Y, Vec3::Z),
            lit.clone(),
        ));
    };
    decoy_point(&mut commands, -3.0);
    decoy_spot(&mut commands, -2.0);
    commands.spawn((
        PointLight {
            intensity: lumens(CANDELA),
            range: RANGE,
            radius: 0.05,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_translation(LAMP),
        lit.clone(),
        Lamp,
    ));
    commands.spawn((
        SpotLight {
            intensity: 0.0,
            range: RANGE,
            radius: 0.05,
            inner_angle: 0.4,
            outer_angle: 0.5,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_translation(SPOT).looking_to(Vec3::X, Vec3::Y),
        lit.clone(),
        Spot,
    ));
    decoy_point(&mut commands, 3.0);
    decoy_spot(&mut commands, 2.0);
}

/// Runs a few frames (Bevy re-renders the changed lights' maps) and reads the fog's
/// scattering volume on Bevy's device.
fn frame(app: &mut App) -> Frame {
    for _ in 0..4 {
        app.update();
    }
    let world = app.sub_app(RenderApp).world();
    let view = world.resource::<FogViews>().primary().expect("a fog view");
    let texture = view.fog.scattering_texture();
    let gpu = volfog_testkit::gpu::Gpu {
        adapter: (**world.resource::<RenderAdapter>()).clone(),
        device: world.resource::<RenderDevice>().wgpu_device().clone(),
        queue: (**world.resource::<RenderQueue>()).clone(),
        info: (**world.resource::<RenderAdapterInfo>()).clone(),
    };
    let bytes = gpu.read_texture_raw(texture, 8).expect("read the volume");
    assert_eq!(texture.format(), wgpu::TextureFormat::Rgba16Float);
    let texels = bytes
        .chunks_exact(8)
        .map(|p| {
            let h = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
            vg::Vec4::new(h(0), h(1), h(2), h(3))
        })
        .collect();
    let stats = view.fog.local_shadow_stats();
    let mut views = world
        .try_query::<&ExtractedFroxelFog>()
        .expect("registered");
    let fog = views.iter(world).next().expect("an extracted fog").clone();
    Frame { texels, fog, stats }
}

/// Sets a light's intensity and shadows.
fn set_light<T: Component>(app: &mut App, on: bool, shadows: bool) {
    let world = app.world_mut();
    let mut q =
        world.query_filtered::<(Option<&mut PointLight>, Option<&mut SpotLight>), With<T>>();
    let (point, spot) = q.single_mut(world).unwrap();
    let intensity = if on { lumens(CANDELA) } else { 0.0 };
    if let Some(mut l) = point {
        (l.intensity, l.shadow_maps_enabled) = (intensity, shadows);
    }
    if let Some(mut l) = spot {
        (l.intensity, l.shadow_maps_enabled) = (intensity, shadows);
    }
}

fn set_budget(app: &mut App, points: u32) {
    let world = app.world_mut();
    let mut q = world.query::<&mut FroxelFog>();
    q.single_mut(world).unwrap().point_shadows = points;
}

/// Bevy's clustered index of a light (its render entity in `entity_to_index`).
fn bevy_index<T: Component>(app: &mut App) -> usize {
    let world = app.world_mut();
    let mut q = world.query_filtered::<&RenderEntity, With<T>>();
    let entity = q.single(world).unwrap().id();
    let render = app.sub_app(RenderApp).world();
    *render
        .resource::<bevy::pbr::GlobalClusterableObjectMeta>()
        .entity_to_index
        .get(&entity)
        .expect("the light is clustered")
}

#[test]
fn bevys_cube_faces_are_volfogs() {
    // Bevy renders face f of a point light with the view of `CUBE_MAP_FACES[f]` at the
    // light; the plugin's camera gives volfog's `cube_face_view(f) * cube_from_world`
    // with cube_from_world = scale(1, 1, -1) * translate(-light) (Bevy's `flip_z`).
    let position = Vec3::new(1.0, 2.0, -3.0);
    let flip_z = vg::Mat4::from_scale(vg::Vec3::new(1.0, 1.0, -1.0));
    let cube_from_world =
        flip_z * vg::Mat4::from_translation(-vg::Vec3::from_array(position.to_array()));
    for (f, face) in bevy::camera::primitives::CUBE_MAP_FACES.iter().enumerate() {
        let world_from_view =
            Transform::from_translation(position).looking_at(position + face.target, face.up);
        let bevy =
            vg::Mat4::from_cols_array(&world_from_view.to_matrix().inverse().to_cols_array());
        let ours = volfog::uniforms::LightCamera::cube_face_view(f as u32) * cube_from_world;
        assert!(
            bevy.abs_diff_eq(ours, 1e-6),
            "face {f}: {bevy:?} vs {ours:?}"
        );
    }
}

#[test]
fn bevys_point_and_spot_shadows_keep_the_fog_outside_a_closed_room_dark() {
    let mut app = app();
    app.update();
    let shadowed = frame(&mut app);
    let lamp_index = bevy_index::<Lamp>(&mut app);
    let spot_index = bevy_index::<Spot>(&mut app);
    let local = shadowed.fog.config.local_shadows.expect("local shadows");
    eprintln!(
        "Bevy's order: the lamp is clustered light {lamp_index} (cube {lamp_index}), the spot light {spot_index} \
         (3 point lights before it, 4 sun cascades: directional layer {}); atlas {} texels for Bevy's {MAP}-texel maps; \
         stats with shadows {:?}",
        spot_index - 3 + 4,
        local.resolution,
        shadowed.stats
    );
    assert_eq!(local.resolution, MAP / 4);
    assert!(lamp_index > 0, "the lamp is not Bevy's first cube");
    assert!(spot_index > 3, "the spot is not Bevy's first spot map");
    // Budget: two shadowed point lights (the lamp, the nearer of the range spheres,
    // and a decoy), all three spot lights; the other decoy is unshadowed.
    assert_eq!(
        (
            shadowed.stats.point_shadows,
            shadowed.stats.spot_shadows,
            shadowed.stats.unshadowed
        ),
        (2, 3, 1)
    );
    set_light::<Lamp>(&mut app, true, false);
    let open = frame(&mut app);
    set_light::<Lamp>(&mut app, true, true);
    set_budget(&mut app, 0);
    let over_budget = frame(&mut app);
    set_budget(&mut app, 2);
    set_light::<Lamp>(&mut app, false, true);
    set_light::<Spot>(&mut app, true, true);
    let spot_shadowed = frame(&mut app);
    set_light::<Spot>(&mut app, true, false);
    let spot_open = frame(&mut app);

    let m = Measure::new(&shadowed.fog, DENSITY);
    let bias = PointLight::DEFAULT_SHADOW_DEPTH_BIAS;
    let lamp = m.point_lamp(
        &shadowed.texels,
        &open.texels,
        to_vg(LAMP),
        RANGE,
        bias,
        MAP,
    );
    eprintln!("{lamp}");
    lamp.assert_bounds(2000, 200);

    // With the lamp's shadows off (or past the fog's budget) the fog outside is lit as
    // the CPU mirror lights it.
    let cpu = m.against_cpu(&open.texels, &open.fog.lights, to_vg(LAMP));
    let budget = m.against_cpu(&over_budget.texels, &over_budget.fog.lights, to_vg(LAMP));
    eprintln!(
        "fog outside the room against the CPU mirror's unshadowed light: lamp shadows off {cpu}; \
         lamp past the budget (point_shadows = 0, stats {:?}) {budget}",
        over_budget.stats
    );
    assert_eq!(over_budget.stats.point_shadows, 0);
    for c in [&cpu, &budget] {
        assert!(c.count > 2000, "{c}");
        assert!((0.95..=1.05).contains(&c.median), "{c}");
        assert!(c.low >= 0.8, "{c}");
    }

    let spot_bias = SpotLight::DEFAULT_SHADOW_DEPTH_BIAS;
    let spot = m.spot_wall(
        &spot_shadowed.texels,
        &spot_open.texels,
        to_vg(SPOT),
        RANGE,
        spot_bias,
    );
    let spot_cpu = m.against_cpu(&spot_open.texels, &spot_open.fog.lights, to_vg(SPOT));
    eprintln!("{spot}; with its shadows off, the fog outside against the CPU mirror: {spot_cpu}");
    spot.assert_bounds(2000, 10);
    assert!(spot_cpu.count > 200, "{spot_cpu}");
    assert!((0.95..=1.05).contains(&spot_cpu.median), "{spot_cpu}");
}

fn to_vg(v: Vec3) -> vg::Vec3 {
    vg::Vec3::from_array(v.to_array())
}
