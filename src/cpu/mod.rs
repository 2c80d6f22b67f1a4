//! The shader formulas in Rust: the same functions as the WGSL modules, with the
//! same names and constants, evaluated in f32 like the GPU (glam types).
//!
//! They are the oracle of the GPU tests and a public API for gameplay queries, such
//! as how much fog lies between two points.

pub mod ambient;
pub mod apply;
pub mod clouds;
pub mod density;
pub mod epipolar;
pub mod esm;
pub mod fog_volume;
pub mod froxel;
pub mod frustum;
pub mod height_fog;
pub mod hull;
pub mod inject;
pub mod lightning;
pub mod lights;
pub mod noise;
pub mod phase;
pub mod scan;
pub mod sky;
pub mod soft_particles;
pub mod temporal;
pub mod transparent;
pub mod water;
