//! [`EpipolarApply`]: the fullscreen composite of the shafts alone onto the lit scene.

use super::{EpipolarError, EpipolarShafts};
use crate::pipeline::apply::FOG_BLEND;
use crate::pipeline::{
    RenderPipelineDesc, bind_group, bind_group_layout, render_pipeline, shader_module,
};

impl EpipolarShafts {
    /// The fullscreen composite of the shafts alone for colour targets of `format`
    /// (after `set_inputs`; create it again when the inputs change).
    pub fn create_apply(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> Result<EpipolarApply, EpipolarError> {
        let g = self
            .groups
            .as_ref()
            .ok_or(EpipolarError::NotReady("set_inputs"))?;
        let layout = bind_group_layout(device, "epipolar_apply", &Self::apply_entries());
        let vs = shader_module(device, "fullscreen", &[])?;
        let fs = shader_module(device, "epipolar_apply", &[])?;
        let pipeline = render_pipeline(
            device,
            RenderPipelineDesc {
                label: "volfog epipolar apply",
                vertex: (&vs, "fullscreen_vs"),
                fragment: (&fs, "epipolar_apply_fs"),
                bind_group_layouts: &[Some(&layout)],
                buffers: &[],
                primitive: wgpu::PrimitiveState::default(),
                target: wgpu::ColorTargetState {
                    format,
                    blend: Some(FOG_BLEND),
                    write_mask: wgpu::ColorWrites::ALL,
                },
                samples: 1,
            },
        );
        let shafts = self.shaft_view();
        let group = bind_group(
            device,
            "epipolar_apply",
            &layout,
            &[
                (0, self.frame.as_entire_binding()),
                (1, self.medium.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&g.depth)),
                (3, wgpu::BindingResource::TextureView(&shafts)),
            ],
        );
        Ok(EpipolarApply {
            pipeline,
            group,
            format,
        })
    }

    /// Records a render pass that loads `color` and blends the medium's fog with the
    /// shafts onto it.
    pub fn record_apply(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        apply: &EpipolarApply,
        color: &wgpu::TextureView,
    ) {
        let mut pass =
            crate::pipeline::apply::composite_pass(encoder, "volfog epipolar apply", color, None);
        apply.draw(&mut pass);
    }
}

/// The fullscreen composite of [`EpipolarShafts`] for one colour format.
#[derive(Debug)]
pub struct EpipolarApply {
    pipeline: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
    format: wgpu::TextureFormat,
}

impl EpipolarApply {
    /// The colour target format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Draws into the caller's render pass (colour attachment: the lit scene, loaded).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}
