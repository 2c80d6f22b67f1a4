//! Errors of the cost crate.

use crate::Chip;

/// Debian command that installs Mesa's Vulkan drivers (RADV and lavapipe) and the loader.
pub const INSTALL_RADV: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

/// Everything that can go wrong while costing a pass.
#[derive(Debug, thiserror::Error)]
pub enum CostError {
    /// RADV's ICD file is not installed.
    #[error(
        "Mesa's RADV Vulkan driver is not installed ({icd} is missing); install it with `{INSTALL_RADV}`"
    )]
    RadvMissing {
        /// The ICD file looked for.
        icd: String,
    },
    /// A pass failed to compose or translate.
    #[error(transparent)]
    Codegen(#[from] volfog_codegen::CodegenError),
    /// A module failed naga's validation (after a transformation of this crate).
    #[error("{what}: naga validation: {message}")]
    Validation {
        /// The module.
        what: String,
        /// naga's message.
        message: String,
    },
    /// naga's SPIR-V writer failed.
    #[error("{what}: SPIR-V: {message}")]
    Spirv {
        /// The module and entry point.
        what: String,
        /// naga's message.
        message: String,
    },
    /// An export folder's manifest is unreadable or lacks a field.
    #[error("{path}: {message}")]
    Manifest {
        /// The manifest or file.
        path: String,
        /// What is wrong (naming the field).
        message: String,
    },
    /// The worker process could not be started or talked to.
    #[error("the RADV worker for {chip} ({program}): {message}")]
    Worker {
        /// The chip it compiles for.
        chip: Chip,
        /// The worker's program.
        program: String,
        /// What failed, with the tail of its stderr.
        message: String,
    },
    /// A Vulkan call of the worker failed.
    #[error(transparent)]
    Vulkan(#[from] vkcheck::VkError),
    /// Reading or writing the worker's messages failed.
    #[error("the worker's messages: {0}")]
    Protocol(String),
    /// A statistic RADV always reports is missing.
    #[error("{pipeline}: RADV reported no {statistic:?} statistic")]
    MissingStatistic {
        /// The pipeline.
        pipeline: String,
        /// The statistic's name.
        statistic: &'static str,
    },
    /// A loop of a pass that survives into ACO's code has no trip count.
    #[error(
        "{pipeline}: loop `{label}` survives into ACO's code on {chip} and has no trip count \
         (loops given: {given:?})"
    )]
    NoTripCount {
        /// The pipeline.
        pipeline: String,
        /// The loop's label.
        label: String,
        /// The chip.
        chip: Chip,
        /// The labels that have one.
        given: Vec<String>,
    },
    /// An argument is out of range (the message names the field).
    #[error("{field}: {message}")]
    Invalid {
        /// The field.
        field: &'static str,
        /// Why.
        message: String,
    },
}
