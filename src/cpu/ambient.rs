//! Ambient light as L1 spherical harmonics of radiance, as the injection's ambient
//! term reads it (`FogLighting.ambient_r/g/b`).
//!
//! ```
//! use glam::Vec3;
//! use volfog::cpu::ambient::AmbientSh;
//!
//! let sky = AmbientSh::sky_ground(Vec3::new(0.2, 0.3, 0.5), Vec3::splat(0.05), Vec3::Y);
//! // Band 0 holds the mean radiance times sqrt(4 pi).
//! let mean = sky.rgb[2].x / (4.0 * std::f32::consts::PI).sqrt();
//! assert!((mean - 0.275).abs() < 1e-6);
//! ```

use glam::{Vec3, Vec4};

use crate::cpu::phase::SH_Y1;

/// L1 SH coefficients (Y00, Y1-1, Y10, Y11) of ambient radiance per channel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AmbientSh {
    /// Red, green and blue coefficients.
    pub rgb: [Vec4; 3],
}

impl AmbientSh {
    /// Constant ambient radiance from every direction.
    pub fn constant(radiance: Vec3) -> Self {
        let k = (4.0 * std::f32::consts::PI).sqrt();
        Self {
            rgb: [0, 1, 2].map(|c| Vec4::new(radiance[c] * k, 0.0, 0.0, 0.0)),
        }
    }

    /// Radiance `sky` from above (along `up`) blending linearly to `ground` from below:
    /// L(w) = mix(ground, sky, 0.5 + 0.5 dot(w, up)), which is exactly L1.
    pub fn sky_ground(sky: Vec3, ground: Vec3, up: Vec3) -> Self {
        let k0 = (4.0 * std::f32::consts::PI).sqrt();
        let k1 = SH_Y1 * 4.0 * std::f32::consts::PI / 3.0;
        let mean = (sky + ground) * 0.5;
        let slope = (sky - ground) * 0.5;
        Self {
            rgb: [0, 1, 2].map(|c| {
                Vec4::new(
                    mean[c] * k0,
                    k1 * slope[c] * up.y,
                    k1 * slope[c] * up.z,
                    k1 * slope[c] * up.x,
                )
            }),
        }
    }

    /// Converts SH of irradiance (cosine-convolved, as many engines store) to SH of
    /// radiance: band 0 divided by pi, band 1 by 2 pi / 3.
    pub fn from_irradiance(irradiance: [Vec4; 3]) -> Self {
        let a0 = std::f32::consts::PI;
        let a1 = 2.0 * std::f32::consts::PI / 3.0;
        Self {
            rgb: irradiance.map(|e| Vec4::new(e.x / a0, e.y / a1, e.z / a1, e.w / a1)),
        }
    }
}
