//! `volfog bench`: a quick run through the binary writes a complete JSON report
//! (structure and plausibility only: performance is never asserted), and the cost model
//! reads each pass's textures from its shader. The per-pixel raymarch reference is
//! checked in `raymarch.rs`.

use volfog::pipeline::FogConfig;

#[test]
fn quick_bench_writes_every_ratio_memory_and_adapter() {
    let dir = std::env::temp_dir().join(format!("volfog-bench-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("bench.json");
    let started = std::time::Instant::now();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_volfog"))
        .args([
            "bench", "--quick", "--json", "--warmup", "0", "--frames", "1", "--out",
        ])
        .arg(&out)
        .output()
        .expect("the volfog binary runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    eprintln!(
        "{stdout}\n{stderr}\nbench took {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(run.status.success(), "volfog bench failed: {stderr}");
    for line in [
        "scan / copy",
        "apply / blit",
        "raymarch / froxel pipeline",
        "froxel cost 4K / 720p camera",
        "inject (baseline) / write",
        "inject (fast) / write",
        "raymarch / froxel fast",
        "froxels live after depth culling",
        "sky and clouds / blit 1080p",
        "apply stages / blit 1080p",
        "epipolar march: every section / tree",
        "epipolar: per-pixel / epipolar path",
        "epipolar image: lit fraction error",
        "EpipolarShafts::memory_bytes",
        "inject shadowed / unshadowed",
        "(inject + atlas) / inject unshadowed",
        "inject shadowed / None",
        "(inject + atlas) / inject None",
        "inject unshadowed / None",
        "local shadow atlas memory",
        "light through the local shadows",
        "sun: compare inject / ESM path",
        "sun: compare 2 taps / ESM path",
        "sun: compare inject / ESM inject",
        "lamps: compare inject / unshadowed",
        "lamps: compare / ESM inject + atlas",
        "lamps: compare / ESM, maps kept",
        "raymarch's ESM (the ESM fog's)",
        "fused inject / inject + temporal apart",
        "VolumetricFog::memory_bytes",
        "memory floor",
    ] {
        assert!(
            stderr.contains(line),
            "the table (on stderr with --json) lacks {line:?}"
        );
    }

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let printed: serde_json::Value =
        serde_json::from_str(&stdout).expect("with --json stdout is the report alone");
    assert_eq!(
        printed, report,
        "stdout carries the report written to --out"
    );
    let cost = report["cost"]["passes"].as_array().expect("cost model");
    assert_eq!(cost.len(), 12, "every modelled pass: {}", report["cost"]);
    for pass in cost {
        for key in ["floor_ms", "measured_vs_floor"] {
            let values = pass[key].as_array().expect("one per bandwidth");
            assert_eq!(values.len(), 2, "{pass}");
            assert!(
                values
                    .iter()
                    .all(|v| v.as_f64().is_some_and(|v| v.is_finite() && v > 0.0)),
                "{key}: {pass}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    for ratio in [
        "scan_vs_copy",
        "apply_vs_blit",
        "raymarch_vs_froxel",
        "froxel_4k_vs_720p",
        "inject_vs_write",
        "inject_fast_vs_write",
        "raymarch_vs_froxel_fast",
    ] {
        let r = &report["ratios"][ratio];
        let value = r["value"].as_f64().unwrap_or(f64::NAN);
        assert!(
            value.is_finite() && value > 0.0,
            "ratio {ratio} = {value}: {r}"
        );
        assert!(r["target"].is_string() && r["met"].is_boolean(), "{r}");
        // Each target ratio is the median of its paired samples: one per measured frame
        // (one here, which runs the raymarch too), three pairs of cameras per frame for
        // the 4K / 720p ratio.
        let mut frames: Vec<f64> = r["frames"]["samples"]
            .as_array()
            .expect("paired ratios")
            .iter()
            .map(|v| v.as_f64().expect("a number"))
            .collect();
        let pairs = if ratio == "froxel_4k_vs_720p" { 3 } else { 1 };
        assert_eq!(frames.len(), pairs, "{r}");
        frames.sort_by(f64::total_cmp);
        assert_eq!(frames[pairs / 2], value, "{r}");
    }
    let fused = &report["fused_temporal"];
    for key in [
        "fused_inject_ms",
        "separate_inject_temporal_ms",
        "fused_vs_separate",
        "froxel_fast_fused_vs_separate",
    ] {
        let v = fused[key].as_f64().unwrap_or(f64::NAN);
        assert!(v.is_finite() && v > 0.0, "fused_temporal {key} = {v}");
    }
    for key in [
        "sky_solve_vs_blit",
        "cloud_shadow_vs_blit",
        "distance_clouds_vs_blit",
    ] {
        let v = report["atmosphere"][key].as_f64().unwrap_or(f64::NAN);
        assert!(v.is_finite() && v > 0.0, "atmosphere {key} = {v}");
    }
    let stages = &report["apply_breakdown"];
    for key in [
        "depth_vs_blit",
        "unproject_vs_blit",
        "lookup_vs_blit",
        "tail_untaken_vs_blit",
        "apply_vs_blit",
    ] {
        let v = stages[key].as_f64().unwrap_or(f64::NAN);
        assert!(v.is_finite() && v > 0.0, "apply_breakdown {key} = {v}");
    }
    let beyond = stages["beyond_far_fraction"].as_f64().unwrap_or(f64::NAN);
    assert!(
        beyond > 0.0 && beyond < 1.0,
        "the bench scene has pixels on both sides of the far plane: {beyond}"
    );
    for ratio in ["march_steps_vs_tree", "reference_vs_epipolar"] {
        let r = &report["shafts"][ratio];
        let value = r["value"].as_f64().unwrap_or(f64::NAN);
        assert!(
            value.is_finite() && value > 0.0,
            "shafts {ratio} = {value}: {r}"
        );
    }
    let image = &report["shafts"]["image"];
    for key in [
        "lit_fraction_mean_abs_error",
        "fine_mean_abs_error",
        "reference_vs_fine_mean_abs_error",
    ] {
        let v = image[key].as_f64().unwrap_or(f64::NAN);
        assert!(
            v.is_finite() && (0.0..1.0).contains(&v),
            "shafts image {key} = {v}"
        );
    }
    assert_eq!(image["nan_pixels"], 0, "no NaN in the shafts");
    assert!(image["memory_bytes"].as_u64().unwrap_or(0) > 0);
    let passes = report["passes"].as_object().expect("passes");
    for key in [
        "inject",
        "temporal",
        "scan",
        "copy",
        "apply_1080p",
        "blit_1080p",
        "froxel_1080p",
        "raymarch_1080p",
        "sky_solve",
        "cloud_shadow_1080p",
        "distance_clouds_1080p",
        "froxel_720p",
        "froxel_4k",
        "cull",
        "inject_cull",
        "inject_checkerboard",
        "inject_noise_texture",
        "inject_fast",
        "inject_fast_separate",
        "temporal_fast",
        "froxel_fast_separate_1080p",
        "write",
        "froxel_fast_1080p",
        "epipolar_tree",
        "epipolar_march_tree",
        "epipolar_march_steps",
        "epipolar_1080p",
        "epipolar_reference_1080p",
        "local_inject_compiled_out",
        "local_inject_unshadowed",
        "local_inject_shadowed",
        "local_shadow_atlas",
        "local_shadowed_total",
        "local_inject_kept",
        "local_kept_total",
        "local_compare_unshadowed",
        "local_compare_shadowed",
        "inject_compare_2",
        "esm_downsample",
        "esm_blur",
        "inject_esm",
        "esm_filter_total",
    ] {
        let median = passes[key]["median_ms"].as_f64().unwrap_or(f64::NAN);
        assert!(median.is_finite() && median > 0.0, "{key}: {median}");
    }
    let local = &report["local_shadows"];
    let ratio = |key: &str| {
        let r = &local[key];
        assert_eq!(r["target"], "<= 1.5", "{key}: {r}");
        assert!(r["met"].is_boolean(), "{key}: {r}");
        r["value"].as_f64().unwrap_or(f64::NAN)
    };
    let inject = ratio("inject_shadowed_vs_unshadowed");
    let total = ratio("total_shadowed_vs_unshadowed");
    assert!(
        inject.is_finite() && inject > 0.5 && total > inject,
        "local shadows: inject {inject}, with the atlas {total}: {local}"
    );
    let inject = ratio("inject_shadowed_vs_compiled_out");
    let total = ratio("total_shadowed_vs_compiled_out");
    assert!(
        inject.is_finite() && inject > 0.5 && total > inject,
        "against local_shadows None: inject {inject}, with the atlas {total}: {local}"
    );
    // With the maps unchanged the atlas keeps all 16 layers and fills none.
    let kept = ratio("total_kept_vs_unshadowed");
    assert!(kept.is_finite() && kept > 0.5, "maps kept: {kept}: {local}");
    assert_eq!(local["kept_layers"], 4 + 6 * 2, "{local}");
    assert_eq!(local["kept_filled"], 0, "{local}");
    let compiled_in = local["unshadowed_vs_compiled_out"]
        .as_f64()
        .unwrap_or(f64::NAN);
    assert!(compiled_in.is_finite() && compiled_in > 0.0, "{local}");
    assert!(
        local["atlas_ms"].as_f64().unwrap_or(f64::NAN) > 0.0,
        "{local}"
    );
    assert_eq!(local["spot_shadows"], 4, "{local}");
    assert_eq!(local["point_shadows"], 2, "{local}");
    assert_eq!(local["over_budget"], 0, "{local}");
    assert_eq!(local["atlas_layers"], 4 + 6 * 2, "{local}");
    assert_eq!(local["atlas_resolution"], 256, "{local}");
    assert_eq!(local["depth_map_resolution"], 1024, "{local}");
    // The atlas and the blur's scratch array: 16 R32Float layers of 256 x 256 each.
    assert_eq!(local["atlas_bytes"], 2 * 16 * 256 * 256 * 4, "{local}");
    assert_eq!(local["depth_map_bytes"], 16 * 1024 * 1024 * 4, "{local}");
    let lit = local["light_through_shadows"].as_f64().unwrap_or(f64::NAN);
    assert!(
        lit > 0.0 && lit < 1.0,
        "the lights' shadows darken the fog the camera sees: {lit}"
    );

    // The two shadow filters side by side: the sun's pairs are taken frame by frame
    // (one frame here), the lamps' from the medians.
    let filters = &report["shadow_filters"];
    for key in ["sun_compare_vs_esm", "sun_compare_2_vs_esm"] {
        let r = &filters[key];
        let value = r["value"].as_f64().unwrap_or(f64::NAN);
        assert!(value.is_finite() && value > 0.0, "{key}: {r}");
        assert_eq!(r["target"], "<= 1", "{key}: {r}");
        assert!(r["met"].is_boolean(), "{key}: {r}");
        assert_eq!(
            r["frames"]["samples"],
            serde_json::json!([value]),
            "{key}: {r}"
        );
    }
    let passes_ms = |key: &str| passes[key]["median_ms"].as_f64().unwrap_or(f64::NAN);
    assert!(
        passes_ms("esm_filter_total") > passes_ms("inject_esm"),
        "the ESM path is its passes and its inject: {filters}"
    );
    for (key, target) in [
        ("lamps_compare_vs_unshadowed", "<= 1.5"),
        ("lamps_compare_vs_esm", "<= 1"),
    ] {
        let r = &filters[key];
        let value = r["value"].as_f64().unwrap_or(f64::NAN);
        assert!(value.is_finite() && value > 0.5, "{key}: {r}");
        assert_eq!(r["target"], target, "{key}: {r}");
        assert!(r["met"].is_boolean(), "{key}: {r}");
    }
    for key in [
        "sun_inject_compare_vs_esm",
        "sun_compare_2_vs_compare",
        "sun_esm_passes_ms",
        "lamps_compare_vs_esm_kept",
        "lamps_unshadowed_compare_vs_esm",
    ] {
        let v = filters[key].as_f64().unwrap_or(f64::NAN);
        assert!(v.is_finite() && v > 0.0, "shadow_filters {key} = {v}");
    }
    // The compare filter tests the lamps' own depth maps: no atlas.
    assert!(
        filters["lamps_compare_bytes"]
            .as_u64()
            .is_some_and(|b| b < local["atlas_bytes"].as_u64().unwrap_or(0) / 100),
        "{filters}"
    );
    let lit = filters["lamps_compare_light_through_shadows"]
        .as_f64()
        .unwrap_or(f64::NAN);
    assert!(
        lit > 0.0 && lit < 1.0,
        "under the compare filter too the lamps' shadows darken the fog: {lit}"
    );
    // The raymarch reads a filtered ESM of the four 256-texel cascades, not the 1 x 1
    // placeholder of the compare filter's fog: occluders at more than one depth.
    let esm = &report["raymarch_esm"];
    assert_eq!(esm["size"], serde_json::json!([256, 256, 4]), "{esm}");
    assert_eq!(esm["nan_texels"], 0, "{esm}");
    let (lo, hi) = (
        esm["occluder_depth_min"].as_f64().unwrap_or(f64::NAN),
        esm["occluder_depth_max"].as_f64().unwrap_or(f64::NAN),
    );
    assert!(
        lo >= -1e-3 && lo + 1e-2 < hi && hi <= 1.0 + 1e-3,
        "occluder depths {lo} to {hi}: {esm}"
    );

    let bytes = report["memory"]["bytes"].as_u64().unwrap_or(0);
    assert!(bytes > 0, "memory figure: {}", report["memory"]);
    assert!(report["memory"]["met"].is_boolean());
    let adapter = report["adapter"].as_str().unwrap_or("");
    assert!(!adapter.is_empty(), "adapter name");
    assert!(report["clock"].is_string());
    assert_eq!(report["settings"]["raymarch_steps"], 64);
    let live = report["culling"]["live_fraction"]
        .as_f64()
        .unwrap_or(f64::NAN);
    assert!(live > 0.0 && live < 1.0, "the bench scene culls: {live}");

    // Short-lived lights: the baseline's scan without, with one and with eight; eight
    // lights evaluated at every froxel cost more than none.
    assert!(stdout.contains("short-lived lights") || stderr.contains("short-lived lights"));
    let t = &report["transient_lights"];
    let get = |key: &str| t[key].as_f64().unwrap_or(f64::NAN);
    for key in [
        "scan_ms",
        "scan_1_ms",
        "scan_8_ms",
        "separate_pass_floor_ms",
    ] {
        assert!(get(key).is_finite() && get(key) > 0.0, "{key}: {t}");
    }
    // The JSON's numbers are parsed back within an ulp, not always to the same bits.
    let added = get("scan_8_ms") - get("scan_ms");
    assert!(
        (added - get("added_8_ms")).abs() <= 1e-9 * get("scan_8_ms"),
        "{t}"
    );
    assert!(get("scan_8_ms") > get("scan_ms"), "{t}");
    for key in ["scan_1_vs_none", "scan_8_vs_none"] {
        assert_eq!(
            t[key]["samples"].as_array().map(Vec::len),
            Some(1),
            "{key}: {t}"
        );
    }

    // Area lights: inject with four point, rectangle and disk lights added, and the
    // cost per light of each kind against a point light.
    let a = &report["area_lights"];
    let get = |key: &str| a[key].as_f64().unwrap_or(f64::NAN);
    assert!(get("inject_ms") > 0.0, "{a}");
    for key in [
        "point_ms",
        "rect_ms",
        "disk_ms",
        "rect_vs_point",
        "disk_vs_point",
    ] {
        assert!(get(key).is_finite(), "{key}: {a}");
    }
    // One unwarmed frame times each configuration once: the differences are left to
    // the full run (a timed test would fail on a busy machine).
    eprintln!("area lights, one frame: {a}");

    // Particles: inject with none, 1,000 and 10,000, and the ratios to none.
    let p = &report["particles"];
    let get = |key: &str| p[key].as_f64().unwrap_or(f64::NAN);
    for key in [
        "baseline_inject_ms",
        "inject_0_ms",
        "inject_1000_ms",
        "inject_10000_ms",
    ] {
        assert!(get(key) > 0.0, "{key}: {p}");
    }
    for key in ["ratio_1000_vs_0", "ratio_10000_vs_0"] {
        assert!(get(key).is_finite(), "{key}: {p}");
    }
    eprintln!("particles, one frame: {p}");

    // The medium's shadows: their pass and inject beside the baseline's inject.
    let m = &report["medium_shadows"];
    let get = |key: &str| m[key].as_f64().unwrap_or(f64::NAN);
    for key in [
        "pass_ms",
        "inject_ms",
        "baseline_inject_ms",
        "total_vs_inject",
    ] {
        assert!(get(key).is_finite() && get(key) > 0.0, "{key}: {m}");
    }
    eprintln!("medium shadows, one frame: {m}");
}

/// The cost model reads the passes' textures from their composed shaders: the copy
/// reads its source and writes its destination, one volume each; the fused inject
/// reads the history and writes the stabilised volume, not the scattering volume the
/// separate path writes; culling scales the volume traffic by the live share; each
/// floor is the bytes over the bandwidth.
#[test]
fn cost_model_counts_each_pass_textures_from_its_shader() {
    use volfog_cli::bench::cost;
    let config = FogConfig {
        fuse_temporal: false,
        ..FogConfig::default()
    };
    let live = 0.25;
    let model = cost::model(&config, &cost::sizes(&config, live), &|_| 2.0).unwrap();
    let volume = 160 * 90 * 128 * 8u64;
    let pass = |series: &str| {
        model
            .passes
            .iter()
            .find(|p| p.series == series)
            .unwrap_or_else(|| panic!("no {series} in {model:#?}"))
    };
    let texture = |series: &str, name: &str| {
        pass(series)
            .textures
            .iter()
            .find(|t| t.uses.name == name)
            .map(|t| (t.uses.read_sites, t.uses.write_sites, t.bytes))
    };
    let copy = pass("copy");
    assert_eq!(
        (copy.bytes_read, copy.bytes_written),
        (volume, volume),
        "{copy:#?}"
    );
    assert_eq!(
        texture("copy", "source").map(|t| (t.0 > 0, t.1)),
        Some((true, 0))
    );
    assert_eq!(
        texture("copy", "destination").map(|t| (t.0, t.1 > 0)),
        Some((0, true))
    );
    for (i, bandwidth) in cost::BANDWIDTHS_TB_S.iter().enumerate() {
        let floor = 2.0 * volume as f64 / (bandwidth * 1e12) * 1e3;
        assert!((copy.floor_ms[i] - floor).abs() < 1e-12, "{copy:#?}");
        assert!((copy.measured_vs_floor[i] - 2.0 / floor).abs() < 1e-9);
    }
    let write = pass("write");
    assert_eq!(
        (write.bytes_read, write.bytes_written),
        (0, volume),
        "{write:#?}"
    );

    let quarter = (volume as f64 * live).round() as u64;
    // The fused inject writes the stabilised volume through its output binding.
    let fused = texture("inject_fast", "scattering").expect("the fused inject writes its output");
    assert!(fused.1 > 0 && fused.2 == quarter, "{fused:?}");
    assert!(
        texture("inject_fast", "history").is_some_and(|t| t.0 > 0 && t.1 == 0 && t.2 == quarter),
        "the fused inject reads the history: {:#?}",
        pass("inject_fast")
    );
    let separate = texture("inject_fast_separate", "scattering")
        .expect("the separate inject writes scattering");
    assert!(separate.1 > 0 && separate.2 == quarter, "{separate:?}");
    assert!(texture("inject_fast_separate", "history").is_none());
    let baseline = texture("inject", "scattering").expect("inject writes scattering");
    assert_eq!(baseline.2, volume, "the baseline covers every froxel");
    // The sun's shadow: the full-resolution map under the compare filter (the
    // default), the ESM under the ESM filter; each sized as a whole texture.
    let shadow = texture("inject", "shadow_map").or_else(|| texture("inject", "esm_array"));
    assert!(
        shadow.is_some_and(|t| t.0 > 0 && t.2 > 0),
        "inject reads the sun's shadow: {:#?}",
        pass("inject")
    );
    assert!(
        pass("inject").bytes_read > 0 && pass("scan").bytes_written >= volume,
        "{model:#?}"
    );
    let apply = pass("apply_1080p");
    assert!(
        texture("apply_1080p", "scene_depth").is_some_and(|t| t.0 > 0 && t.2 == 1920 * 1080 * 4),
        "{apply:#?}"
    );
    let target = 1920 * 1080 * 8;
    assert_eq!(
        (apply.target_read_bytes, apply.target_written_bytes),
        (target, target)
    );
    let blit = pass("blit_1080p");
    assert_eq!(
        (blit.bytes_read, blit.bytes_written),
        (target, target),
        "{blit:#?}"
    );
}
