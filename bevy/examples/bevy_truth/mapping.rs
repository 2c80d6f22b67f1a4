//! A truth scene (`volfog_testkit::truth::scene::TruthScene`) in Bevy 0.20's own terms:
//! the components that render it with Bevy's ray-marched `VolumetricFog` and
//! `FogVolume`s, in the units `BevyFogCompat` maps between Bevy and volfog.
//!
//! Units. Bevy's lights are photometric and its image is exposed: a light's values
//! times the camera's `Exposure::exposure()` are volfog's (and the truth scenes')
//! radiometric units, as `BevyFogCompat` and the plugin read them. So with the
//! camera's exposure `e`:
//! - the sun: `DirectionalLight.illuminance = max(color) / e`, `color = color /
//!   max(color)` (linear), so that Bevy's light colour times illuminance times
//!   exposure is the scene's irradiance;
//! - a point or spot light: `intensity = 4 pi max(color) / e` lumens (Bevy divides a
//!   lamp's lumens by 4 pi for its candela, the scene's radiant intensity);
//! - the medium: `FogVolume.density_factor` the extinction, `scattering` the
//!   albedo's largest channel, `absorption` one less it, `fog_color` the albedo over
//!   that channel: Bevy's extinction `density_factor (absorption + scattering)` is
//!   the scene's, its scattering coefficient `density_factor scattering fog_color`
//!   the scene's `density albedo`; `scattering_asymmetry` is the scene's
//!   Henyey-Greenstein `g`; `light_tint` white and `light_intensity` 1 leave the lights
//!   as they are;
//! - `VolumetricFog.ambient_intensity` 0: the scenes have no ambient light.
//!
//! The read-back image is then in the scene's units (Bevy's fog multiplies its light
//! by the exposure, as its surfaces do).
//!
//! Shapes. The global medium is one `FogVolume` over the scene's medium box; an
//! exponential height profile is that volume's `density_texture` (1 x
//! [`HEIGHT_TEXELS`] x 1 texels, linear filtering, clamped at the faces). A local
//! volume is a `FogVolume` over its box whose `density_texture`
//! ([`VOLUME_TEXELS`] per side) holds the scene's edge fade of a box or an ellipsoid;
//! Bevy draws each volume as a pass of its own, blended over the image as
//! `src + dst * (1 - alpha)`, in the order they were spawned: the global medium
//! first. Occluders are unit cuboids scaled to their boxes with one unlit material,
//! black for the radiance and white for the transmittance.

use bevy::camera::Exposure;
use bevy::light::{CascadeShadowConfig, CascadeShadowConfigBuilder, FogVolume, VolumetricFog};
use bevy::prelude::*;
use volfog::glam as vg;
use volfog::limits::{InvalidValue, check};
use volfog_testkit::truth::scene::{TruthScene, TruthShape, TruthVolume};
use volfog_testkit::truth::scenes::medium_box;
use volfog_testkit::truth::volfog::TruthView;

/// Texels of the height profile's density texture, bottom to top of the medium box.
pub const HEIGHT_TEXELS: u32 = 256;
/// Texels per side of a local volume's density texture.
pub const VOLUME_TEXELS: u32 = 64;
/// A lamp's `range` is this many times its largest distance to a corner of the medium
/// box: Bevy's range window `(1 - (d / range)^4)^2` then stays above `1 - 2 / 20^4`
/// wherever there is fog.
pub const RANGE_FACTOR: f32 = 20.0;
/// The lamps' `radius` (m): Bevy's fog does not read it (its inverse-square law is
/// clamped at 1 cm); its surfaces would.
pub const LAMP_RADIUS: f32 = 0.01;
/// Bevy's default steps per ray of `VolumetricFog` (and the default of the tables).
pub const DEFAULT_STEPS: u32 = 64;

/// A density texture: `size` texels (x, y, z), `values` x fastest, in the volume's
/// unit cube (texel `(i, j, k)` centred at `((i, j, k) + 0.5) / size`).
#[derive(Debug, Clone, PartialEq)]
pub struct DensityGrid {
    /// Texels per axis.
    pub size: UVec3,
    /// Values, x fastest, then y, then z.
    pub values: Vec<f32>,
}

impl DensityGrid {
    /// The value at `uvw` (the unit cube), trilinear between texel centres and clamped
    /// to the edge texels beyond them, as Bevy samples the texture.
    pub fn sample(&self, uvw: Vec3) -> f32 {
        let size = self.size.as_vec3();
        let p = (uvw * size - 0.5).clamp(Vec3::ZERO, size - 1.0);
        let i0 = p.floor().as_uvec3().min(self.size - 1);
        let i1 = (i0 + 1).min(self.size - 1);
        let f = p - i0.as_vec3();
        let at = |x: u32, y: u32, z: u32| {
            self.values[(x + self.size.x * (y + self.size.y * z)) as usize]
        };
        let mut sum = 0.0;
        for (k, wz) in [(i0.z, 1.0 - f.z), (i1.z, f.z)] {
            for (j, wy) in [(i0.y, 1.0 - f.y), (i1.y, f.y)] {
                for (i, wx) in [(i0.x, 1.0 - f.x), (i1.x, f.x)] {
                    sum += wx * wy * wz * at(i, j, k);
                }
            }
        }
        sum
    }
}

/// A `FogVolume` of the scene with its transform and density texture.
#[derive(Debug, Clone)]
pub struct MappedVolume {
    /// Bevy's volume (its `density_texture` is set when spawned, from `grid`).
    pub volume: FogVolume,
    /// The unit cube's transform: the box's centre and size.
    pub transform: Transform,
    /// The density texture, if any.
    pub grid: Option<DensityGrid>,
}

/// Everything Bevy renders of a scene.
#[derive(Debug, Clone)]
pub struct MappedScene {
    /// The scene's name.
    pub name: String,
    /// Image width and height (pixels).
    pub size: [u32; 2],
    /// The camera's transform.
    pub camera: Transform,
    /// The camera's projection.
    pub projection: PerspectiveProjection,
    /// The camera's exposure (EV100, [`MappedScene::exposure`]).
    pub ev100: f32,
    /// Bevy's fog settings on the camera.
    pub fog: VolumetricFog,
    /// The sun, with its transform and cascades.
    pub sun: Option<(DirectionalLight, Transform, CascadeShadowConfig)>,
    /// Point lights.
    pub points: Vec<(PointLight, Transform)>,
    /// Spot lights.
    pub spots: Vec<(SpotLight, Transform)>,
    /// The global medium first, then the local volumes.
    pub volumes: Vec<MappedVolume>,
    /// The occluders: transforms of the unit cuboid.
    pub occluders: Vec<Transform>,
}

/// A vector of the truth scene (volfog's glam) in Bevy's.
pub fn bv(v: vg::Vec3) -> Vec3 {
    Vec3::from_array(v.to_array())
}

/// The medium box (Bevy's vectors).
pub fn medium_bounds(scene: &TruthScene) -> (Vec3, Vec3) {
    let (min, max) = medium_box(&scene.medium);
    (bv(min), bv(max))
}

impl MappedScene {
    /// The camera's `Exposure`.
    pub fn exposure(&self) -> Exposure {
        Exposure { ev100: self.ev100 }
    }
}

/// A colour's largest channel and the colour over it (linear), or the field's error.
fn split_color(color: Vec3, field: &'static str) -> Result<(f32, Color), InvalidValue> {
    let max = color.max_element();
    check(
        color.is_finite() && color.min_element() >= 0.0 && max > 0.0,
        field,
        color,
        "finite, non-negative, not black",
    )?;
    let c = color / max;
    Ok((max, Color::linear_rgb(c.x, c.y, c.z)))
}

/// The transform of a light at `position` facing `direction` (an up vector that is
/// not parallel to it).
fn facing(position: Vec3, direction: Vec3) -> Transform {
    let up = if direction.normalize().y.abs() > 0.99 {
        Vec3::X
    } else {
        Vec3::Y
    };
    Transform::from_translation(position).looking_to(direction, up)
}

/// The scene's medium as a `FogVolume` without its shape: extinction `density`, the
/// scene's albedo and phase.
fn medium_volume(scene: &TruthScene, density: f32) -> Result<FogVolume, InvalidValue> {
    let m = &scene.medium;
    check(
        m.albedo.is_finite() && m.albedo.min_element() >= 0.0 && m.albedo.max_element() <= 1.0,
        "TruthMedium.albedo",
        m.albedo,
        "each channel in [0, 1]",
    )?;
    check(
        m.phase_g.is_finite() && m.phase_g.abs() < 1.0,
        "TruthMedium.phase_g",
        m.phase_g,
        "-1 < g < 1",
    )?;
    let albedo = bv(m.albedo);
    let a = albedo.max_element();
    let fog_color = if a > 0.0 { albedo / a } else { Vec3::ONE };
    Ok(FogVolume {
        density_factor: density,
        absorption: 1.0 - a,
        scattering: a,
        fog_color: Color::linear_rgb(fog_color.x, fog_color.y, fog_color.z),
        light_tint: Color::WHITE,
        scattering_asymmetry: m.phase_g,
        light_intensity: 1.0,
        density_texture: None,
        density_texture_offset: Vec3::ZERO,
    })
}

/// The global medium over the medium box, its height profile (if any) as a density
/// texture.
fn global_volume(scene: &TruthScene) -> Result<MappedVolume, InvalidValue> {
    let m = &scene.medium;
    check(
        m.density.is_finite() && m.density >= 0.0,
        "TruthMedium.density",
        m.density,
        "finite, >= 0 (1/m)",
    )?;
    check(
        m.falloff.is_finite() && m.falloff >= 0.0,
        "TruthMedium.falloff",
        m.falloff,
        "finite, >= 0 (1/m)",
    )?;
    let (min, max) = medium_bounds(scene);
    check(
        min.is_finite() && max.is_finite() && (max - min).min_element() > 0.0,
        "TruthMedium.bounds_min",
        (min, max),
        "a box of positive size below `top`",
    )?;
    let transform = Transform::from_translation((min + max) * 0.5).with_scale(max - min);
    if m.falloff == 0.0 {
        return Ok(MappedVolume {
            volume: medium_volume(scene, m.density)?,
            transform,
            grid: None,
        });
    }
    // exp(-falloff (y - base)) is largest at the bottom: the texture holds the profile
    // over that value, which density_factor carries.
    let profile = |y: f32| (-m.falloff * (y - m.base_height)).exp();
    let peak = profile(min.y);
    let values = (0..HEIGHT_TEXELS)
        .map(|j| {
            let y = min.y + (j as f32 + 0.5) / HEIGHT_TEXELS as f32 * (max.y - min.y);
            profile(y) / peak
        })
        .collect();
    Ok(MappedVolume {
        volume: medium_volume(scene, m.density * peak)?,
        transform,
        grid: Some(DensityGrid {
            size: UVec3::new(1, HEIGHT_TEXELS, 1),
            values,
        }),
    })
}

/// A local volume over its bounding box, its shape and edge fade as a density texture:
/// `clamp((1 - m) / edge, 0, 1)` with `m` the largest coordinate (box) or the length
/// (ellipsoid) of the point in the unit shape.
fn local_volume(scene: &TruthScene, v: &TruthVolume) -> Result<MappedVolume, InvalidValue> {
    check(
        v.density.is_finite() && v.density > 0.0,
        "TruthVolume.density",
        v.density,
        "finite, > 0 (1/m)",
    )?;
    check(
        v.edge.is_finite() && v.edge > 0.0 && v.edge <= 1.0,
        "TruthVolume.edge",
        v.edge,
        "in (0, 1]",
    )?;
    check(
        v.center.is_finite() && v.half_extents.is_finite() && v.half_extents.min_element() > 0.0,
        "TruthVolume.half_extents",
        v.half_extents,
        "finite and > 0 (m)",
    )?;
    let n = VOLUME_TEXELS;
    let mut values = Vec::with_capacity((n * n * n) as usize);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let p = (UVec3::new(i, j, k).as_vec3() + 0.5) / n as f32 * 2.0 - 1.0;
                let m = match v.shape {
                    TruthShape::Box => p.abs().max_element(),
                    TruthShape::Ellipsoid => p.length(),
                };
                values.push(((1.0 - m) / v.edge).clamp(0.0, 1.0));
            }
        }
    }
    Ok(MappedVolume {
        volume: medium_volume(scene, v.density)?,
        transform: Transform::from_translation(bv(v.center)).with_scale(2.0 * bv(v.half_extents)),
        grid: Some(DensityGrid {
            size: UVec3::splat(n),
            values,
        }),
    })
}

/// The range of a lamp at `position`: [`RANGE_FACTOR`] times its largest distance to
/// a corner of the medium box.
fn lamp_range(scene: &TruthScene, position: Vec3) -> f32 {
    let (min, max) = medium_bounds(scene);
    let far = (0..8)
        .map(|i| {
            let corner = Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            );
            corner.distance(position)
        })
        .fold(1.0f32, f32::max);
    RANGE_FACTOR * far
}

/// The scene in Bevy's components with `steps` ray-march steps per pixel (Bevy's
/// default 64, no jitter). Bad input is an error naming the scene's field.
pub fn map_scene(scene: &TruthScene, steps: u32) -> Result<MappedScene, InvalidValue> {
    // The camera's checks (resolution, field of view, planes, direction).
    TruthView::new(scene)?;
    check(steps >= 1, "VolumetricFog.step_count", steps, "at least 1")?;
    let exposure = Exposure::default();
    let e = exposure.exposure();
    let c = &scene.camera;
    let [w, h] = scene.resolution;
    let projection = PerspectiveProjection {
        fov: c.fov_y_deg.to_radians(),
        aspect_ratio: w as f32 / h as f32,
        near: c.near,
        // Culling only (Bevy's projection has no far plane).
        far: 4.0 * c.far,
        ..default()
    };
    let sun = match &scene.sun {
        None => None,
        Some(s) => {
            let (max, color) = split_color(bv(s.color), "TruthSun.color")?;
            check(
                s.direction.is_finite() && s.direction.length() > 0.0,
                "TruthSun.direction",
                s.direction,
                "a finite, non-zero direction",
            )?;
            // Bevy's four default cascades, reaching past the farthest surface in view.
            let cascades = CascadeShadowConfigBuilder {
                maximum_distance: CascadeShadowConfigBuilder::default()
                    .maximum_distance
                    .max(1.5 * c.far),
                ..default()
            }
            .build();
            let light = DirectionalLight {
                color,
                illuminance: max / e,
                shadow_maps_enabled: true,
                ..default()
            };
            let toward = bv(s.direction).normalize();
            Some((light, facing(Vec3::ZERO, -toward), cascades))
        }
    };
    let lumens = |max: f32| 4.0 * std::f32::consts::PI * max / e;
    let mut points = Vec::new();
    for p in &scene.points {
        let (max, color) = split_color(bv(p.color), "TruthPoint.color")?;
        check(
            p.position.is_finite(),
            "TruthPoint.position",
            p.position,
            "finite (m)",
        )?;
        let light = PointLight {
            color,
            intensity: lumens(max),
            range: lamp_range(scene, bv(p.position)),
            radius: LAMP_RADIUS,
            shadow_maps_enabled: true,
            ..default()
        };
        points.push((light, Transform::from_translation(bv(p.position))));
    }
    let mut spots = Vec::new();
    for s in &scene.spots {
        let (max, color) = split_color(bv(s.color), "TruthSpot.color")?;
        check(
            s.inner_deg.is_finite()
                && s.outer_deg.is_finite()
                && 0.0 <= s.inner_deg
                && s.inner_deg < s.outer_deg
                && s.outer_deg < 90.0,
            "TruthSpot.outer_deg",
            (s.inner_deg, s.outer_deg),
            "0 <= inner < outer < 90 degrees",
        )?;
        check(
            s.position.is_finite() && s.direction.is_finite() && s.direction.length() > 0.0,
            "TruthSpot.direction",
            s.direction,
            "a finite, non-zero direction from a finite position",
        )?;
        let light = SpotLight {
            color,
            intensity: lumens(max),
            range: lamp_range(scene, bv(s.position)),
            radius: LAMP_RADIUS,
            inner_angle: s.inner_deg.to_radians(),
            outer_angle: s.outer_deg.to_radians(),
            shadow_maps_enabled: true,
            ..default()
        };
        spots.push((light, facing(bv(s.position), bv(s.direction))));
    }
    let mut volumes = vec![global_volume(scene)?];
    for v in &scene.volumes {
        volumes.push(local_volume(scene, v)?);
    }
    let mut occluders = Vec::new();
    for b in &scene.occluders {
        check(
            b.min.is_finite() && b.max.is_finite() && (b.max - b.min).min_element() > 0.0,
            "TruthBox.max",
            (b.min, b.max),
            "a finite box of positive size",
        )?;
        occluders.push(
            Transform::from_translation(bv(b.min + b.max) * 0.5).with_scale(bv(b.max - b.min)),
        );
    }
    Ok(MappedScene {
        name: scene.name.clone(),
        size: scene.resolution,
        camera: Transform::from_translation(bv(c.position)).looking_at(bv(c.target), Vec3::Y),
        projection,
        ev100: exposure.ev100,
        fog: VolumetricFog {
            step_count: steps,
            jitter: 0.0,
            ambient_color: Color::WHITE,
            ambient_intensity: 0.0,
        },
        sun,
        points,
        spots,
        volumes,
        occluders,
    })
}
