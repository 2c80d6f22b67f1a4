//! The web demo's scene: a colonnade under a roof slab on a ground plane, a sun whose
//! elevation the page sets, a warm point light, a blue spot light, two local volumes,
//! and the fog configuration. Everything here is plain data, the same on the web and
//! natively, so the browser test can render the very same frame on lavapipe.

use glam::{Mat4, Quat, UVec3, Vec3};
use volfog::cpu::ambient::AmbientSh;
use volfog::pipeline::{FogConfig, FrameInputs, cascade_projection, cascade_splits};
use volfog::uniforms::{
    DirectionalLight, FogLight, FogMedium, HeightFog, LocalVolume, ShadowCascades, VolumeShape,
};

/// What the page's sliders set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Fog density at the ground (1/m), 0..=0.2.
    pub density: f32,
    /// Henyey-Greenstein asymmetry, -0.9..=0.9.
    pub phase_g: f32,
    /// Sun elevation above the horizon (degrees), 5..=90.
    pub sun_elevation: f32,
    /// Seconds since start (noise animation).
    pub time: f32,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            density: 0.04,
            phase_g: 0.6,
            sun_elevation: 35.0,
            time: 1.5,
        }
    }
}

/// A slider's range: the page builds its inputs from these and clamps what it passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slider {
    /// Parameter name, as the page labels it.
    pub name: &'static str,
    /// Smallest value.
    pub min: f32,
    /// Largest value.
    pub max: f32,
}

/// The sliders, in the order of [`Params`]' fields.
pub const SLIDERS: [Slider; 3] = [
    Slider {
        name: "density",
        min: 0.0,
        max: 0.2,
    },
    Slider {
        name: "phase_g",
        min: -0.9,
        max: 0.9,
    },
    Slider {
        name: "sun_elevation",
        min: 5.0,
        max: 90.0,
    },
];

impl Params {
    /// The parameters with every slider value clamped to its range (NaN becomes the
    /// default), so no input from the page reaches the GPU outside the valid ranges.
    pub fn clamped(self) -> Self {
        let d = Self::default();
        let clamp = |v: f32, s: Slider, fallback: f32| {
            if v.is_nan() {
                fallback
            } else {
                v.clamp(s.min, s.max)
            }
        };
        Self {
            density: clamp(self.density, SLIDERS[0], d.density),
            phase_g: clamp(self.phase_g, SLIDERS[1], d.phase_g),
            sun_elevation: clamp(self.sun_elevation, SLIDERS[2], d.sun_elevation),
            time: if self.time.is_finite() {
                self.time
            } else {
                d.time
            },
        }
    }

    /// Unit direction towards the sun (azimuth fixed, from the left and behind).
    pub fn sun_direction(&self) -> Vec3 {
        let (el, az) = (self.sun_elevation.to_radians(), 2.2f32);
        Vec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin()).normalize()
    }
}

/// The fog configuration: a 64 x 36 x 64 volume to 80 m, one cascade. `animated`
/// turns on jitter and temporal reprojection (the page's render loop); the browser
/// test's frame runs without them so that one frame is the whole answer.
pub fn config(animated: bool) -> FogConfig {
    FogConfig {
        volume_size: UVec3::new(64, 36, 64),
        near: 0.5,
        far: 80.0,
        slice_curve: 3.0,
        esm_resolution: 128,
        cascades: 1,
        esm_exponent: 80.0,
        max_lights: 4,
        max_local_volumes: 4,
        jitter: animated,
        temporal: animated,
        amortize: animated,
        ..FogConfig::default()
    }
}

/// Camera position (m).
pub const EYE: Vec3 = Vec3::new(0.0, 2.5, 8.0);

/// Vertical field of view (degrees).
pub const FOV_Y: f32 = 60.0;

/// World -> view of the camera: at [`EYE`], looking down -Z, pitched up a little.
pub fn view_from_world() -> Mat4 {
    let dir = Vec3::new(0.0, 0.05, -1.0).normalize();
    glam::camera::rh::view::look_to_mat4(EYE, dir, Vec3::Y)
}

/// View -> clip for an image `width` x `height` (standard depth, 0.1..300 m).
pub fn clip_from_view(width: u32, height: u32) -> Mat4 {
    let aspect = width as f32 / height.max(1) as f32;
    glam::camera::rh::proj::directx::perspective(FOV_Y.to_radians(), aspect, 0.1, 300.0)
}

/// The point and spot lights.
pub fn lights() -> [FogLight; 2] {
    [
        FogLight::point(
            Vec3::new(-2.5, 1.5, -10.0),
            Vec3::new(24.0, 12.0, 4.0),
            10.0,
        ),
        FogLight::spot(
            Vec3::new(2.5, 7.0, -20.0),
            Vec3::new(0.1, -1.0, 0.1),
            Vec3::new(6.0, 20.0, 40.0),
            16.0,
            0.35,
            0.55,
        ),
    ]
}

/// The local volumes: a dense box of mist at the colonnade's far end and an
/// ellipsoid that thins the fog near the camera.
pub fn local_volumes() -> [LocalVolume; 2] {
    [
        LocalVolume::new(
            Mat4::from_scale_rotation_translation(
                Vec3::new(5.0, 1.5, 4.0),
                Quat::from_rotation_y(0.3),
                Vec3::new(0.0, 0.5, -28.0),
            ),
            VolumeShape::Box,
            0.15,
            0.3,
        )
        .expect("a valid volume"),
        LocalVolume::new(
            Mat4::from_scale_rotation_translation(Vec3::splat(4.0), Quat::IDENTITY, EYE),
            VolumeShape::Ellipsoid,
            -0.02,
            0.5,
        )
        .expect("a valid volume"),
    ]
}

/// The medium for `params`: noisy, falling with height.
pub fn medium(params: &Params) -> FogMedium {
    FogMedium {
        density: params.density,
        height_falloff: 0.12,
        noise_strength: 0.6,
        noise_scale: 0.25,
        phase_g: params.phase_g,
        albedo: Vec3::splat(0.9),
        ..FogMedium::default()
    }
}

/// The sun for `params`.
pub fn sun(params: &Params) -> DirectionalLight {
    DirectionalLight {
        direction: params.sun_direction(),
        color: Vec3::new(4.0, 3.6, 3.0),
        ..DirectionalLight::default()
    }
}

/// The one shadow cascade: a 90 m square around the colonnade, seen from the sun.
pub fn cascades(config: &FogConfig, params: &Params) -> ShadowCascades {
    let mut cascades = ShadowCascades {
        splits: cascade_splits(config.cascades, config.near, config.far, 0.5),
        count: config.cascades,
        exponent: config.esm_exponent,
        ..Default::default()
    };
    cascades.light_from_world[0] = cascade_projection(
        params.sun_direction(),
        Vec3::new(0.0, 0.0, -25.0),
        45.0,
        200.0,
    );
    cascades
}

/// Ambient radiance from above (linear rgb).
pub const SKY: Vec3 = Vec3::new(0.15, 0.22, 0.35);
/// Ambient radiance from below (linear rgb).
pub const GROUND: Vec3 = Vec3::new(0.05, 0.045, 0.04);

/// Sky and ground ambient radiance, [`SKY`] above and [`GROUND`] below.
pub fn ambient() -> AmbientSh {
    AmbientSh::sky_ground(SKY, GROUND, Vec3::Y)
}

/// One frame's fog inputs for an image `width` x `height`; `lights` and `volumes` are
/// [`lights`] and [`local_volumes`], borrowed by the inputs.
pub fn frame_inputs<'a>(
    config: &FogConfig,
    params: &Params,
    size: (u32, u32),
    lights: &'a [FogLight],
    volumes: &'a [LocalVolume],
) -> FrameInputs<'a> {
    let medium = medium(params);
    FrameInputs {
        medium,
        sun: sun(params),
        ambient: ambient(),
        lights,
        local_volumes: volumes,
        cascades: cascades(config, params),
        tail: HeightFog::from_medium(&medium, Vec3::splat(0.25)),
        ..FrameInputs::new(
            view_from_world(),
            clip_from_view(size.0, size.1),
            params.time,
        )
    }
}

/// A box: centre, half extents, albedo.
#[derive(Debug, Clone, Copy)]
pub struct Block {
    /// Centre (m).
    pub center: Vec3,
    /// Half extents (m).
    pub half: Vec3,
    /// Diffuse albedo.
    pub albedo: Vec3,
}

/// The scene's solid geometry: the ground, two rows of pillars and the roof slab.
pub fn blocks() -> Vec<Block> {
    let stone = Vec3::new(0.55, 0.5, 0.45);
    let mut blocks = vec![Block {
        center: Vec3::new(0.0, -0.5, -40.0),
        half: Vec3::new(150.0, 0.5, 150.0),
        albedo: Vec3::new(0.3, 0.32, 0.28),
    }];
    for i in 0..5 {
        for x in [-4.5f32, 4.5] {
            blocks.push(Block {
                center: Vec3::new(x, 3.5, -6.0 - 6.0 * i as f32),
                half: Vec3::new(0.5, 3.5, 0.5),
                albedo: stone,
            });
        }
    }
    blocks.push(Block {
        center: Vec3::new(0.0, 7.4, -18.0),
        half: Vec3::new(5.5, 0.4, 13.0),
        albedo: stone,
    });
    blocks
}

/// A vertex: position, normal, albedo.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// World position (m).
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Diffuse albedo.
    pub albedo: [f32; 3],
}

/// The triangles of `blocks`, counter-clockwise seen from outside.
pub fn mesh(blocks: &[Block]) -> Vec<Vertex> {
    let mut out = Vec::with_capacity(blocks.len() * 36);
    for b in blocks {
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                // Two tangents with u x v = n.
                let u = Vec3::from_array({
                    let mut t = [0.0; 3];
                    t[(axis + 1) % 3] = 1.0;
                    t
                });
                let v = n.cross(u);
                let c = b.center + n * b.half;
                let (hu, hv) = (u * b.half, v * b.half);
                let corners = [c - hu - hv, c + hu - hv, c + hu + hv, c - hu + hv];
                for i in [0, 1, 2, 0, 2, 3] {
                    out.push(Vertex {
                        position: corners[i].to_array(),
                        normal: n.to_array(),
                        albedo: b.albedo.to_array(),
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_cannot_pass_values_outside_the_sliders() {
        let p = Params {
            density: 5.0,
            phase_g: f32::NAN,
            sun_elevation: -30.0,
            time: f32::INFINITY,
        }
        .clamped();
        assert_eq!(p.density, 0.2);
        assert_eq!(p.phase_g, Params::default().phase_g);
        assert_eq!(p.sun_elevation, 5.0);
        assert_eq!(p.time, Params::default().time);
        let config = config(false);
        let (lights, volumes) = (lights(), local_volumes());
        let inputs = frame_inputs(&config, &p, (320, 180), &lights, &volumes);
        assert!(inputs.validate(&config).is_ok());
    }

    #[test]
    fn every_face_points_out_of_its_block() {
        for b in blocks() {
            for tri in mesh(&[b]).chunks_exact(3) {
                let [a, bb, c] = [tri[0], tri[1], tri[2]].map(|v| Vec3::from(v.position));
                let winding = (bb - a).cross(c - a).normalize();
                assert!(winding.dot(Vec3::from(tri[0].normal)) > 0.99);
                assert!((a - b.center).dot(Vec3::from(tri[0].normal)) > 0.0);
            }
        }
    }
}
