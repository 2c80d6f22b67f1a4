//! Recording the demo's passes: every shadow cascade, the lamp's six cube faces, the
//! lit opaque pass and sky, the semi-transparent pass fogged by the forward snippet,
//! the tonemap.

use volfog::pipeline::VolumetricFog;

use super::Renderer;

impl Renderer {
    /// Renders every cascade layer of the shadow map (opaque geometry only).
    pub fn encode_shadows(&self, encoder: &mut wgpu::CommandEncoder) {
        self.encode_depth_views(
            encoder,
            "demo shadow map",
            0,
            &self.shadow_layers,
            &self.cascade_groups,
        );
    }

    /// Renders the six faces of the lamp's cube shadow map (opaque geometry only; the
    /// faces are mirrored views, and the shadow pipeline does not cull).
    pub fn encode_lamp_shadow(&self, encoder: &mut wgpu::CommandEncoder) {
        self.encode_depth_views(
            encoder,
            "demo lamp shadow map",
            1,
            &self.lamp_faces,
            &self.lamp_groups,
        );
    }

    /// Renders the opaque geometry's depth into each view with the shadow pipeline and
    /// the view's camera group, timed as one span of timestamp pair `pair`.
    fn encode_depth_views(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pair: u32,
        views: &[wgpu::TextureView],
        groups: &[wgpu::BindGroup],
    ) {
        let last = views.len() - 1;
        for (i, (view, group)) in views.iter().zip(groups).enumerate() {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.render_timestamps(pair, i == 0, i == last),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, group, &[]);
            self.opaque.draw(&mut pass);
        }
    }

    /// The lit opaque pass and the sky: clears colour and depth.
    pub fn encode_opaque(&self, encoder: &mut wgpu::CommandEncoder, timed: bool) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo opaque"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: if timed {
                self.render_timestamps(2, true, true)
            } else {
                None
            },
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.opaque_pipeline);
        pass.set_bind_group(0, &self.scene_group, &[]);
        self.opaque.draw(&mut pass);
        self.emissive.draw(&mut pass);
        pass.set_pipeline(&self.sky_pipeline);
        pass.draw(0..3, 0..1);
    }

    /// The semi-transparent sphere and the pool's water surface, fogged through the
    /// forward snippet, blended over the fogged opaque image.
    pub fn encode_transparent(&self, encoder: &mut wgpu::CommandEncoder, fog: &VolumetricFog) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo transparent"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: self.render_timestamps(3, true, true),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.transparent_pipeline);
        pass.set_bind_group(0, &self.scene_group, &[]);
        pass.set_bind_group(1, fog.fog_bind_group(), &[]);
        self.glass.draw(&mut pass);
        pass.set_pipeline(&self.water_pipeline);
        self.water_surface.draw(&mut pass);
    }

    /// HDR -> sRGB display colour.
    pub fn encode_tonemap(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("demo tonemap"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.ldr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: self.render_timestamps(4, true, true),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.tonemap_pipeline);
        pass.set_bind_group(0, &self.tonemap_group, &[]);
        pass.draw(0..3, 0..1);
    }
}
