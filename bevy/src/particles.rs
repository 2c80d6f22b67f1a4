//! [`FroxelFogParticles`]: smoke, steam or dust from the app's particle system in the
//! fog, written each frame.

use bevy::prelude::*;
pub use volfog::uniforms::FogParticle;

/// Particles in the fog: soft spheres of extinction, albedo and emission (volfog's
/// [`FogParticle`], positions and radii in world space, metres) that every
/// [`FroxelFog`](crate::FroxelFog) camera with room for them
/// ([`FroxelFog::max_particles`](crate::FroxelFog::max_particles) > 0) adds to its
/// medium, lit and shadowed as the medium. Put it on any entity and rewrite the list
/// from your particle system each frame; the lists of all entities are concatenated
/// in entity order. The entity's transform is not applied.
///
/// A particle's emission is scaled by the camera's exposure, as the medium's is. More
/// particles than the camera's `max_particles`, or a particle out of range (a NaN
/// position, a radius <= 0, a negative extinction ...), switch the fog off for that
/// camera with one warning naming the field and its range
/// (`FrameInputs.particles`, `FogParticle.radius` ...). A camera with
/// `max_particles` 0 takes no particles.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct FroxelFogParticles(pub Vec<FogParticle>);
