//! The scene as the fog shaders' loops see it, on the CPU: the depth of every pixel
//! (the scene's boxes and ground, ray cast: the glass sphere is alpha-blended and
//! writes no depth), and how many times each loop of Bevy's fog shader runs per wave.
//!
//! Bevy's fragment shader (`bevy_pbr-0.20.1/src/volumetric_fog/volumetric_fog.wesl`,
//! `fragment`) clips the pixel's ray from the near plane to the fog volume's box, ends
//! it at the depth buffer, and marches it twice in `step_count` equal steps of view
//! depth: once per volumetric directional light (the shadow map's cascade found by
//! `get_cascade_index`'s loop over the cascades, `render/shadows.wesl`), then once for
//! the point and spot lights of the cluster each step falls in (the loop over the
//! cluster's point and spot lights, `render/clustered_forward.wesl` for the cluster's
//! index). A march stops early when the transmittance falls below 0.001.
//!
//! A wave is taken as an 8 x 8 block of pixels (64 fragments, RADV's wave64), sampled
//! at its four corners and its centre; a wave runs a loop until its last invocation
//! leaves it, so each count is the most of the sampled pixels at each step.

use bevy::light::cluster::assign::calculate_cluster_factors;
use bevy::prelude::*;

use crate::capture::BevyFog;
use crate::scene;

/// Half the side of the scene's ground plane (m): `Plane3d` of 600 x 600 at the origin.
const GROUND_HALF: f32 = 300.0;
/// Bevy's march stops when the transmittance falls below this.
const MIN_TRANSMITTANCE: f32 = 0.001;

/// The scene's depth at every pixel of a screen.
pub struct Depth {
    pub width: u32,
    pub height: u32,
    /// View depth (m) of the nearest opaque surface along each pixel's centre ray;
    /// infinite where the ray sees the sky.
    pub view_depth: Vec<f32>,
    /// The depth buffer's value there (`clip_from_view`'s z / w; 0 for the sky under
    /// Bevy's reverse-Z infinite projection).
    pub ndc: Vec<f32>,
}

/// The view-space point of a pixel-centre NDC position (`position_ndc_to_view`).
fn ndc_to_view(view_from_clip: Mat4, ndc: Vec3) -> Vec3 {
    let p = view_from_clip * ndc.extend(1.0);
    p.truncate() / p.w
}

/// The NDC xy of pixel (x, y)'s centre (`frag_coord_to_ndc`).
fn pixel_ndc(x: u32, y: u32, screen: (u32, u32)) -> Vec2 {
    let uv = Vec2::new(
        (x as f32 + 0.5) / screen.0 as f32,
        (y as f32 + 0.5) / screen.1 as f32,
    );
    Vec2::new(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y)
}

/// The scene's depth at `screen` seen by a camera `world_from_view`, `clip_from_view`.
pub fn scene_depth(world_from_view: Mat4, clip_from_view: Mat4, screen: (u32, u32)) -> Depth {
    let view_from_clip = clip_from_view.inverse();
    let view_from_world = world_from_view.inverse();
    let eye = world_from_view.transform_point3(Vec3::ZERO);
    let boxes = scene::boxes();
    // Each box's screen rectangle (pixels, inclusive), from its corners; the whole
    // screen when a corner is not in front of the camera.
    let rects: Vec<[f32; 4]> = boxes
        .iter()
        .map(|b| {
            let mut r = [
                f32::INFINITY,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::NEG_INFINITY,
            ];
            for i in 0..8 {
                let s = Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                let v = view_from_world.transform_point3(b.center + b.rotation * (b.half * s));
                if v.z > -1e-3 {
                    return [
                        f32::NEG_INFINITY,
                        f32::NEG_INFINITY,
                        f32::INFINITY,
                        f32::INFINITY,
                    ];
                }
                let c = clip_from_view * v.extend(1.0);
                let px = (c.x / c.w * 0.5 + 0.5) * screen.0 as f32;
                let py = (0.5 - c.y / c.w * 0.5) * screen.1 as f32;
                r = [r[0].min(px), r[1].min(py), r[2].max(px), r[3].max(py)];
            }
            [r[0] - 1.0, r[1] - 1.0, r[2] + 1.0, r[3] + 1.0]
        })
        .collect();
    let n = (screen.0 * screen.1) as usize;
    let (mut view_depth, mut ndc) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for y in 0..screen.1 {
        for x in 0..screen.0 {
            let v = ndc_to_view(view_from_clip, pixel_ndc(x, y, screen).extend(0.5)).normalize();
            let dir = world_from_view.transform_vector3(v);
            let mut t = f32::INFINITY;
            if dir.y < 0.0 {
                let g = -eye.y / dir.y;
                let p = eye + dir * g;
                if p.x.abs() <= GROUND_HALF && p.z.abs() <= GROUND_HALF {
                    t = g;
                }
            }
            let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
            for (b, r) in boxes.iter().zip(&rects) {
                if fx >= r[0] && fx <= r[2] && fy >= r[1] && fy <= r[3] {
                    t = t.min(b.hit(eye, dir).unwrap_or(f32::INFINITY));
                }
            }
            if t.is_finite() {
                let p = v * t;
                let c = clip_from_view * p.extend(1.0);
                view_depth.push(-p.z);
                ndc.push(c.z / c.w);
            } else {
                view_depth.push(f32::INFINITY);
                ndc.push(0.0);
            }
        }
    }
    Depth {
        width: screen.0,
        height: screen.1,
        view_depth,
        ndc,
    }
}

/// How often the loops of Bevy's fog shader run in the scene, per wave.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct BevyTrips {
    /// Waves (8 x 8 blocks) of the screen, and those with a pixel that marches.
    pub waves: u64,
    pub marching_waves: u64,
    /// Iterations of the directional light loop per wave.
    pub directional_lights: f64,
    /// Steps of the directional march per wave and light.
    pub sun_steps: f64,
    /// Iterations of `get_cascade_index`'s loop per wave and step.
    pub cascade_search: f64,
    /// Steps of the point and spot light march per wave.
    pub light_steps: f64,
    /// Point and spot lights of the step's cluster per wave and step (the loop's
    /// trips).
    pub cluster_lights: f64,
    /// The same samples' lights whose range (and, for a spot, cone) holds the sample:
    /// what a cluster must list at least.
    pub lights_reaching: f64,
    /// Of those, the lights with a `VolumetricLight`: the iterations that light the
    /// fog (the loop skips the others after reading their flags).
    pub volumetric_reaching: f64,
    /// Samples (pixel and step) whose cluster lists fewer lights than reach them.
    pub under_listed: u64,
    pub samples: u64,
}

/// One pixel's ray through the fog volume, as Bevy's shader marches it.
struct Ray {
    start_view: Vec3,
    dir_view: Vec3,
    start_world: Vec3,
    dir_world: Vec3,
    step: f32,
    steps: u32,
}

fn ray(fog: &BevyFog, depth: &Depth, x: u32, y: u32) -> Ray {
    let view_from_clip = fog.clip_from_view.inverse();
    let ndc = pixel_ndc(x, y, fog.screen);
    let ro = ndc_to_view(view_from_clip, ndc.extend(1.0));
    let rd = (ndc_to_view(view_from_clip, ndc.extend(0.5)) - ro).normalize();
    let local_from_view = fog.local_from_world * fog.world_from_view;
    let (o, d) = (
        local_from_view.transform_point3(ro),
        local_from_view.transform_vector3(rd),
    );
    let (mut t_enter, mut t_exit, mut misses) = (0.0f32, f32::MAX, false);
    for a in 0..3 {
        if d[a].abs() < 1e-9 {
            misses |= o[a].abs() > 0.5;
            continue;
        }
        let (t0, t1) = ((-0.5 - o[a]) / d[a], (0.5 - o[a]) / d[a]);
        t_enter = t_enter.max(t0.min(t1));
        t_exit = t_exit.min(t0.max(t1));
    }
    let start_view = ro + rd * t_enter;
    let dir_world = fog.world_from_view.transform_vector3(rd).normalize();
    let start_world = fog.world_from_view.transform_point3(start_view);
    let mut r = Ray {
        start_view,
        dir_view: rd,
        start_world,
        dir_world,
        step: 0.0,
        steps: 0,
    };
    if misses || t_exit <= t_enter {
        return r;
    }
    let end = (-(ro + rd * t_exit).z).min(depth.view_depth[(y * depth.width + x) as usize]);
    let length = (end - -start_view.z).max(0.0);
    if length == 0.0 {
        return r;
    }
    r.step = length / fog.step_count as f32;
    // The march breaks at the first step whose transmittance so far is below 0.001.
    let per_step = r.step * fog.extinction;
    let limit = -MIN_TRANSMITTANCE.ln();
    r.steps = if per_step * fog.step_count as f32 <= limit {
        fog.step_count
    } else {
        ((limit / per_step).floor() as u32 + 1).min(fog.step_count)
    };
    r
}

/// Lights of the scene whose range (and cone) holds `p`, and how many of them are
/// volumetric.
fn lights_reaching(fog: &BevyFog, p: Vec3) -> (u32, u32) {
    fog.lights
        .iter()
        .filter(|l| {
            let to = p - l.position;
            to.length() < l.range
                && l.spot
                    .is_none_or(|(dir, angle)| to.normalize_or_zero().dot(dir) >= angle.cos())
        })
        .fold((0, 0), |(n, v), l| (n + 1, v + u32::from(l.volumetric)))
}

/// The trip counts of Bevy's fog loops over `depth`'s screen (which must be the
/// capture's).
pub fn bevy_trips(fog: &BevyFog, depth: &Depth) -> BevyTrips {
    let c = &fog.clusters;
    let factors = calculate_cluster_factors(c.near, c.far, c.dimensions.z as f32, false);
    let total = (c.dimensions.x * c.dimensions.y * c.dimensions.z) as usize;
    let cluster_lights = |x: u32, y: u32, view_z: f32| -> u32 {
        let cx = ((x as f32 + 0.5) * c.dimensions.x as f32 / fog.screen.0 as f32).floor() as u32;
        let cy = ((y as f32 + 0.5) * c.dimensions.y as f32 / fog.screen.1 as f32).floor() as u32;
        // `u32(f32)` saturates: a slice below 0 is 0.
        let z = ((-view_z).ln() * factors.x - factors.y + 1.0).max(0.0) as u32;
        let z = z.min(c.dimensions.z - 1);
        let index = (((cy * c.dimensions.x + cx) * c.dimensions.z + z) as usize).min(total - 1);
        c.lights[index]
    };
    let cascades = fog.cascade_bounds.len() as u32;
    let cascade_iterations = |view_z: f32| -> u32 {
        fog.cascade_bounds
            .iter()
            .position(|&b| -view_z < b)
            .map_or(cascades, |i| i as u32 + 1)
    };
    // Lights are sorted volumetric first; the loop breaks at the first other one.
    let light_loop = fog.directional.min(fog.volumetric_directional + 1);
    let mut t = BevyTrips::default();
    let (mut sum_sun, mut sum_cascade, mut sum_light) = (0.0, 0.0, 0.0);
    let (mut sum_cluster, mut sum_reach, mut sum_volumetric) = (0.0, 0.0, 0.0);
    let (bw, bh) = (fog.screen.0.div_ceil(8), fog.screen.1.div_ceil(8));
    for by in 0..bh {
        for bx in 0..bw {
            t.waves += 1;
            let (x0, y0) = (bx * 8, by * 8);
            let (x1, y1) = (
                (x0 + 7).min(fog.screen.0 - 1),
                (y0 + 7).min(fog.screen.1 - 1),
            );
            let pixels = [
                (x0, y0),
                (x1, y0),
                (x0, y1),
                (x1, y1),
                ((x0 + 4).min(x1), (y0 + 4).min(y1)),
            ];
            let rays: Vec<(u32, u32, Ray)> = pixels
                .iter()
                .map(|&(x, y)| (x, y, ray(fog, depth, x, y)))
                .collect();
            let steps = rays.iter().map(|r| r.2.steps).max().unwrap_or(0);
            if steps == 0 {
                continue;
            }
            t.marching_waves += 1;
            sum_sun += f64::from(steps);
            sum_light += f64::from(steps);
            for k in 0..steps {
                let (mut cascade, mut cluster, mut reach, mut volumetric) = (0, 0, 0, 0);
                for (x, y, r) in rays.iter().filter(|r| k < r.2.steps) {
                    let along = k as f32 * r.step;
                    let view_z = (r.start_view + r.dir_view * along).z;
                    cascade = cascade.max(cascade_iterations(view_z));
                    let listed = cluster_lights(*x, *y, view_z);
                    let (reaching, lit) = lights_reaching(fog, r.start_world + r.dir_world * along);
                    cluster = cluster.max(listed);
                    reach = reach.max(reaching);
                    volumetric = volumetric.max(lit);
                    t.samples += 1;
                    t.under_listed += u64::from(listed < reaching);
                }
                sum_cascade += f64::from(cascade);
                sum_cluster += f64::from(cluster);
                sum_reach += f64::from(reach);
                sum_volumetric += f64::from(volumetric);
            }
        }
    }
    let marching = t.marching_waves.max(1) as f64;
    t.directional_lights = f64::from(light_loop) * t.marching_waves as f64 / t.waves as f64;
    // Each loop's trips per iteration of the loop around it: the directional march
    // per light of a marching wave (every light marches the same steps), the other
    // march per wave (none where no pixel marches), the inner loops per step.
    t.sun_steps = sum_sun / marching;
    t.light_steps = sum_light / t.waves as f64;
    t.cascade_search = sum_cascade / sum_sun.max(1.0);
    t.cluster_lights = sum_cluster / sum_light.max(1.0);
    t.lights_reaching = sum_reach / sum_light.max(1.0);
    t.volumetric_reaching = sum_volumetric / sum_light.max(1.0);
    t
}
