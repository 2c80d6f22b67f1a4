//! The demo's shaders (composed with the volfog modules) and the render pipelines
//! of its passes: shadow, opaque, sky, transparent, water and tonemap.

use std::borrow::Cow;
use std::collections::HashMap;

use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog::pipeline::VolumetricFog;

use super::{DEPTH_FORMAT, HDR_FORMAT, LDR_FORMAT};
use crate::demo::scene::Vertex;

const SCENE_WGSL: &str = include_str!("scene.wgsl");
const SHADOW_WGSL: &str = include_str!("shadow.wgsl");
const TONEMAP_WGSL: &str = include_str!("tonemap.wgsl");

/// Composes a demo shader with the volfog modules (the fog group at index 1).
fn compose(source: &str, file_path: &str) -> Result<naga::Module, String> {
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).map_err(|e| e.to_string())?;
    let shader_defs = HashMap::from([("VOLFOG_FOG_GROUP".to_string(), ShaderDefValue::UInt(1))]);
    composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path,
            shader_defs,
            ..Default::default()
        })
        .map_err(|e| e.emit_to_string(&composer))
}

/// The render pipelines of the demo's passes.
pub(super) struct Pipelines {
    pub shadow_pipeline: wgpu::RenderPipeline,
    pub opaque_pipeline: wgpu::RenderPipeline,
    pub sky_pipeline: wgpu::RenderPipeline,
    pub transparent_pipeline: wgpu::RenderPipeline,
    pub water_pipeline: wgpu::RenderPipeline,
    pub tonemap_pipeline: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Compiles the demo's shaders and creates its pipelines over the bind group
    /// layouts of the scene, a shadow cascade and the tonemap.
    pub fn new(
        device: &wgpu::Device,
        fog: &VolumetricFog,
        scene_layout: &wgpu::BindGroupLayout,
        cascade_layout: &wgpu::BindGroupLayout,
        tonemap_layout: &wgpu::BindGroupLayout,
    ) -> Result<Self, String> {
        let scene_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo scene"),
            source: wgpu::ShaderSource::Naga(Cow::Owned(compose(
                SCENE_WGSL,
                "cli/src/demo/passes/scene.wgsl",
            )?)),
        });
        let shadow_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo shadow"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(SHADOW_WGSL)),
        });
        let tonemap_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("demo tonemap"),
            source: wgpu::ShaderSource::Naga(Cow::Owned(compose(
                TONEMAP_WGSL,
                "cli/src/demo/passes/tonemap.wgsl",
            )?)),
        });
        let layout = |label: &str, groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> =
                groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let scene_pipeline_layout = layout("demo scene", &[scene_layout]);
        let transparent_layout = layout(
            "demo transparent",
            &[scene_layout, fog.fog_bind_group_layout()],
        );
        let depth_state = |write: bool, compare| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            })
        };
        let color = |format, blend| {
            [Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })]
        };
        let back_culled = wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        };
        let vertex_layout = [Some(Vertex::layout())];
        let render_pipeline =
            |label: &str,
             layout: &wgpu::PipelineLayout,
             module: &wgpu::ShaderModule,
             vs: &str,
             buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
             fs: Option<(&str, &[Option<wgpu::ColorTargetState>])>,
             primitive: wgpu::PrimitiveState,
             depth: Option<wgpu::DepthStencilState>| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(layout),
                    vertex: wgpu::VertexState {
                        module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive,
                    depth_stencil: depth,
                    multisample: Default::default(),
                    fragment: fs.map(|(entry, targets)| wgpu::FragmentState {
                        module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        let shadow_pipeline = render_pipeline(
            "demo shadow",
            &layout("demo shadow", &[cascade_layout]),
            &shadow_module,
            "shadow_vs",
            &vertex_layout,
            None,
            wgpu::PrimitiveState::default(),
            depth_state(true, wgpu::CompareFunction::Less),
        );
        let opaque_pipeline = render_pipeline(
            "demo opaque",
            &scene_pipeline_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("opaque_fs", &color(HDR_FORMAT, None))),
            back_culled,
            depth_state(true, wgpu::CompareFunction::Less),
        );
        let sky_pipeline = render_pipeline(
            "demo sky",
            &scene_pipeline_layout,
            &scene_module,
            "sky_vs",
            &[],
            Some(("sky_fs", &color(HDR_FORMAT, None))),
            wgpu::PrimitiveState::default(),
            depth_state(false, wgpu::CompareFunction::LessEqual),
        );
        // Colour: alpha blending; alpha: the destination's (the probe's sun visibility).
        let glass_blend = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::SrcAlpha,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let transparent_pipeline = render_pipeline(
            "demo transparent",
            &transparent_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("transparent_fs", &color(HDR_FORMAT, Some(glass_blend)))),
            back_culled,
            depth_state(false, wgpu::CompareFunction::Less),
        );
        // The water surface: seen from above and from below (no culling).
        let water_pipeline = render_pipeline(
            "demo water",
            &transparent_layout,
            &scene_module,
            "scene_vs",
            &vertex_layout,
            Some(("water_fs", &color(HDR_FORMAT, Some(glass_blend)))),
            wgpu::PrimitiveState::default(),
            depth_state(false, wgpu::CompareFunction::Less),
        );
        let tonemap_pipeline = render_pipeline(
            "demo tonemap",
            &layout("demo tonemap", &[tonemap_layout]),
            &tonemap_module,
            "tonemap_vs",
            &[],
            Some(("tonemap_fs", &color(LDR_FORMAT, None))),
            wgpu::PrimitiveState::default(),
            None,
        );

        Ok(Self {
            shadow_pipeline,
            opaque_pipeline,
            sky_pipeline,
            transparent_pipeline,
            water_pipeline,
            tonemap_pipeline,
        })
    }
}
