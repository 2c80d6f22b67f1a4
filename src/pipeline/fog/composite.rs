//! The fullscreen apply of [`VolumetricFog`] onto the lit scene, and the fog group
//! forward shaders read the integrated volume through.

use super::{FogError, VolumetricFog, timings};
use crate::pipeline::apply::{ApplyPipeline, FogResources};

impl VolumetricFog {
    /// The fullscreen apply pass for colour targets of `format`, reading this fog's
    /// group (create one per format; it stays valid until the fog is reconfigured
    /// with another `apply_filtering`).
    pub fn create_apply(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::Depth)
    }

    /// The fullscreen apply pass reading `input` at group 1 (the forms of
    /// [`VolumetricFog::create_apply`], [`VolumetricFog::create_apply_resolved`] and
    /// [`VolumetricFog::create_apply_far_field`]).
    pub fn create_apply_with(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        input: crate::options::ApplyInput,
    ) -> Result<ApplyPipeline, FogError> {
        Ok(ApplyPipeline::with_input(
            device,
            &self.fog_layout,
            self.config.apply_filtering,
            format,
            input,
        )?)
    }

    /// The fullscreen apply pass for a multisampled scene: it reads the resolved MSAA
    /// fog layout ([`crate::options::FOG_LAYOUT_FORMAT`]) instead of the depth buffer.
    /// Lay out each sample with `volfog::apply::fog_layout` (the fog of the sample,
    /// from the fog group) into a multisampled target of that format, resolve it, and
    /// bind the resolved view with [`ApplyPipeline::depth_bind_group`].
    pub fn create_apply_resolved(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::ResolvedLayout)
    }

    /// The fullscreen apply pass with the far field of epipolar sun shafts: beyond the
    /// far plane the tail's sun light is shadowed by the lit fraction of an
    /// [`EpipolarShafts`](crate::pipeline::epipolar::EpipolarShafts) prepared with
    /// `start_depth` = `FogConfig::far`, the frame's tail as its medium and
    /// `max_depth` at least the camera's far plane. Bind its group 1 with
    /// [`ApplyPipeline::far_field_bind_group`].
    pub fn create_apply_far_field(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<ApplyPipeline, FogError> {
        self.create_apply_with(device, format, crate::options::ApplyInput::FarField)
    }

    /// The fullscreen apply pass of [`VolumetricFog::create_apply`] for a colour
    /// target of `samples` samples per pixel (1, 2, 4 or 8; the count the scene was
    /// rendered with, which the device supports for `format`): composite the fog onto
    /// a multisampled scene before it is resolved, with [`VolumetricFog::draw_apply`]
    /// in a render pass whose colour attachment is the multisampled target. The depth
    /// it reads is single-sampled: one depth per pixel (e.g. the farthest of the
    /// pixel's samples, which is also the depth that culls no visible froxel), so
    /// every sample of a pixel gets the same fog and a silhouette's pixels get the fog
    /// of that depth.
    pub fn create_apply_multisampled(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
    ) -> Result<ApplyPipeline, FogError> {
        crate::limits::check(
            matches!(samples, 1 | 2 | 4 | 8),
            "samples",
            samples,
            "1, 2, 4 or 8 samples per pixel",
        )?;
        Ok(ApplyPipeline::with_samples(
            device,
            &self.fog_layout,
            self.config.apply_filtering,
            format,
            crate::options::ApplyInput::Depth,
            samples,
        )?)
    }

    /// The prepared frame's far-plane tail: [`Tail::Empty`](crate::pipeline::apply::Tail::Empty)
    /// when its density is 0, and then [`VolumetricFog::draw_apply`] and
    /// [`VolumetricFog::record_apply`] draw the apply without it. Pass it to
    /// [`ApplyPipeline::draw_tail`] when drawing an apply of your own.
    pub fn tail(&self) -> crate::pipeline::apply::Tail {
        self.tail
    }

    fn check_apply(&self, apply: &ApplyPipeline) -> Result<(), FogError> {
        if apply.filtering() != self.config.apply_filtering {
            return Err(FogError::ApplyMismatch {
                pipeline: apply.filtering(),
                fog: self.config.apply_filtering,
            });
        }
        self.frame_index().map(|_| ()).ok_or(FogError::NotPrepared)
    }

    /// Draws the fullscreen apply into the caller's render pass (its colour
    /// attachment is the lit scene in `apply`'s format, loaded): `depth_group` comes
    /// from [`ApplyPipeline::depth_bind_group`]. A frame prepared with an empty tail
    /// (density 0, e.g. `HeightFog::none()`) is drawn by the variant without it: the
    /// same image for less work per pixel.
    pub fn draw_apply(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        apply: &ApplyPipeline,
        depth_group: &wgpu::BindGroup,
    ) -> Result<(), FogError> {
        self.check_apply(apply)?;
        apply.draw_tail(pass, &self.fog_group, depth_group, self.tail);
        Ok(())
    }

    /// Records the fullscreen apply in a render pass of its own that loads `color`
    /// (timed when timestamps are on), without the tail when the prepared frame's is
    /// empty (as [`VolumetricFog::draw_apply`]).
    pub fn record_apply(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &ApplyPipeline,
        color: &wgpu::TextureView,
        depth_group: &wgpu::BindGroup,
    ) -> Result<(), FogError> {
        self.check_apply(apply)?;
        let timestamps = self
            .timestamps
            .as_ref()
            .map(|t| t.render(timings::APPLY_PAIR, true, true));
        apply.record_tail(
            encoder,
            color,
            &self.fog_group,
            depth_group,
            timestamps,
            self.tail,
        );
        Ok(())
    }

    /// The `volfog::bindings` layout forward shaders use to read the fog (visible to
    /// fragment and compute stages).
    pub fn fog_bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.fog_layout
    }

    /// The bind group matching [`VolumetricFog::fog_bind_group_layout`].
    pub fn fog_bind_group(&self) -> &wgpu::BindGroup {
        &self.fog_group
    }

    /// The resources of the fog group, for a group of the caller's own that holds
    /// them (a material's group in an engine whose bind groups are all taken, at the
    /// bindings of `volfog::bindings`). They stay the same until the fog is
    /// reconfigured.
    pub fn fog_resources(&self) -> FogResources<'_> {
        FogResources {
            froxels: &self.buffers.froxels,
            integrated: &self.integrated_view,
            tail: &self.buffers.tail,
            view: &self.buffers.view,
            sampler: &self.fog_sampler,
        }
    }
}
