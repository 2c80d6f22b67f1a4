//! Deterministic inputs for tests: a 64-bit LCG and relative errors.

/// A small deterministic generator for test inputs (64-bit LCG, top 24 bits).
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
    /// Log-uniform in [lo, hi) (both > 0).
    pub fn log(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f()).exp()
    }
    /// Uniform in the cube [-r, r)^3.
    pub fn vec(&mut self, r: f32) -> glam::Vec3 {
        glam::Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    /// A unit vector, uniform on the sphere (rejection from the cube).
    pub fn unit(&mut self) -> glam::Vec3 {
        loop {
            let v = self.vec(1.0);
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
    /// A random rotation.
    pub fn quat(&mut self) -> glam::Quat {
        glam::Quat::from_axis_angle(self.unit(), self.range(0.0, std::f32::consts::TAU))
    }
}

/// Relative error with a floor on the denominator.
pub fn rel_err(got: f32, want: f32, floor: f32) -> f32 {
    (got - want).abs() / want.abs().max(floor)
}
