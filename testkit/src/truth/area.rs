//! The scenes' area lights as volfog takes them ([`fog_area_lights`]).

use volfog::uniforms::{AREA_LIGHT_DISK, AREA_LIGHT_RECT, AreaLight};

use super::scene::{TruthAreaShape, TruthScene};
use super::volfog::{LIGHT_RANGE_FACTOR, TruthView, volume_corners};

/// The scene's area lights as volfog's [`AreaLight`]s: the same centre, axes, extents
/// and radiance, range [`LIGHT_RANGE_FACTOR`] times the farthest distance from the
/// centre to the froxel volume's corners (as the point lights'), so the range window
/// stays above `1 - 1.25e-5` in view.
pub fn fog_area_lights(scene: &TruthScene, view: &TruthView) -> Vec<AreaLight> {
    let corners = volume_corners(view, scene.camera.near, scene.camera.far);
    scene
        .areas
        .iter()
        .map(|a| {
            let d = corners
                .iter()
                .map(|c| c.distance(a.center))
                .fold(0.0f32, f32::max);
            AreaLight {
                shape: match a.shape {
                    TruthAreaShape::Rectangle => AREA_LIGHT_RECT,
                    TruthAreaShape::Disk => AREA_LIGHT_DISK,
                },
                ..AreaLight::rect(
                    a.center,
                    a.axis_x,
                    a.axis_y,
                    a.half_x,
                    a.half_y,
                    a.radiance,
                    LIGHT_RANGE_FACTOR * d.max(1.0),
                )
            }
        })
        .collect()
}
