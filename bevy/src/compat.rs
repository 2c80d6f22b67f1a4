//! Bevy's own fog components rendered by volfog: with [`BevyFogCompat`], a camera
//! with Bevy's `VolumetricFog` and the scene's `FogVolume`s get volfog's froxel fog
//! instead of Bevy's ray-marched pass.
//!
//! The mapping, per camera with `VolumetricFog` (and no `FroxelFog` of its own):
//!
//! | Bevy | volfog |
//! | --- | --- |
//! | `FogVolume` (unit cube) | `FroxelFogVolume` box, extinction `density_factor * (absorption + scattering)`, `BlendMode::Add` |
//! | `scattering / (absorption + scattering) * fog_color * light_tint` | the medium's albedo (clamped to 1) |
//! | `scattering_asymmetry` | the medium's Henyey-Greenstein `phase_g` |
//! | `light_intensity` | `sun_scattering` and `light_scattering` |
//! | `VolumetricFog.ambient_color * ambient_intensity` | `ambient_radiance` (divided by the camera's exposure: Bevy adds it after exposure) |
//! | `VolumetricLight` on lights | `FogLightSelection::Volumetric`: only those lights light the fog |
//! | `DistanceFog`, `FogFalloff::Exponential { density }`, opaque `color` | the medium: `density`, emission `color * density` (divided by the exposure), the analytic tail beyond `far` |
//!
//! Bevy's exponential distance fog, `mix(surface, color, 1 - exp(-density d))`, is the
//! light of a uniform medium of extinction `density` that emits `color * density` and
//! scatters nothing: volfog renders it exactly, in the froxels and in the tail, and
//! Bevy's own distance fog is switched off for that camera. Other falloffs, a
//! translucent `color` and a `directional_light_color` keep Bevy's own distance fog,
//! with one warning naming the field. With `VolumetricFog` on the same camera the
//! distance fog's medium scatters the lights with the volumes' albedo. Unlike Bevy's,
//! volfog's distance fog also covers the sky (the tail reaches infinity).
//!
//! Outside the volumes there is no fog (the medium's density is 0, no tail), as in
//! Bevy. volfog's medium has one albedo and one phase: the volumes' values are taken
//! from the first volume (by entity), and a volume that differs is warned about once,
//! naming the field. A `density_texture` and its offset become the volume's
//! `FroxelFogVolumeTexture` (the same sampling: the unit cube spans the texture once,
//! repeat addressing). `VolumetricFog.step_count` and `jitter` are the ray
//! marcher's quality settings; the froxel grid's slices and temporal jitter take their
//! place.
//!
//! Bevy's `FogVolume` has no blend mode: Bevy ray-marches each volume on its own and
//! composites it over the others, so overlapping volumes' optical depths add, which is
//! volfog's `BlendMode::Add` (the mapped volumes' blend). The other modes (subtract,
//! multiply, min, max, overwrite) have no Bevy equivalent; give the entity its own
//! `FroxelFogVolume` with a `blend` for them (the entity's own volume wins over the
//! mapping).

use std::collections::HashSet;

use bevy::camera::Exposure;
use bevy::light::{FogVolume, VolumetricFog};
use bevy::pbr::{DistanceFog, FogFalloff};
use bevy::prelude::*;
use bevy::render::sync_world::RenderEntity;
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderSystems};

use crate::settings::{
    BlendMode, FogLightSelection, FogMediumSettings, FogVolumeShape, FroxelFog, FroxelFogVolume,
    FroxelFogVolumeTexture,
};

/// Renders Bevy's `VolumetricFog` cameras and `FogVolume`s with volfog (add it next to
/// [`VolumetricFogPlugin`](crate::VolumetricFogPlugin)). Bevy's own volumetric pass
/// then runs for no camera, and Bevy's materials leave out an exponential
/// `DistanceFog` that volfog renders instead.
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
            render_app
                .add_systems(ExtractSchedule, extract_distance_fog_marks)
                .add_systems(
                    Render,
                    drop_bevy_fog
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

/// Marks a camera whose `DistanceFog` volfog renders (Bevy's own is off for it).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct FromDistanceFog;

/// The render world's mark of a view whose `DistanceFog` Bevy leaves out.
#[derive(Component, Clone, Copy)]
struct DropDistanceFog;

/// The medium density and emission (before exposure) of a Bevy `DistanceFog` that
/// volfog renders exactly, or the field that keeps it Bevy's.
pub fn distance_fog_medium(
    fog: &DistanceFog,
    exposure: f32,
) -> Result<(f32, LinearRgba), &'static str> {
    let FogFalloff::Exponential { density } = fog.falloff else {
        return Err("DistanceFog.falloff");
    };
    let color = fog.color.to_linear();
    if color.alpha < 1.0 {
        return Err("DistanceFog.color");
    }
    if fog.directional_light_color.alpha() > 0.0 {
        return Err("DistanceFog.directional_light_color");
    }
    let e = density / exposure.max(1e-12);
    Ok((
        density,
        LinearRgba::rgb(color.red * e, color.green * e, color.blue * e),
    ))
}

/// The `FroxelFog` of a camera with only Bevy's `DistanceFog` (exponential): the medium
/// glows and scatters nothing.
pub fn distance_froxel_fog(density: f32, emission: LinearRgba) -> FroxelFog {
    FroxelFog {
        medium: FogMediumSettings {
            density,
            albedo: LinearRgba::BLACK,
            height_falloff: 0.0,
            phase_g: 0.0,
            noise_strength: 0.0,
            emission,
            ..default()
        },
        tail: true,
        // Bevy's distance fog starts at the eye: the froxels from Bevy's default near
        // plane (0.1 m), leaving out 0.1 m of it instead of 0.5.
        near: DISTANCE_FOG_NEAR,
        ..FroxelFog::default()
    }
}

/// Where the froxels of a mapped `DistanceFog` start (m): Bevy's default near plane.
pub const DISTANCE_FOG_NEAR: f32 = 0.1;

/// The `FroxelFogVolume` of a Bevy `FogVolume`.
pub fn froxel_fog_volume(volume: &FogVolume) -> FroxelFogVolume {
    FroxelFogVolume {
        shape: FogVolumeShape::Box,
        density: volume.density_factor * (volume.absorption + volume.scattering),
        // Bevy's volumes have hard faces; volfog's soft edge as thin as it goes
        // without aliasing on the froxel grid of a volume a few metres wide.
        edge: 0.02,
        // Bevy marches each volume on its own and composites them over each other:
        // their optical depths add.
        blend: BlendMode::Add,
        order: 0,
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

/// A Bevy `FogVolume` and what it was converted to.
type BevyVolumeItems = (
    Entity,
    &'static FogVolume,
    &'static InheritedVisibility,
    Option<&'static FroxelFogVolume>,
    Option<&'static FroxelFogVolumeTexture>,
);

/// Gives every Bevy `FogVolume` its `FroxelFogVolume`, and warns once per volume and
/// field for what volfog does not take.
fn sync_fog_volumes(
    mut commands: Commands,
    volumes: Query<BevyVolumeItems>,
    mut gone: RemovedComponents<FogVolume>,
    converted: Query<(), With<FromBevyFog>>,
    mut warned: Local<HashSet<(Entity, &'static str)>>,
) {
    for entity in gone.read() {
        if converted.contains(entity)
            && let Ok(mut e) = commands.get_entity(entity)
        {
            e.remove::<(FroxelFogVolume, FroxelFogVolumeTexture, FromBevyFog)>();
        }
    }
    let mut sorted: Vec<_> = volumes.iter().collect();
    sorted.sort_by_key(|(e, ..)| *e);
    let first = sorted.first().map(|(_, v, ..)| volume_medium(v));
    for (entity, volume, visible, current, current_texture) in sorted {
        let mut warn = |field: &'static str, why: &str| {
            if warned.insert((entity, field)) {
                warn!("volfog: FogVolume {entity}: {field} {why}");
            }
        };
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
                    .remove::<(FroxelFogVolume, FroxelFogVolumeTexture, FromBevyFog)>();
            }
            continue;
        }
        let want = froxel_fog_volume(volume);
        if current != Some(&want) {
            commands.entity(entity).insert((want, FromBevyFog));
        }
        let texture = volume
            .density_texture
            .clone()
            .map(|image| FroxelFogVolumeTexture {
                image,
                offset: volume.density_texture_offset,
            });
        match (texture, current_texture) {
            (Some(want), have) if have != Some(&want) => {
                commands.entity(entity).insert(want);
            }
            (None, Some(_)) => {
                commands.entity(entity).remove::<FroxelFogVolumeTexture>();
            }
            _ => {}
        }
    }
}

/// Gives every camera with Bevy's `VolumetricFog` or an exponential `DistanceFog` (and
/// no `FroxelFog` of its own) the `FroxelFog` they map to, and takes it away with them.
#[allow(clippy::type_complexity)]
fn sync_fog_cameras(
    mut commands: Commands,
    cameras: Query<(
        Entity,
        Option<&VolumetricFog>,
        Option<&DistanceFog>,
        Option<&FroxelFog>,
        Has<FromBevyFog>,
        Has<FromDistanceFog>,
        Option<&Exposure>,
    )>,
    volumes: Query<(Entity, &FogVolume)>,
    mut warned: Local<HashSet<(Entity, &'static str)>>,
) {
    let first = volumes.iter().min_by_key(|(e, _)| *e).map(|(_, v)| v);
    for (entity, bevy_fog, distance, froxel, converted, from_distance, exposure) in &cameras {
        if froxel.is_some() && !converted {
            // The camera's own FroxelFog wins.
            continue;
        }
        let exposure = exposure.copied().unwrap_or_default().exposure();
        let distance = distance.and_then(|d| match distance_fog_medium(d, exposure) {
            Ok(medium) => Some(medium),
            Err(field) => {
                if warned.insert((entity, field)) {
                    warn!(
                        "volfog: camera {entity}: {field} has no exact volfog equivalent \
                         (only FogFalloff::Exponential with an opaque colour and no \
                         directional light colour); Bevy's own DistanceFog stays on"
                    );
                }
                None
            }
        });
        let want = match (bevy_fog, distance) {
            (Some(bevy_fog), distance) => {
                let mut want = froxel_fog(bevy_fog, first, exposure);
                if let Some((density, emission)) = distance {
                    want.medium.density = density;
                    want.medium.emission = emission;
                    want.tail = true;
                    want.near = DISTANCE_FOG_NEAR;
                }
                Some(want)
            }
            (None, Some((density, emission))) => Some(distance_froxel_fog(density, emission)),
            (None, None) => None,
        };
        let mut e = commands.entity(entity);
        match want {
            Some(want) => {
                if froxel != Some(&want) {
                    e.insert((want, FromBevyFog));
                }
            }
            None if converted => {
                e.remove::<(FroxelFog, FromBevyFog)>();
            }
            None => {}
        }
        match (distance.is_some(), from_distance) {
            (true, false) => {
                e.insert(FromDistanceFog);
            }
            (false, true) => {
                e.remove::<FromDistanceFog>();
            }
            _ => {}
        }
    }
}

/// The cameras as [`extract_distance_fog_marks`] reads them.
type MarkedCameras<'w, 's> = Query<'w, 's, (RenderEntity, Has<FromDistanceFog>), With<Camera>>;

/// Marks the render views whose `DistanceFog` volfog renders.
fn extract_distance_fog_marks(mut commands: Commands, cameras: Extract<MarkedCameras>) {
    for (render, mapped) in &cameras {
        let Ok(mut e) = commands.get_entity(render) else {
            continue;
        };
        if mapped {
            e.insert(DropDistanceFog);
        } else {
            e.remove::<DropDistanceFog>();
        }
    }
}

/// Bevy's volumetric pass runs for views that hold Bevy's `VolumetricFog` in the
/// render world, and its materials apply the `DistanceFog` a view holds: with
/// [`BevyFogCompat`] no view keeps the first, and the views whose distance fog volfog
/// renders lose the second.
fn drop_bevy_fog(
    mut commands: Commands,
    views: Query<Entity, With<VolumetricFog>>,
    distance: Query<Entity, (With<DistanceFog>, With<DropDistanceFog>)>,
) {
    for view in &views {
        commands.entity(view).remove::<VolumetricFog>();
    }
    for view in &distance {
        commands.entity(view).remove::<DistanceFog>();
    }
}
