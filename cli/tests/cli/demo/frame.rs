//! The frame as a whole: every pass runs and is timed, the probe images are finite,
//! the semi-transparent pass blends over the fogged image, and the PNG decodes.

use super::{FRAMES, HEIGHT, WIDTH, num, read_f32, read_rgba, run, sum3};

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
            "lamp shadow map",
            "opaque + sky",
            "froxel cull",
            "esm downsample",
            "esm blur",
            "local shadows",
            "inject + temporal",
            "scan",
            "fog apply",
            "transparent",
            "tonemap"
        ]
    );
    // The compare filter reads the shadow maps themselves: no ESM pass runs.
    let compare = p["fog"]["shadow_filter"]
        .as_str()
        .unwrap()
        .starts_with("Compare");
    let esm_passes = ["esm downsample", "esm blur", "local shadows"];
    if p["timestamps"] == true {
        for pass in p["passes"].as_array().unwrap() {
            let runs = pass["frames_with_gpu_time"].as_u64().unwrap();
            let ms = num(&pass["gpu_ms_median"]);
            eprintln!(
                "{:<16} {runs} frames timed, median {ms:.3} ms",
                pass["name"]
            );
            if compare && esm_passes.contains(&pass["name"].as_str().unwrap()) {
                assert_eq!(runs, 0, "{} ran with the compare filter", pass["name"]);
                continue;
            }
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
    // The shadow map the fog reads holds occluders (the ESM: values below the
    // unoccluded exp(c * 1), log space: c; the map: depths below the far plane's 1) and
    // the integrated volume attenuates towards its far end.
    let fog = &p["fog"];
    // The demo culls by its depth buffer: the ground and pillars hide part of the
    // volume, the sky none of it.
    let live = num(&fog["live_fraction"]);
    eprintln!(
        "demo: {:.1} % of the froxels live after depth culling",
        100.0 * live
    );
    assert!(live > 0.2 && live < 0.95, "live fraction {live}");
    let (low, high) = if compare {
        read_f32(run, "sun_shadow.f32")
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &d| {
                (l.min(d), h.max(d))
            })
    } else {
        (num(&fog["esm_min"]) as f32, num(&fog["esm_max"]) as f32)
    };
    let t_far = num(&fog["mean_transmittance_far"]);
    eprintln!("shadow map range {low:.2}..{high:.2}, mean far transmittance {t_far:.3}");
    assert!(low < 0.9 * high, "the shadow map has occluders");
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
