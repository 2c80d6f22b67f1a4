//! The Bevy examples of `docs/bevy.md`, line for line (the root host tests check that
//! the guide's blocks are here): the plugin, a camera with `FroxelFog`, a sun with
//! shadow maps and an ellipsoid `FroxelFogVolume`; and a scene written for Bevy's own
//! `VolumetricFog` rendered by volfog under `BevyFogCompat` (`-- --bevy-fog`).
//!
//! Compiled with the workspace's examples (`cargo check --examples` in `bevy/`).

fn main() {
    if std::env::args().any(|a| a == "--bevy-fog") {
        bevy_fog_compat();
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
