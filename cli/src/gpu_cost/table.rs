//! The text tables of `volfog gpu-cost`.

use std::fmt::Write as _;

use volfog_cost::measure::PassModel;

use super::{FilterModel, FrameModel, Report};

/// A time in ms: 3 decimals under 1 ms, 2 from there.
pub(super) fn ms(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

fn pass_row(out: &mut String, m: &PassModel, ac4: Option<f64>) {
    let s = &m.stats;
    let c = &m.corrected;
    let e = &m.estimate;
    let bound = if e.memory_bound {
        "memory".to_string()
    } else if e.latency_bound {
        format!("latency ({} waves)", s.waves_per_simd)
    } else {
        "issue".to_string()
    };
    let _ = writeln!(
        out,
        "| {} | {} | {} | {} | {:.0} | {:.0} | {} | {} | {} | {} |{}",
        m.pass.name,
        s.vgprs,
        s.waves_per_simd,
        s.instructions,
        c.aco_latency,
        c.latency,
        ms(e.alu_ms),
        ms(e.memory_ms),
        ms(e.ms),
        bound,
        ac4.map_or(String::new(), |t| format!(
            " {} ({}) |",
            ms(t),
            if e.ms <= t { "met" } else { "missed" }
        )),
    );
}

fn frame(out: &mut String, f: &FrameModel) {
    let g = &f.gpu;
    let _ = writeln!(
        out,
        "\n## {}: {} compute units x {} SIMDs at {:.0} MHz, {:.0} GB/s ({}); grid {}x{}x{}, apply at {}x{}",
        g.name,
        g.compute_units,
        g.chip.simds_per_cu(),
        g.clock_hz / 1e6,
        g.bandwidth_bytes_s / 1e9,
        g.chip.generation(),
        f.grid[0],
        f.grid[1],
        f.grid[2],
        f.workload.screen.0,
        f.workload.screen.1
    );
    let w = &f.workload;
    let _ = writeln!(
        out,
        "bench scene: {} of {} blocks live ({:.1} % of the froxels), {:.2} lights and {:.2} volumes per block, \
         {:.2} cascade steps and {:.1} scan slices per wave",
        w.blocks.0,
        w.blocks.1,
        100.0 * w.live_fraction,
        w.lights_per_block,
        w.volumes_per_block,
        w.cascade_steps,
        w.scan_live
    );
    let with_ac4 = !f.ac4.is_empty();
    let _ = writeln!(
        out,
        "\n| pass | VGPRs | waves/SIMD | instructions | ACO latency | latency, loops by trip count | ALU ms | memory ms | estimate ms | bound |{}",
        if with_ac4 { " AC4 ms |" } else { "" }
    );
    let _ = writeln!(
        out,
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |{}",
        if with_ac4 { " ---: |" } else { "" }
    );
    for m in &f.passes {
        // AC4's figure beside the first pass of its row.
        let ac4 = with_ac4
            .then(|| {
                let first = f.passes.iter().position(|p| p.pass.ac4 == m.pass.ac4)?;
                let here = f.passes.iter().position(|p| std::ptr::eq(p, m))?;
                (first == here).then_some(())?;
                f.ac4
                    .iter()
                    .find(|r| Some(r.name) == m.pass.ac4)
                    .map(|r| r.target_ms)
            })
            .flatten();
        pass_row(out, m, ac4);
    }
    let _ = writeln!(
        out,
        "| **froxel pipeline** | | | | | | | | **{}** | |{}",
        ms(f.total_ms),
        if with_ac4 {
            format!(" {} |", ms(super::AC4_TOTAL_MS))
        } else {
            String::new()
        }
    );
    pass_row(out, &f.raymarch, None);
    for m in &f.floors {
        pass_row(out, m, None);
    }
    let _ = writeln!(
        out,
        "\nraymarch / froxel pipeline: {:.1}x",
        f.raymarch.estimate.ms / f.total_ms
    );
    let floor = |name: &str| f.floors.iter().find(|m| m.pass.name.contains(name));
    let pass = |name: &str| f.passes.iter().find(|m| m.pass.name == name);
    for (fog, base, label) in [
        ("inject", "write", "inject / plain write"),
        ("scan", "copy", "scan / plain copy"),
        ("apply", "blit", "apply / blit"),
    ] {
        if let (Some(a), Some(b)) = (pass(fog), floor(base)) {
            let _ = writeln!(out, "{label}: {:.2}x", a.estimate.ms / b.estimate.ms);
        }
    }
    if with_ac4 {
        let _ = writeln!(out, "\nAC4 (Wronski 2014, Xbox One) against the model:");
        for r in &f.ac4 {
            match r.model_ms {
                Some(m) => {
                    let _ = writeln!(
                        out,
                        "  {:15} {:>7} ms  model {:>7} ms  {}",
                        r.name,
                        ms(r.target_ms),
                        ms(m),
                        if m <= r.target_ms { "met" } else { "missed" }
                    );
                }
                None => {
                    let _ = writeln!(
                        out,
                        "  {:15} {:>7} ms  (no such pass in this configuration)",
                        r.name,
                        ms(r.target_ms)
                    );
                }
            }
        }
    }
}

/// The report as text: the pipelines per chip, then the frame on each model.
pub fn table(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "volfog gpu-cost: every pipeline compiled by Mesa's RADV (ACO) on its null device; \
         waves/SIMD are waves of 64 per SIMD (RADV reports GFX10 and later in wave32 units)"
    );
    for (i, (chip, device)) in report.chips.iter().enumerate() {
        let _ = writeln!(out, "\n## Pipelines on {chip}: {device}\n");
        let _ = writeln!(
            out,
            "| pipeline | VGPRs | SGPRs | spilled VGPRs / SGPRs | scratch B | LDS B | waves/SIMD | instructions | ACO latency | ACO inverse throughput | used by |"
        );
        let _ = writeln!(
            out,
            "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"
        );
        for p in &report.pipelines {
            let s = &p.stats[i];
            let mut users: Vec<&str> = p
                .used_by
                .iter()
                .map(|u| u.split(" (").next().unwrap_or(u))
                .collect();
            users.dedup();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} / {} | {} | {} | {} | {} | {:.0} | {:.0} | {} |",
                p.label,
                s.vgprs,
                s.sgprs,
                s.spilled_vgprs,
                s.spilled_sgprs,
                s.scratch_bytes,
                s.lds_bytes,
                s.waves_per_simd,
                s.instructions,
                s.latency,
                s.inverse_throughput,
                users.join(", ")
            );
        }
    }
    for f in &report.frames {
        frame(&mut out, f);
    }
    filters(&mut out, &report.filters);
    super::transient::table(&mut out, &report.transient);
    super::stereo::table(&mut out, &report.stereo);
    super::medium::table(&mut out, &report.medium_shadows);
    if let Some(peer) = &report.bevy {
        super::bevy::table(&mut out, peer);
    }
    out
}

/// The shadow filters side by side: the passes that depend on the filter and the whole
/// froxel pipeline, per GPU model.
fn filters(out: &mut String, rows: &[FilterModel]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Shadow filters: the bench scene's frame with each (ms)\n\n\
         | GPU model | filter | ESM downsample + blur | inject | froxel pipeline |\n\
         | --- | --- | ---: | ---: | ---: |"
    );
    for r in rows {
        let esm: f64 = r
            .passes
            .iter()
            .filter(|m| m.pass.variant.pass != "inject")
            .map(|m| m.estimate.ms)
            .sum();
        let inject: f64 = r
            .passes
            .iter()
            .filter(|m| m.pass.variant.pass == "inject")
            .map(|m| m.estimate.ms)
            .sum();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} |",
            r.gpu,
            r.filter,
            if esm > 0.0 { ms(esm) } else { "-".to_string() },
            ms(inject),
            ms(r.total_ms)
        );
    }
}
