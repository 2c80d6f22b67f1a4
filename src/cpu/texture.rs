//! The 3D density texture of the inject pass (also the baked noise texture), sampled
//! trilinearly with repeat addressing.

use glam::Vec3;

/// A 3D density texture (r channel) sampled trilinearly with repeat addressing, as the
/// inject pass's density sampler does.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityTexture {
    /// Size in texels.
    pub size: [u32; 3],
    /// Texels, x fastest.
    pub texels: Vec<f32>,
}

impl DensityTexture {
    fn at(&self, x: i32, y: i32, z: i32) -> f32 {
        let w = |v: i32, n: u32| v.rem_euclid(n as i32) as usize;
        let [sx, sy, sz] = self.size;
        self.texels[(w(z, sz) * sy as usize + w(y, sy)) * sx as usize + w(x, sx)]
    }

    /// Trilinear sample with repeat addressing at texture coordinate `uvw`.
    pub fn sample(&self, uvw: Vec3) -> f32 {
        let size = Vec3::new(
            self.size[0] as f32,
            self.size[1] as f32,
            self.size[2] as f32,
        );
        let t = uvw * size - 0.5;
        let b = t.floor();
        let f = t - b;
        let (x, y, z) = (b.x as i32, b.y as i32, b.z as i32);
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let plane = |z: i32| {
            lerp(
                lerp(self.at(x, y, z), self.at(x + 1, y, z), f.x),
                lerp(self.at(x, y + 1, z), self.at(x + 1, y + 1, z), f.x),
                f.y,
            )
        };
        lerp(plane(z), plane(z + 1), f.z)
    }
}
