//! The lamp's yard: the colonnade's bay left of the arch closed by a wall with a
//! doorway, a walled yard behind it, and a point light in the yard whose shadowed
//! light leaves through the doorway as a shaft towards the camera's side (and over
//! the wall, through the bay above it, into the fog).

use glam::{Mat4, Vec3};
use volfog::limits::InvalidValue;
use volfog::uniforms::{FogLight, LightCamera};

use super::mesh::Mesh;

/// The wall across the bay: from the magenta spot's pillar to the arch's left pier
/// (x), its faces (z) and its height (m); the bay stays open above it up to the
/// lintel.
const WALL_X: [f32; 2] = [-6.2, -3.4];
const WALL_Z: [f32; 2] = [-25.2, -24.8];
const WALL_HEIGHT: f32 = 4.6;
/// The doorway through the wall: its extent along x and its height (m).
const DOORWAY_X: [f32; 2] = [-5.25, -4.35];
const DOORWAY_HEIGHT: f32 = 2.5;
/// The far end of the yard behind the wall (z, m), the height and thickness of its
/// side and back walls.
const YARD_BACK: f32 = -29.8;
const YARD_WALL_HEIGHT: f32 = 7.0;
const YARD_WALL: f32 = 0.3;
/// The lamp in the yard, behind the doorway.
const LAMP_POSITION: Vec3 = Vec3::new(-4.8, 3.0, -28.5);
/// Near plane of the lamp's cube shadow camera (m).
const LAMP_NEAR: f32 = 0.05;

/// Where the lamp's wall and yard stand and which light is the lamp.
#[derive(Debug, Clone, Copy)]
pub struct LampYard {
    /// Index of the lamp in `Scene::lights`.
    pub light: u32,
    /// The wall with the doorway, a box from its floor corner to its top.
    pub wall_min: Vec3,
    pub wall_max: Vec3,
    /// The doorway's opening through the wall, floor to lintel.
    pub doorway_min: Vec3,
    pub doorway_max: Vec3,
    /// The yard's inside behind the wall (the lamp's side), to the top of its walls.
    pub yard_min: Vec3,
    pub yard_max: Vec3,
}

impl LampYard {
    /// The lamp's cube shadow camera (volfog's choice: faces along the world axes,
    /// standard depth from `LAMP_NEAR` to the lamp's range).
    pub fn camera(lamp: &FogLight) -> Result<LightCamera, InvalidValue> {
        LightCamera::point(lamp, LAMP_NEAR)
    }

    /// World -> clip of each cube face of `camera`, as the shadow pass renders them.
    pub fn face_matrices(camera: &LightCamera) -> [Mat4; 6] {
        let LightCamera::Point {
            cube_from_world,
            clip_from_view,
        } = *camera
        else {
            unreachable!("the lamp is a point light")
        };
        std::array::from_fn(|face| {
            clip_from_view * LightCamera::cube_face_view(face as u32) * cube_from_world
        })
    }
}

/// The lamp: a cool white point light whose light counts several times over in the
/// fog (`fog_intensity`), so that its shaft stands out of the haze while the surfaces
/// it lights stay in range.
pub fn lamp() -> FogLight {
    FogLight {
        radius: 0.08,
        fog_intensity: 30.0,
        ..FogLight::point(LAMP_POSITION, Vec3::new(0.6, 0.85, 1.0) * 80.0, 16.0)
    }
}

/// Adds the wall and the yard's walls to `opaque`, the lamp being light `light` of
/// the scene.
pub fn build(opaque: &mut Mesh, light: u32, color: Vec3) -> LampYard {
    let ([x0, x1], [z0, z1]) = (WALL_X, WALL_Z);
    let [d0, d1] = DOORWAY_X;
    // The wall around its doorway: west of it, east of it and the lintel.
    opaque.aabb(
        Vec3::new(x0, 0.0, z0),
        Vec3::new(d0, WALL_HEIGHT, z1),
        color,
    );
    opaque.aabb(
        Vec3::new(d1, 0.0, z0),
        Vec3::new(x1, WALL_HEIGHT, z1),
        color,
    );
    opaque.aabb(
        Vec3::new(d0, DOORWAY_HEIGHT, z0),
        Vec3::new(d1, WALL_HEIGHT, z1),
        color,
    );
    // The yard: side walls from behind the pillar and the pier, and the back wall.
    let (h, t) = (YARD_WALL_HEIGHT, YARD_WALL);
    opaque.aabb(
        Vec3::new(x0 - t, 0.0, YARD_BACK),
        Vec3::new(x0, h, z0 - 0.3),
        color,
    );
    opaque.aabb(
        Vec3::new(x1, 0.0, YARD_BACK),
        Vec3::new(x1 + t, h, z0 - 0.3),
        color,
    );
    opaque.aabb(
        Vec3::new(x0 - t, 0.0, YARD_BACK - t),
        Vec3::new(x1 + t, h, YARD_BACK),
        color,
    );
    LampYard {
        light,
        wall_min: Vec3::new(x0, 0.0, z0),
        wall_max: Vec3::new(x1, WALL_HEIGHT, z1),
        doorway_min: Vec3::new(d0, 0.0, z0),
        doorway_max: Vec3::new(d1, DOORWAY_HEIGHT, z1),
        yard_min: Vec3::new(x0, 0.0, YARD_BACK),
        yard_max: Vec3::new(x1, h, z0),
    }
}
