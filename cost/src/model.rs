//! The time model: ACO's cycles with every loop counted by its real trip count, set
//! against the pass's memory floor on a named GPU.
//!
//! # ACO's figures (Mesa 22.3, `aco_statistics.cpp`)
//!
//! ACO estimates each basic block's issue and stall cycles for one wave and sums them
//! weighted by a static guess of how often the block runs: x8 inside one loop, x32
//! inside two, x64 inside three (x2 per level beyond), x0.5 per enclosing uniform
//! branch and x0.75 per divergent one. That sum is "Latency". "Inverse Throughput" is
//! `max(Latency / waves, busiest unit's cycles) x 64 / wave size`: the cycles a SIMD
//! is busy per wave of 64 invocations when `waves` waves (the occupancy) hide each
//! other's latency.
//!
//! # Loops by their trip counts
//!
//! For each loop of the shader (in naga's IR, through calls) the model compiles the
//! shader again with that loop taken out ([`crate::loops::without`]). The difference
//! of the two latencies is what ACO counted for the loop and everything in it; ACO's
//! IR says whether the loop is still a loop in the code (its `loop-header` blocks
//! drop) or was unrolled by NIR (then ACO counted its real iterations already and
//! nothing changes). For a loop left in the code, at depth `d` among such loops:
//!
//! ```text
//! own(l)        = delta(l) - sum of delta(c) over the loops c directly in l
//! per_iter(l)   = own(l) / W(d)            W(1) = 8, W(2) = 32, W(3) = 64, ...
//! latency'      = L - sum of delta(l) over the outermost loops
//!               + sum over loops of per_iter(l) * n(l) * n(parent) * ...
//! ```
//!
//! where `n` is the loop's mean trip count per wave in the frame (the most any of
//! the wave's invocations runs). The branch weights inside the loop stay ACO's. The
//! inverse throughput is scaled by `latency' / L` (exact where the latency term is
//! the larger, an approximation where a unit is busiest).

use serde::Serialize;

use crate::{GpuModel, ShaderStats};

/// ACO's static weight of a block inside `depth` nested loops.
pub fn aco_loop_weight(depth: u32) -> f64 {
    match depth {
        0 => 1.0,
        1 => 8.0,
        2 => 32.0,
        d => 32.0 * 2f64.powi(d as i32 - 2),
    }
}

/// One loop of a shader as measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopMeasure {
    /// Its label ([`crate::loops::LoopInfo::label`]).
    pub label: String,
    /// The loop it runs in (index into the list).
    pub parent: Option<usize>,
    /// How many loops ACO's IR lost when it was taken out (0: NIR unrolled it).
    pub aco_loops_removed: u32,
    /// ACO's latency of the whole shader minus its latency without the loop.
    pub delta_latency: f64,
    /// Its mean trip count per wave in the frame, where it is still a loop.
    pub trips: Option<f64>,
}

impl LoopMeasure {
    /// Whether the loop is still a loop in ACO's code.
    pub fn in_code(&self) -> bool {
        self.aco_loops_removed > 0
    }
}

/// One loop's share of the corrected latency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopTerm {
    /// The loop.
    pub label: String,
    /// Its depth among the loops left in ACO's code.
    pub depth: u32,
    /// ACO's cycles of the loop's own blocks (its inner loops' taken off), weighted.
    pub aco_cycles: f64,
    /// Cycles of one iteration (ACO's weight taken off).
    pub cycles_per_iteration: f64,
    /// Its trip count.
    pub trips: f64,
    /// Iterations per wave: its trip count times its enclosing loops'.
    pub iterations: f64,
    /// Cycles it adds per wave.
    pub cycles: f64,
}

/// ACO's latency with the loops counted by their trip counts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Corrected {
    /// ACO's latency.
    pub aco_latency: f64,
    /// Cycles outside every loop left in the code.
    pub straight_cycles: f64,
    /// Per loop left in the code.
    pub loops: Vec<LoopTerm>,
    /// The corrected latency.
    pub latency: f64,
}

/// Counts the loops of a shader by their trip counts (see the module docs). Errors
/// with the label of a loop left in the code that has no trip count.
pub fn correct(aco_latency: f64, loops: &[LoopMeasure]) -> Result<Corrected, String> {
    // The nearest enclosing loop that is still a loop.
    let kept_parent = |mut i: usize| -> Option<usize> {
        while let Some(p) = loops[i].parent {
            if loops[p].in_code() {
                return Some(p);
            }
            i = p;
        }
        None
    };
    let depth = |mut i: usize| -> u32 {
        let mut d = 1;
        while let Some(p) = kept_parent(i) {
            d += 1;
            i = p;
        }
        d
    };
    let mut terms = Vec::new();
    let mut straight = aco_latency;
    for (i, l) in loops.iter().enumerate() {
        if !l.in_code() {
            continue;
        }
        let trips = l.trips.ok_or_else(|| l.label.clone())?;
        if kept_parent(i).is_none() {
            straight -= l.delta_latency;
        }
        let inner: f64 = loops
            .iter()
            .enumerate()
            .filter(|(j, c)| c.in_code() && kept_parent(*j) == Some(i))
            .map(|(_, c)| c.delta_latency)
            .sum();
        let own = (l.delta_latency - inner).max(0.0);
        let d = depth(i);
        let mut iterations = trips;
        let mut at = i;
        while let Some(p) = kept_parent(at) {
            iterations *= loops[p].trips.ok_or_else(|| loops[p].label.clone())?;
            at = p;
        }
        let per_iteration = own / aco_loop_weight(d);
        terms.push(LoopTerm {
            label: l.label.clone(),
            depth: d,
            aco_cycles: own,
            cycles_per_iteration: per_iteration,
            trips,
            iterations,
            cycles: per_iteration * iterations,
        });
    }
    let straight = straight.max(0.0);
    let latency = straight + terms.iter().map(|t| t.cycles).sum::<f64>();
    Ok(Corrected {
        aco_latency,
        straight_cycles: straight,
        loops: terms,
        latency,
    })
}

/// A pass's estimated time on a GPU model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Invocations the pass runs (threads, or pixels).
    pub invocations: f64,
    /// The corrected latency of one wave (cycles).
    pub latency: f64,
    /// The corrected inverse throughput (SIMD cycles per wave of 64).
    pub inverse_throughput: f64,
    /// Time of the arithmetic and latency: the waves spread over every SIMD, at
    /// least one wave's latency (ms).
    pub alu_ms: f64,
    /// The memory floor's bytes at the model's bandwidth (ms).
    pub memory_ms: f64,
    /// The larger of the two (ms).
    pub ms: f64,
    /// Whether the memory floor is the larger.
    pub memory_bound: bool,
    /// Whether more waves per SIMD would lower the ALU time (ACO's latency term is
    /// the larger at this occupancy).
    pub latency_bound: bool,
}

/// The estimate of a pass running `invocations` invocations of a shader with
/// `stats` and the corrected latency `corrected`, that must move `bytes` bytes.
pub fn estimate(
    gpu: &GpuModel,
    stats: &ShaderStats,
    corrected: f64,
    invocations: f64,
    bytes: f64,
) -> Estimate {
    let scale = if stats.latency > 0.0 {
        corrected / stats.latency
    } else {
        1.0
    };
    let inverse_throughput = stats.inverse_throughput * scale;
    let waves64 = invocations / 64.0;
    let cycles = (waves64 * inverse_throughput / f64::from(gpu.simds())).max(corrected);
    let alu_ms = cycles / gpu.clock_hz * 1e3;
    let memory_ms = bytes / gpu.bandwidth_bytes_s * 1e3;
    Estimate {
        invocations,
        latency: corrected,
        inverse_throughput,
        alu_ms,
        memory_ms,
        ms: alu_ms.max(memory_ms),
        memory_bound: memory_ms > alu_ms,
        latency_bound: stats.latency_bound(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measure(
        label: &str,
        parent: Option<usize>,
        removed: u32,
        delta: f64,
        trips: f64,
    ) -> LoopMeasure {
        LoopMeasure {
            label: label.to_string(),
            parent,
            aco_loops_removed: removed,
            delta_latency: delta,
            trips: Some(trips),
        }
    }

    #[test]
    fn weights_are_aco_s() {
        assert_eq!(aco_loop_weight(0), 1.0);
        assert_eq!(aco_loop_weight(1), 8.0);
        assert_eq!(aco_loop_weight(2), 32.0);
        assert_eq!(aco_loop_weight(3), 64.0);
        assert_eq!(aco_loop_weight(4), 128.0);
    }

    #[test]
    fn nested_loops_are_recounted_by_their_trips() {
        // A shader of 100 straight cycles, an outer loop whose own blocks cost 10 per
        // iteration and an inner one of 3 per iteration: ACO counts
        // 100 + 8 * 10 + 32 * 3 = 276. With 64 outer and 4 inner iterations the
        // shader runs 100 + 64 * 10 + 256 * 3 = 1508 cycles.
        let loops = [
            measure("outer", None, 2, 8.0 * 10.0 + 32.0 * 3.0, 64.0),
            measure("inner", Some(0), 1, 32.0 * 3.0, 4.0),
        ];
        let c = correct(276.0, &loops).unwrap();
        assert_eq!(c.straight_cycles, 100.0);
        assert_eq!(c.loops[0].cycles_per_iteration, 10.0);
        assert_eq!(c.loops[1].cycles_per_iteration, 3.0);
        assert_eq!(c.loops[1].iterations, 256.0);
        assert_eq!(c.latency, 1508.0);
    }

    #[test]
    fn an_unrolled_loop_is_left_as_aco_counted_it_and_lifts_its_inner_loop() {
        // The middle loop was unrolled (no ACO loop removed with it): the inner loop,
        // twice in the code, is at depth 1 and ACO's count of the rest stands.
        let loops = [
            measure("unrolled", None, 0, 50.0, 4.0),
            measure("inner", Some(0), 2, 2.0 * 8.0 * 5.0, 3.0),
        ];
        let c = correct(200.0, &loops).unwrap();
        assert_eq!(c.loops.len(), 1);
        assert_eq!(c.loops[0].depth, 1);
        assert_eq!(c.straight_cycles, 120.0);
        assert_eq!(c.latency, 120.0 + 10.0 * 3.0);
        let missing = [LoopMeasure {
            trips: None,
            ..loops[1].clone()
        }];
        assert_eq!(correct(200.0, &missing).unwrap_err(), "inner");
    }
}
