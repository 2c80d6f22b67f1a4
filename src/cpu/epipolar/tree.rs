//! The 1D min/max tree of each slice's height map (the `epipolar_tree` pass) and its
//! level layout.

use glam::Vec2;

use super::height_map::{ShadowLayer, height, slice_map};
use crate::uniforms::EpipolarFrame;

/// The 1D min/max trees of all slices: the two ping-pong tree textures of the
/// `epipolar_tree` pass as one array; replaces `volfog::epipolar::epipolar_tree_node`'s
/// textures.
#[derive(Debug, Clone, PartialEq)]
pub struct MinMaxTree {
    /// Shadow map side (texels), the entries of level 0.
    pub size: u32,
    /// Slices (rows).
    pub slices: u32,
    /// `2 * size` (min, max) nodes per slice, level `l` from [`level_offset`]`(size, l)`
    /// (level 0 is h itself as (h, h)); row `j` is slice `j`.
    pub nodes: Vec<Vec2>,
}

impl MinMaxTree {
    /// The trees of every slice of `frame` over `shadow` (side `frame.shadow_size`),
    /// level 0 as `epipolar_tree_init` and levels 1 ..= log2(size) as
    /// `epipolar_tree_level` build them.
    pub fn build(frame: &EpipolarFrame, shadow: &ShadowLayer) -> Self {
        let size = frame.shadow_size;
        assert_eq!(
            shadow.size, size,
            "the shadow layer's side is frame.shadow_size"
        );
        assert_eq!(shadow.depths.len(), (size * size) as usize);
        let row = 2 * size as usize;
        let mut nodes = vec![Vec2::ZERO; row * frame.slices as usize];
        for slice in 0..frame.slices {
            let at = row * slice as usize;
            let map = slice_map(frame, slice);
            for x in 0..size {
                let h = height(shadow, map, x, frame.depth_bias);
                nodes[at + x as usize] = Vec2::new(h, h);
            }
            for level in 1..=size.trailing_zeros() {
                let src = at + level_offset(size, level - 1) as usize;
                let dst = at + level_offset(size, level) as usize;
                for i in 0..(size >> level) as usize {
                    let a = nodes[src + 2 * i];
                    let b = nodes[src + 2 * i + 1];
                    nodes[dst + i] = Vec2::new(a.x.min(b.x), a.y.max(b.y));
                }
            }
        }
        Self {
            size,
            slices: frame.slices,
            nodes,
        }
    }

    /// min and max (light depth) of tree node `index` of level `level` in row `slice`;
    /// mirror of `volfog::epipolar::epipolar_tree_node`.
    pub fn node(&self, slice: u32, level: u32, index: u32) -> Vec2 {
        let at = 2 * self.size as usize * slice as usize
            + (level_offset(self.size, level) + index) as usize;
        self.nodes[at]
    }
}

/// Index of the first node of tree level `level` in a slice's row of `2 * size` nodes
/// (level 0 is h itself); mirror of `volfog::epipolar::epipolar_level_offset`.
pub fn level_offset(size: u32, level: u32) -> u32 {
    2 * size - ((2 * size) >> level)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::TestRng as Rng;
    use crate::cpu::epipolar::test_scene::{Scene, suns};

    #[test]
    fn tree_nodes_bound_their_entries() {
        let mut rng = Rng(6);
        let scene = Scene::new(suns()[0], &mut rng, 200);
        let frame = &scene.frame;
        let tree = MinMaxTree::build(frame, &scene.layer());
        let size = frame.shadow_size;
        assert_eq!(tree.nodes.len(), (2 * size * frame.slices) as usize);
        assert_eq!(level_offset(size, size.trailing_zeros()), 2 * size - 2);
        for slice in [0, 1, 77, frame.slices - 1] {
            let map = slice_map(frame, slice);
            let h: Vec<f32> = (0..size)
                .map(|k| height(&scene.layer(), map, k, 0.0))
                .collect();
            for level in 0..=size.trailing_zeros() {
                for (index, part) in h.chunks(1 << level).enumerate() {
                    let lo = part.iter().copied().fold(f32::INFINITY, f32::min);
                    let hi = part.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                    assert_eq!(tree.node(slice, level, index as u32), Vec2::new(lo, hi));
                }
            }
        }
    }
}
