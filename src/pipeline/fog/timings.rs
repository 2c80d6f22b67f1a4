//! The GPU timings of [`VolumetricFog`]: its passes ([`FogPass`]), their timestamp
//! pairs and the milliseconds read back ([`PassTimings`]).

use super::VolumetricFog;

/// GPU time per pass in milliseconds (when timestamps are enabled and supported).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PassTimings {
    /// Depth culling (froxel_cull).
    pub cull: f64,
    /// ESM downsample.
    pub esm_downsample: f64,
    /// ESM blur (both directions).
    pub esm_blur: f64,
    /// The local-light shadow atlas: downsample and blur of the frame's shadowed point
    /// and spot lights.
    pub local_shadows: f64,
    /// The medium's shadows (the `medium_shadow` pass; with
    /// `FogConfig::medium_shadows`).
    pub medium_shadow: f64,
    /// Inject.
    pub inject: f64,
    /// Temporal reprojection.
    pub temporal: f64,
    /// Scan.
    pub scan: f64,
    /// Fullscreen apply (recorded with `VolumetricFog::record_apply`).
    pub apply: f64,
}

impl PassTimings {
    pub(crate) fn from_ms(ms: &[f64]) -> Self {
        Self {
            esm_downsample: ms[0],
            esm_blur: ms[1],
            inject: ms[2],
            temporal: ms[3],
            scan: ms[4],
            cull: ms[5],
            local_shadows: ms[6],
            medium_shadow: ms[7],
            apply: ms[8],
        }
    }
}

/// The compute passes of a frame, in the order [`VolumetricFog::encode`] records them
/// (see [`VolumetricFog::encode_pass`]).
///
/// [`VolumetricFog::encode`]: super::VolumetricFog::encode
/// [`VolumetricFog::encode_pass`]: super::VolumetricFog::encode_pass
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FogPass {
    /// ESM downsample (only with a shadow map and cascades).
    EsmDownsample,
    /// ESM blur, both directions (only with a shadow map and cascades).
    EsmBlur,
    /// Density and lighting injection.
    Inject,
    /// Temporal reprojection (only with `FogConfig::temporal`).
    Temporal,
    /// Front-to-back integration.
    Scan,
    /// Live slices per froxel column from the scene depth (only with
    /// `FogConfig::depth_cull` and a scene depth set); recorded first.
    Cull,
    /// The local-light shadow atlas (only when the frame has shadowed point or spot
    /// lights); recorded after the ESM blur.
    LocalShadows,
    /// The medium-shadow volume (only with `FogConfig::medium_shadows`); recorded
    /// before inject.
    MediumShadow,
}

impl FogPass {
    /// Every pass, in order.
    pub const ALL: [FogPass; 8] = [
        FogPass::Cull,
        FogPass::EsmDownsample,
        FogPass::EsmBlur,
        FogPass::LocalShadows,
        FogPass::MediumShadow,
        FogPass::Inject,
        FogPass::Temporal,
        FogPass::Scan,
    ];

    /// Its timestamp pair (the apply pass is pair 8).
    pub(crate) fn timestamp_pair(self) -> u32 {
        self as u32
    }
}

/// Timestamp pairs: the eight compute passes and the apply.
pub(crate) const TIMESTAMP_PAIRS: u32 = 9;
/// The timestamp pair of the apply pass.
pub(crate) const APPLY_PAIR: u32 = 8;

impl VolumetricFog {
    pub(super) fn timestamp_writes(
        &self,
        pass: FogPass,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.timestamps
            .as_ref()
            .map(|t| t.compute(pass.timestamp_pair()))
    }

    /// Resolves the timestamps of the recorded frame into the readback buffer; call
    /// after `encode` and `record_apply`, before submitting.
    pub fn resolve_timestamps(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(t) = &self.timestamps {
            t.resolve(encoder);
        }
    }

    /// Reads the per-pass GPU times of the last resolved frame (blocks until the GPU
    /// is done). `None` without timestamps or when the readback fails. Passes that
    /// did not run read 0.
    pub fn read_timings(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<PassTimings> {
        let ms = self.timestamps.as_ref()?.read_ms(device, queue).ok()?;
        Some(PassTimings::from_ms(&ms))
    }
}
