//! [`TransientFogLight`]: lights that light the froxel fog only in the frames they are
//! in (volfog's `FrameInputs::transient_lights`).

use bevy::prelude::*;

/// Marks a `PointLight`, `SpotLight` or `DirectionalLight` as short-lived for the
/// froxel fog: a muzzle flash, an explosion, a lightning strike.
///
/// Without it, a light that appears for a frame shows in the fog at the temporal
/// blend's share (1 - `FroxelFog::history_weight`, 10 % by default) and leaves a ghost
/// that fades over the next frames. With it, the light lights the fog of every frame
/// it exists in with its whole contribution, and nothing of it stays in the fog's
/// history: despawn it (or remove the component, or the light) and the next frame's fog
/// is as if it had never been there. The fog's scan adds it to every froxel after the
/// temporal blend (see volfog's wgpu guide, "Short-lived lights").
///
/// The light is converted as the fog's other lights are (colour, intensity, range,
/// radius, cone, the camera's exposure, `FroxelFog::light_scattering` or, for a
/// directional light, `FroxelFog::sun_scattering`), lights the fog whatever
/// `FroxelFog::lights` selects, and is never the fog's sun. Its shadow map is not used
/// in the fog (transient lights are unshadowed there). A camera's fog takes the first
/// `volfog::limits::MAX_TRANSIENT_LIGHTS` (16) such lights, point and spot lights
/// first.
///
/// ```
/// use bevy::prelude::*;
/// use volfog_bevy::TransientFogLight;
///
/// let mut world = World::new();
/// // The frame a gun fires: a flash at the muzzle, despawned next frame.
/// let flash = world
///     .spawn((
///         PointLight { intensity: 2.0e5, range: 12.0, ..default() },
///         Transform::from_xyz(0.3, 1.5, -1.0),
///         TransientFogLight,
///     ))
///     .id();
/// assert!(world.get::<TransientFogLight>(flash).is_some());
/// world.despawn(flash);
/// ```
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TransientFogLight;
