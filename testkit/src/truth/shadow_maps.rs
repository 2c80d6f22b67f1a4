//! Shadow maps of a scene's lights ([`TruthScene`](super::scene::TruthScene)), ray
//! cast on the CPU from its occluder boxes (slab tests), so the geometry the fog
//! should see is known exactly:
//! - the sun's cascades ([`sun_shadow`]): for each texel the first hit of a ray cast
//!   along `-sun.direction` from above every box, as the depth of the cascade's
//!   orthographic projection (0 nearest the sun, standard z);
//! - the point lights' cubes and the spot lights' maps ([`lamp_shadows`]): for each
//!   texel the first hit of the ray from the light through the texel's centre, as the
//!   depth of the light's perspective [`LightCamera`] (volfog's own choice of camera:
//!   [`LightCamera::point`], faces +X, -X, +Y, -Y, +Z, -Z as
//!   [`LightCamera::cube_face_view`] lays them out, and [`LightCamera::spot`]), 1
//!   where the ray meets nothing before the camera's far plane.

use glam::{Mat4, Vec3};
use volfog::limits::InvalidValue;
use volfog::pipeline::{FogConfig, ShadowedLight, cascade_projection, cascade_splits};
use volfog::uniforms::{FogLight, LightCamera, ShadowCascades};

use super::scene::TruthBox;
use super::volfog::{TruthView, volume_corners};

/// Split scheme of the cascades: 0.5 blends logarithmic and uniform splits equally.
pub const CASCADE_LAMBDA: f32 = 0.5;

/// Near plane (m) of the lamps' shadow cameras.
pub const LAMP_SHADOW_NEAR: f32 = 0.05;

/// The first hit `t >= 0` (in units of `|dir|`) of the ray `origin + t dir` with the
/// boxes (slab test); 0 when the origin lies inside one, `None` when it hits none.
pub fn trace(origin: Vec3, dir: Vec3, boxes: &[TruthBox]) -> Option<f32> {
    let inv = dir.recip();
    let mut best = f32::INFINITY;
    for b in boxes {
        let a = (b.min - origin) * inv;
        let c = (b.max - origin) * inv;
        let near = a.min(c).max_element();
        let far = a.max(c).min_element();
        if near <= far && far >= 0.0 {
            best = best.min(near.max(0.0));
        }
    }
    best.is_finite().then_some(best)
}

/// Whether `p` lies inside one of the boxes (faces included).
pub fn inside(p: Vec3, boxes: &[TruthBox]) -> bool {
    boxes
        .iter()
        .any(|b| p.cmpge(b.min).all() && p.cmple(b.max).all())
}

/// Whether a light reaches `p` unblocked by the boxes: `towards` is the unit direction
/// to a directional light (`segment` false) or the vector from `p` to a point light
/// (`segment` true). A point inside a box is unlit.
pub fn lit(p: Vec3, towards: Vec3, segment: bool, boxes: &[TruthBox]) -> bool {
    match trace(p, towards, boxes) {
        None => true,
        Some(t) => segment && t >= 1.0,
    }
}

/// The sun's cascades and their shadow-map depths (one layer per cascade, row-major
/// from the top, `config.shadow_map_size().0` texels per side; reversed, `1 - depth`,
/// when `config.shadow_reversed_z`).
///
/// Cascade `i` covers the bounding sphere (centre `c`, radius `r`) of the view frustum
/// between its split depths. Its orthographic projection spans that sphere's square
/// footprint (2 % wider) across the sun, and along it from `r` below the centre to
/// `r + m` above it (towards the sun): `m` is the height above the sphere of the
/// highest occluder in the footprint, at most `0.35 r`. Occluders higher still are
/// clamped to depth 0 (pancaking): receivers of the cascade lie at least
/// `0.35 r / (2.35 r) = 0.15` below them in depth, where the ESM visibility is below
/// `exp(-0.15 c)` (0.25 % at c = 40).
pub fn sun_shadow(
    config: &FogConfig,
    view: &TruthView,
    sun: Vec3,
    boxes: &[TruthBox],
) -> (ShadowCascades, Vec<Vec<f32>>) {
    let count = config.cascades;
    let splits = cascade_splits(count, config.near, config.far, CASCADE_LAMBDA);
    let mut cascades = ShadowCascades {
        splits,
        count,
        exponent: config.esm_exponent,
        ..Default::default()
    };
    // Above every box: where the rays towards the ground start.
    let top = boxes
        .iter()
        .flat_map(|b| box_corners(b).map(|c| c.dot(sun)))
        .fold(f32::NEG_INFINITY, f32::max);
    let size = config.shadow_map_size().0;
    let mut layers = Vec::with_capacity(count as usize);
    for i in 0..count as usize {
        let z0 = if i == 0 { config.near } else { splits[i - 1] };
        let corners = volume_corners(view, z0, splits[i]);
        let center = corners.iter().copied().sum::<Vec3>() / 8.0;
        let radius = corners
            .iter()
            .map(|c| c.distance(center))
            .fold(0.0f32, f32::max)
            .max(1e-3);
        let half = radius * 1.02;
        // The lateral grid of the texels does not depend on the depth range: trace
        // first, then place the near plane.
        let probe = cascade_projection(sun, center, half, 2.0 * radius);
        let inv = probe.inverse();
        let texel_world = |x: f32, y: f32| {
            inv.project_point3(Vec3::new(
                2.0 * x / size as f32 - 1.0,
                1.0 - 2.0 * y / size as f32,
                0.0,
            ))
        };
        let origin = texel_world(0.5, 0.5);
        let step_x = texel_world(1.5, 0.5) - origin;
        let step_y = texel_world(0.5, 1.5) - origin;
        let sphere_top = center.dot(sun) + radius;
        let start = top.max(sphere_top) + 1.0;
        let lift = sun * (start - origin.dot(sun));
        // Height along the sun of each texel's first hit, NaN where there is none.
        let hits: Vec<f32> = (0..size * size)
            .map(|t| {
                let p = origin + step_x * (t % size) as f32 + step_y * (t / size) as f32 + lift;
                trace(p, -sun, boxes).map_or(f32::NAN, |t| start - t)
            })
            .collect();
        let highest = hits
            .iter()
            .copied()
            .filter(|h| !h.is_nan())
            .fold(f32::NEG_INFINITY, f32::max);
        let margin = (highest - sphere_top).clamp(0.0, 0.35 * radius);
        let range = 2.0 * radius + margin;
        let near = sphere_top + margin;
        cascades.light_from_world[i] =
            cascade_projection(sun, center + sun * (0.5 * margin), half, range);
        let depth = |h: f32| {
            let d = if h.is_nan() {
                1.0
            } else {
                ((near - h) / range).clamp(0.0, 1.0)
            };
            if config.shadow_reversed_z { 1.0 - d } else { d }
        };
        layers.push(hits.iter().map(|&h| depth(h)).collect());
    }
    (cascades, layers)
}

fn box_corners(b: &TruthBox) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { b.min.x } else { b.max.x },
            if k & 2 == 0 { b.min.y } else { b.max.y },
            if k & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

/// The point and spot lights' shadow cameras and depth maps.
#[derive(Debug, Clone, Default)]
pub struct LampShadows {
    /// One per point or spot light, in the order of the lights: the cube `k` of the
    /// point maps for the `k`-th point light, the layer `k` of the spot maps for the
    /// `k`-th spot light.
    pub shadowed: Vec<ShadowedLight>,
    /// Texels per side of every map.
    pub size: u32,
    /// The spot lights' depth maps, one layer each (row-major from the top).
    pub spot_layers: Vec<Vec<f32>>,
    /// The point lights' cube faces, six layers each (+X, -X, +Y, -Y, +Z, -Z).
    pub point_layers: Vec<Vec<f32>>,
}

/// Depth maps of `size` texels per side for each point and spot light of `lights`
/// (directional ones are skipped), with the shadow cameras volfog would choose
/// ([`LightCamera::point`] and [`LightCamera::spot`] with near plane
/// [`LAMP_SHADOW_NEAR`] and the light's range as far plane; standard depth).
pub fn lamp_shadows(
    lights: &[FogLight],
    boxes: &[TruthBox],
    size: u32,
) -> Result<LampShadows, InvalidValue> {
    let mut out = LampShadows {
        size,
        ..LampShadows::default()
    };
    for (i, light) in lights.iter().enumerate() {
        if light.is_directional() {
            continue;
        }
        let spot = light.cos_outer > -1.0 && light.cos_outer < 1.0;
        if spot {
            let camera = LightCamera::spot(light, LAMP_SHADOW_NEAR)?;
            let LightCamera::Spot {
                view_from_world,
                clip_from_view,
            } = camera
            else {
                unreachable!("LightCamera::spot makes a spot camera")
            };
            let layer = out.spot_layers.len() as u32;
            out.spot_layers.push(depth_map(
                light.position,
                view_from_world,
                clip_from_view,
                size,
                boxes,
            ));
            out.shadowed
                .push(ShadowedLight::new(i as u32, camera).with_shadow(layer));
        } else {
            let camera = LightCamera::point(light, LAMP_SHADOW_NEAR)?;
            let LightCamera::Point {
                cube_from_world,
                clip_from_view,
            } = camera
            else {
                unreachable!("LightCamera::point makes a point camera")
            };
            let cube = (out.point_layers.len() / 6) as u32;
            for face in 0..6 {
                let view = LightCamera::cube_face_view(face) * cube_from_world;
                out.point_layers
                    .push(depth_map(light.position, view, clip_from_view, size, boxes));
            }
            out.shadowed
                .push(ShadowedLight::new(i as u32, camera).with_shadow(cube));
        }
    }
    Ok(out)
}

/// One perspective depth map: for each texel centre (row 0 at the top) the projected
/// depth of the first box the ray from `eye` through it meets, 1 where it meets none
/// before the far plane.
fn depth_map(
    eye: Vec3,
    view_from_world: Mat4,
    clip_from_view: Mat4,
    size: u32,
    boxes: &[TruthBox],
) -> Vec<f32> {
    let clip_from_world = clip_from_view * view_from_world;
    let world_from_view = view_from_world.inverse();
    let view_from_clip = clip_from_view.inverse();
    let n = size as f32;
    (0..size * size)
        .map(|t| {
            let (x, y) = ((t % size) as f32 + 0.5, (t / size) as f32 + 0.5);
            let ndc = Vec3::new(2.0 * x / n - 1.0, 1.0 - 2.0 * y / n, 0.5);
            let dir = world_from_view.transform_vector3(view_from_clip.project_point3(ndc));
            match trace(eye, dir, boxes) {
                Some(t) => {
                    let d = clip_from_world.project_point3(eye + dir * t).z;
                    if (0.0..=1.0).contains(&d) { d } else { 1.0 }
                }
                None => 1.0,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(center: Vec3) -> TruthBox {
        TruthBox {
            min: center - 0.5,
            max: center + 0.5,
        }
    }

    #[test]
    fn lit_follows_the_segment_and_the_ray() {
        let boxes = [unit_box(Vec3::new(0.0, 0.0, -5.0))];
        let p = Vec3::ZERO;
        // The light beyond the box: blocked; in front of it: lit.
        assert!(!lit(p, Vec3::new(0.0, 0.0, -10.0), true, &boxes));
        assert!(lit(p, Vec3::new(0.0, 0.0, -4.0), true, &boxes));
        assert!(!lit(p, Vec3::NEG_Z, false, &boxes));
        assert!(lit(p, Vec3::Z, false, &boxes));
        // Inside the box: unlit.
        assert!(!lit(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, false, &boxes));
    }

    /// A point light's cube maps hold, at the texel a direction falls in, the depth of
    /// the box that direction meets: the texel of a world point recovered with the
    /// face's own matrices, and the depth turned back into a distance.
    #[test]
    fn cube_texels_hold_the_depth_of_the_box_in_their_direction() {
        let light = FogLight::point(Vec3::new(1.0, 2.0, 3.0), Vec3::ONE, 50.0);
        // A box on each side of the light along each axis, at different distances.
        let boxes: Vec<TruthBox> = (0..6)
            .map(|f| {
                let axis = volfog::uniforms::CUBE_FACE_AXES[f][2];
                unit_box(light.position + axis * (3.0 + f as f32))
            })
            .collect();
        let size = 32;
        let maps = lamp_shadows(&[light], &boxes, size).unwrap();
        assert_eq!(maps.point_layers.len(), 6);
        assert_eq!(maps.shadowed[0].shadow, Some(0));
        let LightCamera::Point {
            cube_from_world,
            clip_from_view,
        } = maps.shadowed[0].camera
        else {
            panic!("a point camera")
        };
        for face in 0..6u32 {
            let [right, up, axis] = volfog::uniforms::CUBE_FACE_AXES[face as usize];
            // The near face of the box on this axis, a little off the axis.
            let world = light.position + axis * (2.5 + face as f32) + (right + 2.0 * up) * 0.07;
            let view = LightCamera::cube_face_view(face) * cube_from_world;
            let clip = clip_from_view * view * world.extend(1.0);
            let (u, v) = (clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
            let texel = ((v * size as f32) as u32) * size + (u * size as f32) as u32;
            let d = maps.point_layers[face as usize][texel as usize];
            let want = clip.z / clip.w;
            assert!((d - want).abs() < 2e-4, "face {face}: {d} against {want}");
        }
    }
}
