//! [`FogError`]: everything [`VolumetricFog`](super::VolumetricFog) rejects.

use crate::limits::InvalidValue;
use crate::shaders::CodegenError;

/// Errors of [`VolumetricFog`](super::VolumetricFog).
#[derive(Debug, thiserror::Error)]
pub enum FogError {
    /// A configuration or input value is out of range.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// A texture handed to the fog does not fit the configuration.
    #[error("{texture}: {property} is {found}; expected {expected}")]
    Texture {
        /// Which texture, e.g. `the shadow map`.
        texture: &'static str,
        /// Which property, e.g. `size`.
        property: &'static str,
        /// What it is.
        found: String,
        /// What the configuration needs.
        expected: String,
    },
    /// The device lacks a capability the configuration needs.
    #[error("the device lacks {what}: {detail}")]
    MissingCapability {
        /// The capability.
        what: &'static str,
        /// What is needed and what the device offers.
        detail: String,
    },
    /// `encode` was called before any `prepare`.
    #[error("no frame is prepared: call VolumetricFog::prepare before encoding")]
    NotPrepared,
    /// An apply pipeline built for other fog groups.
    #[error(
        "the apply pipeline reads {pipeline:?}-filtered fog groups, the fog has \
         {fog:?}; create it with VolumetricFog::create_apply"
    )]
    ApplyMismatch {
        /// The pipeline's filtering.
        pipeline: crate::options::Filtering,
        /// The fog's.
        fog: crate::options::Filtering,
    },
    /// Composing a shader variant failed.
    #[error(transparent)]
    Shader(#[from] CodegenError),
}
