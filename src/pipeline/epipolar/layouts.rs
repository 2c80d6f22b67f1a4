//! The bind group layout of each epipolar pass, spelled out (and compared with the
//! shader's reflection by the tests).

use super::{COORD_FORMAT, EpipolarShafts, SHAFT_FORMAT, SOURCE_FORMAT, TERM_FORMAT, TREE_FORMAT};
use crate::pipeline::{
    storage_buffer_entry, storage_entry, texture_entry, uint_texture_entry, uniform_entry,
};

const C: wgpu::ShaderStages = wgpu::ShaderStages::COMPUTE;
pub(super) const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;

fn unfilterable(binding: u32) -> wgpu::BindGroupLayoutEntry {
    texture_entry(binding, C, D2, false)
}

fn shadow_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    texture_entry(binding, C, wgpu::TextureViewDimension::D2Array, false)
}
impl EpipolarShafts {
    /// Layout of `epipolar_coords`: 0 frame, 1 scene depth, 2 coordinates (rgba32float).
    pub fn coords_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        vec![
            uniform_entry(0, C),
            unfilterable(1),
            storage_entry(2, D2, COORD_FORMAT),
        ]
    }

    /// Layout of `epipolar_refine`: 0 frame, 1 coordinates, 2 packed sources (r32uint).
    pub fn refine_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        vec![
            uniform_entry(0, C),
            unfilterable(1),
            storage_entry(2, D2, SOURCE_FORMAT),
        ]
    }

    /// Layout of `epipolar_tree`: 0 frame, 1 shadow map, 2 the tree (read), 3 the level
    /// written (rgba32float), 4 the level uniform.
    pub fn tree_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        vec![
            uniform_entry(0, C),
            shadow_entry(1),
            unfilterable(2),
            storage_entry(3, D2, TREE_FORMAT),
            uniform_entry(4, C),
        ]
    }

    /// Layout of `epipolar_march` (`steps`: `EPIPOLAR_BRUTE_FORCE`; `colored`:
    /// `EPIPOLAR_COLORED`): 0 frame, 1 medium, 2 coordinates, 3 sources, 4 the tree
    /// (the shadow map), 5 lit fractions (rgba32float), 6 the light colours (coloured).
    pub fn march_entries(steps: bool, colored: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = vec![
            uniform_entry(0, C),
            uniform_entry(1, C),
            unfilterable(2),
            uint_texture_entry(3),
        ];
        entries.push(if steps {
            shadow_entry(4)
        } else {
            unfilterable(4)
        });
        entries.push(storage_entry(5, D2, TERM_FORMAT));
        entries.extend(colored.then(|| unfilterable(6)));
        entries
    }

    /// Layout of `epipolar_interpolate`: 0 frame, 1 sources, 2 marched, 3 interpolated.
    pub fn interpolate_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        vec![
            uniform_entry(0, C),
            uint_texture_entry(1),
            unfilterable(2),
            storage_entry(3, D2, TERM_FORMAT),
        ]
    }

    /// Layout of `epipolar_resolve`: 0 frame, 1 medium, 2 scene depth, 3 coordinates,
    /// 4 interpolated, 5 shadow map, 6 resolved (rgba16float), 7 counters, 8 the light
    /// colours (`colored`).
    pub fn resolve_entries(colored: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = vec![
            uniform_entry(0, C),
            uniform_entry(1, C),
            unfilterable(2),
            unfilterable(3),
            unfilterable(4),
            shadow_entry(5),
            storage_entry(6, D2, SHAFT_FORMAT),
            storage_buffer_entry(7, C, false),
        ];
        entries.extend(colored.then(|| unfilterable(8)));
        entries
    }

    /// Layout of `epipolar_upscale`: 0 frame, 1 medium, 2 scene depth, 3 resolved, 4
    /// shadow map, 5 shafts (rgba16float), 6 counters, 7 the light colours (`colored`).
    pub fn upscale_entries(colored: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = vec![
            uniform_entry(0, C),
            uniform_entry(1, C),
            unfilterable(2),
            unfilterable(3),
            shadow_entry(4),
            storage_entry(5, D2, SHAFT_FORMAT),
            storage_buffer_entry(6, C, false),
        ];
        entries.extend(colored.then(|| unfilterable(7)));
        entries
    }

    /// Layout of `epipolar_reference`: 0 frame, 1 medium, 2 scene depth, 3 shadow map,
    /// 4 shafts (rgba16float), 5 the light colours (`colored`).
    pub fn reference_entries(colored: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = vec![
            uniform_entry(0, C),
            uniform_entry(1, C),
            unfilterable(2),
            shadow_entry(3),
            storage_entry(4, D2, SHAFT_FORMAT),
        ];
        entries.extend(colored.then(|| unfilterable(5)));
        entries
    }

    /// Layout of `epipolar_apply`: 0 frame, 1 medium, 2 scene depth, 3 shafts.
    pub fn apply_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        let f = wgpu::ShaderStages::FRAGMENT;
        vec![
            uniform_entry(0, f),
            uniform_entry(1, f),
            texture_entry(2, f, D2, false),
            texture_entry(3, f, D2, false),
        ]
    }
}
