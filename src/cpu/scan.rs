//! Mirror of `volfog::scan`: front-to-back integration of a froxel column.
//!
//! ```
//! use glam::{Vec3, Vec4};
//! use volfog::cpu::scan::{scan_step, SCAN_START};
//! use volfog::options::ScanStep;
//! // Homogeneous fog: sigma_s = sigma_t = 0.1 / m, in-scattered light 1.
//! let medium = Vec4::new(0.1, 0.1, 0.1, 0.1);
//! let mut acc = SCAN_START;
//! for _ in 0..10 {
//!     acc = scan_step(acc, medium, 1.0, ScanStep::EnergyConserving);
//! }
//! // 10 m: T = exp(-1), L = (sigma_s / sigma_t) (1 - T).
//! assert!((acc.w - (-1.0f32).exp()).abs() < 1e-6);
//! assert!((acc.x - (1.0 - (-1.0f32).exp())).abs() < 1e-6);
//! ```

use glam::{Vec3, Vec4};

pub use crate::options::ScanStep;

/// Accumulator before the first slice (no in-scatter, transmittance 1).
pub const SCAN_START: Vec4 = Vec4::new(0.0, 0.0, 0.0, 1.0);

/// Below this optical depth the slice integral uses its series.
pub const SCAN_SERIES_LIMIT: f32 = 1e-2;

/// In-scattering of one homogeneous slice of path length `ds` seen from its front.
pub fn slice_inscatter(medium: Vec4, ds: f32, step: ScanStep) -> Vec3 {
    slice_inscatter_through(medium, ds, (-medium.w.max(0.0) * ds).exp(), step)
}

/// [`slice_inscatter`] given the slice's own transmittance `exp(-sigma_t ds)`, which
/// the scan step needs too.
pub fn slice_inscatter_through(medium: Vec4, ds: f32, transmittance: f32, step: ScanStep) -> Vec3 {
    match step {
        ScanStep::Wronski => medium.truncate() * ds,
        ScanStep::EnergyConserving => {
            let sigma_t = medium.w.max(0.0);
            let tau = sigma_t * ds;
            if tau < SCAN_SERIES_LIMIT {
                medium.truncate() * (ds * (1.0 - tau * (0.5 - tau * (1.0 / 6.0))))
            } else {
                medium.truncate() * ((1.0 - transmittance) / sigma_t)
            }
        }
    }
}

/// One scan step: a slice of `medium` (rgb = sigma_s L_in, a = sigma_t) and path
/// length `ds` behind `acc` (rgb = in-scatter, a = transmittance).
pub fn scan_step(acc: Vec4, medium: Vec4, ds: f32, step: ScanStep) -> Vec4 {
    let transmittance = (-medium.w.max(0.0) * ds).exp();
    (acc.truncate() + acc.w * slice_inscatter_through(medium, ds, transmittance, step))
        .extend(acc.w * transmittance)
}
