//! The Bevy examples of `docs/bevy.md`, line for line (the root host tests check that
//! the guide's blocks are here): the plugin, a camera with `FroxelFog`, a sun with
//! shadow maps and an ellipsoid `FroxelFogVolume`; and a scene written for Bevy's own
//! `VolumetricFog` rendered by volfog under `BevyFogCompat` (`-- --bevy-fog`); and a
//! muzzle flash that lights the fog for one frame, `TransientFogLight` (`-- --flash`,
//! the space bar fires).
//!
//! Compiled with the workspace's examples (`cargo check --examples` in `bevy/`).

fn main() {
    if std::env::args().any(|a| a == "--bevy-fog") {
        bevy_fog_compat();
    } else if std::env::args().any(|a| a == "--flash") {
        muzzle_flash();
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
        commands.spawn((FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5 },
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
