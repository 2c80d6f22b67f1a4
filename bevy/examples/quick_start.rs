//! The Bevy example of `docs/bevy.md`, line for line (the root host tests check that
//! the guide's block is here): the plugin, a camera with `FroxelFog`, a sun with
//! shadow maps and an ellipsoid `FroxelFogVolume`.
//!
//! Compiled with the workspace's examples (`cargo check --examples` in `bevy/`).

#[rustfmt::skip]
fn main() {
    use bevy::prelude::*;
    use volfog_bevy::{FogVolumeShape, FroxelFog, FroxelFogVolume, VolumetricFogPlugin};

    App::new().add_plugins((DefaultPlugins, VolumetricFogPlugin)).add_systems(Startup, |mut commands: Commands| {
        commands.spawn((Camera3d::default(), FroxelFog { far: 150.0, ..default() }));
        commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, Transform::default()));
        commands.spawn((FroxelFogVolume { shape: FogVolumeShape::Ellipsoid, density: 0.2, edge: 0.5 },
                        Transform::from_xyz(0.0, 2.0, -10.0).with_scale(Vec3::splat(6.0))));
    }).run();
}
