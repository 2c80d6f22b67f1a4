//! The bench report as the text table `volfog bench` prints.

use super::*;

/// The report as a text table.
pub fn table(report: &Report) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(out, "\nadapter: {}", report.adapter_details);
    let _ = writeln!(out, "clock: {}", report.clock.describe());
    let _ = writeln!(
        out,
        "{:<30} {:>10} {:>10} {:>10}",
        "pass", "median ms", "min ms", "max ms"
    );
    for (key, _) in SERIES {
        let s = &report.passes[*key];
        let _ = writeln!(
            out,
            "{:<30} {:>10.3} {:>10.3} {:>10.3}",
            s.label, s.median_ms, s.min_ms, s.max_ms
        );
    }
    let _ = writeln!(
        out,
        "  * inject + temporal + scan + apply (the compare filter: no ESM pass; the raymarch reads \
         the ESM fog's {}x{}x{} ESM, untimed)",
        report.raymarch_esm.size[0], report.raymarch_esm.size[1], report.raymarch_esm.size[2]
    );
    let _ = writeln!(out, "  ** inject + temporal + scan, apply excluded");
    let _ = writeln!(
        out,
        "  the baseline and the rows with one of + run the temporal pass apart; \"all three\" \
         fuses it into inject (FogConfig::default), \"apart\" runs the same path with it apart"
    );
    let _ = writeln!(
        out,
        "  *** coords + refine + trees + march + interpolate + resolve + upscale, 512 slices x 256 samples, downscale 2"
    );
    let _ = writeln!(
        out,
        "  + 1080p with the scene depth: culling, checkerboard amortisation, noise texture \
         (the rows without + are the baseline: none of them)"
    );
    let _ = writeln!(
        out,
        "  # the sun's shadow filters: the rows without # take the compare filter at one tap \
         (FogConfig::default); the ESM rows a fog with ShadowFilter::Esm, its inject beside them"
    );
    let _ = writeln!(
        out,
        "  ~ the baseline's scan with short-lived lights (FrameInputs::transient_lights): \
         none, a muzzle flash, eight (six points, a spot, a directional)"
    );
    let l = &report.local_shadows;
    let _ = writeln!(
        out,
        "  ++ baseline, the scene's lights replaced by {} spot + {} point lights, the ESM filter \
         unless \"compare\"; atlas {} layers of {}x{} from {}x{} depth maps; None: \
         FogConfig::local_shadows None; maps kept: their maps unchanged, {} layers kept and {} filled",
        l.spot_shadows,
        l.point_shadows,
        l.atlas_layers,
        l.atlas_resolution,
        l.atlas_resolution,
        l.depth_map_resolution,
        l.depth_map_resolution,
        l.kept_layers,
        l.kept_filled
    );
    let _ = writeln!(
        out,
        "\n{:<36} {:>10} {:>10}  status",
        "ratio", "value", "target"
    );
    let r = &report.ratios;
    for (name, ratio) in [
        ("scan / copy", &r.scan_vs_copy),
        ("apply / blit", &r.apply_vs_blit),
        (
            "raymarch / froxel pipeline (speed-up)",
            &r.raymarch_vs_froxel,
        ),
        ("froxel cost 4K / 720p camera", &r.froxel_4k_vs_720p),
        ("inject (baseline) / write", &r.inject_vs_write),
        ("inject (fast) / write", &r.inject_fast_vs_write),
        (
            "raymarch / froxel fast (speed-up)",
            &r.raymarch_vs_froxel_fast,
        ),
        (
            "epipolar march: every section / tree",
            &report.shafts.march_steps_vs_tree,
        ),
        (
            "epipolar: per-pixel / epipolar path",
            &report.shafts.reference_vs_epipolar,
        ),
        (
            "inject shadowed / unshadowed",
            &l.inject_shadowed_vs_unshadowed,
        ),
        (
            "(inject + atlas) / inject unshadowed",
            &l.total_shadowed_vs_unshadowed,
        ),
        ("inject shadowed / None", &l.inject_shadowed_vs_compiled_out),
        (
            "(inject + atlas) / inject None",
            &l.total_shadowed_vs_compiled_out,
        ),
        (
            "(inject + atlas) kept / unshadowed",
            &l.total_kept_vs_unshadowed,
        ),
        (
            "sun: compare inject / ESM path",
            &report.shadow_filters.sun_compare_vs_esm,
        ),
        (
            "sun: compare 2 taps / ESM path",
            &report.shadow_filters.sun_compare_2_vs_esm,
        ),
        (
            "lamps: compare inject / unshadowed",
            &report.shadow_filters.lamps_compare_vs_unshadowed,
        ),
        (
            "lamps: compare / ESM inject + atlas",
            &report.shadow_filters.lamps_compare_vs_esm,
        ),
    ] {
        let spread = ratio
            .frames
            .as_ref()
            .map(|f| {
                format!(
                    "  (median of {} paired samples, {:.3}x to {:.3}x)",
                    f.samples.len(),
                    f.min,
                    f.max
                )
            })
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "{:<36} {:>9.3}x {:>10}  {}{}",
            name,
            ratio.value,
            ratio.target,
            status(ratio.met),
            spread
        );
    }
    let _ = writeln!(
        out,
        "{:<36} {:>9.1}%  (inject {:.2}x cheaper with culling alone)",
        "froxels live after depth culling",
        100.0 * report.culling.live_fraction,
        report.culling.inject_saving
    );
    let a = &report.atmosphere;
    let _ = writeln!(
        out,
        "{:<36} {:>9.2}x / {:.2}x / {:.2}x  (sky solve, cloud shadow, distance clouds)",
        "sky and clouds / blit 1080p",
        a.sky_solve_vs_blit,
        a.cloud_shadow_vs_blit,
        a.distance_clouds_vs_blit
    );
    let b = &report.apply_breakdown;
    let _ = writeln!(
        out,
        "{:<36} {:>9.2}x / {:.2}x / {:.2}x / {:.2}x / {:.2}x  (depth texel, + view position, + volume look-up, tail not taken, apply as drawn: the scene has no tail, so without it; {:.1}% of the pixels beyond far)",
        "apply stages / blit 1080p",
        b.depth_vs_blit,
        b.unproject_vs_blit,
        b.lookup_vs_blit,
        b.tail_untaken_vs_blit,
        b.apply_vs_blit,
        100.0 * b.beyond_far_fraction
    );
    let i = &report.shafts.image;
    let _ = writeln!(
        out,
        "{:<36} {:>10.2e}  (p99 {:.3}) against {} steps/pixel, {:.2e} (p99 {:.3}) against {} ({} alone: {:.2e}); {} pixels corrected by a march, {} not finite",
        "epipolar image: lit fraction error",
        i.lit_fraction_mean_abs_error,
        i.lit_fraction_p99_abs_error,
        report.shafts.reference_steps,
        i.fine_mean_abs_error,
        i.fine_p99_abs_error,
        i.fine_reference_steps,
        report.shafts.reference_steps,
        i.reference_vs_fine_mean_abs_error,
        i.corrected_pixels,
        i.nan_pixels
    );
    let _ = writeln!(
        out,
        "{:<36} {:>6.2} MiB",
        "EpipolarShafts::memory_bytes",
        to_mib(i.memory_bytes)
    );
    let fused = &report.fused_temporal;
    let _ = writeln!(
        out,
        "{:<36} {:>9.3}x  ({:.3} ms against {:.3} ms inject + temporal; the whole cheap path {:.3}x)",
        "fused inject / inject + temporal apart",
        fused.fused_vs_separate,
        fused.fused_inject_ms,
        fused.separate_inject_temporal_ms,
        fused.froxel_fast_fused_vs_separate
    );
    let _ = writeln!(
        out,
        "{:<36} {:>9.3}x  (the sun and the scene's lights through the medium's height profile)",
        "inject / inject, transmittance off", report.transmittance_inject_vs_without
    );
    let _ = writeln!(
        out,
        "{:<36} {:>9.3}x  (a frame without shadowed lights runs inject without local shadows: 1 but for noise)",
        "inject unshadowed / None", l.unshadowed_vs_compiled_out
    );
    let _ = writeln!(
        out,
        "{:<36} {:>6.2} MiB  (atlas pass {:.3} ms; the lights' depth maps {:.2} MiB, the caller's)",
        "local shadow atlas memory",
        l.atlas_mib,
        l.atlas_ms,
        to_mib(l.depth_map_bytes)
    );
    let _ = writeln!(
        out,
        "{:<36} {:>10.3}  (the six lights' in-scattering with / without their shadows, ESM; \
         compare filter {:.3})",
        "light through the local shadows",
        l.light_through_shadows,
        report.shadow_filters.lamps_compare_light_through_shadows
    );
    let sf = &report.shadow_filters;
    let _ = writeln!(
        out,
        "{:<36} {:>9.3}x  (inject alone; the ESM passes {:.3} ms; 2 taps / 1 tap {:.3}x)",
        "sun: compare inject / ESM inject",
        sf.sun_inject_compare_vs_esm,
        sf.sun_esm_passes_ms,
        sf.sun_compare_2_vs_compare
    );
    let _ = writeln!(
        out,
        "{:<36} {:>9.3}x  (the maps kept; unshadowed compare / ESM {:.3}x; the compare filter \
         adds {} bytes: no atlas)",
        "lamps: compare / ESM, maps kept",
        sf.lamps_compare_vs_esm_kept,
        sf.lamps_unshadowed_compare_vs_esm,
        sf.lamps_compare_bytes
    );
    let e = &report.raymarch_esm;
    let _ = writeln!(
        out,
        "{:<36} {}x{}x{}  (occluder depth {:.3} to {:.3}, {} texels not finite)",
        "raymarch's ESM (the ESM fog's)",
        e.size[0],
        e.size[1],
        e.size[2],
        e.occluder_depth_min,
        e.occluder_depth_max,
        e.nan_texels
    );
    let c = &report.cost;
    let _ = writeln!(
        out,
        "\nmemory floor (each texture once per direction; buffers and arithmetic left out)\n{:<22} {:>9} {:>9} {:>11} {:>11} {:>11}  texture read/write sites in the shader",
        "series",
        "read MB",
        "write MB",
        format!("@{} TB/s", c.bandwidths_tb_s[0]),
        format!("@{} TB/s", c.bandwidths_tb_s[1]),
        "measured"
    );
    for p in &c.passes {
        let sites: Vec<String> = p
            .textures
            .iter()
            .map(|t| {
                format!(
                    "{} {}/{}",
                    t.uses.name, t.uses.read_sites, t.uses.write_sites
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "{:<22} {:>9.2} {:>9.2} {:>8.4} ms {:>8.4} ms {:>8.3} ms  {}",
            p.series,
            p.bytes_read as f64 / 1e6,
            p.bytes_written as f64 / 1e6,
            p.floor_ms[0],
            p.floor_ms[1],
            p.measured_ms,
            sites.join(", ")
        );
    }
    transient_table(&mut out, &report.transient_lights);
    area_light_table(&mut out, &report.area_lights);
    stereo_table(&mut out, &report.stereo);
    particle_table(&mut out, &report.particles);
    medium_shadow_table(&mut out, &report.medium_shadows);
    let m = &report.memory;
    let _ = writeln!(
        out,
        "{:<36} {:>6.2} MiB {:>6} MiB  {} ({} bytes)",
        "VolumetricFog::memory_bytes (default)",
        m.mib,
        format!("<= {}", m.limit_mib),
        status(m.met),
        m.bytes
    );
    let _ = writeln!(
        out,
        "{} warm-up + {} measured frames ({} with the raymarch), wall time {:.1} s",
        report.settings.warmup,
        report.settings.frames,
        report.settings.raymarch_frames,
        report.wall_seconds
    );
    out
}
