//! The inject pass through `VolumetricFog`: against the CPU mirror for a full scene,
//! against closed forms (homogeneous fog lit by the sun, with and without an occluder),
//! against numerical integration (a height-fog column), and with lights placed exactly
//! at froxel centres; the density-texture variant, the culling of local volumes,
//! directional fog lights and squared spot cones, and typed errors for bad frame inputs.

mod closed_form;
mod inputs;
mod light_kinds;
mod local_volumes;
mod mirror;
mod textured_volumes;
