//! The shader formulas in Rust: the same functions as the WGSL modules, with the
//! same names and constants, evaluated in f32 like the GPU (glam types).
//!
//! They are the oracle of the GPU tests and a public API for gameplay queries, such
//! as how much fog lies between two points.

pub mod ambient;
pub mod apply;
pub mod area;
pub mod clouds;
pub mod density;
pub mod epipolar;
pub mod esm;
pub mod fog_lit;
pub mod fog_volume;
pub mod froxel;
pub mod frustum;
pub mod height_fog;
pub mod hull;
pub mod inject;
pub mod lightning;
pub mod lights;
pub mod local_shadow;
pub mod medium_shadow;
pub mod noise;
pub mod particles;
pub mod phase;
pub mod scan;
pub mod shadow;
pub mod sky;
pub mod soft_particles;
pub mod stereo;
pub mod temporal;
pub mod texture;
pub mod transient;
pub mod transparent;
pub mod water;

/// A small deterministic generator (splitmix64) for the mirrors' unit tests.
#[cfg(test)]
pub(crate) struct TestRng(pub(crate) u64);

#[cfg(test)]
impl TestRng {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in lo..=hi.
    pub(crate) fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next() % u64::from(hi - lo + 1)) as u32
    }

    /// Uniform in [lo, hi)^3.
    pub(crate) fn vec(&mut self, lo: f32, hi: f32) -> glam::Vec3 {
        glam::Vec3::new(self.unit(), self.unit(), self.unit()) * (hi - lo) + lo
    }
}
