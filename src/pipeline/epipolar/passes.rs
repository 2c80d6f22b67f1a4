//! Which passes [`EpipolarShafts`](super::EpipolarShafts) runs: the marches
//! ([`EpipolarMode`]) and the passes in timing order ([`EpipolarPass`]).

/// Which march fills the shaft texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EpipolarMode {
    /// Epipolar sampling with the min/max tree march (Yusov's Algorithm 2).
    #[default]
    Tree,
    /// Epipolar sampling, each ray-marching sample visiting every section of its
    /// slice's height map in the shadow map (Algorithm 1; the same result, slower).
    Steps,
    /// No epipolar sampling: every pixel marched with `reference_steps` fixed steps.
    Reference,
}

/// The passes of [`EpipolarShafts`], in the order of [`EpipolarShafts::read_timings`].
///
/// [`EpipolarShafts`]: super::EpipolarShafts
/// [`EpipolarShafts::read_timings`]: super::EpipolarShafts::read_timings
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EpipolarPass {
    /// `epipolar_coords`: the coordinate texture.
    Coords,
    /// `epipolar_refine`: the ray-marching samples and interpolation sources.
    Refine,
    /// `epipolar_tree`: the 1D min/max trees (every level).
    Tree,
    /// `epipolar_march`: the march of the ray-marching samples.
    March,
    /// `epipolar_interpolate`: the other samples.
    Interpolate,
    /// `epipolar_resolve`: back to the (downscaled) screen.
    Resolve,
    /// `epipolar_upscale`: to full resolution (downscale > 1).
    Upscale,
    /// `epipolar_reference`: the per-pixel brute-force march.
    Reference,
}

impl EpipolarPass {
    /// Every pass, in timing order.
    pub const ALL: [EpipolarPass; 8] = [
        Self::Coords,
        Self::Refine,
        Self::Tree,
        Self::March,
        Self::Interpolate,
        Self::Resolve,
        Self::Upscale,
        Self::Reference,
    ];

    /// The pass's name (its WGSL file).
    pub fn name(self) -> &'static str {
        match self {
            Self::Coords => "epipolar_coords",
            Self::Refine => "epipolar_refine",
            Self::Tree => "epipolar_tree",
            Self::March => "epipolar_march",
            Self::Interpolate => "epipolar_interpolate",
            Self::Resolve => "epipolar_resolve",
            Self::Upscale => "epipolar_upscale",
            Self::Reference => "epipolar_reference",
        }
    }

    /// The passes `mode` runs, in order, for a resolve downscaled by `downscale`.
    pub fn of(mode: EpipolarMode, downscale: u32) -> Vec<EpipolarPass> {
        match mode {
            EpipolarMode::Reference => vec![Self::Reference],
            EpipolarMode::Tree | EpipolarMode::Steps => Self::ALL[..7]
                .iter()
                .copied()
                .filter(|p| !(*p == Self::Tree && mode == EpipolarMode::Steps))
                .filter(|p| !(*p == Self::Upscale && downscale == 1))
                .collect(),
        }
    }
}
