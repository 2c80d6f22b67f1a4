//! The compare filter over frames (`ShadowFilter::Compare`): the taps the fused
//! temporal blend takes with and without history against the CPU mirror, the
//! visibility it converges to against the exact visibility averaged over each froxel
//! (from the occluder's geometry, not its shadow map), and how far a moving shadow's
//! edge lags behind, beside the ESM filter.
//!
//! The scenes: homogeneous isotropic fog without ambient light or light transmittance
//! under an overhead sun, so a froxel's in-scattering is a constant times its sun
//! visibility, and a slab above part of the view casts the shadow.

use crate::common::gpu;
use crate::common::scene::*;
use glam::{UVec3, Vec3, Vec4};
use volfog::cpu::ambient::AmbientSh;
use volfog::cpu::froxel::froxel_view_position;
use volfog::cpu::inject::{InjectInputs, froxel_scattering_taps};
use volfog::options::ShadowFilter;
use volfog::pipeline::{FogConfig, FrameInputs, FrameUniforms, VolumetricFog};
use volfog::uniforms::{DirectionalLight, FogMedium, ShadowCascades};

/// Sun irradiance (per channel).
const SUN: f32 = 4.0;
/// Fog extinction (1/m), albedo 1.
const DENSITY: f32 = 0.03;

fn config(filter: ShadowFilter) -> FogConfig {
    FogConfig {
        shadow_filter: filter,
        jitter: true,
        temporal: true,
        light_transmittance: false,
        depth_cull: false,
        ..small_config()
    }
}

fn medium() -> FogMedium {
    FogMedium {
        albedo: Vec3::ONE,
        density: DENSITY,
        height_falloff: 0.0,
        noise_strength: 0.0,
        phase_g: 0.0,
        ..FogMedium::default()
    }
}

fn frame(cascades: ShadowCascades, time: f32) -> FrameInputs<'static> {
    FrameInputs {
        medium: medium(),
        sun: DirectionalLight {
            direction: Vec3::Y,
            color: Vec3::splat(SUN),
            ..DirectionalLight::default()
        },
        ambient: AmbientSh::constant(Vec3::ZERO),
        cascades,
        ..FrameInputs::new(view(3.0, 0.0), projection(), time)
    }
}

/// A froxel's sun visibility from its in-scattering: sigma_s E p with p = 1 / (4 pi).
fn visibility(v: Vec4) -> f32 {
    v.x / (DENSITY * SUN / (4.0 * std::f32::consts::PI))
}

/// Whether a world point lies in the slab's shadow (the sun straight overhead).
fn under(slab: &Slab, p: Vec3) -> bool {
    p.x > slab.x.0 && p.x < slab.x.1 && p.z > slab.z.0 && p.z < slab.z.1 && p.y < slab.top
}

/// The exact sun visibility averaged over froxel `id` in froxel coordinates (the space
/// the taps cover): `n`^3 points at the centres of a regular grid of its cell.
fn froxel_mean_visibility(u: &FrameUniforms, slab: &Slab, id: UVec3, n: u32) -> f32 {
    let f = &u.froxels;
    let mut lit = 0;
    for k in 0..n * n * n {
        let o = (Vec3::new((k % n) as f32, (k / n % n) as f32, (k / (n * n)) as f32) + 0.5)
            / n as f32
            - 0.5;
        let view = froxel_view_position(id, o, f.size, f.view_from_clip, f.near, f.far, f.curve);
        if !under(slab, u.frame.world_from_view.transform_point3(view)) {
            lit += 1;
        }
    }
    lit as f32 / (n * n * n) as f32
}

/// Runs `frames` frames of a still camera with the slab's shadow map and returns the
/// last stabilised volume.
fn converge(filter: ShadowFilter, slab: Slab, frames: u32) -> (FogConfig, Vec<Vec4>) {
    let gpu = gpu();
    let config = config(filter);
    let (cascades, layers) = overhead_sun(&config, Some(slab));
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
        .unwrap();
    let mut last = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        frames,
        |f| frame(cascades, f as f32),
        |f, fog| {
            if f + 1 == frames {
                last = read_volume(gpu, fog.stabilised_texture().expect("temporal"));
            }
        },
    );
    (config, last)
}

/// The fused blend takes `ShadowTaps::fresh` taps where a froxel has no history (every
/// froxel of the first frame) and `ShadowTaps::count` where it has: frame 0 against the
/// CPU mirror with four taps, frame 1 (a still camera) against the mirror with one tap
/// blended with frame 0's volume.
#[test]
fn fused_blend_takes_more_taps_where_history_is_missing() {
    let gpu = gpu();
    let config = config(ShadowFilter::Compare { taps: 1 });
    let (cascades, layers) = overhead_sun(&config, Some(SLAB));
    let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
    fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
        .unwrap();
    let mut volumes = Vec::new();
    run_frames(
        gpu,
        &mut fog,
        2,
        |f| frame(cascades, f as f32),
        |_, fog| volumes.push(read_volume(gpu, fog.stabilised_texture().unwrap())),
    );
    let size = config.volume_size;
    let mirror = |f: u32, taps: u32| -> Vec<Vec4> {
        let inputs = frame(cascades, f as f32);
        let u = expected_uniforms(&config, &inputs, f);
        let cpu = InjectInputs {
            froxels: &u.froxels,
            frame: &u.frame,
            medium: &u.medium,
            lighting: &u.lighting,
            cascades: &u.cascades,
            esm: &layers,
            shadow_taps: &u.shadow_taps,
            lights: &[],
            local_volumes: &[],
            options: config.inject_options(),
            density_texture: None,
            noise_texture: None,
            clouds: None,
            local_shadows: None,
            scene_depth: None,
            medium_shadow: None,
        };
        let mut out = vec![Vec4::ZERO; (size.x * size.y * size.z) as usize];
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    out[index(size, x, y, z)] =
                        froxel_scattering_taps(&cpu, UVec3::new(x, y, z), taps);
                }
            }
        }
        out
    };
    let scale = DENSITY * SUN / (4.0 * std::f32::consts::PI);
    let worst = |got: &[Vec4], want: &[Vec4]| {
        got.iter()
            .zip(want)
            .map(|(g, w)| (*g - *w).truncate().abs().max_element() / scale)
            .fold(0.0f32, f32::max)
    };
    let (fresh, one) = (mirror(0, 4), mirror(0, 1));
    let first = worst(&volumes[0], &fresh);
    let first_one = worst(&volumes[0], &one);
    let w = config.history_weight;
    let blended: Vec<Vec4> = mirror(1, 1)
        .iter()
        .zip(&volumes[0])
        .map(|(now, past)| *now * (1.0 - w) + *past * w)
        .collect();
    let second = worst(&volumes[1], &blended);
    eprintln!(
        "fused compare filter: frame 0 vs the mirror with 4 taps {first:.2e} (with 1 tap {first_one:.2e}), frame 1 vs 1 tap blended with frame 0 {second:.2e} (of the unshadowed term; bound 2e-3)"
    );
    assert!(first <= 2e-3 && second <= 2e-3, "{first} {second}");
    // The tap count matters in this scene: one tap instead of four misses.
    assert!(first_one > 0.1, "{first_one}");
}

/// With a still camera the compare filter's temporal accumulation converges to the
/// sun visibility averaged over each froxel: after 64 frames, the froxels the slab's
/// edges cross against the exact mean of 8^3 points of each froxel. The ESM filter's
/// blur and leak band keep it far from that mean.
#[test]
fn compare_filter_converges_to_the_froxel_mean_visibility() {
    let slab = SLAB;
    let mut errors = Vec::new();
    for filter in [ShadowFilter::Compare { taps: 1 }, ShadowFilter::Esm] {
        let (config, volume) = converge(filter, slab, 64);
        let inputs = frame(ShadowCascades::default(), 63.0);
        let u = expected_uniforms(&config, &inputs, 63);
        let size = config.volume_size;
        let (mut sum, mut worst, mut partial) = (0.0f64, 0.0f32, 0);
        let mut sum_all = 0.0f64;
        for z in 0..size.z {
            for y in 0..size.y {
                for x in 0..size.x {
                    let id = UVec3::new(x, y, z);
                    let exact = froxel_mean_visibility(&u, &slab, id, 8);
                    let got = visibility(volume[index(size, x, y, z)]);
                    let e = (got - exact).abs();
                    sum_all += f64::from(e);
                    if exact > 0.02 && exact < 0.98 {
                        partial += 1;
                        sum += f64::from(e);
                        worst = worst.max(e);
                    }
                }
            }
        }
        let mean = sum / f64::from(partial);
        let mean_all = sum_all / f64::from(size.x * size.y * size.z);
        eprintln!(
            "{filter:?} after 64 still frames: sun visibility vs the exact froxel mean over {partial} froxels the shadow's edges cross: mean {mean:.3}, worst {worst:.3}; over all froxels mean {mean_all:.4}"
        );
        errors.push((mean, worst, mean_all));
    }
    let (compare, esm) = (errors[0], errors[1]);
    // Bounds. The temporal blend weights one 16-frame cycle of tap positions
    // 0.1 0.9^k / (1 - 0.9^16), from 0.123 down to 0.025, instead of 1/16 each: a froxel
    // whose points are lit in some frames and not in others ends up to 0.20 (half the
    // L1 distance of those weights from uniform) and typically 0.05 (their standard
    // deviation for an even split) from the mean of its 16 points; those 16 points
    // stand for the froxel's volume within about 1/16 at a straight edge, and the 2 x 2
    // filter blurs the map's edge over a texel (0.14 to 0.27 m, a tenth to a fifth of a
    // froxel here). Hence at most 0.3 per froxel and 0.1 on average where the edges
    // cross; froxels the edges miss are exact.
    assert!(compare.0 <= 0.1, "mean {}", compare.0);
    assert!(compare.1 <= 0.3, "worst {}", compare.1);
    assert!(compare.2 <= 0.01, "mean over all froxels {}", compare.2);
    assert!(
        esm.0 > 2.0 * compare.0,
        "the ESM's mean {} is not worse",
        esm.0
    );
}

/// A shadow edge moving one froxel per frame: the slab's edge slides along x at the
/// speed that crosses one froxel column per frame at 20 m; after 40 frames, the
/// column where the fog at that depth is half lit trails where it lies with the edge
/// held still there by what the temporal blend keeps of the past (its median age is
/// ln 2 / -ln(0.9) = 6.6 frames), with either filter, and by no more than one history
/// time constant (1 / (1 - 0.9) = 10 frames = 10 froxels).
#[test]
fn a_moving_shadow_lags_at_most_one_time_constant() {
    let gpu = gpu();
    let mut lags = Vec::new();
    for filter in [ShadowFilter::Compare { taps: 1 }, ShadowFilter::Esm] {
        // 64 columns, so the edge stays in view for 40 frames.
        let config = FogConfig {
            volume_size: UVec3::new(64, 18, 48),
            ..config(filter)
        };
        let size = config.volume_size;
        let frames = 40;
        let inputs = frame(ShadowCascades::default(), 0.0);
        let u = expected_uniforms(&config, &inputs, 0);
        // The slice at 20 m and the row below the slab's top (the camera is 3 m up).
        let depth = 20.0;
        let t =
            volfog::cpu::froxel::slice_coord(depth, config.near, config.far, config.slice_curve);
        let z = (t * size.z as f32) as u32;
        let column_x = |x: f32| {
            let f = &u.froxels;
            let centre = froxel_view_position(
                UVec3::new(0, size.y / 2, z),
                Vec3::ZERO,
                f.size,
                f.view_from_clip,
                f.near,
                f.far,
                f.curve,
            );
            let next = froxel_view_position(
                UVec3::new(1, size.y / 2, z),
                Vec3::ZERO,
                f.size,
                f.view_from_clip,
                f.near,
                f.far,
                f.curve,
            );
            // World x of column coordinate x (0 at the centre of column 0) at this depth.
            centre.x + (next.x - centre.x) * x
        };
        let width = column_x(1.0) - column_x(0.0);
        // The edge starts between columns 1 and 2 and moves a column per frame.
        let edge = |f: u32| column_x(2.0 + f as f32 - 0.5);
        // Wide in z, so the ESM's blur (11 ESM texels, 12 m in cascade 1) sees the
        // slab alone and casts a full shadow too.
        let slab_at = |f: u32| Slab {
            x: (edge(f), 80.0),
            z: (-depth - 25.0, -depth + 15.0),
            top: 7.0,
        };
        let (cascades, _) = overhead_sun(&config, None);
        let last = frames - 1;
        // The half-lit column of the row after the frames, the edge moving or held
        // where the moving one ends.
        let crossing = |moving: bool| {
            let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
            for f in 0..frames {
                let at = if moving { f } else { last };
                let (_, layers) = overhead_sun(&config, Some(slab_at(at)));
                fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
                    .unwrap();
                fog.prepare(&gpu.queue, &frame(cascades, f as f32)).unwrap();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                fog.encode(&mut encoder).unwrap();
                gpu.queue.submit([encoder.finish()]);
            }
            let volume = read_volume(gpu, fog.stabilised_texture().unwrap());
            // Columns left of the edge are lit (1), right of it shadowed (0).
            let row: Vec<f32> = (0..size.x)
                .map(|x| visibility(volume[index(size, x, size.y / 2, z)]))
                .collect();
            // Where the lit fraction falls through the middle of its lit and shadowed
            // levels, scanning from the lit side.
            let (high, low) = (row[0], row[size.x as usize - 1]);
            assert!(
                high - low > 0.9,
                "{filter:?}: the row is lit from {low} to {high}"
            );
            let mid = 0.5 * (high + low);
            (1..size.x as usize)
                .find(|&x| row[x - 1] >= mid && row[x] < mid)
                .map(|x| x as f32 - 1.0 + (row[x - 1] - mid) / (row[x - 1] - row[x]))
                .expect("the row crosses its middle level")
        };
        let (still, moving) = (crossing(false), crossing(true));
        // The filter's own offset of the edge (the ESM's blur and leak) is in both.
        let lag = still - moving;
        eprintln!(
            "{filter:?}: a shadow edge moving {width:.2} m (one froxel) per frame at {depth} m: after {frames} frames the half-lit point trails it by {lag:.2} froxels (frames); held still, the half-lit point sits {:.2} froxels from the edge",
            still - (2.0 + last as f32 - 0.5)
        );
        lags.push(lag);
    }
    for lag in &lags {
        assert!(*lag <= 10.0 && *lag >= 0.0, "{lag}");
    }
}

/// The ray through screen position `uv` (v down) of a camera at `view`, `projection`:
/// its origin and unit direction in world space.
fn screen_ray(view: glam::Mat4, projection: glam::Mat4, uv: glam::Vec2) -> (Vec3, Vec3) {
    let world_from_view = view.inverse();
    let eye = world_from_view.transform_point3(Vec3::ZERO);
    let ndc = glam::Vec2::new(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
    let target = projection.inverse().project_point3(ndc.extend(0.5));
    (
        eye,
        (world_from_view.transform_point3(target) - eye).normalize(),
    )
}

/// Where the ray through screen position `uv` meets the ground plane (y = 0), if it
/// does.
fn ground_hit(view: glam::Mat4, projection: glam::Mat4, uv: glam::Vec2) -> Option<Vec3> {
    let (eye, dir) = screen_ray(view, projection, uv);
    (dir.y < -1e-4).then(|| eye - dir * (eye.y / dir.y))
}

/// Device depths of a ground plane (y = 0) seen through `view` and `projection` at
/// `size` pixels (the far plane's 1 where the ray misses it).
fn ground_depth(view: glam::Mat4, projection: glam::Mat4, size: (u32, u32)) -> Vec<f32> {
    let (w, h) = size;
    let mut out = Vec::with_capacity((w * h) as usize);
    for py in 0..h {
        for px in 0..w {
            let uv = glam::Vec2::new((px as f32 + 0.5) / w as f32, (py as f32 + 0.5) / h as f32);
            out.push(match ground_hit(view, projection, uv) {
                Some(p) => projection
                    .project_point3(view.transform_point3(p))
                    .z
                    .clamp(0.0, 1.0),
                None => 1.0,
            });
        }
    }
    out
}

/// The fog over an open ground in sunlight is lit down to the ground: the sun's
/// shadow map holds the ground, so a tap below it reads the ground's own shadow; with
/// the scene's depth set (depth culling) the compare filter moves every tap of a
/// froxel the ground cuts into the part in front of the ground, and such froxels are
/// wholly lit (four taps, no temporal blend). Without the scene depth they come out
/// partly dark. The pass interpolates the depth between texel centres, which is exact
/// on a plane: the check takes the froxels whose near face lies in front of the ground
/// along every tap's ray and whose taps' four nearest depth texels all hold the ground
/// (not the sky beyond the horizon), computed here from the plane.
#[test]
fn taps_below_the_visible_surface_are_moved_in_front() {
    let gpu = gpu();
    let config = FogConfig {
        shadow_filter: ShadowFilter::Compare { taps: 1 },
        jitter: false,
        temporal: false,
        light_transmittance: false,
        depth_cull: true,
        ..small_config()
    };
    let ground = Slab {
        x: (-1.0e4, 1.0e4),
        z: (-1.0e4, 1.0e4),
        top: 0.0,
    };
    let (cascades, layers) = overhead_sun(&config, Some(ground));
    let (view, projection) = (view(2.0, -0.35), projection());
    let size = (203u32, 117u32);
    let depth = volfog_testkit::selfcheck::depth_texture(
        gpu,
        size.0,
        size.1,
        &ground_depth(view, projection, size),
    )
    .unwrap();
    let inputs = FrameInputs {
        medium: medium(),
        sun: frame(cascades, 0.0).sun,
        ambient: AmbientSh::constant(Vec3::ZERO),
        cascades,
        ..FrameInputs::new(view, projection, 0.0)
    };
    let run = |with_depth: bool| {
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.set_shadow_map(&gpu.device, &shadow_map(gpu, &layers))
            .unwrap();
        if with_depth {
            fog.set_scene_depth(&gpu.device, &depth, 0).unwrap();
        }
        let mut out = Vec::new();
        run_frames(
            gpu,
            &mut fog,
            1,
            |_| inputs.clone(),
            |_, fog| {
                out = read_volume(gpu, fog.scattering_texture());
            },
        );
        out
    };
    let (with, without) = (run(true), run(false));
    let u = expected_uniforms(&config, &inputs, 0);
    let camera = u.frame.camera_position;
    let s = config.volume_size;
    let texels = glam::Vec2::new(size.0 as f32, size.1 as f32);
    // The view depth (m) at which the ray through uv meets the ground.
    let ground_at = |uv: glam::Vec2| {
        ground_hit(view, projection, uv).map_or(f32::INFINITY, |p| -view.transform_point3(p).z)
    };
    let (mut sorted, mut straddling, mut worst, mut darkened) = (0, 0, 0.0f32, 0);
    for z in 0..s.z {
        let near_face = volfog::cpu::froxel::slice_depth(
            z as f32 / s.z as f32,
            config.near,
            config.far,
            config.slice_curve,
        );
        for y in 0..s.y {
            for x in 0..s.x {
                let id = UVec3::new(x, y, z);
                // Per tap: its view depth, where its ray meets the ground, and whether
                // the rays of its four nearest depth texels meet the ground.
                let taps: Vec<(f32, f32, bool)> = (0..u.shadow_taps.count)
                    .map(|t| {
                        let offset = u.shadow_taps.offsets[t as usize].truncate();
                        let (_, depth) = volfog::cpu::shadow::shadow_tap_world(
                            &u.froxels,
                            &u.shadow_taps,
                            camera,
                            id,
                            offset,
                        );
                        let uv = (id.as_vec3().truncate() + 0.5 + offset.truncate())
                            / s.as_vec3().truncate();
                        let base = (uv * texels - 0.5).floor();
                        let ground = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].iter().all(
                            |&(dx, dy)| {
                                let texel = (base + glam::Vec2::new(dx, dy))
                                    .clamp(glam::Vec2::ZERO, texels - 1.0);
                                ground_at((texel + 0.5) / texels).is_finite()
                            },
                        );
                        (depth, ground_at(uv), ground)
                    })
                    .collect();
                if !taps
                    .iter()
                    .all(|&(_, own, ground)| ground && near_face < own)
                {
                    continue;
                }
                let i = index(s, x, y, z);
                sorted += 1;
                worst = worst.max((visibility(with[i]) - 1.0).abs());
                if taps.iter().any(|&(depth, own, _)| depth > own) {
                    straddling += 1;
                    darkened += usize::from(visibility(without[i]) < 0.9);
                }
            }
        }
    }
    eprintln!(
        "open ground under the sun: {sorted} froxels whose near face lies in front of the ground along their taps' rays, over ground texels: sun visibility within {worst:.1e} of 1 with the scene depth (bound 2e-3); of the {straddling} the ground cuts, {darkened} below 0.9 without the scene depth"
    );
    assert!(sorted > 1000 && straddling > 50, "{sorted} {straddling}");
    assert!(worst <= 2e-3, "{worst}");
    assert!(darkened * 2 > straddling, "{darkened} of {straddling}");
}
