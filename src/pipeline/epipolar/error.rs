//! [`EpipolarError`]: what [`EpipolarShafts`](super::EpipolarShafts) reports.

use crate::limits::InvalidValue;
use crate::pipeline::TimestampError;
use crate::shaders::CodegenError;

/// Errors of [`EpipolarShafts`].
///
/// [`EpipolarShafts`]: super::EpipolarShafts
#[derive(Debug, thiserror::Error)]
pub enum EpipolarError {
    /// A value is out of range.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// A shader failed to compose.
    #[error(transparent)]
    Shader(#[from] CodegenError),
    /// An input texture does not fit the sampling.
    #[error("{texture}: {property} is {found}, expected {expected}")]
    Texture {
        /// Which texture.
        texture: &'static str,
        /// The property that does not fit.
        property: &'static str,
        /// What it is.
        found: String,
        /// What it must be.
        expected: String,
    },
    /// `encode` or `create_apply` before `set_inputs`, or `encode` before `prepare`.
    #[error("EpipolarShafts: {0} first")]
    NotReady(&'static str),
    /// Reading timestamps or counters failed.
    #[error(transparent)]
    Timestamp(#[from] TimestampError),
}
