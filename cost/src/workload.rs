//! What a scene asks of the froxel passes in one frame: the blocks inject runs over,
//! and the trip counts of their loops — lights and volumes gathered per block, the
//! cascade search per froxel, the live slices per column — taken per wave (the most
//! any of a wave's 64 invocations runs, since a wave runs a loop until its last
//! invocation leaves it) and averaged over the waves of the dispatch. Computed on the
//! CPU with the formulas of `volfog::cpu` that the shaders' tests hold them to.

use glam::{Mat4, UVec2, UVec3, Vec3, Vec4};
use serde::Serialize;
use volfog::cpu::esm::esm_cascade;
use volfog::cpu::froxel::{froxel_cull_cell, froxel_view_position};
use volfog::cpu::lights::light_touches_sphere;
use volfog::uniforms::{FogLight, Froxels, LocalVolume};

/// Invocations per wave (RADV 22.3 compiles compute and fragment shaders as wave64).
pub const WAVE: u32 = 64;
/// Lights a block gathers at most (`TILE_LIGHTS` of `inject.wgsl`).
pub const TILE_LIGHTS: u32 = 64;
/// Local volumes a block gathers at most (`TILE_VOLUMES` of `inject.wgsl`).
pub const TILE_VOLUMES: u32 = 64;
/// Froxels per inject block (`volfog::pipeline::cull::BLOCK`).
pub const BLOCK: [u32; 3] = [4, 4, 8];

/// A scene's frame, as the passes see it.
#[derive(Debug, Clone, Copy)]
pub struct SceneFrame<'a> {
    /// The froxel placement (projection, grid, slices).
    pub froxels: &'a Froxels,
    /// View -> world of the camera.
    pub world_from_view: Mat4,
    /// Point, spot and directional lights.
    pub lights: &'a [FogLight],
    /// Indices (into `lights`) of the lights with a shadow map (the frame's
    /// `ShadowedLight`s), which inject gathers apart.
    pub shadowed_lights: &'a [u32],
    /// Local fog volumes.
    pub local_volumes: &'a [LocalVolume],
    /// The sun's cascade splits (view depth) and their count.
    pub cascades: (Vec4, u32),
    /// Live slices per column (x fastest) from the scene's depth
    /// (`volfog::cpu::froxel::live_slices_from_depth`); `None`: every froxel is live.
    pub live_slices: Option<&'a [u32]>,
    /// The screen (width, height) the depth and the apply are at.
    pub screen: (u32, u32),
    /// Whether pixels beyond the volume get the far-plane tail (the frame's
    /// `HeightFog` has density): the apply with the tail runs, else the one without.
    pub far_tail: bool,
    /// Shadow taps per froxel with history where inject tests shadows by depth
    /// compares (the compare filter's `taps`; 1 for the ESM, which reads one value).
    pub shadow_taps: u32,
}

/// Means per wave of what the passes' loops run, and the blocks inject runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Workload {
    /// The grid.
    pub grid: [u32; 3],
    /// The screen.
    pub screen: (u32, u32),
    /// Whether the apply draws the far-plane tail.
    pub far_tail: bool,
    /// Blocks inject runs (the live ones), of the grid's.
    pub blocks: (u64, u64),
    /// Share of the grid's froxels that are live.
    pub live_fraction: f64,
    /// Lights in the light buffer.
    pub lights: u32,
    /// Local volumes in their buffer.
    pub local_volumes: u32,
    /// Iterations per wave of inject's light gather (`i < light_count`, strided by the
    /// workgroup).
    pub light_gather: f64,
    /// Iterations per wave of inject's volume gather.
    pub volume_gather: f64,
    /// Unshadowed lights gathered per block.
    pub lights_per_block: f64,
    /// Shadowed lights gathered per block.
    pub shadowed_per_block: f64,
    /// Local volumes gathered per block.
    pub volumes_per_block: f64,
    /// Iterations per wave of inject's loop that puts the gathered volumes back in
    /// buffer order (`other < tile_gathered`): the first `tile_gathered` (at most
    /// `TILE_VOLUMES`) invocations of a block, all in its first wave, run it
    /// `tile_gathered` times.
    pub volume_sort: f64,
    /// Iterations per wave of the cascade search (`esm_cascade`).
    pub cascade_steps: f64,
    /// Shadow taps per froxel beyond the first (the compare filter's tap loop).
    pub extra_shadow_taps: f64,
    /// Iterations per wave of the scan's loop over live slices.
    pub scan_live: f64,
    /// Iterations per wave of the scan's loop over the slices behind them.
    pub scan_rest: f64,
    /// Iterations per wave of the block compaction's loop (`z < count`).
    pub compact_blocks: f64,
    /// Depth texels per culling cell (rows, columns), per wave.
    pub cell_texels: (f64, f64),
}

/// Iterations per wave of a loop `for (i = local_index; i < n; i += group)` over a
/// workgroup of `group` invocations: wave `w` holds indices `64 w ..`, and runs as
/// long as its first invocation does.
pub fn gather_iterations(n: u32, group: u32) -> f64 {
    let waves = group.div_ceil(WAVE);
    let total: u32 = (0..waves)
        .map(|w| n.saturating_sub(w * WAVE).div_ceil(group))
        .sum();
    f64::from(total) / f64::from(waves)
}

/// Means over waves, from per-wave maxima.
#[derive(Default)]
struct Mean {
    sum: f64,
    n: f64,
}

impl Mean {
    fn add(&mut self, v: f64) {
        self.sum += v;
        self.n += 1.0;
    }
    fn get(&self) -> f64 {
        if self.n > 0.0 { self.sum / self.n } else { 0.0 }
    }
}

impl Workload {
    /// The workload of `frame` for inject workgroups of `group` invocations (128, or
    /// 64 with the checkerboard).
    pub fn of(frame: &SceneFrame<'_>, group: u32) -> Workload {
        let f = frame.froxels;
        let size = f.size;
        let columns = (size.x * size.y) as usize;
        let live = |x: u32, y: u32| -> u32 {
            frame
                .live_slices
                .filter(|l| l.len() == columns)
                .map_or(size.z, |l| l[(y * size.x + x) as usize].min(size.z))
        };
        let world = |id: UVec3, offset: Vec3| -> Vec3 {
            let view =
                froxel_view_position(id, offset, size, f.view_from_clip, f.near, f.far, f.curve);
            frame.world_from_view.transform_point3(view)
        };
        let grid = UVec3::new(
            size.x.div_ceil(BLOCK[0]),
            size.y.div_ceil(BLOCK[1]),
            size.z.div_ceil(BLOCK[2]),
        );
        let (mut lights, mut shadowed, mut volumes, mut cascade, mut sorted) = (
            Mean::default(),
            Mean::default(),
            Mean::default(),
            Mean::default(),
            Mean::default(),
        );
        let (mut blocks, mut live_froxels) = (0u64, 0u64);
        let mut compact = Mean::default();
        for by in 0..grid.y {
            for bx in 0..grid.x {
                let first = UVec2::new(bx * BLOCK[0], by * BLOCK[1]);
                let last =
                    (first + UVec2::new(BLOCK[0] - 1, BLOCK[1] - 1)).min(size.truncate() - 1);
                let mut deepest = 0;
                for y in first.y..=last.y {
                    for x in first.x..=last.x {
                        deepest = deepest.max(live(x, y));
                        live_froxels += u64::from(live(x, y));
                    }
                }
                compact.add(f64::from(deepest.div_ceil(BLOCK[2])));
                for bz in 0..deepest.div_ceil(BLOCK[2]) {
                    blocks += 1;
                    let block = UVec3::new(bx, by, bz);
                    let lo = block * UVec3::from(BLOCK);
                    let hi = (lo + UVec3::from(BLOCK) - 1).min(size - 1);
                    // The block's bounding sphere as inject builds it: the corners of
                    // its first and last froxel and three corners of its far face.
                    let corners = [
                        world(UVec3::new(lo.x, lo.y, lo.z), Vec3::new(-0.5, -0.5, -0.5)),
                        world(UVec3::new(hi.x, hi.y, hi.z), Vec3::new(0.5, 0.5, 0.5)),
                        world(UVec3::new(lo.x, lo.y, hi.z), Vec3::new(-0.5, -0.5, 0.5)),
                        world(UVec3::new(hi.x, lo.y, hi.z), Vec3::new(0.5, -0.5, 0.5)),
                        world(UVec3::new(lo.x, hi.y, hi.z), Vec3::new(-0.5, 0.5, 0.5)),
                    ];
                    let center = 0.5 * (corners[0] + corners[1]);
                    let radius = corners
                        .iter()
                        .map(|c| c.distance(center))
                        .fold(0.0, f32::max);
                    let (mut plain, mut with_maps) = (0u32, 0u32);
                    for (i, l) in frame.lights.iter().enumerate() {
                        if light_touches_sphere(l, center, radius) {
                            if frame.shadowed_lights.contains(&(i as u32)) {
                                with_maps += 1;
                            } else {
                                plain += 1;
                            }
                        }
                    }
                    lights.add(f64::from(plain.min(TILE_LIGHTS)));
                    shadowed.add(f64::from(with_maps.min(TILE_LIGHTS)));
                    let touching = frame
                        .local_volumes
                        .iter()
                        .filter(|v| {
                            volfog::cpu::density::local_volume_touches_sphere(v, center, radius)
                        })
                        .count() as u32;
                    volumes.add(f64::from(touching));
                    // The first wave runs the sort, the block's other waves skip it.
                    sorted.add(f64::from(touching.min(TILE_VOLUMES)));
                    for _ in 1..group.div_ceil(WAVE) {
                        sorted.add(0.0);
                    }
                    // Two waves per block (z 0..4 and 4..8): the cascade search runs as
                    // far as the wave's deepest froxel needs.
                    for half in 0..2u32 {
                        let mut steps = 0;
                        for z in 0..4u32 {
                            for y in 0..BLOCK[1] {
                                for x in 0..BLOCK[0] {
                                    let id = lo + UVec3::new(x, y, half * 4 + z);
                                    if id.x >= size.x || id.y >= size.y || id.z >= size.z {
                                        continue;
                                    }
                                    let view = froxel_view_position(
                                        id,
                                        Vec3::ZERO,
                                        size,
                                        f.view_from_clip,
                                        f.near,
                                        f.far,
                                        f.curve,
                                    );
                                    steps = steps.max(esm_cascade(
                                        view.z.abs(),
                                        frame.cascades.0,
                                        frame.cascades.1,
                                    ));
                                }
                            }
                        }
                        cascade.add(f64::from(steps));
                    }
                }
            }
        }
        // The scan: one invocation per column, 8 x 8 columns per wave.
        let (mut scan_live, mut scan_rest) = (Mean::default(), Mean::default());
        for wy in 0..size.y.div_ceil(8) {
            for wx in 0..size.x.div_ceil(8) {
                let (mut most, mut rest) = (0, 0);
                for y in wy * 8..(wy * 8 + 8).min(size.y) {
                    for x in wx * 8..(wx * 8 + 8).min(size.x) {
                        most = most.max(live(x, y));
                        rest = rest.max(size.z - live(x, y));
                    }
                }
                scan_live.add(f64::from(most));
                scan_rest.add(f64::from(rest));
            }
        }
        // Culling cells: half a column each, its rectangle of depth texels.
        let cells = 2 * size.truncate();
        let texels = UVec2::new(frame.screen.0, frame.screen.1);
        let (mut rows, mut cols) = (0u64, 0u64);
        for c in 0..cells.x.max(cells.y) {
            let [x0, y0, x1, y1] = froxel_cull_cell(
                UVec2::new(c.min(cells.x - 1), c.min(cells.y - 1)),
                cells,
                texels,
            );
            if c < cells.x {
                cols = cols.max(u64::from(x1 - x0 + 1));
            }
            if c < cells.y {
                rows = rows.max(u64::from(y1 - y0 + 1));
            }
        }
        let all_blocks = u64::from(grid.x) * u64::from(grid.y) * u64::from(grid.z);
        Workload {
            grid: size.to_array(),
            screen: frame.screen,
            far_tail: frame.far_tail,
            blocks: (blocks, all_blocks),
            live_fraction: live_froxels as f64 / (columns as f64 * f64::from(size.z)),
            lights: frame.lights.len() as u32,
            local_volumes: frame.local_volumes.len() as u32,
            light_gather: gather_iterations(frame.lights.len() as u32, group),
            volume_gather: gather_iterations(frame.local_volumes.len() as u32, group),
            lights_per_block: lights.get(),
            shadowed_per_block: shadowed.get(),
            volumes_per_block: volumes.get(),
            volume_sort: sorted.get(),
            cascade_steps: cascade.get(),
            extra_shadow_taps: f64::from(frame.shadow_taps.max(1) - 1),
            scan_live: scan_live.get(),
            scan_rest: scan_rest.get(),
            compact_blocks: compact.get(),
            cell_texels: (rows as f64, cols as f64),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gather_runs_in_the_waves_its_indices_reach() {
        // 8 lights over 128 invocations: the first wave once, the second not at all.
        assert_eq!(gather_iterations(8, 128), 0.5);
        assert_eq!(gather_iterations(0, 128), 0.0);
        // 100 lights: wave 0 holds 0..64 (and 128.. none), wave 1 holds 64..100.
        assert_eq!(gather_iterations(100, 128), 1.0);
        // 300 lights over 64 invocations: 5 strides.
        assert_eq!(gather_iterations(300, 64), 5.0);
    }

    #[test]
    fn an_empty_scene_with_every_froxel_live() {
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.1, 100.0);
        let froxels = Froxels::new(projection, UVec3::new(16, 9, 32), 0.5, 64.0, 3.0).unwrap();
        let frame = SceneFrame {
            froxels: &froxels,
            world_from_view: Mat4::IDENTITY,
            lights: &[],
            shadowed_lights: &[],
            local_volumes: &[],
            cascades: (Vec4::new(4.0, 8.0, 16.0, 64.0), 4),
            live_slices: None,
            screen: (160, 90),
            far_tail: false,
            shadow_taps: 1,
        };
        let w = Workload::of(&frame, 128);
        assert_eq!(w.blocks, (4 * 3 * 4, 4 * 3 * 4));
        assert_eq!(w.live_fraction, 1.0);
        assert_eq!((w.scan_live, w.scan_rest), (32.0, 0.0));
        assert_eq!(w.compact_blocks, 4.0);
        assert_eq!(w.lights_per_block, 0.0);
        // 160 x 90 texels over 32 x 18 cells: 5 columns and 5 rows each, and the
        // next cell's first (the rectangle is inclusive).
        assert_eq!(w.cell_texels, (6.0, 6.0));
        // Splits in front of the volume's near plane: the search runs all 4 steps
        // everywhere; behind its far plane: none; at 16 m: 1 step where the slices
        // cross it, so between the two.
        let at = |splits: Vec4| {
            Workload::of(
                &SceneFrame {
                    cascades: (splits, 4),
                    ..frame
                },
                128,
            )
            .cascade_steps
        };
        assert_eq!(at(Vec4::splat(0.1)), 4.0);
        assert_eq!(at(Vec4::splat(1000.0)), 0.0);
        let one = at(Vec4::new(16.0, 1000.0, 1000.0, 1000.0));
        assert!(one > 0.0 && one < 1.0, "{one}");
    }
}
