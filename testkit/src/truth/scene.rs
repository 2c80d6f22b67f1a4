//! The scenes volfog is held against a path tracer with: one description, rendered by
//! volfog's froxel pipeline (`truth::volfog`) and by Mitsuba 3 (`truth::mitsuba`).
//!
//! Units are volfog's: metres, world space with +Y up, a right-handed camera looking
//! along its forward vector. Light colours follow `volfog::uniforms`:
//! - the sun's `color` is the irradiance (W / m^2 per channel) it brings to a surface
//!   facing it outside the medium: Mitsuba's `directional` emitter with
//!   `irradiance = color` and `direction = -sun.direction`;
//! - a point or spot light's `color` is its radiant intensity (W / sr per channel):
//!   Mitsuba's `point` and `spot` emitters with `intensity = color`.
//!
//! - an area light's `radiance` is the radiance (W / (m^2 sr) per channel) its front
//!   face emits: Mitsuba's `rectangle` or `disk` shape with an `area` emitter of that
//!   `radiance` (one-sided, towards `axis_x x axis_y`).
//!
//! In-scattered radiance is `sigma_s * color * phase * transmittance` in both.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A scene: camera, medium, lights, local volumes and opaque black occluders.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthScene {
    /// Short name (file stems, report rows).
    pub name: String,
    /// Image width and height (pixels).
    pub resolution: [u32; 2],
    /// The camera.
    pub camera: TruthCamera,
    /// The global medium.
    pub medium: TruthMedium,
    /// The directional light, if any.
    pub sun: Option<TruthSun>,
    /// Point lights.
    pub points: Vec<TruthPoint>,
    /// Spot lights.
    pub spots: Vec<TruthSpot>,
    /// Area lights (left out of the JSON when there are none, so the scenes without
    /// them keep their cached renders).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub areas: Vec<TruthArea>,
    /// Local volumes added to the medium.
    pub volumes: Vec<TruthVolume>,
    /// Opaque occluders that absorb all light (reflectance 0): the ground, walls. Every
    /// camera ray should hit one before `camera.far` so that no ray leaves the froxel
    /// range.
    pub occluders: Vec<TruthBox>,
}

/// A pinhole camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthCamera {
    /// Eye position (m).
    pub position: Vec3,
    /// The point looked at (m).
    pub target: Vec3,
    /// Vertical field of view (degrees).
    pub fov_y_deg: f32,
    /// Near and far planes of the froxel volume (m).
    pub near: f32,
    /// Far plane of the froxel volume (m).
    pub far: f32,
}

/// The global medium: extinction `density * exp(-falloff * (y - base_height))` below
/// `top` (m), none above it; the medium also ends at `bounds` in Mitsuba (chosen so
/// that light paths leave it only through the top).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthMedium {
    /// Extinction at `base_height` (1/m).
    pub density: f32,
    /// Height falloff (1/m), >= 0.
    pub falloff: f32,
    /// Height of the reference extinction (m).
    pub base_height: f32,
    /// Single-scattering albedo per channel.
    pub albedo: Vec3,
    /// Henyey-Greenstein mean cosine (g > 0 scatters forwards).
    pub phase_g: f32,
    /// Height where the medium ends (m).
    pub top: f32,
    /// Lower corner of the medium's box in Mitsuba (m); its top face is at `top`.
    pub bounds_min: Vec3,
    /// Upper x and z of the box (m); y is `top`.
    pub bounds_max_xz: [f32; 2],
}

/// The sun.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthSun {
    /// Unit direction from the scene towards the sun.
    pub direction: Vec3,
    /// Irradiance outside the medium (W / m^2 per channel).
    pub color: Vec3,
}

/// A point light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthPoint {
    /// Position (m).
    pub position: Vec3,
    /// Radiant intensity (W / sr per channel).
    pub color: Vec3,
}

/// A spot light: full intensity inside `inner_deg`, none outside `outer_deg`
/// (half-angles), Mitsuba's linear-in-angle falloff between them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthSpot {
    /// Position (m).
    pub position: Vec3,
    /// Unit axis (m), pointing away from the light.
    pub direction: Vec3,
    /// Radiant intensity on the axis (W / sr per channel).
    pub color: Vec3,
    /// Half-angle of full intensity (degrees).
    pub inner_deg: f32,
    /// Half-angle beyond which the light is off (degrees).
    pub outer_deg: f32,
}

/// The shape of an area light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TruthAreaShape {
    /// A rectangle of `2 half_x` by `2 half_y` (Mitsuba's `rectangle`).
    Rectangle,
    /// A disk of radius `half_x` (= `half_y`; Mitsuba's `disk`).
    Disk,
}

/// A one-sided Lambertian area light in the plane of `axis_x` and `axis_y`, emitting
/// `radiance` towards `axis_x x axis_y`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthArea {
    /// Rectangle or disk.
    pub shape: TruthAreaShape,
    /// Centre (m).
    pub center: Vec3,
    /// Unit axis of the emitter's plane.
    pub axis_x: Vec3,
    /// Unit axis of the emitter's plane, orthogonal to `axis_x`.
    pub axis_y: Vec3,
    /// Half extent along `axis_x`, or the disk's radius (m).
    pub half_x: f32,
    /// Half extent along `axis_y`, or the disk's radius (m).
    pub half_y: f32,
    /// Emitted radiance (W / (m^2 sr) per channel).
    pub radiance: Vec3,
}

/// The shape of a local volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TruthShape {
    /// The box of the given half extents.
    Box,
    /// The ellipsoid of the given semi-axes.
    Ellipsoid,
}

/// A local volume: extinction `density` inside an axis-aligned box or ellipsoid with a
/// linear fade over `edge` (fraction of the unit extent, volfog's `LocalVolume.edge`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthVolume {
    /// Box or ellipsoid.
    pub shape: TruthShape,
    /// Centre (m).
    pub center: Vec3,
    /// Half extents or semi-axes (m).
    pub half_extents: Vec3,
    /// Extinction added inside (1/m), > 0.
    pub density: f32,
    /// Edge fade, fraction of the unit extent, (0, 1].
    pub edge: f32,
}

/// An axis-aligned opaque box (reflectance 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthBox {
    /// Lower corner (m).
    pub min: Vec3,
    /// Upper corner (m).
    pub max: Vec3,
}

/// What a renderer makes of a scene: per pixel (row-major, top row first) the
/// in-scattered radiance reaching the eye over black, and the transmittance from the
/// eye to the first occluder.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TruthImage {
    /// Width (pixels).
    pub width: u32,
    /// Height (pixels).
    pub height: u32,
    /// In-scattered radiance (linear rgb).
    pub radiance: Vec<Vec3>,
    /// Transmittance (rgb).
    pub transmittance: Vec<Vec3>,
}
