//! The froxel pipeline held against a path tracer: each scene of
//! `volfog_testkit::truth::scenes` rendered by `VolumetricFog` at the default
//! configuration (160 x 90 x 128 froxels, jitter and temporal blending at history
//! weight 0.9, light transmittance, shadowed lamps) with the medium's shadows
//! (`VolfogOptions::default`) for `CONVERGED_FRAMES` frames of a still camera, and by
//! Mitsuba 3's `volpath` in single scattering, compared in blocks of 4 x 4 pixels
//! (`volfog_testkit::truth::report`).
//!
//! Bounds on the converged image (the last frame's), mean relative error over the
//! compared blocks: in-scattered radiance 3 % in the scenes whose only occluder is the
//! ground (2 % with local volumes), 8 % in the shadowed scenes (the sun's shaft through
//! a slot, whose 95th percentile must also stay within 25 %; a lamp behind a pillar; a
//! spot light through a barred window; a dense column of medium casting a shaft of
//! shadow into thin fog, whose 95th percentile must stay within 15 %); transmittance
//! 1 %. The first frame's error and the grid
//! floor (`truth::floor`: a perfect shadow term at the same grid, on the CPU) are
//! printed beside it; in the scenes shadowed by occluders the floor must meet the same
//! bound (else the bound is out of the grid's reach), and the image must have stopped
//! changing over its last jitter cycle. Mitsuba's own noise is measured from a second
//! seed and printed; it must stay below the bounds.
//!
//! Negative controls, which must miss the same bounds: twice the density, the wrong
//! phase g, the lamps unshadowed, the local volumes casting no shadow, and for the slot
//! the former default shadow filter (blurred exponential shadow maps of 256 texels per
//! cascade).

use crate::common::gpu;
use volfog_testkit::truth::compare::ErrorStats;
use volfog_testkit::truth::mitsuba::MitsubaOptions;
use volfog_testkit::truth::report::{Reference, Row, SPP, SceneErrors, floor_errors, row};
use volfog_testkit::truth::scene::TruthScene;
use volfog_testkit::truth::scenes;
use volfog_testkit::truth::volfog::VolfogOptions;

/// Mean relative error of the in-scattered radiance in scenes whose only occluder is
/// the ground.
const RADIANCE_BOUND: f32 = 0.03;
/// The same in the scenes whose lights are shadowed by occluders in view.
const SHADOWED_RADIANCE_BOUND: f32 = 0.08;
/// The 95th percentile of the radiance error in the slot's shaft.
const SLOT_P95_BOUND: f32 = 0.25;
/// Mean relative error of the radiance with local volumes, whose shadows on the fog
/// come from the medium-shadow volume (FogConfig::medium_shadows; without it the
/// volumes' own extinction is left out of the light's paths, about 3 % here).
const LOCAL_VOLUME_BOUND: f32 = 0.02;
/// The same where a dense column casts a shaft of shadow into thin fog (its edges
/// resolved by the medium-shadow volume's texels and the froxels).
const SHADOW_COLUMN_BOUND: f32 = 0.08;
/// The 95th percentile of the radiance error there: the shaft covers a few percent of
/// the blocks, so its error shows in the tail rather than the mean.
const SHADOW_COLUMN_P95_BOUND: f32 = 0.15;
/// Mean relative error of the transmittance.
const TRANSMITTANCE_BOUND: f32 = 0.01;
/// Mitsuba's noise of one compared block must stay below this fraction of the radiance
/// bound.
const NOISE_SHARE: f32 = 1.0;
/// Mean relative change of the compared blocks over the last jitter cycle. What is
/// left of the history's transient in the last image decays by 0.9 a frame, so it is
/// `0.9^16 / (1 - 0.9^16) = 0.23` times the change over the last 16 frames: at most
/// 0.23 % of the radiance here, small against the bounds.
const SETTLED: f32 = 0.01;

/// The bounds of a scene: the mean radiance error and, for the slot, its 95th
/// percentile.
fn bounds(scene: &TruthScene) -> (f32, Option<f32>) {
    if scene.name == "shadow_column" {
        return (SHADOW_COLUMN_BOUND, Some(SHADOW_COLUMN_P95_BOUND));
    }
    if !scene.volumes.is_empty() {
        return (LOCAL_VOLUME_BOUND, None);
    }
    if scene.name == "slot_shaft" {
        return (SHADOWED_RADIANCE_BOUND, Some(SLOT_P95_BOUND));
    }
    // Occluders besides the ground put shadows in view.
    if scene.occluders.len() > 1 {
        (SHADOWED_RADIANCE_BOUND, None)
    } else {
        (RADIANCE_BOUND, None)
    }
}

/// Whether `error` is at most `bound` (a NaN error is not).
fn within(error: f32, bound: f32) -> bool {
    error <= bound
}

/// Whether the errors meet the scene's bounds (the message says which does not).
fn within_bounds(scene: &TruthScene, e: &SceneErrors) -> Result<(), String> {
    let (mean, p95) = bounds(scene);
    let mut missed = Vec::new();
    if !within(e.radiance.mean, mean) {
        missed.push(format!(
            "radiance mean {:.2} % > {:.0} %",
            e.radiance.mean * 100.0,
            mean * 100.0
        ));
    }
    if let Some(p95) = p95
        && !within(e.radiance.p95, p95)
    {
        missed.push(format!(
            "radiance p95 {:.2} % > {:.0} %",
            e.radiance.p95 * 100.0,
            p95 * 100.0
        ));
    }
    if !within(e.transmittance.mean, TRANSMITTANCE_BOUND) {
        missed.push(format!(
            "transmittance mean {:.2} % > {:.0} %",
            e.transmittance.mean * 100.0,
            TRANSMITTANCE_BOUND * 100.0
        ));
    }
    if missed.is_empty() {
        Ok(())
    } else {
        Err(missed.join(", "))
    }
}

fn pair(s: &ErrorStats) -> String {
    format!("{:.2} / {:.2} %", s.mean * 100.0, s.p95 * 100.0)
}

fn print(label: &str, e: &SceneErrors) {
    let mut line = format!(
        "{label}: radiance mean / p95 {} ({} blocks, volfog/Mitsuba {:.4}), transmittance {}",
        pair(&e.radiance),
        e.radiance.pixels,
        e.radiance_ratio,
        pair(&e.transmittance)
    );
    if let (Some(o), Some(i)) = (e.outside_penumbra, e.inside_penumbra) {
        line += &format!(
            "; outside the sun's penumbra {} ({} blocks), inside {} ({} blocks)",
            pair(&o),
            o.pixels,
            pair(&i),
            i.pixels
        );
    }
    eprintln!("{line}");
}

fn reference(scene: &TruthScene) -> Reference {
    let mitsuba = MitsubaOptions {
        spp: SPP,
        ..MitsubaOptions::default()
    };
    let reference = Reference::render(scene, &mitsuba).unwrap_or_else(|e| panic!("{e}"));
    let noise = reference.noise;
    eprintln!(
        "{}: Mitsuba noise {:.2} % per pixel, {:.2} % per 4x4 block, {:.3} % of the image mean",
        scene.name,
        noise.per_pixel * 100.0,
        reference.block_noise * 100.0,
        noise.image_mean * 100.0,
    );
    assert!(
        reference.block_noise <= NOISE_SHARE * bounds(scene).0,
        "{}: Mitsuba's noise {:.2} % per block is too large against the bound",
        scene.name,
        reference.block_noise * 100.0
    );
    reference
}

/// A configuration that must miss the scene's bounds.
enum Wrong {
    /// volfog renders this variant of the scene (one frame: a check that the comparison
    /// can fail, not a measurement).
    Scene(&'static str, TruthScene),
    /// volfog renders the scene under these options.
    Options(&'static str, VolfogOptions),
}

/// Compares the scene at the default configuration, converged, with Mitsuba (and
/// prints the first frame's and the grid floor's errors), then each deliberately wrong
/// variant (which must miss the bounds). Returns the default's row.
fn compare(scene: TruthScene, wrong: &[Wrong]) -> Row {
    let gpu = gpu();
    let reference = reference(&scene);
    let options = VolfogOptions::default();
    let r = row(gpu, &reference, "default", &options).unwrap_or_else(|e| panic!("{e}"));
    let floor = floor_errors(&reference, &options).unwrap_or_else(|e| panic!("{e}"));
    print(
        &format!("{} converged ({} frames)", scene.name, r.frames),
        &r.converged,
    );
    print(&format!("{} first frame", scene.name), &r.first);
    print(&format!("{} grid floor", scene.name), &floor);
    let settled = r.last_cycle.expect("more frames than a jitter cycle");
    eprintln!(
        "{}: change over the last jitter cycle mean {:.4} %, max {:.4} %",
        scene.name,
        settled.mean * 100.0,
        settled.max * 100.0
    );
    // The spot light's cone, the smallest lit area, covers 60 blocks of 880.
    assert!(
        r.converged.radiance.pixels >= 50,
        "{}: only {} blocks compared",
        scene.name,
        r.converged.radiance.pixels
    );
    // In the shadowed scenes the floor says whether a shadow filter can meet the bound
    // at this grid. (It samples each froxel's light at its centre, so elsewhere the
    // jittered image can beat it: at a spot cone's edge, which is no shadow.)
    if scene.occluders.len() > 1
        && let Err(missed) = within_bounds(&scene, &floor)
    {
        panic!(
            "{}: the grid floor misses the bounds ({missed}): no shadow filter can meet them at this grid",
            scene.name
        );
    }
    let (mean, _) = bounds(&scene);
    if let Err(missed) = within_bounds(&scene, &r.converged) {
        panic!(
            "{} against Mitsuba, converged: {missed} (first frame {}, grid floor {}, bound {:.0} %)",
            scene.name,
            pair(&r.first.radiance),
            pair(&floor.radiance),
            mean * 100.0
        );
    }
    assert!(
        settled.mean <= SETTLED,
        "{}: the image still changes by {:.3} % over the last jitter cycle",
        scene.name,
        settled.mean * 100.0
    );
    for wrong in wrong {
        let (label, errors) = match wrong {
            Wrong::Scene(label, variant) => {
                let bad = Reference {
                    scene: variant.clone(),
                    ..reference.clone()
                };
                let once = VolfogOptions {
                    frames: 1,
                    ..options.clone()
                };
                let r = row(gpu, &bad, label, &once).unwrap_or_else(|e| panic!("{e}"));
                (label, r.converged)
            }
            Wrong::Options(label, o) => {
                let r = row(gpu, &reference, label, o).unwrap_or_else(|e| panic!("{e}"));
                (label, r.converged)
            }
        };
        print(
            &format!("{} with {label} (negative control)", scene.name),
            &errors,
        );
        assert!(
            within_bounds(&scene, &errors).is_err(),
            "{}: volfog with {label} still meets the bounds",
            scene.name
        );
    }
    r
}

/// The light's paths dimmed by the height profile alone: the local volumes cast no
/// shadow (converged, like the default).
fn medium_unshadowed() -> Wrong {
    Wrong::Options(
        "no medium shadows",
        VolfogOptions::default().with_config(|c| c.medium_shadows = None),
    )
}

/// The lamps of the scene lit unshadowed (one frame).
fn lamps_unshadowed() -> Wrong {
    let options = VolfogOptions {
        frames: 1,
        ..VolfogOptions::default()
    };
    Wrong::Options(
        "the lamps unshadowed",
        options.with_config(|c| c.local_shadows = None),
    )
}

#[test]
fn homogeneous_sun_matches_mitsuba() {
    let scene = scenes::homogeneous_sun();
    let mut doubled = scene.clone();
    doubled.medium.density *= 2.0;
    compare(scene, &[Wrong::Scene("twice the density", doubled)]);
}

#[test]
fn height_fog_under_a_low_sun_matches_mitsuba() {
    let scene = scenes::height_fog_low_sun();
    let mut isotropic = scene.clone();
    isotropic.medium.phase_g = 0.0;
    compare(scene, &[Wrong::Scene("g = 0 instead of 0.6", isotropic)]);
}

/// The sun's shaft through a slot in a wall. The former default shadow filter, blurred
/// exponential shadow maps of 256 texels per cascade (exponent 40), leaks light around
/// the shaft and must miss the bounds (converged, like the default).
#[test]
fn sun_shaft_through_a_slot_matches_mitsuba() {
    compare(
        scenes::slot_shaft(),
        &[Wrong::Options(
            "the blurred 256-texel ESM",
            VolfogOptions::default().esm_256(),
        )],
    );
}

#[test]
fn point_light_matches_mitsuba() {
    let scene = scenes::point_light();
    let mut backwards = scene.clone();
    backwards.medium.phase_g = -scene.medium.phase_g;
    compare(scene, &[Wrong::Scene("g = -0.3 instead of 0.3", backwards)]);
}

#[test]
fn spot_light_matches_mitsuba() {
    compare(scenes::spot_light(), &[]);
}

#[test]
fn local_volumes_match_mitsuba() {
    compare(scenes::local_volumes(), &[medium_unshadowed()]);
}

/// A dense column's shadow shaft in thin fog.
#[test]
fn shadow_column_matches_mitsuba() {
    compare(scenes::shadow_column(), &[medium_unshadowed()]);
}

/// A point lamp behind a pillar whose shadow wedge crosses the view.
#[test]
fn lamp_behind_a_pillar_matches_mitsuba() {
    compare(scenes::pillar_lamp(), &[lamps_unshadowed()]);
}

/// A spot light through a barred window in a wall.
#[test]
fn spot_through_a_window_matches_mitsuba() {
    compare(scenes::spot_window(), &[lamps_unshadowed()]);
}
