//! The demo through the `volfog` binary on the GPU at a small resolution: every pass
//! runs, the ground recedes into fog (transmittance measured per pixel falls with
//! distance, at a rate the medium allows), the fog's shadow map agrees with the
//! ground's shadows, the fog shows light shafts (sunlit columns of the froxel volume
//! scatter several times more than neighbouring columns in a pillar's shadow), the
//! semi-transparent sphere is drawn, the pool's water fogs what lies under it seen
//! from above and everything seen from the second camera under water (per pixel
//! equal to the CPU mirror of `volfog::water`), nothing is NaN, and the PNGs decode
//! at the requested size.
//!
//! The demo's `--probe` output gives linear float images of the last frame: the lit
//! surfaces before the fog (alpha: sun visibility), the image after the fullscreen
//! apply, the final image, and the same frame with every surface black (only the
//! fog's in-scattering L remains). With fogged = surface * T + L, the per-pixel
//! transmittance is T = (fogged - L) / surface.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use glam::{Mat4, UVec3, Vec3, Vec4};
use serde_json::Value;
use volfog::cpu::esm::{self, Layer};
use volfog::cpu::inject::froxel_world_position;
use volfog::uniforms::{FogFrame, Froxels, ShadowCascades};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 108;
const FRAMES: u32 = 3;

struct Run {
    dir: PathBuf,
    stdout: String,
    probe: Value,
}

/// Runs the demo once for every test in this file.
fn run() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("demo_test");
        let _ = std::fs::remove_dir_all(&dir);
        let output = Command::new(env!("CARGO_BIN_EXE_volfog"))
            .args(["demo", "--out"])
            .arg(&dir)
            .args([
                "--width",
                &WIDTH.to_string(),
                "--height",
                &HEIGHT.to_string(),
                "--frames",
                &FRAMES.to_string(),
                "--probe",
            ])
            .env("MESA_SHADER_CACHE_DISABLE", "true")
            .output()
            .expect("the volfog binary starts");
        let stdout = String::from_utf8_lossy(&output.stdout).to_string();
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        eprintln!("{stdout}");
        assert!(
            output.status.success(),
            "volfog demo failed ({}):\n{stdout}\n{stderr}",
            output.status
        );
        let text = std::fs::read_to_string(dir.join("probe/probe.json")).expect("probe.json");
        let probe = serde_json::from_str(&text).expect("probe.json parses");
        Run { dir, stdout, probe }
    })
}

fn read_f32(run: &Run, name: &str) -> Vec<f32> {
    let bytes = std::fs::read(run.dir.join("probe").join(name)).expect("probe image");
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn read_rgba(run: &Run, name: &str) -> Vec<Vec4> {
    let values = read_f32(run, name);
    assert_eq!(
        values.len(),
        (WIDTH * HEIGHT * 4) as usize,
        "{name} holds one rgba texel per pixel"
    );
    values.chunks_exact(4).map(Vec4::from_slice).collect()
}

fn mat(v: &Value) -> Mat4 {
    let cols: Vec<f32> = v
        .as_array()
        .expect("matrix array")
        .iter()
        .map(|x| x.as_f64().expect("number") as f32)
        .collect();
    Mat4::from_cols_slice(&cols)
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is a number"))
}

fn median(mut v: Vec<f32>) -> f32 {
    assert!(!v.is_empty(), "median of nothing");
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn sum3(v: Vec4) -> f32 {
    v.x + v.y + v.z
}

/// One ground pixel: world position, distance from the camera (m), surface
/// radiance, fogged radiance, in-scattering (rgb sums), sun visibility of the surface.
#[derive(Debug, Clone, Copy)]
struct GroundPixel {
    world: Vec3,
    distance: f32,
    surface: f32,
    fogged: f32,
    inscatter: f32,
    sun: f32,
}

impl GroundPixel {
    fn transmittance(&self) -> f32 {
        (self.fogged - self.inscatter) / self.surface
    }
}

/// Ground pixels (world y = 0 by the depth buffer, off the sky), from the probe images.
fn ground_pixels(run: &Run) -> Vec<GroundPixel> {
    let camera = &run.probe["camera"];
    let world_from_clip = mat(&camera["world_from_clip"]);
    let eye = vec3(&camera["position"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let fogged = read_rgba(run, "fogged.f32");
    let inscatter = read_rgba(run, "inscatter.f32");
    let mut out = Vec::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = (y * WIDTH + x) as usize;
            if depth[i] >= 1.0 {
                continue;
            }
            let ndc = Vec3::new(
                (x as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / HEIGHT as f32 * 2.0,
                depth[i],
            );
            let world = world_from_clip.project_point3(ndc);
            if world.y.abs() > 0.02 {
                continue;
            }
            out.push(GroundPixel {
                world,
                distance: world.distance(eye),
                surface: sum3(surface[i]),
                fogged: sum3(fogged[i]),
                inscatter: sum3(inscatter[i]),
                sun: surface[i].w,
            });
        }
    }
    out
}

#[test]
fn every_pass_runs_and_reports_gpu_time() {
    let run = run();
    let p = &run.probe;
    assert_eq!(p["width"], WIDTH);
    assert_eq!(p["height"], HEIGHT);
    assert_eq!(
        p["fog"]["frames_prepared"], FRAMES,
        "the fog encoded every frame"
    );
    for line in ["adapter:", "per-pass GPU time", "frame   3/3"] {
        assert!(run.stdout.contains(line), "stdout lacks {line:?}");
    }
    let names: Vec<&str> = p["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "shadow maps",
            "opaque + sky",
            "froxel cull",
            "esm downsample",
            "esm blur",
            "inject",
            "temporal",
            "scan",
            "fog apply",
            "transparent",
            "tonemap"
        ]
    );
    if p["timestamps"] == true {
        for pass in p["passes"].as_array().unwrap() {
            let runs = pass["frames_with_gpu_time"].as_u64().unwrap();
            let ms = num(&pass["gpu_ms_median"]);
            eprintln!(
                "{:<16} {runs} frames timed, median {ms:.3} ms",
                pass["name"]
            );
            assert_eq!(runs, u64::from(FRAMES), "{} ran every frame", pass["name"]);
            assert!(ms > 0.0 && ms.is_finite(), "{}: {ms} ms", pass["name"]);
        }
    } else {
        eprintln!("NOTE: the adapter lacks TIMESTAMP_QUERY: per-pass GPU times not checked");
        assert!(
            run.stdout
                .contains("unavailable (the adapter lacks TIMESTAMP_QUERY)")
        );
    }
    // The ESM holds occluders (values below the unoccluded exp(c * 1), log space: c)
    // and the integrated volume attenuates towards its far end.
    let fog = &p["fog"];
    // The demo culls by its depth buffer: the ground and pillars hide part of the
    // volume, the sky none of it.
    let live = num(&fog["live_fraction"]);
    eprintln!(
        "demo: {:.1} % of the froxels live after depth culling",
        100.0 * live
    );
    assert!(live > 0.2 && live < 0.95, "live fraction {live}");
    let (esm_min, esm_max) = (num(&fog["esm_min"]), num(&fog["esm_max"]));
    let t_far = num(&fog["mean_transmittance_far"]);
    eprintln!("ESM range {esm_min:.2}..{esm_max:.2}, mean far transmittance {t_far:.3}");
    assert!(esm_min < 0.9 * esm_max, "the shadow map has occluders");
    assert!(t_far > 0.01 && t_far < 0.9, "far transmittance {t_far}");
    assert_eq!(fog["integrated_finite"], true);
}

#[test]
fn probe_images_have_no_nan() {
    let run = run();
    for name in [
        "surface.f32",
        "surface_dry.f32",
        "fogged.f32",
        "final.f32",
        "inscatter.f32",
        "water.f32",
        "depth.f32",
        "underwater_surface.f32",
        "underwater_dry.f32",
        "underwater_water.f32",
        "underwater_final.f32",
        "underwater_depth.f32",
    ] {
        let values = read_f32(run, name);
        let bad = values.iter().filter(|v| !v.is_finite()).count();
        assert_eq!(bad, 0, "{name}: {bad} NaN or infinite values");
        assert!(values.iter().all(|v| *v >= 0.0), "{name} is non-negative");
    }
}

/// Fog on the ground: the per-pixel transmittance falls with distance, and the
/// extinction it implies lies within what the medium allows.
#[test]
fn ground_recedes_into_fog() {
    let run = run();
    let pixels = ground_pixels(run);
    let medium = &run.probe["medium"];
    let density = num(&medium["density"]) as f32;
    let noise = num(&medium["noise_strength"]) as f32;
    let falloff = num(&medium["height_falloff"]) as f32;
    let eye_height = num(&run.probe["camera"]["position"][1]) as f32;
    // Between the ground and the eye the extinction lies within these bounds, outside
    // the local fog pocket (the medians below are dominated by pixels off the pocket).
    let sigma_min = density * (1.0 - noise) * (-falloff * eye_height).exp();
    let sigma_max = density * (1.0 + noise);
    let bin = |lo: f32, hi: f32| {
        let t: Vec<f32> = pixels
            .iter()
            .filter(|p| p.distance >= lo && p.distance < hi && p.surface > 0.05)
            .map(GroundPixel::transmittance)
            .collect();
        let n = t.len();
        (median(t), n, 0.5 * (lo + hi))
    };
    let (t_near, n_near, d_near) = bin(3.0, 8.0);
    let (t_mid, n_mid, d_mid) = bin(10.0, 20.0);
    let (t_far, n_far, d_far) = bin(25.0, 60.0);
    eprintln!(
        "ground transmittance (median): {t_near:.3} at {d_near} m ({n_near} px), {t_mid:.3} at {d_mid} m ({n_mid} px), {t_far:.3} at {d_far} m ({n_far} px)"
    );
    for (t, d, n) in [
        (t_near, d_near, n_near),
        (t_mid, d_mid, n_mid),
        (t_far, d_far, n_far),
    ] {
        assert!(n >= 30, "{n} ground pixels near {d} m");
        let sigma = -t.ln() / d;
        eprintln!(
            "  implied extinction at {d} m: {sigma:.4} 1/m (medium allows {sigma_min:.4}..{sigma_max:.4})"
        );
        assert!(
            sigma >= sigma_min * 0.8 && sigma <= sigma_max * 1.25,
            "implied extinction {sigma} at {d} m outside {sigma_min}..{sigma_max}"
        );
    }
    assert!(t_near < 0.98, "fog attenuates even the nearest ground");
    assert!(
        t_mid < t_near - 0.05 && t_far < t_mid - 0.05,
        "transmittance falls with distance: {t_near} {t_mid} {t_far}"
    );
    // Farther ground is closer to the fog colour: the share of in-scattering in the
    // fogged radiance grows.
    let share = |lo: f32, hi: f32| {
        median(
            pixels
                .iter()
                .filter(|p| p.distance >= lo && p.distance < hi && p.fogged > 0.0)
                .map(|p| p.inscatter / p.fogged)
                .collect(),
        )
    };
    let (s_near, s_far) = (share(3.0, 8.0), share(25.0, 60.0));
    eprintln!(
        "in-scattering share of the ground's fogged radiance: {s_near:.3} near, {s_far:.3} far"
    );
    assert!(s_far > s_near + 0.1, "{s_near} -> {s_far}");
}

fn vec3(v: &Value) -> Vec3 {
    let a: Vec<f32> = v
        .as_array()
        .expect("vector array")
        .iter()
        .map(|x| num(x) as f32)
        .collect();
    Vec3::from_slice(&a)
}

/// The fog's shadow inputs as the probe recorded them: cascades and ESM layers.
fn shadow_inputs(run: &Run) -> (ShadowCascades, Vec<Layer>, bool) {
    let c = &run.probe["cascades"];
    let mut cascades = ShadowCascades {
        splits: Vec4::from_slice(
            &c["splits"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| num(x) as f32)
                .collect::<Vec<_>>(),
        ),
        count: c["count"].as_u64().unwrap() as u32,
        exponent: num(&c["exponent"]) as f32,
        ..ShadowCascades::default()
    };
    for (i, m) in c["light_from_world"].as_array().unwrap().iter().enumerate() {
        cascades.light_from_world[i] = mat(m);
    }
    let n = run.probe["fog"]["esm_resolution"].as_u64().unwrap() as u32;
    let esm = read_f32(run, "esm.f32");
    assert_eq!(esm.len(), (n * n * cascades.count) as usize);
    let layers = esm
        .chunks_exact((n * n) as usize)
        .map(|c| Layer {
            width: n,
            height: n,
            texels: c.to_vec(),
        })
        .collect();
    (cascades, layers, run.probe["fog"]["esm_log_space"] == true)
}

/// The filtered ESM the fog uses agrees with the demo's own shadow test of the
/// ground (3x3 PCF on the raw shadow map): the shadows reach the fog where they are.
#[test]
fn fog_shadow_map_matches_the_ground_shadows() {
    let run = run();
    let (cascades, layers, log_space) = shadow_inputs(run);
    let view_from_world = mat(&run.probe["camera"]["view_from_world"]);
    let (mut agree, mut total, mut shadowed) = (0, 0, 0);
    for p in ground_pixels(run) {
        if p.sun > 0.05 && p.sun < 0.95 {
            continue;
        }
        // Just above the ground, which is itself in the shadow map.
        let world = p.world + Vec3::Y * 0.3;
        let depth = -view_from_world.transform_point3(world).z;
        let v = esm::esm_shadow(&layers, &cascades, world, depth, log_space);
        total += 1;
        shadowed += usize::from(p.sun < 0.05);
        agree += usize::from((v > 0.5) == (p.sun > 0.5));
    }
    let share = agree as f32 / total as f32;
    eprintln!(
        "ESM vs ground shadow test: {:.1}% of {total} ground pixels agree ({shadowed} in shadow; bound 85%)",
        share * 100.0
    );
    assert!(shadowed >= 100 && total - shadowed >= 100);
    assert!(share >= 0.85, "{share}");
}

/// Light shafts in the fog: in the integrated volume, the radiance each froxel
/// scatters towards the eye, J = dL / (-dT) between consecutive slices (the source
/// function sigma_s L_in / sigma_t, independent of the density), is several times
/// larger in sunlit columns than in neighbouring columns in a pillar's shadow (same
/// slice and row, at most 4 columns apart, 3 to 13 m from the camera). Without the
/// sun in the fog the median ratio measures 0.99, with it 2.3 (the coloured lights
/// add to both sides); the bound is 1.6.
#[test]
fn fog_shows_light_shafts() {
    let run = run();
    let p = &run.probe;
    let fog = &p["fog"];
    let size = UVec3::from_slice(
        &fog["volume_size"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap() as u32)
            .collect::<Vec<_>>(),
    );
    let froxels = Froxels::new(
        mat(&p["camera"]["clip_from_view"]),
        size,
        num(&fog["near"]) as f32,
        num(&fog["far"]) as f32,
        num(&fog["slice_curve"]) as f32,
    )
    .expect("valid froxels");
    let frame = FogFrame {
        world_from_view: mat(&p["camera"]["view_from_world"]).inverse(),
        camera_position: vec3(&p["camera"]["position"]),
        ..FogFrame::default()
    };
    let (cascades, layers, log_space) = shadow_inputs(run);
    let volume: Vec<Vec4> = read_f32(run, "integrated.f32")
        .chunks_exact(4)
        .map(Vec4::from_slice)
        .collect();
    assert_eq!(volume.len() as u32, size.x * size.y * size.z);
    let at = |x: u32, y: u32, z: u32| volume[((z * size.y + y) * size.x + x) as usize];
    let (mut ratios, mut lit_count, mut shadow_count) = (Vec::new(), 0, 0);
    for z in 1..size.z {
        // (sun visibility, J) of every froxel of this slice with enough extinction.
        let mut row: Vec<Option<(f32, f32)>> = vec![None; size.x as usize];
        for y in 0..size.y {
            for x in 0..size.x {
                let (front, back) = (at(x, y, z - 1), at(x, y, z));
                let (world, depth) =
                    froxel_world_position(&froxels, &frame, UVec3::new(x, y, z), false);
                let d_t = front.w - back.w;
                row[x as usize] = if (3.0..13.0).contains(&depth) && d_t > 2e-3 * front.w {
                    let j = sum3(back - front) / d_t;
                    let v = esm::esm_shadow(&layers, &cascades, world, depth, log_space);
                    Some((v, j))
                } else {
                    None
                };
            }
            for x in 0..size.x as usize {
                let Some((v, j_shadow)) = row[x] else {
                    continue;
                };
                if v > 0.05 {
                    lit_count += usize::from(v > 0.95);
                    continue;
                }
                shadow_count += 1;
                let neighbours = &row[x.saturating_sub(4)..(x + 5).min(size.x as usize)];
                for (vn, j_lit) in neighbours.iter().flatten() {
                    if *vn > 0.95 && j_shadow > 0.0 {
                        ratios.push(j_lit / j_shadow);
                    }
                }
            }
        }
    }
    let n = ratios.len();
    eprintln!(
        "froxels 3..13 m from the camera: {lit_count} sunlit, {shadow_count} in shadow, {n} neighbour pairs"
    );
    assert!(n >= 200, "{n} lit/shadowed neighbour pairs");
    ratios.sort_by(|a, b| a.total_cmp(b));
    let (q25, q50, q75) = (ratios[n / 4], ratios[n / 2], ratios[3 * n / 4]);
    eprintln!(
        "scattered radiance J, sunlit / shadowed neighbouring columns: median {q50:.2} (quartiles {q25:.2}, {q75:.2}; bound: median >= 1.6)"
    );
    assert!(q50 >= 1.6, "shafts too weak: median ratio {q50}");
}

/// The semi-transparent sphere changes the final image (over part of it) and keeps
/// the probe alpha.
#[test]
fn transparent_pass_blends_over_the_fogged_image() {
    let run = run();
    let fogged = read_rgba(run, "fogged.f32");
    let final_image = read_rgba(run, "final.f32");
    let changed = fogged
        .iter()
        .zip(&final_image)
        .filter(|(a, b)| (sum3(**a) - sum3(**b)).abs() > 0.02 * sum3(**a).max(1e-3))
        .count();
    let share = changed as f32 / fogged.len() as f32;
    eprintln!(
        "the transparent pass changed {:.2}% of the pixels",
        share * 100.0
    );
    assert!(share > 0.002 && share < 0.2, "{share}");
    assert!(fogged.iter().zip(&final_image).all(|(a, b)| a.w == b.w));
}

#[test]
fn png_decodes_at_the_requested_size() {
    let run = run();
    let file = std::fs::File::open(run.dir.join("demo.png")).expect("demo.png exists");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut pixels = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut pixels).expect("PNG data");
    assert_eq!((info.width, info.height), (WIDTH, HEIGHT));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let rgb = &pixels[..info.buffer_size()];
    let distinct: std::collections::HashSet<&[u8]> = rgb.chunks_exact(4).collect();
    eprintln!(
        "demo.png: {}x{}, {} distinct colours",
        info.width,
        info.height,
        distinct.len()
    );
    assert!(distinct.len() > 100, "the picture is not flat");
}

/// The pool's water as the probe recorded it, and the demo's test for "in the water"
/// (the footprint with 1 cm of slack, below the surface).
fn pool(run: &Run) -> (volfog::uniforms::Water, impl Fn(Vec3) -> bool) {
    let w = &run.probe["water"];
    let water: volfog::uniforms::Water =
        serde_json::from_value(w["uniform"].clone()).expect("Water deserializes");
    let (lo, hi) = (vec3(&w["pool_min"]), vec3(&w["pool_max"]));
    let inside = move |p: Vec3| {
        p.x >= lo.x - 0.01
            && p.x <= hi.x + 0.01
            && p.z >= lo.z - 0.01
            && p.z <= hi.z + 0.01
            && p.dot(water.normal) <= water.height
    };
    (water, inside)
}

/// World positions of the pixels off the sky, from a depth image.
fn world_positions(depth: &[f32], world_from_clip: Mat4) -> Vec<Option<Vec3>> {
    (0..(WIDTH * HEIGHT) as usize)
        .map(|i| {
            let (x, y) = ((i as u32 % WIDTH) as f32, (i as u32 / WIDTH) as f32);
            (depth[i] < 1.0).then(|| {
                world_from_clip.project_point3(Vec3::new(
                    (x + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                    1.0 - (y + 0.5) / HEIGHT as f32 * 2.0,
                    depth[i],
                ))
            })
        })
        .collect()
}

/// Per pixel of the pool's water: the demo's underwater in-scattering (every surface
/// black, before the air's fog) against `cpu::water::water_fog` for the same eye and
/// point. Returns the pixel count and the worst error.
fn check_water_inscatter(
    water: &volfog::uniforms::Water,
    inside: &impl Fn(Vec3) -> bool,
    eye: Vec3,
    world: &[Option<Vec3>],
    black: &[Vec4],
) -> (usize, f32) {
    let (mut n, mut worst) = (0, 0.0f32);
    for (i, p) in world.iter().enumerate() {
        let Some(p) = *p else { continue };
        if !inside(p) {
            continue;
        }
        let want = volfog::cpu::water::water_fog(water, eye, p).truncate();
        let got = black[i].truncate();
        // rgba16float storage (2^-11) and the depth buffer's reconstruction.
        let e = ((got - want).abs() / (want.abs() + Vec3::splat(0.02))).max_element();
        worst = worst.max(e);
        assert!(e <= 5e-3, "pixel {i} at {p}: demo {got} cpu {want}");
        n += 1;
    }
    (n, worst)
}

/// Seen from above: the water's in-scattering in the pool equals the CPU mirror, and
/// the submerged surfaces, lit through the water, turn bluer than the dry pool.
#[test]
fn pool_water_seen_from_above() {
    let run = run();
    let (water, inside) = pool(run);
    let camera = &run.probe["camera"];
    let eye = vec3(&camera["position"]);
    let world = world_positions(&read_f32(run, "depth.f32"), mat(&camera["world_from_clip"]));
    let (n, worst) =
        check_water_inscatter(&water, &inside, eye, &world, &read_rgba(run, "water.f32"));
    let wet = read_rgba(run, "surface.f32");
    let dry = read_rgba(run, "surface_dry.f32");
    let (mut wet_sum, mut dry_sum) = (Vec3::ZERO, Vec3::ZERO);
    for (i, p) in world.iter().enumerate() {
        if p.is_some_and(&inside) {
            wet_sum += wet[i].truncate();
            dry_sum += dry[i].truncate();
        }
    }
    let ratio = |v: Vec3| v.z / v.x.max(1e-6);
    eprintln!(
        "pool from above: {n} pixels under water, in-scatter vs cpu::water worst rel {worst:.2e} \
         (bound 5e-3); blue/red of the submerged surfaces wet {:.2}, dry {:.2}",
        ratio(wet_sum),
        ratio(dry_sum)
    );
    assert!(n > 300, "the pool is in view: {n} pixels");
    assert!(ratio(wet_sum) > 1.2 * ratio(dry_sum));
}

/// The second camera, under water: everything in the pool carries the water's
/// in-scattering (equal to the CPU mirror), what lies beyond the surface is seen
/// through the water (darker and bluer than dry), and the PNG is written.
#[test]
fn pool_water_seen_from_below() {
    let run = run();
    let text =
        std::fs::read_to_string(run.dir.join("probe/underwater.json")).expect("underwater.json");
    let info: Value = serde_json::from_str(&text).expect("parses");
    let (water, inside) = pool(run);
    let eye = vec3(&info["camera"]["position"]);
    assert!(inside(eye), "the second camera is under water");
    let world = world_positions(
        &read_f32(run, "underwater_depth.f32"),
        mat(&info["camera"]["world_from_clip"]),
    );
    let (n, worst) = check_water_inscatter(
        &water,
        &inside,
        eye,
        &world,
        &read_rgba(run, "underwater_water.f32"),
    );
    let wet = read_rgba(run, "underwater_surface.f32");
    let dry = read_rgba(run, "underwater_dry.f32");
    // Beyond the surface (the sky and the scene above the water).
    let (mut wet_above, mut dry_above, mut above) = (Vec3::ZERO, Vec3::ZERO, 0);
    for (i, p) in world.iter().enumerate() {
        if p.is_none_or(|p| !inside(p)) {
            wet_above += wet[i].truncate();
            dry_above += dry[i].truncate();
            above += 1;
        }
    }
    eprintln!(
        "pool from below: {n} pixels in the water, in-scatter vs cpu::water worst rel {worst:.2e} \
         (bound 5e-3); {above} pixels beyond the surface, mean wet {:?} vs dry {:?}",
        wet_above / above.max(1) as f32,
        dry_above / above.max(1) as f32
    );
    assert!(n > 1000, "the pool fills most of the view: {n}");
    assert!(above > 100, "the surface shows the world above: {above}");
    assert!(wet_above.z / wet_above.x > dry_above.z / dry_above.x);
    let file = std::fs::File::open(run.dir.join("underwater.png")).expect("underwater.png exists");
    let info = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("decodes")
        .info()
        .clone();
    assert_eq!((info.width, info.height), (WIDTH, HEIGHT));
}

/// World direction of each pixel (from the camera through the pixel's centre).
fn pixel_directions(run: &Run) -> Vec<Vec3> {
    let camera = &run.probe["camera"];
    let world_from_clip = mat(&camera["world_from_clip"]);
    (0..WIDTH * HEIGHT)
        .map(|i| {
            let ndc = glam::Vec2::new(
                ((i % WIDTH) as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
                1.0 - ((i / WIDTH) as f32 + 0.5) / HEIGHT as f32 * 2.0,
            );
            let near = world_from_clip.project_point3(ndc.extend(0.0));
            let far = world_from_clip.project_point3(ndc.extend(1.0));
            (far - near).normalize()
        })
        .collect()
}

/// The sky behind the scene is the solved Nishita sky with the phase per pixel
/// (`volfog::sky`): every 5th sky pixel away from the sun's disc against
/// `cpu::sky` evaluated exactly in its direction.
#[test]
fn sky_is_the_solved_atmosphere() {
    use volfog::cpu::sky::{sky_radiance, sky_single_scattering};
    let run = run();
    let atmosphere: volfog::uniforms::SkyAtmosphere =
        serde_json::from_value(run.probe["sky"]["atmosphere"].clone()).expect("SkyAtmosphere");
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let dirs = pixel_directions(run);
    let (mut n, mut worst, mut sum) = (0, 0.0f32, 0.0f32);
    let (mut toward, mut away) = (Vec3::ZERO, Vec3::ZERO);
    for i in (0..(WIDTH * HEIGHT) as usize).step_by(5) {
        let d = dirs[i];
        if depth[i] < 1.0 || d.y < 0.0 || d.dot(atmosphere.sun_direction) > 0.999 {
            continue;
        }
        let want = sky_radiance(
            &sky_single_scattering(&atmosphere, d),
            d.dot(atmosphere.sun_direction),
            &atmosphere,
        );
        let got = surface[i].truncate();
        // The texture's bilinear interpolation between 128 x 64 directions and f16.
        let e = ((got - want).abs() / want.max(Vec3::splat(1e-3))).max_element();
        worst = worst.max(e);
        sum += e;
        n += 1;
        assert!(e <= 0.01, "pixel {i} {d}: {got} vs {want}");
        if d.dot(atmosphere.sun_direction) > 0.9 {
            toward += got;
        } else {
            away += got;
        }
    }
    let (ct, ca) = (toward / toward.element_sum(), away / away.element_sum());
    eprintln!(
        "sky: {n} pixels vs cpu::sky worst rel {worst:.3} mean {:.4} (bound 0.01); chromaticity \
         towards the sun {ct:.3}, elsewhere {ca:.3}",
        sum / n as f32
    );
    assert!(n > 200, "the sky is in view: {n}");
    assert!(ct.x > ca.x, "redder towards the low sun");
}

/// The cloud layer and its map as the probe recorded them.
fn cloud_layer(run: &Run) -> (volfog::cpu::clouds::CloudMap, volfog::uniforms::CloudLayer) {
    let layer = serde_json::from_value(run.probe["clouds"]["layer"].clone()).expect("CloudLayer");
    let size = run.probe["clouds"]["map_size"].as_u64().unwrap() as u32;
    let map = volfog::cpu::clouds::CloudMap {
        width: size,
        height: size,
        texels: read_f32(run, "cloud_map.f32"),
    };
    (map, layer)
}

/// Distance clouds over the sky: each sky pixel after the clouds pass equals the sky
/// attenuated and lit by `cpu::clouds::distance_clouds` along its ray, for rays more
/// than 2 degrees above the horizon (nearer to it the slab lies tens of kilometres
/// away and a 1e-6 change of the ray's direction moves its samples by metres, across
/// the map's texels: the ray, not the formula, is then ill-conditioned).
#[test]
fn distance_clouds_cover_the_sky() {
    let run = run();
    let (map, layer) = cloud_layer(run);
    let eye = vec3(&run.probe["camera"]["position"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let clouded = read_rgba(run, "clouded.f32");
    let dirs = pixel_directions(run);
    let (mut n, mut covered, mut worst) = (0, 0, 0.0f32);
    for i in 0..(WIDTH * HEIGHT) as usize {
        if depth[i] < 1.0 || dirs[i].y < 2f32.to_radians().sin() {
            continue;
        }
        let c = volfog::cpu::clouds::distance_clouds(&map, &layer, eye, dirs[i], 1e30);
        let want = surface[i].truncate() * c.w + c.truncate();
        let got = clouded[i].truncate();
        let e = ((got - want).abs() / want.max(Vec3::splat(0.01))).max_element();
        worst = worst.max(e);
        assert!(e <= 0.02, "pixel {i}: {got} vs {want} (clouds {c})");
        n += 1;
        covered += (c.w < 0.8) as usize;
    }
    eprintln!(
        "distance clouds: {n} sky pixels above 2 degrees vs cpu::clouds worst rel {worst:.4} (bound 0.02); {covered} under cloud (T < 0.8)"
    );
    assert!(covered > 50, "clouds in the sky: {covered}");
}

/// The clouds' shadow on the lit scene: each geometry pixel after the clouds pass is
/// its lit colour times `cpu::clouds::cloud_shadow` at its position, at the frame's
/// time; one second earlier the wind had the shadows elsewhere.
#[test]
fn cloud_shadows_move_over_the_scene() {
    use volfog::cpu::clouds::cloud_shadow;
    let run = run();
    let (map, layer) = cloud_layer(run);
    let world_from_clip = mat(&run.probe["camera"]["world_from_clip"]);
    let depth = read_f32(run, "depth.f32");
    let surface = read_rgba(run, "surface.f32");
    let clouded = read_rgba(run, "clouded.f32");
    let earlier = volfog::uniforms::CloudLayer {
        time: layer.time - 1.0,
        ..layer
    };
    let (mut n, mut shadowed, mut moved, mut worst) = (0, 0, 0, 0.0f32);
    for i in 0..(WIDTH * HEIGHT) as usize {
        if depth[i] >= 1.0 || surface[i].truncate().max_element() < 1e-3 {
            continue;
        }
        let ndc = glam::Vec2::new(
            ((i as u32 % WIDTH) as f32 + 0.5) / WIDTH as f32 * 2.0 - 1.0,
            1.0 - ((i as u32 / WIDTH) as f32 + 0.5) / HEIGHT as f32 * 2.0,
        );
        let p = world_from_clip.project_point3(ndc.extend(depth[i]));
        let t = cloud_shadow(&map, &layer, p);
        let want = surface[i].truncate() * t;
        let got = clouded[i].truncate();
        let e = ((got - want).abs() / surface[i].truncate().max(Vec3::splat(1e-3))).max_element();
        worst = worst.max(e);
        assert!(e <= 0.02, "pixel {i} at {p}: {got} vs {want} (shadow {t})");
        n += 1;
        shadowed += (t < 0.5) as usize;
        moved += ((cloud_shadow(&map, &earlier, p) - t).abs() > 0.05) as usize;
    }
    eprintln!(
        "cloud shadows: {n} geometry pixels vs cpu::clouds worst {worst:.4} of the lit colour \
         (bound 0.02); {shadowed} in shadow (T < 0.5); {moved} change by more than 0.05 in 1 s of wind"
    );
    assert!(shadowed > 50 && shadowed < n, "shadows and light");
    assert!(moved > 50, "the shadows move with the wind");
}
