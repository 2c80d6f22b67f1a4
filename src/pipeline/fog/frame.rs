//! Each frame of [`VolumetricFog`]: `prepare` checks and uploads the inputs, `encode`
//! records the passes.

use super::textures::{write_texel, write_unit_density};
use super::{FogError, FogPass, FrameInputs, VolumetricFog};
use crate::pipeline::cull::write_all_live;
use crate::uniforms::{self, AreaLight};

impl VolumetricFog {
    /// Checks one frame's inputs and uploads them; starts the next frame.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        inputs: &FrameInputs<'_>,
    ) -> Result<(), FogError> {
        let mut u = inputs.uniforms(&self.config, self.frames)?;
        // Shadow taps behind the scene's surface are left out once a scene depth is set.
        u.shadow_taps.use_scene_depth =
            u32::from(self.culling.as_ref().is_some_and(|c| c.depth.is_some()));
        if inputs.cascades.count > 0 && self.shadow_map.is_none() {
            return Err(FogError::Invalid(crate::limits::InvalidValue {
                field: "ShadowCascades.count",
                value: inputs.cascades.count.to_string(),
                expected: "0 while no shadow map is set (VolumetricFog::set_shadow_map)".into(),
            }));
        }
        // Every check comes before the first write, so a rejected frame changes nothing.
        let plan = match &self.local_shadows {
            Some(local) => Some(local.plan(inputs.lights, inputs.shadowed_lights)?),
            None => None,
        };
        let medium_shadow = match &self.medium_shadows {
            Some(m) => Some(m.placement(&u)?),
            None => None,
        };
        let b = &self.buffers;
        queue.write_buffer(&b.froxels, 0, &u.froxels.to_bytes());
        queue.write_buffer(&b.frame, 0, &uniforms::to_uniform_bytes(&u.frame));
        queue.write_buffer(&b.medium, 0, &uniforms::to_uniform_bytes(&u.medium));
        queue.write_buffer(&b.lighting, 0, &uniforms::to_uniform_bytes(&u.lighting));
        queue.write_buffer(&b.cascades, 0, &uniforms::to_uniform_bytes(&u.cascades));
        queue.write_buffer(
            &b.shadow_taps,
            0,
            &uniforms::to_uniform_bytes(&u.shadow_taps),
        );
        queue.write_buffer(&b.tail, 0, &u.tail.to_bytes());
        self.tail = crate::pipeline::apply::Tail::of(&u.tail);
        queue.write_buffer(&b.view, 0, &uniforms::to_uniform_bytes(&u.view));
        queue.write_buffer(&b.transient, 0, &uniforms::to_uniform_bytes(&u.transient));
        if !inputs.transient_lights.is_empty() {
            queue.write_buffer(
                &b.transient_lights,
                0,
                &uniforms::to_storage_bytes(inputs.transient_lights),
            );
        }
        self.transient_lights = u.transient.count;
        if self.config.max_area_lights > 0 {
            // Every slot is read: the unused ones are cleared (range 0).
            let mut area = vec![AreaLight::default(); self.config.max_area_lights as usize];
            area[..inputs.area_lights.len()].copy_from_slice(inputs.area_lights);
            queue.write_buffer(&b.area_lights, 0, &uniforms::to_storage_bytes(&area));
        }
        if !inputs.particles.is_empty() {
            // FogMedium.particle_count bounds what inject reads.
            queue.write_buffer(
                &b.particles,
                0,
                &uniforms::to_storage_bytes(inputs.particles),
            );
        }
        let lights = plan.as_ref().map_or(inputs.lights, |p| p.lights.as_slice());
        if !lights.is_empty() {
            queue.write_buffer(&b.lights, 0, &uniforms::to_storage_bytes(lights));
        }
        if let (Some(local), Some(plan)) = (self.local_shadows.as_mut(), &plan) {
            local.write(queue, &self.esm, plan);
        }
        if self.config.custom_density.is_some() {
            queue.write_buffer(
                &b.custom_params,
                0,
                &uniforms::to_uniform_bytes(&inputs.custom_params),
            );
        }
        if let (Some(m), Some(placement)) = (&self.medium_shadows, &medium_shadow) {
            m.write(queue, placement);
        }
        if !inputs.local_volumes.is_empty() {
            queue.write_buffer(
                &b.local_volumes,
                0,
                &uniforms::to_storage_bytes(inputs.local_volumes),
            );
        }
        if let Some(density) = self.density.as_mut().filter(|d| !d.user && !d.unit_written) {
            write_unit_density(queue, &density.texture);
            density.unit_written = true;
        }
        if let Some(clouds) = self.clouds.as_mut() {
            queue.write_buffer(&clouds.layer, 0, &inputs.clouds.to_bytes());
            if !clouds.user && !clouds.empty_written {
                write_texel(queue, &clouds.map, 0);
                clouds.empty_written = true;
            }
        }
        if let Some(c) = self
            .culling
            .as_mut()
            .filter(|c| c.depth.is_none() && !c.all_live)
        {
            for texture in &c.live {
                write_all_live(queue, texture, self.config.volume_size.z);
            }
            c.blocks
                .write_all(queue, self.config.volume_size.to_array());
            c.all_live = true;
        }
        if let Some(n) = self.noise.as_mut().filter(|n| !n.baked) {
            let mut encoder = n
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("volfog noise_bake"),
                });
            n.pass.encode(&n.device, &mut encoder, &n.texture);
            queue.submit([encoder.finish()]);
            n.baked = true;
        }
        self.shadows_enabled = inputs.cascades.count > 0;
        self.frames = self.frames.wrapping_add(1).max(1);
        Ok(())
    }

    /// The index of the prepared frame (frames prepared before it), `None` before
    /// the first `prepare`.
    pub fn frame_index(&self) -> Option<u32> {
        self.frames.checked_sub(1)
    }

    /// Records depth culling, ESM downsample -> blur, the local-light shadow atlas,
    /// the medium's shadows, inject -> temporal -> scan for the prepared frame (the scan adds the frame's
    /// transient lights, if any).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), FogError> {
        for pass in FogPass::ALL {
            self.encode_pass(encoder, pass)?;
        }
        Ok(())
    }

    /// Records one pass of [`VolumetricFog::encode`], e.g. to submit and time each
    /// pass on its own. Passes that do not run in this configuration or frame (ESM
    /// without cascades, temporal when disabled or fused into inject) record nothing.
    pub fn encode_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: FogPass,
    ) -> Result<(), FogError> {
        let index = self.frame_index().ok_or(FogError::NotPrepared)?;
        let parity = (index % 2) as usize;
        let c = &self.config;
        let size = c.volume_size.to_array();
        let label = match pass {
            FogPass::EsmDownsample => "volfog esm_downsample",
            FogPass::EsmBlur => "volfog esm_blur",
            FogPass::Inject => "volfog inject",
            FogPass::Temporal => "volfog temporal",
            FogPass::Scan => "volfog scan",
            FogPass::Cull => "volfog froxel_cull",
            FogPass::LocalShadows => "volfog local shadows",
            FogPass::MediumShadow => "volfog medium_shadow",
        };
        // With culling, inject and temporal run over the listed live blocks.
        let indirect = self.culling.as_ref().map(|c| &c.blocks.dispatch);
        let cull = self
            .culling
            .as_ref()
            .and_then(|c| Some(&c.pass).zip(c.depth.as_ref()));
        let shadow = self.shadow_map.as_ref().filter(|_| self.shadows_enabled);
        let runs = match pass {
            // The compare filter reads the shadow map itself.
            FogPass::EsmDownsample | FogPass::EsmBlur => {
                shadow.is_some() && !c.shadow_filter.compares()
            }
            FogPass::Temporal => self.temporal.as_ref().is_some_and(|t| t.pass.is_some()),
            FogPass::Inject | FogPass::Scan => true,
            FogPass::Cull => cull.is_some(),
            FogPass::LocalShadows => self.local_shadows.as_ref().is_some_and(|l| l.runs()),
            FogPass::MediumShadow => self.medium_shadows.is_some(),
        };
        if !runs {
            return Ok(());
        }
        let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: self.timestamp_writes(pass),
        });
        match pass {
            FogPass::EsmDownsample => {
                let group = &shadow.expect("checked above").group;
                self.esm
                    .encode_downsample(&mut compute, group, c.esm_resolution, c.cascades);
            }
            FogPass::EsmBlur => {
                for (axis, group) in self.blur_groups.iter().enumerate() {
                    self.esm.encode_blur(
                        &mut compute,
                        group,
                        axis as u32,
                        c.esm_resolution,
                        c.cascades,
                    );
                }
            }
            FogPass::Inject => {
                // The local-shadow variant only for frames whose lights project
                // something: the others cost what they cost without the feature.
                let projects = self.local_shadows.as_ref().is_some_and(|l| l.projects());
                let (pass, groups) = match &self.inject_shadowed {
                    Some((pass, groups)) if projects => (pass, groups),
                    _ => (&self.inject, &self.inject_groups),
                };
                pass.encode(&mut compute, &groups[parity], size, indirect)
            }
            FogPass::Temporal => {
                let (pass, groups) = self
                    .temporal
                    .as_ref()
                    .and_then(|t| t.pass.as_ref())
                    .expect("checked above");
                pass.encode(&mut compute, &groups[parity], size, indirect);
            }
            FogPass::Scan => {
                // The transient variant only for frames with transient lights.
                let (pass, groups) = match &self.scan_transient {
                    Some((pass, groups)) if self.transient_lights > 0 => (pass, groups),
                    _ => (&self.scan, &self.scan_groups),
                };
                pass.encode(&mut compute, &groups[parity], [size[0], size[1]]);
            }
            FogPass::Cull => {
                let (pass, (_, _, groups)) = cull.expect("checked above");
                pass.encode(&mut compute, &groups[parity], size);
            }
            FogPass::LocalShadows => {
                let local = self.local_shadows.as_ref().expect("checked above");
                local.encode(&mut compute, &self.esm);
            }
            FogPass::MediumShadow => {
                let medium = self.medium_shadows.as_ref().expect("checked above");
                medium.encode(&mut compute);
            }
        }
        Ok(())
    }
}
