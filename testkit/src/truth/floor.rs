//! The floor a froxel grid sets: the image volfog would make of a scene with a perfect
//! shadow term, on the CPU.
//!
//! Each froxel's scattering is the CPU mirror of the inject pass
//! ([`volfog::cpu::inject::froxel_scattering`]) at the froxel's centre with every
//! light unshadowed, one light at a time, each light's share multiplied by the
//! light's exact visibility averaged over the froxel ([`froxel_visibility`]); the
//! volume is then scanned and applied as volfog scans and applies it
//! ([`crate::selfcheck::cpu_scan`], the mirror of the scan pass over rgba16float
//! values, and [`volfog::cpu::apply`]'s trilinear look-up at each pixel's depth). What
//! this image misses of Mitsuba's is the grid's own share of the error (the froxels'
//! size, slices, the trilinear look-up across a shadow edge) and the light models',
//! not the shadow filter's.
//!
//! A froxel's visibility is exact where no shadow boundary can cross it: a ball around
//! the froxel (its eight corners' centroid, radius the farthest corner) is lit
//! everywhere when the ray (sun) or segment (lamp) from its centre misses every box
//! grown by the radius, and dark everywhere when it meets a box shrunk by the radius
//! (for a lamp, the segment from a point of the ball to the light stays within the
//! radius of the centre's segment). Other froxels take the mean over
//! [`SUBSAMPLES`]^3 stratified points (cell centres of a regular grid in the froxel's
//! coordinates, where volfog's jitter spreads its samples) that lie in the medium,
//! outside every box, each lit when its ray or segment to the light meets no box. The
//! points inside a box are left out: no fog is there (Mitsuba's medium stops at the
//! boxes), and the camera sees the fog in front of the box's surface, which its part
//! of the froxel should not darken. (A depth compare at such a point reads the box's
//! own shadow; a froxel straddling the ground would be darkened by its part below
//! it.) A froxel with no point in the medium is dark.

use glam::{UVec3, Vec2, Vec3, Vec4};
use volfog::cpu::apply::{Volume, fog_coord};
use volfog::cpu::froxel::{froxel_view_position, slice_coord};
use volfog::cpu::inject::{InjectInputs, froxel_scattering};
use volfog::pipeline::FrameInputs;
use volfog::uniforms::{FogLight, FogLighting, ShadowCascades};

use super::scene::{TruthBox, TruthImage, TruthScene};
use super::shadow_maps::{inside, lit};
use super::volfog::{
    TruthError, TruthView, VolfogOptions, fog_config, fog_lights, fog_medium, fog_sun, fog_volumes,
    pixel_depths,
};
use crate::selfcheck::cpu_scan;

/// Stratified points per axis of a froxel a shadow boundary may cross.
pub const SUBSAMPLES: u32 = 4;

/// A light as the visibility sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Occluded {
    /// A directional light: the unit direction towards it.
    Sun(Vec3),
    /// A point or spot light at this position.
    Lamp(Vec3),
}

/// The grid floor of a scene ([`grid_floor`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GridFloor {
    /// The image: in-scattered radiance and transmittance per pixel.
    pub image: TruthImage,
    /// Froxels whose scattering was computed (those in front of the surfaces the
    /// apply reads, per light).
    pub froxels: usize,
    /// Of those, per light, the froxels a shadow boundary may cross (sub-sampled).
    pub sampled: usize,
}

/// Whether the ray from `c` along `dir` (for `segment`, the points `c + t dir` with `t`
/// in [0, 1)) meets the box `[min, max]`.
fn meets(c: Vec3, dir: Vec3, segment: bool, min: Vec3, max: Vec3) -> bool {
    if min.cmpgt(max).any() {
        return false;
    }
    let inv = dir.recip();
    let a = (min - c) * inv;
    let b = (max - c) * inv;
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element();
    near <= far && (!segment || near < 1.0)
}

/// The mean visibility of `light` over froxel `id`: 1 or 0 where the froxel's ball
/// cannot hold a shadow boundary, else the mean over those of [`SUBSAMPLES`]^3
/// stratified points that lie outside every box (0 if none does); the second value
/// says whether it was sampled. `world_at` maps an offset
/// from the froxel's centre (froxel units, each in [-0.5, 0.5]) to world space.
pub fn froxel_visibility(
    light: Occluded,
    boxes: &[TruthBox],
    world_at: impl Fn(Vec3) -> Vec3,
) -> (f32, bool) {
    let corners: [Vec3; 8] = std::array::from_fn(|k| {
        world_at(Vec3::new(
            if k & 1 == 0 { -0.5 } else { 0.5 },
            if k & 2 == 0 { -0.5 } else { 0.5 },
            if k & 4 == 0 { -0.5 } else { 0.5 },
        ))
    });
    let center = corners.iter().copied().sum::<Vec3>() / 8.0;
    let radius = corners
        .iter()
        .map(|c| c.distance(center))
        .fold(0.0f32, f32::max)
        * (1.0 + 1e-4)
        + 1e-5;
    let (dir, segment) = match light {
        Occluded::Sun(s) => (s, false),
        Occluded::Lamp(q) => (q - center, true),
    };
    let grown = |b: &TruthBox| meets(center, dir, segment, b.min - radius, b.max + radius);
    if !boxes.iter().any(grown) {
        return (1.0, false);
    }
    let shrunk = |b: &TruthBox| meets(center, dir, segment, b.min + radius, b.max - radius);
    if boxes.iter().any(shrunk) {
        return (0.0, false);
    }
    let n = SUBSAMPLES;
    let (mut seen, mut counted) = (0u32, 0u32);
    for k in 0..n * n * n {
        let cell = Vec3::new((k % n) as f32, (k / n % n) as f32, (k / (n * n)) as f32);
        let p = world_at((cell + 0.5) / n as f32 - 0.5);
        if inside(p, boxes) {
            continue;
        }
        let towards = match light {
            Occluded::Sun(s) => s,
            Occluded::Lamp(q) => q - p,
        };
        counted += 1;
        seen += u32::from(lit(p, towards, segment, boxes));
    }
    let mean = if counted == 0 {
        0.0
    } else {
        seen as f32 / counted as f32
    };
    (mean, true)
}

/// The grid floor of `scene` at `options.config`'s grid (its light transmittance,
/// slices and scan step; the shadow filter, jitter and history play no part).
pub fn grid_floor(scene: &TruthScene, options: &VolfogOptions) -> Result<GridFloor, TruthError> {
    let view = TruthView::new(scene)?;
    let config = {
        let mut c = fog_config(scene, options)?;
        c.jitter = false;
        c
    };
    let medium = fog_medium(scene);
    let sun = fog_sun(scene);
    sun.validate()?;
    let lights = fog_lights(scene, &view);
    let volumes = fog_volumes(scene)?;
    let inputs = FrameInputs {
        medium,
        sun,
        ambient: volfog::cpu::ambient::AmbientSh::constant(Vec3::ZERO),
        lights: &lights,
        local_volumes: &volumes,
        cascades: ShadowCascades::default(),
        tail: volfog::uniforms::HeightFog::none(),
        ..FrameInputs::new(view.view_from_world, view.clip_from_view, 0.0)
    };
    let u = inputs.uniforms(&config, 0)?;
    let froxels = u.froxels;
    let size = froxels.size;
    let [w, h] = scene.resolution;

    // Per pixel the view depth of its surface (the far plane where it meets none).
    let forward = view.world_from_view.transform_vector3(Vec3::NEG_Z);
    let distances = pixel_depths(scene);
    let depths: Vec<f32> = (0..w * h)
        .map(|i| {
            let dir = view.pixel_ray(scene.resolution, i % w, i / w);
            let d = distances[i as usize] * dir.dot(forward);
            if d.is_finite() { d } else { config.far }
        })
        .collect();
    // Per froxel column the slices the apply can read: up to the deepest surface of
    // the pixels within one column of it, plus the slice the trilinear look-up blends.
    let mut deepest = vec![0.0f32; (size.x * size.y) as usize];
    for (i, d) in depths.iter().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let cx = ((x as f32 + 0.5) / w as f32 * size.x as f32) as u32;
        let cy = ((y as f32 + 0.5) / h as f32 * size.y as f32) as u32;
        for ny in cy.saturating_sub(1)..=(cy + 1).min(size.y - 1) {
            for nx in cx.saturating_sub(1)..=(cx + 1).min(size.x - 1) {
                let k = (ny * size.x + nx) as usize;
                deepest[k] = deepest[k].max(*d);
            }
        }
    }
    let live: Vec<u32> = deepest
        .iter()
        .map(|&d| {
            let s = slice_coord(d, froxels.near, froxels.far, froxels.curve) * size.z as f32;
            (s.floor() as u32 + 2).min(size.z)
        })
        .collect();

    // One light at a time: the sun (if any), then each lamp.
    let mut terms: Vec<(FogLighting, &[FogLight], Occluded)> = Vec::new();
    let dark_sun = FogLighting {
        sun: volfog::uniforms::DirectionalLight {
            color: Vec3::ZERO,
            ..u.lighting.sun
        },
        light_count: 0,
        ..u.lighting
    };
    if scene.sun.is_some() {
        let lighting = FogLighting {
            light_count: 0,
            ..u.lighting
        };
        terms.push((lighting, &[], Occluded::Sun(sun.direction)));
    }
    for l in lights.chunks(1) {
        let lighting = FogLighting {
            light_count: 1,
            ..dark_sun
        };
        terms.push((lighting, l, Occluded::Lamp(l[0].position)));
    }
    let mut options_inject = config.inject_options();
    options_inject.jitter = false;
    options_inject.local_shadows = false;
    options_inject.checkerboard = false;
    let inject = |lighting: &FogLighting, lights: &[FogLight], id: UVec3| {
        froxel_scattering(
            &InjectInputs {
                froxels: &froxels,
                frame: &u.frame,
                medium: &u.medium,
                lighting,
                cascades: &u.cascades,
                esm: &[],
                shadow_taps: &u.shadow_taps,
                lights,
                local_volumes: &volumes,
                options: options_inject,
                density_texture: None,
                noise_texture: None,
                clouds: None,
                local_shadows: None,
                scene_depth: None,
                medium_shadow: None,
            },
            id,
        )
    };
    let boxes = &scene.occluders;
    let column = |x: u32, y: u32, out: &mut Vec<Vec4>, sampled: &mut usize| {
        for z in 0..live[(y * size.x + x) as usize] {
            let id = UVec3::new(x, y, z);
            let world_at = |offset: Vec3| {
                let v = froxel_view_position(
                    id,
                    offset,
                    size,
                    froxels.view_from_clip,
                    froxels.near,
                    froxels.far,
                    froxels.curve,
                );
                u.frame.world_from_view.transform_point3(v)
            };
            let mut sum = Vec4::ZERO;
            if terms.is_empty() {
                sum = inject(&dark_sun, &[], id);
            }
            for (lighting, l, light) in &terms {
                let s = inject(lighting, l, id);
                let (v, sub) = froxel_visibility(*light, boxes, world_at);
                *sampled += usize::from(sub);
                sum = (sum.truncate() + s.truncate() * v).extend(s.w);
            }
            out.push(sum);
        }
    };

    // Rows of columns on every core; each row's froxels in (x, z) order.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let rows: Vec<(Vec<Vec4>, usize)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let column = &column;
                s.spawn(move || {
                    (t..size.y)
                        .step_by(threads as usize)
                        .map(|y| {
                            let (mut out, mut sampled) = (Vec::new(), 0);
                            for x in 0..size.x {
                                column(x, y, &mut out, &mut sampled);
                            }
                            (y, out, sampled)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut rows: Vec<(u32, Vec<Vec4>, usize)> = handles
            .into_iter()
            .flat_map(|h| h.join().expect("a floor thread panicked"))
            .collect();
        rows.sort_by_key(|r| r.0);
        rows.into_iter().map(|(_, out, n)| (out, n)).collect()
    });
    let mut medium_volume = vec![Vec4::ZERO; (size.x * size.y * size.z) as usize];
    let (mut computed, mut sampled) = (0, 0);
    for (y, (values, n)) in rows.iter().enumerate() {
        let mut values = values.iter();
        for x in 0..size.x {
            for z in 0..live[(y as u32 * size.x + x) as usize] {
                let i = ((z * size.y + y as u32) * size.x + x) as usize;
                medium_volume[i] = *values.next().expect("one value per live froxel");
                computed += 1;
            }
        }
        sampled += n;
    }
    let volume = Volume {
        size: size.to_array(),
        texels: cpu_scan(config.scan_step, &froxels, &medium_volume),
    };
    let fog: Vec<Vec4> = (0..w * h)
        .map(|i| {
            let uv = Vec2::new(
                ((i % w) as f32 + 0.5) / w as f32,
                ((i / w) as f32 + 0.5) / h as f32,
            );
            volume.fog(fog_coord(uv, depths[i as usize], &froxels))
        })
        .collect();
    Ok(GridFloor {
        image: TruthImage {
            width: w,
            height: h,
            radiance: fog.iter().map(|f| f.truncate()).collect(),
            transmittance: fog.iter().map(|f| Vec3::splat(f.w)).collect(),
        },
        froxels: computed,
        sampled,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visibility_is_exact_away_from_boundaries_and_sampled_across_them() {
        // A roof over x < 0 at y in [5, 8]; the sun straight up.
        let roof = [TruthBox {
            min: Vec3::new(-100.0, 5.0, -100.0),
            max: Vec3::new(0.0, 8.0, 100.0),
        }];
        let sun = Occluded::Sun(Vec3::Y);
        // A froxel of 1 m around `c`.
        let at = |c: Vec3| move |o: Vec3| c + o;
        assert_eq!(
            froxel_visibility(sun, &roof, at(Vec3::new(5.0, 0.0, 0.0))),
            (1.0, false)
        );
        assert_eq!(
            froxel_visibility(sun, &roof, at(Vec3::new(-5.0, 0.0, 0.0))),
            (0.0, false)
        );
        // The edge x = 0 through the froxel at x = 0.25: a quarter of the points
        // (x < 0: the first of four columns) are dark.
        let (v, sampled) = froxel_visibility(sun, &roof, at(Vec3::new(0.25, 0.0, 0.0)));
        assert!(sampled);
        assert_eq!(v, 0.75);
        // A lamp above the roof's edge at (0, 10, 0): the froxel straight below it at
        // x = 0.25 is crossed by the edge's shadow too, one farther right is lit.
        let lamp = Occluded::Lamp(Vec3::new(0.0, 10.0, 0.0));
        let (v, sampled) = froxel_visibility(lamp, &roof, at(Vec3::new(0.25, 0.0, 0.0)));
        assert!(sampled && v > 0.0 && v < 1.0, "{v}");
        assert_eq!(
            froxel_visibility(lamp, &roof, at(Vec3::new(10.0, 0.0, 0.0))),
            (1.0, false)
        );
        // Inside the roof: dark.
        assert_eq!(
            froxel_visibility(sun, &roof, at(Vec3::new(-5.0, 6.5, 0.0))),
            (0.0, false)
        );
        // A froxel reaching into the ground (y < 0) in the open: the points below its
        // face (the lowest of four rows) are left out, the others lit.
        let ground = [TruthBox {
            min: Vec3::new(-100.0, -1.0, -100.0),
            max: Vec3::new(100.0, 0.0, 100.0),
        }];
        let (v, sampled) = froxel_visibility(sun, &ground, at(Vec3::new(5.0, 0.25, 0.0)));
        assert!(sampled);
        assert_eq!(v, 1.0);
        // Under the roof's edge as well: of the 48 points above the ground, the 12 of
        // x < 0 are dark.
        let both = [roof[0], ground[0]];
        let (v, sampled) = froxel_visibility(sun, &both, at(Vec3::new(0.25, 0.25, 0.0)));
        assert!(sampled);
        assert_eq!(v, 0.75);
    }
}
