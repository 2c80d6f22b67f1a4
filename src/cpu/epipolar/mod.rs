//! Mirror of `volfog::epipolar`: sun shafts sampled along epipolar lines and marched
//! through a 1D min/max tree of the shadow map per line (Yusov 2012, after Engelhardt &
//! Dachsbacher 2010 and Chen et al. 2011).
//!
//! The textures of the WGSL become plain data: a [`ShadowLayer`] is the layer of the
//! shadow map the shafts are marched in, a [`MinMaxTree`] the two ping-pong tree
//! textures of the `epipolar_tree` pass. [`coordinates`] and [`refine_slice`] are the
//! `epipolar_coords` and `epipolar_refine` passes on the CPU.
//!
//! ```
//! use volfog::cpu::epipolar::{border_coord, exit_point};
//!
//! // The border is walked counter-clockwise from the top-left corner.
//! assert_eq!(exit_point(0.0), glam::Vec2::new(-1.0, 1.0));
//! assert_eq!(exit_point(0.25), glam::Vec2::new(-1.0, -1.0));
//! // 0.6 lies on the right edge (edge 2): the point maps back to its coordinate.
//! assert!((border_coord(exit_point(0.6), 2) - 0.6).abs() < 1e-6);
//! ```

mod coords;
mod height_map;
mod lines;
mod march;
mod refine;
mod resolve;
#[cfg(test)]
mod test_scene;
mod tree;

pub use coords::coordinates;
pub use height_map::{
    ColorLayer, EpipolarRay, ShadowLayer, color, height, light_texel, ray, slice_map, view_ray,
};
pub use lines::{
    border_coord, border_distance, entry_point, exit_point, line, line_position, on_screen,
    pixel_slice, sample_position,
};
pub use march::{
    lit, lit_fraction, lit_open, lit_section, march_pixel, march_steps, march_tree, ray_fraction,
    transmittance,
};
pub use refine::{
    continuous, pack_sources, refine_slice, refine_slice_naive, section, sources, unpack_sources,
};
pub use resolve::{fog, phase, pixel_ndc, view_depth};
pub use tree::{MinMaxTree, level_offset};

/// Coordinate (both components) of samples off the screen; mirror of
/// `volfog::epipolar::EPIPOLAR_INVALID`.
pub const INVALID: f32 = -1e4;

/// View depth (m) stored for invalid samples: every difference to it is a depth break;
/// mirror of `volfog::epipolar::EPIPOLAR_INVALID_DEPTH`.
pub const INVALID_DEPTH: f32 = -1e6;

/// Samples per refinement workgroup (four words of packed depth-break flags); mirror of
/// `volfog::epipolar::EPIPOLAR_GROUP`.
pub const GROUP: u32 = 128;

/// Shadow depth of the 1D height map outside the shadow map (always lit); mirror of
/// `volfog::epipolar::EPIPOLAR_LIT_DEPTH`.
pub const LIT_DEPTH: f32 = 2.0;

/// Tolerance of the screen border, normalised device units; mirror of
/// `volfog::epipolar::EPIPOLAR_BORDER`.
pub const BORDER: f32 = 1e-4;

/// WGSL `mix` of scalars: `a (1 - t) + b t`.
fn mix(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// WGSL `fract`: `x - floor(x)`.
fn fract(x: f32) -> f32 {
    x - x.floor()
}
