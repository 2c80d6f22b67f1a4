//! Bevy's own volumetric fog held against the path tracer: every scene of
//! `volfog_testkit::truth::scenes` rendered by Bevy 0.20's `VolumetricFog` and
//! `FogVolume`s at Bevy's default 64 steps (`examples/bevy_truth`), compared with
//! Mitsuba 3 as volfog's rows are (per 4 x 4 block, the same masks and floor), the rows
//! printed in the table's format (`cargo run --example bevy_truth` prints the whole
//! table, with volfog's rows and a second step count).
//!
//! No bound holds Bevy to physics: its fog departs from single scattering by design
//! (`examples/bevy_truth/model.rs` lists how). What is checked:
//! - the comparison ran: every image finite and non-negative, at least 50 blocks
//!   compared per scene;
//! - Bevy renders what its shader says: its image equals Bevy's shader evaluated on
//!   the CPU for the same components (`model::render`) within 1 % (mean over the
//!   compared blocks, radiance and transmittance) in the scenes whose lights no
//!   occluder but the ground shadows. The bound's budget: rgba16float storage of the
//!   image and of the density textures (4.9e-4 relative each), the lamps' range window
//!   (1.3e-5), the rest the GPU's arithmetic. Each of the shader's departures from
//!   single scattering, put into the CPU model, must miss that bound in some scene
//!   without density textures (the comparison tells Bevy's model from the physical
//!   one). In the shadowed scenes the figure is printed, not bounded: Bevy's shadow
//!   maps and their filters stand against exact visibility there;
//! - the units are mapped right: the CPU model with those departures removed
//!   (`ModelOptions::PHYSICAL`) at 256 steps meets Mitsuba within 3 % (mean) in the
//!   uniform fog under the sun and around the point light. The budget: the quadrature
//!   of 256 steps (the transmittance taken at each step's end, sigma_t * step / 2:
//!   0.8 % at 0.04 / m over 100 m), Mitsuba's block noise (0.7 %) and a pixel's centre
//!   against its area (Mitsuba's box filter);
//! - the mapping's arithmetic (no GPU): the scene's irradiance, radiant intensity,
//!   extinction and scattering out of Bevy's components through Bevy's own conversions,
//!   the density textures against the profiles they hold, and bad input rejected with
//!   the field named.

#[path = "../examples/bevy_truth/mapping.rs"]
mod mapping;
#[path = "../examples/bevy_truth/model.rs"]
mod model;
#[path = "../examples/bevy_truth/render.rs"]
mod render;
// The example's JSON output is not used here.
#[allow(dead_code)]
#[path = "../examples/bevy_truth/rows.rs"]
mod rows;

use std::sync::OnceLock;
use std::time::Instant;

use bevy::prelude::*;
use mapping::{DEFAULT_STEPS, MappedScene, map_scene};
use model::ModelOptions;
use render::BevyTruth;
use rows::{Noise, TruthRow};
use volfog::glam as vg;
use volfog_testkit::truth::compare::relative_error;
use volfog_testkit::truth::mitsuba::MitsubaOptions;
use volfog_testkit::truth::report::{BLOCK, Reference, SPP, SceneErrors, block_mask, blocks};
use volfog_testkit::truth::scene::{TruthImage, TruthScene};
use volfog_testkit::truth::scenes;

/// Bevy's image against Bevy's shader on the CPU: mean relative error (radiance and
/// transmittance) over the compared blocks.
const SHADER_BOUND: f32 = 0.01;
/// The CPU model without Bevy's departures against Mitsuba: mean relative error of the
/// radiance.
const PHYSICAL_BOUND: f32 = 0.03;
/// Steps of the physical model.
const PHYSICAL_STEPS: u32 = 256;
/// Fewest blocks compared per scene (the spot light's cone covers about 60).
const MIN_BLOCKS: usize = 50;

/// One scene rendered by Bevy, with its reference.
struct Rendered {
    scene: TruthScene,
    reference: Reference,
    image: TruthImage,
}

struct Run {
    scenes: Vec<Rendered>,
    adapter: String,
    seconds: f32,
}

fn run() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let mitsuba = MitsubaOptions {
            spp: SPP,
            ..MitsubaOptions::default()
        };
        let references: Vec<Reference> = scenes::all()
            .iter()
            .map(|s| Reference::render(s, &mitsuba).unwrap_or_else(|e| panic!("{e}")))
            .collect();
        let start = Instant::now();
        let mut bevy = BevyTruth::new();
        let adapter = bevy.adapter();
        let scenes = references
            .into_iter()
            .map(|reference| {
                let scene = reference.scene.clone();
                let image = bevy
                    .render(&scene, DEFAULT_STEPS)
                    .unwrap_or_else(|e| panic!("{e}"));
                Rendered {
                    scene,
                    reference,
                    image,
                }
            })
            .collect();
        Run {
            scenes,
            adapter,
            seconds: start.elapsed().as_secs_f32(),
        }
    })
}

/// The mean relative errors (radiance, transmittance) of `test` against `against`
/// over the blocks compared with Mitsuba.
fn against(rendered: &Rendered, test: &TruthImage, against: &TruthImage) -> (f32, f32) {
    let r = &rendered.reference;
    let (w, h) = (r.image.width, r.image.height);
    let mask = block_mask(&r.mask, w, h);
    let radiance = relative_error(
        &blocks(&test.radiance, w, h),
        &blocks(&against.radiance, w, h),
        &mask,
        r.floor,
    );
    let transmittance = relative_error(
        &blocks(&test.transmittance, w, h),
        &blocks(&against.transmittance, w, h),
        &mask,
        1e-3,
    );
    (radiance.mean, transmittance.mean)
}

/// Whether no occluder but the ground can shadow the fog.
fn unshadowed(scene: &TruthScene) -> bool {
    scene.occluders.len() == 1
}

#[test]
fn bevy_fog_against_mitsuba() {
    let run = run();
    let mut table = Vec::new();
    let mut noise = Vec::new();
    for r in &run.scenes {
        let name = &r.scene.name;
        for (what, values) in [
            ("radiance", &r.image.radiance),
            ("transmittance", &r.image.transmittance),
        ] {
            let bad = values
                .iter()
                .filter(|v| !v.is_finite() || v.min_element() < 0.0)
                .count();
            assert_eq!(bad, 0, "{name}: {bad} {what} pixels not finite or negative");
        }
        let errors: SceneErrors = r.reference.compare(&r.image);
        assert!(
            errors.radiance.pixels >= MIN_BLOCKS,
            "{name}: {} blocks compared",
            errors.radiance.pixels
        );
        assert!(
            errors.radiance.mean.is_finite() && errors.transmittance.mean.is_finite(),
            "{name}: {errors:?}"
        );
        table.push(TruthRow {
            scene: name.clone(),
            renderer: format!("Bevy VolumetricFog, {DEFAULT_STEPS} steps"),
            errors,
        });
        noise.push(Noise::of(&r.reference));
    }
    eprintln!(
        "Bevy on {}: {} scenes of {}x{} pixels ({BLOCK}x{BLOCK} blocks) in {:.1} s\n{}",
        run.adapter,
        run.scenes.len(),
        scenes::WIDTH,
        scenes::HEIGHT,
        run.seconds,
        rows::markdown(&table, &noise)
    );
}

#[test]
fn bevy_renders_its_shader() {
    let run = run();
    let mut checked = 0;
    let mut missed = Vec::new();
    for r in &run.scenes {
        let name = &r.scene.name;
        let mapped = map_scene(&r.scene, DEFAULT_STEPS).unwrap();
        let start = Instant::now();
        let shader = model::render(&r.scene, &mapped, ModelOptions::default());
        let (radiance, transmittance) = against(r, &r.image, &shader);
        eprintln!(
            "{name}: Bevy against its shader on the CPU: radiance {:.3} %, transmittance {:.3} % ({:.1} s)",
            radiance * 100.0,
            transmittance * 100.0,
            start.elapsed().as_secs_f32()
        );
        if !unshadowed(&r.scene) {
            continue;
        }
        checked += 1;
        assert!(
            radiance <= SHADER_BOUND && transmittance <= SHADER_BOUND,
            "{name}: Bevy's image is {:.2} % (radiance) and {:.2} % (transmittance) from its shader's, bound {:.0} %",
            radiance * 100.0,
            transmittance * 100.0,
            SHADER_BOUND * 100.0
        );
        // Each departure from single scattering that applies to the scene must be told
        // apart from the shader as it is (in the scenes without density textures, whose
        // light paths the CPU integrates quickly).
        if mapped.volumes.iter().any(|v| v.grid.is_some()) {
            continue;
        }
        let lamps = !r.scene.points.is_empty() || !r.scene.spots.is_empty();
        let departures = [
            (
                "the light's path",
                ModelOptions {
                    path_attenuation: true,
                    ..ModelOptions::default()
                },
            ),
            (
                "the lamps' phase",
                ModelOptions {
                    lamp_phase: true,
                    ..ModelOptions::default()
                },
            ),
            (
                "the ray's length",
                ModelOptions {
                    ray_length: true,
                    ..ModelOptions::default()
                },
            ),
        ];
        for (what, options) in departures {
            if what == "the lamps' phase" && !lamps {
                continue;
            }
            let other = model::render(&r.scene, &mapped, options);
            let (radiance, transmittance) = against(r, &r.image, &other);
            eprintln!(
                "{name}: with {what}: radiance {:.2} %, transmittance {:.2} %",
                radiance * 100.0,
                transmittance * 100.0
            );
            if radiance > SHADER_BOUND || transmittance > SHADER_BOUND {
                missed.push(what);
            }
        }
    }
    assert!(checked >= 4, "only {checked} unshadowed scenes");
    for what in ["the light's path", "the lamps' phase", "the ray's length"] {
        assert!(
            missed.contains(&what),
            "the model with {what} met the bound everywhere: the check cannot tell it from Bevy's"
        );
    }
}

#[test]
fn physical_model_meets_mitsuba() {
    let run = run();
    for name in ["homogeneous_sun", "point_light"] {
        let r = run
            .scenes
            .iter()
            .find(|r| r.scene.name == name)
            .expect("the scene");
        let mapped = map_scene(&r.scene, PHYSICAL_STEPS).unwrap();
        let image = model::render(&r.scene, &mapped, ModelOptions::PHYSICAL);
        let errors = r.reference.compare(&image);
        eprintln!(
            "{name}: Bevy's mapping, single scattering on the CPU at {PHYSICAL_STEPS} steps, against Mitsuba: radiance {:.2} / {:.2} % (mean / p95), transmittance {:.2} %, ratio {:.4}",
            errors.radiance.mean * 100.0,
            errors.radiance.p95 * 100.0,
            errors.transmittance.mean * 100.0,
            errors.radiance_ratio
        );
        assert!(
            errors.radiance.mean <= PHYSICAL_BOUND,
            "{name}: {:.2} % > {:.0} %",
            errors.radiance.mean * 100.0,
            PHYSICAL_BOUND * 100.0
        );
    }
}

fn bv(v: vg::Vec3) -> Vec3 {
    Vec3::from_array(v.to_array())
}

fn linear(c: Color) -> Vec3 {
    Vec3::from_array(c.to_linear().to_f32_array_no_alpha())
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() <= 1e-5 * b.length().max(1e-6)
}

#[test]
fn mapping_carries_the_scene_units() {
    let four_pi = 4.0 * std::f32::consts::PI;
    for scene in scenes::all() {
        let m: MappedScene = map_scene(&scene, DEFAULT_STEPS).unwrap();
        let e = m.exposure().exposure();
        if let (Some(sun), Some((light, transform, _))) = (&scene.sun, &m.sun) {
            // Bevy's directional colour: linear colour times illuminance, exposed.
            assert!(close(
                linear(light.color) * light.illuminance * e,
                bv(sun.color)
            ));
            assert!(close(
                -transform.forward().as_vec3(),
                bv(sun.direction).normalize()
            ));
        }
        for (p, (light, transform)) in scene.points.iter().zip(&m.points) {
            // Bevy's candela: lumens / 4 pi.
            let candela = linear(light.color) * light.intensity / four_pi * e;
            assert!(close(candela, bv(p.color)), "{}", scene.name);
            assert_eq!(transform.translation, bv(p.position));
        }
        for (s, (light, transform)) in scene.spots.iter().zip(&m.spots) {
            let candela = linear(light.color) * light.intensity / four_pi * e;
            assert!(close(candela, bv(s.color)), "{}", scene.name);
            assert!(close(
                transform.forward().as_vec3(),
                bv(s.direction).normalize()
            ));
            assert!((light.outer_angle - s.outer_deg.to_radians()).abs() < 1e-6);
        }
        let global = &m.volumes[0].volume;
        // The extinction at the medium box's bottom, where a height profile's texture
        // (values up to 1) is densest.
        let sigma_t = global.density_factor * (global.absorption + global.scattering);
        let medium = &scene.medium;
        let at_bottom =
            medium.density * (-medium.falloff * (medium.bounds_min.y - medium.base_height)).exp();
        assert!(
            (sigma_t - at_bottom).abs() <= 1e-5 * at_bottom,
            "{}: extinction {sigma_t}, want {at_bottom}",
            scene.name
        );
        if let Some(grid) = &m.volumes[0].grid {
            assert!(grid.values.iter().all(|v| (0.0..=1.0).contains(v)));
        }
        let sigma_s = linear(global.fog_color) * global.scattering;
        assert!(close(sigma_s, bv(scene.medium.albedo)), "{}", scene.name);
        assert_eq!(global.scattering_asymmetry, scene.medium.phase_g);
        assert_eq!(m.volumes.len(), 1 + scene.volumes.len());
    }
}

#[test]
fn density_textures_hold_the_profiles() {
    let scene = scenes::height_fog_low_sun();
    let m = map_scene(&scene, DEFAULT_STEPS).unwrap();
    let v = &m.volumes[0];
    let grid = v.grid.as_ref().expect("a height profile");
    let (min, max) = mapping::medium_bounds(&scene);
    let medium = &scene.medium;
    let mut worst = 0.0f32;
    // Between the first and the last texel centres (the texture is clamped beyond).
    for k in 0..=390 {
        let y = 0.5 + k as f32 * 0.1;
        let uvw = (Vec3::new(0.3, y, 0.7) - min) / (max - min);
        let got = v.volume.density_factor * grid.sample(uvw);
        let want = medium.density * (-medium.falloff * (y - medium.base_height)).exp();
        worst = worst.max((got - want).abs() / want);
    }
    // Linear interpolation of the exponential over a texel of 0.16 m: (0.15 * 0.16)^2 / 8.
    assert!(worst < 1e-4, "height profile off by {worst}");

    let scene = scenes::local_volumes();
    let m = map_scene(&scene, DEFAULT_STEPS).unwrap();
    for (truth, v) in scene.volumes.iter().zip(&m.volumes[1..]) {
        let grid = v.grid.as_ref().expect("an edge fade");
        // Well inside the fade-free core the density is the volume's; outside the
        // shape (a corner of an ellipsoid's box) there is none.
        let core = grid.sample(Vec3::splat(0.5));
        assert!((v.volume.density_factor * core - truth.density).abs() < 1e-6);
        let corner = grid.sample(Vec3::splat(0.02));
        match truth.shape {
            volfog_testkit::truth::scene::TruthShape::Ellipsoid => assert_eq!(corner, 0.0),
            volfog_testkit::truth::scene::TruthShape::Box => assert!(corner > 0.0),
        }
    }
}

#[test]
fn bad_scenes_name_their_field() {
    let field = |s: &TruthScene| map_scene(s, DEFAULT_STEPS).unwrap_err().field;
    let mut s = scenes::spot_light();
    s.spots[0].outer_deg = s.spots[0].inner_deg;
    assert_eq!(field(&s), "TruthSpot.outer_deg");
    let mut s = scenes::point_light();
    s.points[0].color = vg::Vec3::ZERO;
    assert_eq!(field(&s), "TruthPoint.color");
    let mut s = scenes::homogeneous_sun();
    s.medium.albedo = vg::Vec3::splat(1.5);
    assert_eq!(field(&s), "TruthMedium.albedo");
    let mut s = scenes::local_volumes();
    s.volumes[0].edge = 0.0;
    assert_eq!(field(&s), "TruthVolume.edge");
    let mut s = scenes::homogeneous_sun();
    s.camera.fov_y_deg = 0.0;
    assert_eq!(field(&s), "TruthCamera.fov_y_deg");
    assert_eq!(
        map_scene(&scenes::homogeneous_sun(), 0).unwrap_err().field,
        "VolumetricFog.step_count"
    );
}
