//! Recording the passes of [`EpipolarShafts`] (the tree build level by level), and
//! reading back the correction counters and the timings.

use super::{EpipolarError, EpipolarMode, EpipolarPass, EpipolarShafts};
use crate::pipeline::TimestampError;

impl EpipolarShafts {
    /// Records the passes of `mode` that fill the shaft texture
    /// ([`EpipolarShafts::shaft_view`]), each timed when the device has
    /// `TIMESTAMP_QUERY` ([`EpipolarShafts::read_timings`]).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        mode: EpipolarMode,
    ) -> Result<(), EpipolarError> {
        for pass in EpipolarPass::of(mode, self.sampling.downscale) {
            let writes = self.timestamps.as_ref().map(|t| t.compute(pass as u32));
            self.encode_pass(encoder, pass, mode, writes)?;
        }
        encoder.copy_buffer_to_buffer(&self.counters, 0, &self.counters_readback, 0, 16);
        if let Some(t) = &self.timestamps {
            t.resolve(encoder);
        }
        Ok(())
    }

    /// Records one pass of `mode` in its own compute pass with the caller's timestamp
    /// writes (for timing passes one by one; [`EpipolarPass::of`] lists them in order).
    /// The first pass of a mode zeroes the correction counters.
    pub fn encode_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: EpipolarPass,
        mode: EpipolarMode,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), EpipolarError> {
        let g = self
            .groups
            .as_ref()
            .ok_or(EpipolarError::NotReady("set_inputs"))?;
        if !self.prepared {
            return Err(EpipolarError::NotReady("prepare"));
        }
        let s = &self.sampling;
        let p = &self.pipelines;
        if matches!(pass, EpipolarPass::Coords | EpipolarPass::Reference) {
            encoder.clear_buffer(&self.counters, 0, None);
        }
        if pass == EpipolarPass::Tree {
            self.encode_tree(encoder, timestamp_writes);
            return Ok(());
        }
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(pass.name()),
            timestamp_writes,
        });
        let (w, h) = (s.width.div_ceil(8), s.height.div_ceil(8));
        let per_sample = (s.samples.div_ceil(64), s.slices);
        let mut run =
            |pipeline: &wgpu::ComputePipeline, group: &wgpu::BindGroup, (x, y): (u32, u32)| {
                cp.set_pipeline(pipeline);
                cp.set_bind_group(0, group, &[]);
                cp.dispatch_workgroups(x, y, 1);
            };
        match pass {
            EpipolarPass::Coords => run(&p.coords.1, &g.coords, per_sample),
            EpipolarPass::Refine => run(&p.refine.1, &g.refine, (s.samples / 128, s.slices)),
            EpipolarPass::Tree => {}
            EpipolarPass::March if mode == EpipolarMode::Steps => {
                run(&p.steps.1, &g.steps, per_sample)
            }
            EpipolarPass::March => run(&p.march.1, &g.march, per_sample),
            EpipolarPass::Interpolate => run(&p.interpolate.1, &g.interpolate, per_sample),
            EpipolarPass::Resolve => {
                let (lw, lh) = s.resolved_size();
                run(&p.resolve.1, &g.resolve, (lw.div_ceil(8), lh.div_ceil(8)));
            }
            EpipolarPass::Upscale => {
                if let Some(upscale) = &g.upscale {
                    run(&p.upscale.1, upscale, (w, h));
                }
            }
            EpipolarPass::Reference => run(&p.reference.1, &g.reference, (w, h)),
        }
        Ok(())
    }

    /// The tree build: level 0 into the tree texture, then each level into the scratch
    /// texture and copied into the tree; the timestamps bracket all of it.
    fn encode_tree(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let (Some(g), s, p) = (self.groups.as_ref(), &self.sampling, &self.pipelines) else {
            return;
        };
        let top = s.shadow_size.trailing_zeros() as usize;
        for (l, group) in g.tree.iter().enumerate() {
            let writes = timestamp_writes
                .as_ref()
                .filter(|_| l == 0 || l == top)
                .map(|w| wgpu::ComputePassTimestampWrites {
                    query_set: w.query_set,
                    beginning_of_pass_write_index: w
                        .beginning_of_pass_write_index
                        .filter(|_| l == 0),
                    end_of_pass_write_index: w.end_of_pass_write_index.filter(|_| l == top),
                });
            let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("epipolar_tree"),
                timestamp_writes: writes,
            });
            // Each thread writes one texel (two nodes).
            let texels = (s.shadow_size >> l).max(2) / 2;
            cp.set_pipeline(if l == 0 { &p.tree.1 } else { &p.tree.2 });
            cp.set_bind_group(0, group, &[]);
            cp.dispatch_workgroups(texels.div_ceil(64), s.slices, 1);
            drop(cp);
            if l > 0 {
                let offset = (2 * s.shadow_size - ((2 * s.shadow_size) >> l)) / 2;
                encoder.copy_texture_to_texture(
                    self.textures.scratch.as_image_copy(),
                    wgpu::TexelCopyTextureInfo {
                        origin: wgpu::Origin3d {
                            x: offset,
                            y: 0,
                            z: 0,
                        },
                        ..self.textures.tree.as_image_copy()
                    },
                    wgpu::Extent3d {
                        width: texels,
                        height: s.slices,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
    }

    /// Pixels the last `encode` corrected by a march: (in the resolve, in the upscale).
    /// Blocks until the GPU is done.
    pub fn read_corrected(&self, device: &wgpu::Device) -> Result<(u32, u32), EpipolarError> {
        let slice = self.counters_readback.slice(..);
        let fail =
            |e: &dyn std::fmt::Display| EpipolarError::Timestamp(TimestampError(e.to_string()));
        crate::pipeline::timestamps::map_blocking(device, &slice).map_err(|e| fail(&e))?;
        let counts: Vec<u32> = {
            let data = slice.get_mapped_range().map_err(|e| fail(&e))?;
            bytemuck::cast_slice::<u8, u32>(&data).to_vec()
        };
        self.counters_readback.unmap();
        Ok((counts[0], counts[1]))
    }

    /// Milliseconds of each pass the last submitted `encode` of `mode` ran, in order;
    /// `None` without `TIMESTAMP_QUERY`. Blocks until the GPU is done.
    pub fn read_timings(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mode: EpipolarMode,
    ) -> Result<Option<Vec<(EpipolarPass, f64)>>, EpipolarError> {
        let Some(t) = &self.timestamps else {
            return Ok(None);
        };
        let ms = t.read_ms(device, queue)?;
        Ok(Some(
            EpipolarPass::of(mode, self.sampling.downscale)
                .into_iter()
                .map(|p| (p, ms[p as usize]))
                .collect(),
        ))
    }
}
