//! The Bevy examples of `docs/bevy.md`, line for line (the root host tests check that
//! the guide's blocks are here): the plugin, a camera with `FroxelFog`, a sun with
//! shadow maps and an ellipsoid `FroxelFogVolume`; and a scene written for Bevy's own
//! `VolumetricFog` rendered by volfog under `BevyFogCompat` (`-- --bevy-fog`); and a
//! muzzle flash that lights the fog for one frame, `TransientFogLight` (`-- --flash`,
//! the space bar fires); and a density of your own, `FroxelFogDensity`, with a
//! `FroxelFogVolume` that clears the fog in a house (`-- --density`); and smoke from a
//! vent as `FroxelFogParticles` (`-- --particles`).
//!
//! Compiled with the workspace's examples (`cargo check --examples` in `bevy/`).

fn main() {
    if std::env::args().any(|a| a == "--bevy-fog") {
        bevy_fog_compat();
    } else if std::env::args().any(|a| a == "--flash") {
        muzzle_flash();
    } else if std::env::args().any(|a| a == "--density") {
        own_density();
    } else if std::env::args().any(|a| a == "--particles") {
        particles();
    } else {
        froxel_fog();
    }
}

#[rustfmt::skip]
fn froxel_fog() {
    use bevy::prelude::*;
    use volfog_bevy::{FogVolumeShape, FroxelFog, FroxelFogVolume, VolumetricFogPlugin};

    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin)).add_systems(Startup, |mut commands: Commands| {
        commands.spawn((Camera3d::default(), FroxelFog { far: 150.0, ..default() }));
        commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::default()));
        commands.spawn((FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5, ..default() },
                        Transform::from_xyz(0.0, 2.0, -10.0).with_scale(Vec3::splat(6.0))));
    }).run();
}

#[rustfmt::skip]
fn bevy_fog_compat() {
    use bevy::light::{FogVolume, VolumetricFog, VolumetricLight};
    use bevy::prelude::*;
    use volfog_bevy::{BevyFogCompat, VolumetricFogPlugin};

    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin, BevyFogCompat)).add_systems(Startup, |mut commands: Commands| {
        commands.spawn((Camera3d::default(), VolumetricFog::default()));
        commands.spawn((FogVolume::default(), Transform::from_scale(Vec3::splat(40.0))));
        commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, VolumetricLight));
    }).run();
}

#[rustfmt::skip]
fn muzzle_flash() {
    use bevy::prelude::*;
    use volfog_bevy::{FroxelFog, TransientFogLight, VolumetricFogPlugin};

    #[derive(Component)]
    struct Flash;
    // The frame the gun fires, a flash at the muzzle; the next frame it is gone, and so
    // is its light in the fog (TransientFogLight: no trail in the fog's history).
    fn fire(mut commands: Commands, keys: Res<ButtonInput<KeyCode>>, flashes: Query<Entity, With<Flash>>) {
        for flash in &flashes {
            commands.entity(flash).despawn();
        }
        if keys.just_pressed(KeyCode::Space) {
            commands.spawn((PointLight { intensity: 2.0e5, range: 12.0, ..default() },
                            Transform::from_xyz(0.3, 1.5, -1.0), TransientFogLight, Flash));
        }
    }
    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin)).add_systems(Update, fire)
        .add_systems(Startup, |mut commands: Commands| {
            commands.spawn((Camera3d::default(), FroxelFog::default()));
        }).run();
}

#[rustfmt::skip]
fn own_density() {
    use bevy::prelude::*;
    use bevy::shader::Shader;
    use volfog_bevy::{BlendMode, FogVolumeShape, FroxelFog, FroxelFogDensity, FroxelFogVolume, VolumetricFogPlugin};

    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin)).add_systems(Startup, |mut commands: Commands, mut shaders: ResMut<Assets<Shader>>| {
        // a module defining volfog_custom_density, WGSL or WESL (or asset_server.load("fog/swirl.wesl"))
        let shader = shaders.add(Shader::from_wgsl(include_str!("../../examples/portal_swirl.wgsl"), "portal_swirl.wgsl"));
        let mut swirl = FroxelFogDensity::new(shader);
        swirl.params[0] = Vec4::new(0.0, 2.0, -25.0, 4.0);   // the portal's centre and radius (m)
        swirl.params[1] = Vec4::new(0.5, 1.5, 3.0, 0.0);     // peak extinction (1/m), swirl speed (rad/s), arms
        swirl.params[2] = Vec4::new(0.6, 0.2, 1.4, 0.0);     // its glow at the peak
        commands.spawn((Camera3d::default(), FroxelFog::default(), swirl));
        // a house that clears the fog inside it, after the volumes of order 0
        commands.spawn((FroxelFogVolume { shape: FogVolumeShape::Box, density: 10.0, edge: 0.05, blend: BlendMode::Subtract, order: 1 },
                        Transform::from_xyz(8.0, 2.5, -20.0).with_scale(Vec3::new(8.0, 5.0, 6.0))));
    }).run();
}

#[rustfmt::skip]
fn particles() {
    use bevy::prelude::*;
    use volfog_bevy::VolumetricFogPlugin;

    use volfog_bevy::volfog::glam as vg;
    use volfog_bevy::{FogParticle, FroxelFog, FroxelFogParticles};

    #[derive(Component)]
    struct Vent;
    fn setup(mut commands: Commands) {
        commands.spawn((Camera3d::default(), FroxelFog { max_particles: 256, ..default() }));
        commands.spawn((FroxelFogParticles::default(), Vent));
    }
    // Every frame: smoke rising from a vent 20 m ahead, the puffs widening and thinning.
    fn smoke(time: Res<Time>, mut vents: Query<&mut FroxelFogParticles, With<Vent>>) {
        let t = time.elapsed_secs();
        for mut particles in &mut vents {
            particles.0 = (0..64)
                .map(|i| {
                    let h = i as f32 * 0.15;
                    let at = vg::Vec3::new(0.3 * (h + t).sin(), h, -20.0);
                    FogParticle::smoke(at, 0.4 + 0.12 * h, 1.5 / (1.0 + h), vg::Vec3::splat(0.4))
                })
                .collect();
        }
    }
    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin))
        .add_systems(Startup, setup).add_systems(Update, smoke).run();
}
