//! The `Scene` uniform of the demo's shaders: camera, sun, sky, shadow, water and
//! lamp parameters of one frame.

use encase::ShaderType;
use glam::{Mat4, Vec3, Vec4};

/// The `Scene` uniform of `scene.wgsl`.
#[derive(Debug, Clone, Copy, ShaderType)]
pub struct SceneUniform {
    pub clip_from_world: Mat4,
    pub view_from_world: Mat4,
    pub world_from_clip: Mat4,
    pub shadow_texel: Vec4,
    pub camera_position: Vec3,
    pub surface_scale: f32,
    pub sun_direction: Vec3,
    pub light_count: u32,
    pub sun_color: Vec3,
    pub sun_disk: f32,
    pub sky_zenith: Vec3,
    pub sky_horizon: Vec3,
    pub glass_alpha: f32,
    pub ambient_ground: Vec3,
    pub shadow_bias: f32,
    /// The pool's water (`volfog::water`).
    pub water: volfog::uniforms::Water,
    /// The medium as analytic height fog, for what a camera under water sees above
    /// the surface.
    pub air: volfog::uniforms::HeightFog,
    /// The pool's footprint (x, z) from `pool_min` to `pool_max`; `pool_min.w` 1 turns
    /// the water on, 0 renders the pool dry (the probe's reference).
    pub pool_min: Vec4,
    pub pool_max: Vec4,
    /// The sky's atmosphere (`volfog::sky`); the sky texture is solved for it.
    pub atmosphere: volfog::uniforms::SkyAtmosphere,
    /// The lamp's position and its index in the lights (shadowed by its cube map).
    pub lamp_position: Vec3,
    pub lamp_index: u32,
}

impl SceneUniform {
    /// A uniform of zeros and identities (sizes the buffer).
    pub(super) fn zeroed() -> Self {
        Self {
            clip_from_world: Mat4::IDENTITY,
            view_from_world: Mat4::IDENTITY,
            world_from_clip: Mat4::IDENTITY,
            shadow_texel: Vec4::ZERO,
            camera_position: Vec3::ZERO,
            surface_scale: 1.0,
            sun_direction: Vec3::Y,
            light_count: 0,
            sun_color: Vec3::ZERO,
            sun_disk: 0.0,
            sky_zenith: Vec3::ZERO,
            sky_horizon: Vec3::ZERO,
            glass_alpha: 0.0,
            ambient_ground: Vec3::ZERO,
            shadow_bias: 0.0,
            water: volfog::uniforms::Water::default(),
            air: volfog::uniforms::HeightFog::default(),
            pool_min: Vec4::ZERO,
            pool_max: Vec4::ZERO,
            atmosphere: volfog::uniforms::SkyAtmosphere::default(),
            lamp_position: Vec3::ZERO,
            lamp_index: u32::MAX,
        }
    }
}
