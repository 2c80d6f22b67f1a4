//! The demo scene: a checkered ground, a colonnade wall of pillars with an arch,
//! a glass sphere on a plinth, a tiled pool of water sunk into the ground, a lamp in
//! a yard behind the colonnade that shines out through a doorway, a low sun,
//! coloured point and spot lights, a local fog pocket, smoke rising from a fire as
//! particles, the medium and the camera paths (the main camera above the ground and one
//! under water).

mod cameras;
mod lamp;
mod mesh;
mod smoke;

use glam::{Mat4, Quat, Vec3};
use volfog::cpu::ambient::AmbientSh;
use volfog::limits::InvalidValue;
use volfog::uniforms::{
    CloudLayer, DirectionalLight, FogLight, FogMedium, HeightFog, LocalVolume, SkyAtmosphere,
    VolumeShape, Water,
};

pub use cameras::{FAR, FOV_Y, NEAR, camera, fit_cascades, underwater_camera};
pub use lamp::LampYard;
use mesh::{CHECKER, EMISSIVE, PLAIN};
pub use mesh::{Mesh, Vertex};
pub use smoke::{PUFFS, smoke};

/// Texels per side of the cloud density map.
pub const CLOUD_MAP_SIZE: u32 = 128;

/// The pool: its footprint on the ground (x, z from min to max), its depth and the
/// water surface's height (m).
pub const POOL_MIN: Vec3 = Vec3::new(-3.5, POOL_FLOOR, -19.0);
pub const POOL_MAX: Vec3 = Vec3::new(0.5, 0.0, -14.5);
const POOL_FLOOR: f32 = -2.0;
const WATER_HEIGHT: f32 = -0.15;

/// Everything that describes the scene, for the renderer and the fog.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Opaque geometry (casts shadows).
    pub opaque: Mesh,
    /// Light markers (emissive, no shadows).
    pub emissive: Mesh,
    /// The semi-transparent object.
    pub glass: Mesh,
    /// The pool's water surface (blended, both sides).
    pub water_surface: Mesh,
    /// The pool's water.
    pub water: Water,
    /// The medium as analytic height fog (seen from under water, beyond the surface).
    pub air: HeightFog,
    /// The sky's atmosphere (`volfog::sky`) for the sun.
    pub atmosphere: SkyAtmosphere,
    /// The cloud layer at time 0 (`volfog::clouds`); its time follows the frames.
    pub clouds: CloudLayer,
    /// The cloud density map, `CLOUD_MAP_SIZE`² texels in [0, 1], each exact in f16
    /// (the R16Float texture holds them unchanged).
    pub cloud_map: Vec<f32>,
    pub sun: DirectionalLight,
    /// The point and spot lights; `lamp.light` is the yard's shadowed lamp.
    pub lights: Vec<FogLight>,
    /// The lamp's wall, doorway and yard.
    pub lamp: LampYard,
    pub local_volumes: Vec<LocalVolume>,
    pub medium: FogMedium,
    pub ambient_sky: glam::Vec3,
    pub ambient_ground: glam::Vec3,
    pub sky_zenith: glam::Vec3,
}

impl Scene {
    pub fn ambient(&self) -> AmbientSh {
        AmbientSh::sky_ground(self.ambient_sky, self.ambient_ground, Vec3::Y)
    }
}

/// The direction towards the sun: 7 degrees above the horizon, 3 degrees to the
/// right of -Z: low behind the arch as seen from the camera.
pub fn sun_direction() -> Vec3 {
    let elevation = 7f32.to_radians();
    let azimuth = 3f32.to_radians();
    Vec3::new(
        azimuth.sin() * elevation.cos(),
        elevation.sin(),
        -azimuth.cos() * elevation.cos(),
    )
    .normalize()
}

/// Builds the scene.
pub fn build() -> Result<Scene, InvalidValue> {
    let stone = Vec3::new(0.62, 0.58, 0.52);
    let dark_stone = Vec3::new(0.45, 0.42, 0.38);
    let mut opaque = Mesh::default();

    // The ground: a 600 m square with a 1 m checkerboard.
    // The ground: a 600 m square with a 1 m checkerboard, around the pool's opening.
    let g = 300.0;
    let ground = Vec3::new(0.55, 0.52, 0.46);
    // The opening includes the pool's walls (t thick), whose tops are its rim.
    let t = 0.3;
    let (p0, p1) = (
        POOL_MIN - Vec3::new(t, 0.0, t),
        POOL_MAX + Vec3::new(t, 0.0, t),
    );
    for (x0, x1, z0, z1) in [
        (-g, g, p1.z, g),
        (-g, g, -g, p0.z),
        (-g, p0.x, p0.z, p1.z),
        (p1.x, g, p0.z, p1.z),
    ] {
        let base = opaque.vertices.len() as u32;
        for (x, z) in [(x0, z1), (x1, z1), (x1, z0), (x0, z0)] {
            opaque.push(Vec3::new(x, 0.0, z), Vec3::Y, ground, CHECKER);
        }
        opaque
            .indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    // The pool: light tiles, walls and floor as boxes whose inner faces line the
    // basin.
    let tiles = Vec3::new(0.7, 0.78, 0.8);
    let (p0, p1) = (POOL_MIN, POOL_MAX);
    opaque.aabb(
        Vec3::new(p0.x - t, POOL_FLOOR - t, p0.z - t),
        Vec3::new(p1.x + t, POOL_FLOOR, p1.z + t),
        tiles,
    );
    for (min, max) in [
        (
            Vec3::new(p0.x - t, POOL_FLOOR, p0.z - t),
            Vec3::new(p0.x, 0.0, p1.z + t),
        ),
        (
            Vec3::new(p1.x, POOL_FLOOR, p0.z - t),
            Vec3::new(p1.x + t, 0.0, p1.z + t),
        ),
        (
            Vec3::new(p0.x, POOL_FLOOR, p0.z - t),
            Vec3::new(p1.x, 0.0, p0.z),
        ),
        (
            Vec3::new(p0.x, POOL_FLOOR, p1.z),
            Vec3::new(p1.x, 0.0, p1.z + t),
        ),
    ] {
        opaque.aabb(min, max, tiles);
    }
    let mut water_surface = Mesh::default();
    let base = water_surface.vertices.len() as u32;
    for (x, z) in [(p0.x, p1.z), (p1.x, p1.z), (p1.x, p0.z), (p0.x, p0.z)] {
        water_surface.push(Vec3::new(x, WATER_HEIGHT, z), Vec3::Y, tiles, PLAIN);
    }
    water_surface
        .indices
        .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    // Clear water lit by the sky: light fades with depth, red first (ocean model).
    let water = Water {
        albedo: Vec3::new(0.8, 0.9, 0.95),
        g: 0.0,
        shore_fade: 0.2,
        ..Water::ocean(
            WATER_HEIGHT,
            Vec3::new(3.0, 5.0, 5.5),
            0.35,
            Vec3::new(0.5, 0.12, 0.08),
        )?
    }
    .validated()?;

    // The colonnade: one row of pillars across the view at z = -25 under a lintel,
    // with an arch in the middle; the low sun stands behind it.
    let row_z = -25.0;
    let height = 7.0;
    let (inner, outer) = (2.4f32, 3.4f32);
    for k in -7i32..=7 {
        let x = 3.6 * k as f32;
        if x.abs() < outer + 0.5 {
            continue;
        }
        opaque.aabb(
            Vec3::new(x - 1.2, 0.0, row_z - 0.8),
            Vec3::new(x + 1.2, 0.4, row_z + 0.8),
            dark_stone,
        );
        opaque.aabb(
            Vec3::new(x - 1.0, 0.4, row_z - 0.55),
            Vec3::new(x + 1.0, height - 0.3, row_z + 0.55),
            stone,
        );
        opaque.aabb(
            Vec3::new(x - 1.15, height - 0.3, row_z - 0.75),
            Vec3::new(x + 1.15, height, row_z + 0.75),
            dark_stone,
        );
    }
    opaque.aabb(
        Vec3::new(-25.0, height, row_z - 0.8),
        Vec3::new(25.0, height + 0.8, row_z + 0.8),
        stone,
    );
    // The attic wall above the lintel: the sun reaches the near side only through
    // the arch and between the pillars.
    opaque.aabb(
        Vec3::new(-25.0, height + 0.8, row_z - 0.5),
        Vec3::new(25.0, height + 4.0, row_z + 0.5),
        dark_stone,
    );

    // The arch: two piers and a semicircle of voussoirs under the lintel.
    let spring = 3.2;
    for side in [-1.0f32, 1.0] {
        let x = side * (inner + outer) * 0.5;
        opaque.aabb(
            Vec3::new(x - 0.5, 0.0, row_z - 0.6),
            Vec3::new(x + 0.5, spring, row_z + 0.6),
            stone,
        );
    }
    let pieces = 11;
    for k in 0..pieces {
        let a = std::f32::consts::PI * (k as f32 + 0.5) / pieces as f32;
        let r = (inner + outer) * 0.5;
        let center = Vec3::new(r * a.cos(), spring + r * a.sin(), row_z);
        let half = Vec3::new(
            (outer - inner) * 0.5,
            outer * std::f32::consts::PI / pieces as f32 * 0.5 + 0.02,
            0.6,
        );
        opaque.cuboid(center, half, Quat::from_rotation_z(a), stone, PLAIN);
    }

    // The plinth of the glass sphere.
    let glass_center = Vec3::new(3.4, 1.9, -18.5);
    opaque.aabb(
        Vec3::new(glass_center.x - 0.6, 0.0, glass_center.z - 0.6),
        Vec3::new(glass_center.x + 0.6, 0.8, glass_center.z + 0.6),
        dark_stone,
    );
    let mut glass = Mesh::default();
    glass.sphere(glass_center, 1.0, Vec3::new(0.35, 0.6, 0.9), 24, 48);

    // Coloured lights: two lanterns on the pillars, two spots, one small red light by
    // the sphere; then the lamp in the yard.
    let front = row_z + 0.75;
    let mut lights = vec![
        FogLight::point(
            Vec3::new(-10.8, 2.6, front - 0.25),
            Vec3::new(60.0, 26.0, 8.0),
            14.0,
        ),
        FogLight::point(
            Vec3::new(10.8, 2.4, front - 0.25),
            Vec3::new(10.0, 40.0, 70.0),
            14.0,
        ),
        FogLight::spot(
            Vec3::new(-7.2, 6.6, front),
            Vec3::new(0.0, -1.0, 0.25),
            Vec3::new(110.0, 18.0, 95.0),
            14.0,
            0.3,
            0.5,
        ),
        FogLight::spot(
            Vec3::new(-14.4, 6.6, front),
            Vec3::new(0.3, -1.0, 0.5),
            Vec3::new(25.0, 90.0, 18.0),
            16.0,
            0.25,
            0.45,
        ),
        FogLight::point(
            glass_center + Vec3::new(1.3, -1.2, 0.8),
            Vec3::new(35.0, 6.0, 3.0),
            6.0,
        ),
    ];
    // The lamp's walls in a darker stone: the lamp lights them from close by.
    let lamp_stone = Vec3::new(0.34, 0.31, 0.28);
    let lamp = lamp::build(&mut opaque, lights.len() as u32, lamp_stone);
    lights.push(lamp::lamp());
    for light in &lights {
        light.validate()?;
    }
    let mut emissive = Mesh::default();
    for light in &lights {
        let color = light.color / light.color.max_element() * 6.0;
        emissive.cuboid(
            light.position,
            Vec3::splat(0.12),
            Quat::IDENTITY,
            color,
            EMISSIVE,
        );
    }

    // A pocket of denser fog under the magenta spot.
    let local_volumes = vec![LocalVolume::new(
        Mat4::from_scale_rotation_translation(
            Vec3::new(2.2, 2.6, 2.2),
            Quat::IDENTITY,
            Vec3::new(-7.2, 2.0, row_z + 3.0),
        ),
        VolumeShape::Ellipsoid,
        0.12,
        0.6,
    )?];

    let medium = FogMedium {
        albedo: Vec3::splat(0.9),
        density: 0.035,
        height_falloff: 0.2,
        base_height: 0.0,
        noise_strength: 0.85,
        noise_scale: 0.15,
        wind: Vec3::new(1.5, 0.2, -0.6),
        phase_g: 0.7,
        ..FogMedium::default()
    };
    medium.validate()?;
    // Surfaces see the full sun; the fog a fraction of it (fog_intensity), so sunlit
    // fog does not drown the scene.
    let sun = DirectionalLight {
        direction: sun_direction(),
        color: Vec3::new(7.5, 5.6, 3.6),
        fog_intensity: 0.6,
        ..DirectionalLight::default()
    };
    sun.validate()?;
    Ok(Scene {
        opaque,
        emissive,
        glass,
        water_surface,
        water,
        air: HeightFog::from_medium(&medium, Vec3::new(0.45, 0.4, 0.33)),
        atmosphere: SkyAtmosphere {
            sun_intensity: Vec3::splat(14.0),
            ..SkyAtmosphere::earth(sun.direction)?
        }
        .validated()?,
        // Cumulus 600 m up, drifting at 8 m/s; lit by the sun and the sky.
        clouds: CloudLayer {
            view_samples: 12,
            sun_samples: 4,
            ..CloudLayer::new(600.0, 150.0, 0.012, 900.0)?
                .with_sun(
                    sun.direction,
                    sun.color * 0.5,
                    Vec3::new(0.2, 0.25, 0.35),
                    0.6,
                )?
                .with_wind(glam::Vec2::new(8.0, -3.0), 0.0)?
        },
        cloud_map: cloud_map(CLOUD_MAP_SIZE),
        sun,
        lights,
        lamp,
        local_volumes,
        medium,
        ambient_sky: Vec3::new(0.04, 0.06, 0.1),
        ambient_ground: Vec3::new(0.025, 0.022, 0.02),
        sky_zenith: Vec3::new(0.06, 0.11, 0.25),
    })
}

/// A tileable cloud density map: four octaves of tiled Perlin noise with a coverage
/// threshold, quantised to 1/256 (exact in f16).
pub fn cloud_map(size: u32) -> Vec<f32> {
    (0..size * size)
        .map(|i| {
            let (x, y) = (
                (i % size) as f32 / size as f32,
                (i / size) as f32 / size as f32,
            );
            let mut v = 0.0;
            let mut amplitude = 0.5;
            for octave in 0..4u32 {
                let period = 4u32 << octave;
                let p = Vec3::new(x * period as f32, y * period as f32, 0.37 + octave as f32);
                v += amplitude * volfog::cpu::noise::perlin_noise_tiled(p, period);
                amplitude *= 0.5;
            }
            let density = ((v + 0.08) * 3.0).clamp(0.0, 1.0);
            (density * 256.0).round() / 256.0
        })
        .collect()
}

/// Is `p` in the pool's water (within the footprint, below the surface)?
/// As `in_pool` of `scene.wgsl`, with its 1 cm of slack around the footprint.
pub fn in_pool(p: Vec3) -> bool {
    p.x >= POOL_MIN.x - 0.01
        && p.x <= POOL_MAX.x + 0.01
        && p.z >= POOL_MIN.z - 0.01
        && p.z <= POOL_MAX.z + 0.01
        && p.y <= WATER_HEIGHT
}
