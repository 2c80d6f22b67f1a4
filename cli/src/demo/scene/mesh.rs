//! The scene's triangle lists: the vertex layout (position, normal, colour, surface
//! kind) and the boxes and spheres the scene is built of.

use glam::{Quat, Vec3};

/// Surface kinds (the `kind` vertex attribute).
pub(super) const PLAIN: f32 = 0.0;
pub(super) const CHECKER: f32 = 1.0;
pub(super) const EMISSIVE: f32 = 2.0;

/// One vertex: position, normal, colour (albedo or emitted radiance) and kind.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub color: [f32; 3],
    pub kind: f32,
}

impl Vertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32
    ];

    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// A triangle list.
#[derive(Debug, Default, Clone)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub(super) fn push(&mut self, position: Vec3, normal: Vec3, color: Vec3, kind: f32) -> u32 {
        self.vertices.push(Vertex {
            position: position.to_array(),
            normal: normal.to_array(),
            color: color.to_array(),
            kind,
        });
        self.vertices.len() as u32 - 1
    }

    /// A box of half extents `half`, rotated by `rotation` about its centre.
    pub(super) fn cuboid(
        &mut self,
        center: Vec3,
        half: Vec3,
        rotation: Quat,
        color: Vec3,
        kind: f32,
    ) {
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                let a = (axis + 1) % 3;
                let b = (axis + 2) % 3;
                let mut du = Vec3::ZERO;
                du[a] = half[a];
                let mut dv = Vec3::ZERO;
                dv[b] = half[b];
                let c = n * half[axis];
                // Counter-clockwise seen from outside: (du x dv) must point along n.
                let (du, dv) = if du.cross(dv).dot(n) > 0.0 {
                    (du, dv)
                } else {
                    (dv, du)
                };
                let corners = [c - du - dv, c + du - dv, c + du + dv, c - du + dv];
                let normal = rotation * n;
                let base = self.vertices.len() as u32;
                for p in corners {
                    self.push(center + rotation * p, normal, color, kind);
                }
                self.indices.extend_from_slice(&[
                    base,
                    base + 1,
                    base + 2,
                    base,
                    base + 2,
                    base + 3,
                ]);
            }
        }
    }

    /// An axis-aligned box from `min` to `max`.
    pub(super) fn aabb(&mut self, min: Vec3, max: Vec3, color: Vec3) {
        self.cuboid(
            (min + max) * 0.5,
            (max - min) * 0.5,
            Quat::IDENTITY,
            color,
            PLAIN,
        );
    }

    /// A UV sphere.
    pub(super) fn sphere(
        &mut self,
        center: Vec3,
        radius: f32,
        color: Vec3,
        rings: u32,
        segments: u32,
    ) {
        let base = self.vertices.len() as u32;
        for r in 0..=rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let phi = std::f32::consts::TAU * s as f32 / segments as f32;
                let n = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                self.push(center + n * radius, n, color, PLAIN);
            }
        }
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let a = base + r * row + s;
                let b = a + row;
                self.indices
                    .extend_from_slice(&[a, a + 1, b, a + 1, b + 1, b]);
            }
        }
    }
}
