//! Bevy's own fog components rendered by volfog: with [`BevyFogCompat`], a camera
//! with Bevy's `VolumetricFog` and the scene's `FogVolume`s get volfog's froxel fog
//! instead of Bevy's ray-marched pass.
//!
//! The mapping, per camera with `VolumetricFog` (and no `FroxelFog` of its own):
//!
//! | Bevy | volfog |
//! | --- | --- |
//! | `FogVolume` (unit cube) | `FroxelFogVolume` box, extinction `density_factor * (absorption + scattering)` |
//! | `scattering / (absorption + scattering) * fog_color * light_tint` | the medium's albedo (clamped to 1) |
//! | `scattering_asymmetry` | the medium's Henyey-Greenstein `phase_g` |
//! | `light_intensity` | `sun_scattering` and `light_scattering` |
//! | `VolumetricFog.ambient_color * ambient_intensity` | `ambient_radiance` (divided by the camera's exposure: Bevy adds it after exposure) |
//! | `VolumetricLight` on lights | `FogLightSelection::Volumetric`: only those lights light the fog |
//!
//! Outside the volumes there is no fog (the medium's density is 0, no tail), as in
//! Bevy. volfog's medium has one albedo and one phase: the volumes' values are taken
//! from the first volume (by entity), and a volume that differs is warned about once,
//! naming the field. A `density_texture` (and its offset) is not read: the volume is
//! uniform, with one warning. `VolumetricFog.step_count` and `jitter` are the ray
//! marcher's quality settings; the froxel grid's slices and temporal jitter take their
//! place.

use std::collections::HashSet;

use bevy::camera::Exposure;
use bevy::light::{FogVolume, VolumetricFog};
use bevy::prelude::*;
use bevy::render::{Render, RenderApp, RenderSystems};

use crate::settings::{
    FogLightSelection, FogMediumSettings, FogVolumeShape, FroxelFog, FroxelFogVolume,
};

/// Renders Bevy's `VolumetricFog` cameras and `FogVolume`s with volfog (add it next to
/// [`VolumetricFogPlugin`](crate::VolumetricFogPlugin)). Bevy's own volumetric pass
/// then runs for no camera.
///
/// A plugin rather than the default: Bevy's fog and volfog's have different lighting
/// models (Bevy's ambient term is added per ray, its light is attenuated by the
/// volume's bounding radius), so an app that keeps Bevy's fog on some cameras and uses
/// volfog's on others is not switched silently.
///
/// ```no_run
/// use bevy::light::{FogVolume, VolumetricFog, VolumetricLight};
/// use bevy::prelude::*;
/// use volfog_bevy::{BevyFogCompat, VolumetricFogPlugin};
///
/// fn setup(mut commands: Commands) {
///     // A scene written for Bevy's volumetric fog, unchanged.
///     commands.spawn((Camera3d::default(), VolumetricFog::default()));
///     commands.spawn((FogVolume::default(), Transform::from_scale(Vec3::splat(40.0))));
///     commands.spawn((DirectionalLight { shadow_maps_enabled: true, ..default() }, VolumetricLight));
/// }
/// # let mut app = App::new();
/// # app.add_plugins((VolumetricFogPlugin, BevyFogCompat)).add_systems(Startup, setup);
/// ```
pub struct BevyFogCompat;

impl Plugin for BevyFogCompat {
    fn build(&self, app: &mut App) {
        app.add_systems(PostUpdate, (sync_fog_volumes, sync_fog_cameras));
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render_app.add_systems(
                Render,
                drop_bevy_volumetric_fog
                    .after(RenderSystems::ExtractCommands)
                    .before(RenderSystems::PrepareAssets),
            );
        }
    }
}

/// Marks a `FroxelFog` or `FroxelFogVolume` that [`BevyFogCompat`] made from Bevy's
/// components (it follows them, and goes with them).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct FromBevyFog;

/// The `FroxelFogVolume` of a Bevy `FogVolume`.
pub fn froxel_fog_volume(volume: &FogVolume) -> FroxelFogVolume {
    FroxelFogVolume {
        shape: FogVolumeShape::Box,
        density: volume.density_factor * (volume.absorption + volume.scattering),
        // Bevy's volumes have hard faces; volfog's soft edge as thin as it goes
        // without aliasing on the froxel grid of a volume a few metres wide.
        edge: 0.02,
    }
}

/// The medium a Bevy `FogVolume` scatters light with: albedo, phase and the lights'
/// scale.
fn volume_medium(volume: &FogVolume) -> (LinearRgba, f32, f32) {
    let extinction = volume.absorption + volume.scattering;
    let share = if extinction > 0.0 {
        volume.scattering / extinction
    } else {
        0.0
    };
    let (color, tint) = (volume.fog_color.to_linear(), volume.light_tint.to_linear());
    let albedo = LinearRgba::rgb(
        (color.red * tint.red * share).clamp(0.0, 1.0),
        (color.green * tint.green * share).clamp(0.0, 1.0),
        (color.blue * tint.blue * share).clamp(0.0, 1.0),
    );
    (
        albedo,
        volume.scattering_asymmetry.clamp(-0.99, 0.99),
        volume.light_intensity,
    )
}

/// The `FroxelFog` of a camera with Bevy's `VolumetricFog`, the first fog volume's
/// medium and the camera's exposure.
pub fn froxel_fog(fog: &VolumetricFog, first: Option<&FogVolume>, exposure: f32) -> FroxelFog {
    let (albedo, phase_g, light_scale) =
        first
            .map(volume_medium)
            .unwrap_or((LinearRgba::WHITE, 0.0, 1.0));
    let ambient = fog.ambient_color.to_linear() * (fog.ambient_intensity / exposure.max(1e-12));
    FroxelFog {
        medium: FogMediumSettings {
            density: 0.0,
            albedo,
            height_falloff: 0.0,
            phase_g,
            noise_strength: 0.0,
            ..default()
        },
        tail: false,
        sun_scattering: light_scale,
        light_scattering: light_scale,
        ambient_scattering: 1.0,
        lights: FogLightSelection::Volumetric,
        ambient_radiance: Some(LinearRgba::rgb(ambient.red, ambient.green, ambient.blue)),
        ..FroxelFog::default()
    }
}

/// Gives every Bevy `FogVolume` its `FroxelFogVolume`, and warns once per volume and
/// field for what volfog does not take.
fn sync_fog_volumes(
    mut commands: Commands,
    volumes: Query<(
        Entity,
        &FogVolume,
        &InheritedVisibility,
        Option<&FroxelFogVolume>,
    )>,
    mut gone: RemovedComponents<FogVolume>,
    converted: Query<(), With<FromBevyFog>>,
    mut warned: Local<HashSet<(Entity, &'static str)>>,
) {
    for entity in gone.read() {
        if converted.contains(entity)
            && let Ok(mut e) = commands.get_entity(entity)
        {
            e.remove::<(FroxelFogVolume, FromBevyFog)>();
        }
    }
    let mut sorted: Vec<_> = volumes.iter().collect();
    sorted.sort_by_key(|(e, ..)| *e);
    let first = sorted.first().map(|(_, v, ..)| volume_medium(v));
    for (entity, volume, visible, current) in sorted {
        let mut warn = |field: &'static str, why: &str| {
            if warned.insert((entity, field)) {
                warn!("volfog: FogVolume {entity}: {field} {why}");
            }
        };
        if volume.density_texture.is_some() {
            warn(
                "FogVolume.density_texture",
                "is not supported by volfog's froxel fog: the volume is uniform",
            );
        }
        if let Some((albedo, phase_g, scale)) = first {
            let (a, g, s) = volume_medium(volume);
            if a != albedo {
                warn(
                    "FogVolume.fog_color",
                    "(with light_tint, absorption and scattering) differs from the first \
                     volume's: volfog's medium has one albedo, the first volume's",
                );
            }
            if g != phase_g {
                warn(
                    "FogVolume.scattering_asymmetry",
                    "differs from the first volume's: volfog's medium has one phase",
                );
            }
            if s != scale {
                warn(
                    "FogVolume.light_intensity",
                    "differs from the first volume's: volfog scales its lights once",
                );
            }
        }
        if current.is_some() && !converted.contains(entity) {
            // The entity's own FroxelFogVolume wins.
            continue;
        }
        if !visible.get() {
            if current.is_some() && converted.contains(entity) {
                commands
                    .entity(entity)
                    .remove::<(FroxelFogVolume, FromBevyFog)>();
            }
            continue;
        }
        let want = froxel_fog_volume(volume);
        if current != Some(&want) {
            commands.entity(entity).insert((want, FromBevyFog));
        }
    }
}

/// Gives every camera with Bevy's `VolumetricFog` (and no `FroxelFog` of its own) the
/// `FroxelFog` it maps to, and takes it away with the `VolumetricFog`.
#[allow(clippy::type_complexity)]
fn sync_fog_cameras(
    mut commands: Commands,
    cameras: Query<(
        Entity,
        Option<&VolumetricFog>,
        Option<&FroxelFog>,
        Has<FromBevyFog>,
        Option<&Exposure>,
    )>,
    volumes: Query<(Entity, &FogVolume)>,
) {
    let first = volumes.iter().min_by_key(|(e, _)| *e).map(|(_, v)| v);
    for (entity, bevy_fog, froxel, converted, exposure) in &cameras {
        match (bevy_fog, froxel.is_some() && !converted) {
            // The camera's own FroxelFog wins.
            (_, true) => {}
            (Some(bevy_fog), false) => {
                let exposure = exposure.copied().unwrap_or_default().exposure();
                let want = froxel_fog(bevy_fog, first, exposure);
                if froxel != Some(&want) {
                    commands.entity(entity).insert((want, FromBevyFog));
                }
            }
            (None, false) => {
                if converted {
                    commands.entity(entity).remove::<(FroxelFog, FromBevyFog)>();
                }
            }
        }
    }
}

/// Bevy's volumetric pass runs for views that hold Bevy's `VolumetricFog` in the
/// render world: with [`BevyFogCompat`] none do.
fn drop_bevy_volumetric_fog(mut commands: Commands, views: Query<Entity, With<VolumetricFog>>) {
    for view in &views {
        commands.entity(view).remove::<VolumetricFog>();
    }
}
