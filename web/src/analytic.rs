//! The WebGL2 tier's scene, for browsers without WebGPU: no compute and no froxels, only
//! the closed forms through the GLSL ES 3.00 snippets in one fragment shader
//! (`www/webgl2.js`): the ground plane under Wenzel's height fog with its sun lobe
//! (volfog::height_fog), two fog volumes composited over it (volfog::fog_volume) and
//! the Nishita sky beyond (volfog::sky), the fog continuing to [`SKY_DISTANCE`] along
//! rays that miss the ground. [`AnalyticScene::to_std140`] is the shader's uniform
//! block; [`AnalyticScene::pixel`] is the same computation through `volfog::cpu`, which
//! the browser test compares the page's image with.

use glam::{Mat4, Quat, Vec3, Vec4};
use volfog::cpu::fog_volume::{fog_over, fog_volume};
use volfog::cpu::height_fog::height_fog;
use volfog::cpu::sky::{sky_radiance, sky_single_scattering};
use volfog::limits::InvalidValue;
use volfog::uniforms::{FogVolume, HeightFog, SkyAtmosphere, VolumeShape};

use crate::scene::{self, Params};

/// How far (m) the fog reaches along a ray that misses the ground (the sky's).
pub const SKY_DISTANCE: f32 = 3000.0;

/// Everything the WebGL2 tier's fragment shader reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalyticScene {
    /// Clip -> world of the camera.
    pub world_from_clip: Mat4,
    /// Camera position (m).
    pub eye: Vec3,
    /// Radiance leaving the ground per unit albedo (linear rgb): the sun's irradiance
    /// on it and the ambient, over pi.
    pub ground: Vec3,
    /// The global height fog, with the sun's lobe.
    pub fog: HeightFog,
    /// The fog volumes, the nearer first.
    pub volumes: [FogVolume; 2],
    /// The sky.
    pub atmosphere: SkyAtmosphere,
}

/// The scene for `params` (clamped to the sliders' ranges) at `size` pixels.
pub fn analytic_scene(params: &Params, size: (u32, u32)) -> Result<AnalyticScene, InvalidValue> {
    let params = params.clamped();
    let medium = scene::medium(&params);
    let sun = scene::sun(&params);
    // In-scattered radiance per unit extinction: the albedo times the ambient, and the
    // sun's lobe on top.
    let fog = HeightFog::from_medium(&medium, medium.albedo * scene::SKY).with_sun(
        sun.direction,
        medium.albedo * sun.color,
        params.phase_g,
    )?;
    let volume = |center: Vec3, half: Vec3, shape, color: Vec3, density| {
        FogVolume::new(
            Mat4::from_scale_rotation_translation(half, Quat::from_rotation_y(0.3), center),
            shape,
            color,
            density,
        )
    };
    let volumes = [
        volume(
            Vec3::new(-3.0, 1.0, -14.0),
            Vec3::new(3.0, 1.0, 2.0),
            VolumeShape::Box,
            Vec3::new(0.5, 0.45, 0.4),
            0.25,
        )?,
        volume(
            Vec3::new(6.0, 3.0, -30.0),
            Vec3::splat(5.0),
            VolumeShape::Ellipsoid,
            Vec3::new(0.3, 0.4, 0.6),
            0.1,
        )?,
    ];
    let world_from_clip =
        (scene::clip_from_view(size.0, size.1) * scene::view_from_world()).inverse();
    let ground = (sun.color * sun.direction.y.max(0.0) + scene::SKY * std::f32::consts::PI)
        / std::f32::consts::PI;
    Ok(AnalyticScene {
        world_from_clip,
        eye: scene::EYE,
        ground,
        fog,
        volumes,
        // 16 x 8 samples instead of the default 64 x 16: the sky is evaluated per pixel
        // here, not once into a table as the froxel pipeline does.
        atmosphere: SkyAtmosphere {
            view_samples: 16,
            light_samples: 8,
            ..SkyAtmosphere::earth(sun.direction)?
        }
        .validated()?,
    })
}

/// The ground's albedo at `p`: a 2 m checkerboard.
pub fn ground_albedo(p: Vec3) -> f32 {
    let cell = (p.x * 0.5).floor() + (p.z * 0.5).floor();
    if cell.rem_euclid(2.0) < 0.5 {
        0.25
    } else {
        0.4
    }
}

impl AnalyticScene {
    /// The uniform block `Scene` of `www/webgl2.js` (std140, which lays these structs
    /// out as WGSL's uniform address space does): `world_from_clip`, `eye` (w: the
    /// sky's fog distance), `ground`, the fog, the volumes, the atmosphere. The browser
    /// test's comparison with [`AnalyticScene::pixel`] checks this layout: a member out
    /// of place would put the image far outside its bound.
    pub fn to_std140(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(bytemuck::bytes_of(&self.world_from_clip));
        out.extend_from_slice(bytemuck::bytes_of(&self.eye.extend(SKY_DISTANCE)));
        out.extend_from_slice(bytemuck::bytes_of(&self.ground.extend(0.0)));
        out.extend(self.fog.to_bytes());
        for v in &self.volumes {
            out.extend(v.to_bytes());
        }
        out.extend(self.atmosphere.to_bytes());
        out
    }

    /// The fogged radiance of pixel (`x`, `y`) of an image `size` pixels, rows counted
    /// from the bottom (as WebGL reads them back): the fragment shader's computation
    /// through the CPU mirror.
    pub fn pixel(&self, x: u32, y: u32, size: (u32, u32)) -> Vec4 {
        let (surface, fog) = self.pixel_parts(x, y, size);
        (surface * fog.w + fog.truncate()).extend(1.0)
    }

    /// What [`AnalyticScene::pixel`] composes: the radiance of the ground or the sky
    /// behind the fog, and the fog (in-scattered radiance rgb, transmittance a).
    pub fn pixel_parts(&self, x: u32, y: u32, size: (u32, u32)) -> (Vec3, Vec4) {
        let ndc = glam::Vec2::new(
            (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0,
            (y as f32 + 0.5) / size.1 as f32 * 2.0 - 1.0,
        );
        let far = self.world_from_clip * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let dir = (far.truncate() / far.w - self.eye).normalize();
        let (point, surface) = if dir.y < -1e-4 {
            let p = self.eye + dir * (self.eye.y / -dir.y).min(SKY_DISTANCE);
            (p, self.ground * ground_albedo(p))
        } else {
            let sky = sky_single_scattering(&self.atmosphere, dir);
            let cos = dir.dot(self.atmosphere.sun_direction);
            (
                self.eye + dir * SKY_DISTANCE,
                sky_radiance(&sky, cos, &self.atmosphere),
            )
        };
        let mut fog = height_fog(&self.fog, self.eye, point - self.eye);
        for v in self.volumes.iter().rev() {
            fog = fog_over(fog_volume(v, self.eye, point), fog);
        }
        (surface, fog)
    }
}
