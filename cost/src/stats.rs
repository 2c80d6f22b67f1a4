//! RADV's statistics of one shader, typed (Mesa 22.3's names, `radv_pipeline.c`
//! `radv_GetPipelineExecutableStatisticsKHR`; ACO's in `aco_statistics.cpp`).

use serde::Serialize;

use crate::worker::{Compiled, ExecutableStats};
use crate::{Chip, CostError};

/// The statistics of the shader a pipeline's work runs in: the compute shader, or a
/// draw's fragment shader.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShaderStats {
    /// The chip it was compiled for.
    pub chip: Chip,
    /// Its wave size.
    pub wave_size: u32,
    /// Vector registers allocated per wave.
    pub vgprs: u32,
    /// Scalar registers allocated per wave.
    pub sgprs: u32,
    /// Vector registers spilled.
    pub spilled_vgprs: u32,
    /// Scalar registers spilled.
    pub spilled_sgprs: u32,
    /// Private (scratch) memory per wave, bytes.
    pub scratch_bytes: u32,
    /// Workgroup (LDS) memory per workgroup, bytes.
    pub lds_bytes: u32,
    /// RADV's "Subgroups per SIMD" as reported: in waves on GCN, in wave32 units on
    /// GFX10 and later (a wave64 counts two).
    pub subgroups_per_simd: u32,
    /// Waves of this shader a SIMD holds (the occupancy), in its own wave size.
    pub waves_per_simd: u32,
    /// Instructions.
    pub instructions: u32,
    /// Code size, bytes.
    pub code_bytes: u32,
    /// ACO's latency: issue and stall cycles of one wave, loops weighted statically.
    pub latency: f64,
    /// ACO's inverse throughput: busy cycles of a SIMD per wave of 64 invocations,
    /// given the occupancy.
    pub inverse_throughput: f64,
    /// Loops left in ACO's code (when counted).
    pub aco_loops: Option<u32>,
}

impl ShaderStats {
    /// Whether anything spilled (registers or scratch).
    pub fn spills(&self) -> bool {
        self.spilled_vgprs > 0 || self.spilled_sgprs > 0 || self.scratch_bytes > 0
    }

    /// The statistics of the executable that runs a pipeline's work (compute, or the
    /// fragment shader of a draw) among `executables`.
    pub fn of(
        chip: Chip,
        label: &str,
        executables: &[ExecutableStats],
    ) -> Result<ShaderStats, CostError> {
        let e = executables
            .iter()
            .find(|e| e.stage == "compute")
            .or_else(|| executables.iter().find(|e| e.stage == "fragment"))
            .ok_or_else(|| CostError::MissingStatistic {
                pipeline: label.to_string(),
                statistic: "compute or fragment executable",
            })?;
        let get = |statistic: &'static str| {
            e.get(statistic).ok_or(CostError::MissingStatistic {
                pipeline: label.to_string(),
                statistic,
            })
        };
        let subgroups_per_simd = get("Subgroups per SIMD")? as u32;
        let waves_per_simd = if chip.counts_wave32_units() {
            subgroups_per_simd * 32 / e.subgroup_size.max(1)
        } else {
            subgroups_per_simd
        };
        Ok(ShaderStats {
            chip,
            wave_size: e.subgroup_size,
            vgprs: get("VGPRs")? as u32,
            sgprs: get("SGPRs")? as u32,
            spilled_vgprs: get("Spilled VGPRs")? as u32,
            spilled_sgprs: get("Spilled SGPRs")? as u32,
            scratch_bytes: get("Scratch size")? as u32,
            lds_bytes: get("LDS size")? as u32,
            subgroups_per_simd,
            waves_per_simd,
            instructions: get("Instructions")? as u32,
            code_bytes: get("Code size")? as u32,
            latency: get("Latency")?,
            inverse_throughput: get("Inverse Throughput")?,
            aco_loops: e.aco_loops,
        })
    }

    /// The statistics of a compiled job, or its compile error as
    /// [`CostError::Worker`].
    pub fn of_compiled(chip: Chip, compiled: &Compiled) -> Result<ShaderStats, CostError> {
        match &compiled.outcome {
            Ok(executables) => Self::of(chip, &compiled.label, executables),
            Err(message) => Err(CostError::Worker {
                chip,
                program: compiled.label.clone(),
                message: format!("the pipeline did not compile: {message}"),
            }),
        }
    }

    /// Whether ACO's figures say more waves per SIMD would buy time: its inverse
    /// throughput is `max(latency / waves, busiest unit) x 64 / wave size`, so a
    /// shader whose latency over its waves is the larger term is latency-bound.
    pub fn latency_bound(&self) -> bool {
        let waves = self.aco_waves();
        self.latency / waves >= self.inverse_throughput * f64::from(self.wave_size) / 64.0 - 1.0
    }

    /// The waves ACO's estimate hides latency over: waves of 64 on every chip
    /// (`program->num_waves`, which for a wave64 shader is `waves_per_simd`).
    pub fn aco_waves(&self) -> f64 {
        f64::from(self.waves_per_simd.max(1))
    }
}
