//! The fog group (`volfog::bindings`), which forward shaders and the fullscreen apply
//! pass read, and the fullscreen apply pass (`shaders/passes/apply.wgsl` with the
//! vertex shader of `shaders/passes/fullscreen.wgsl`).

use std::num::NonZeroU32;

use super::{
    RenderPipelineDesc, bind_group, bind_group_layout, render_pipeline_multiview, shader_module,
    texture_entry, uniform_entry,
};
use crate::options::{ApplyInput, Filtering};
use crate::shaders::CodegenError;

/// The layout entries of the fog group (`volfog::bindings`): 0 `Froxels` uniform,
/// 1 integrated volume (3D float; filterable with a sampler, unfilterable with manual
/// filtering, which only loads texels), 2 linear sampler (absent with manual
/// filtering), 3 `HeightFog` uniform (the analytic tail beyond the far plane, in view
/// space), 4 `FogView` uniform (the camera's world -> view transform).
pub fn fog_layout_entries(
    filtering: Filtering,
    visibility: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut entries = vec![
        uniform_entry(0, visibility),
        texture_entry(
            1,
            visibility,
            wgpu::TextureViewDimension::D3,
            filtering == Filtering::Sampler,
        ),
    ];
    if filtering == Filtering::Sampler {
        entries.push(super::sampler_entry(2, visibility, true));
    }
    entries.push(uniform_entry(3, visibility));
    entries.push(uniform_entry(4, visibility));
    entries
}

/// The layout entries of the stereo fog group (`volfog::stereo_bindings`): the left
/// eye at the bindings of [`fog_layout_entries`] (0 `Froxels`, 1 integrated volume,
/// 2 the sampler shared by both eyes, absent with manual filtering, 3 `HeightFog` tail,
/// 4 `FogView`), the right eye's at those numbers + 5 (5 `Froxels`, 6 integrated volume,
/// 8 tail, 9 `FogView`; 7 is unused).
pub fn stereo_fog_layout_entries(
    filtering: Filtering,
    visibility: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut entries = fog_layout_entries(filtering, visibility);
    let right: Vec<_> = entries
        .iter()
        .filter(|e| !matches!(e.ty, wgpu::BindingType::Sampler(_)))
        .map(|e| wgpu::BindGroupLayoutEntry {
            binding: e.binding + RIGHT_EYE_OFFSET,
            ..*e
        })
        .collect();
    entries.extend(right);
    entries
}

/// How far the right eye's bindings of the stereo fog group lie from the left eye's.
pub const RIGHT_EYE_OFFSET: u32 = 5;

/// The resources of a fog group.
#[derive(Debug, Clone, Copy)]
pub struct FogResources<'a> {
    /// The `Froxels` uniform.
    pub froxels: &'a wgpu::Buffer,
    /// The integrated volume.
    pub integrated: &'a wgpu::TextureView,
    /// The `HeightFog` tail uniform (view space).
    pub tail: &'a wgpu::Buffer,
    /// The `FogView` uniform.
    pub view: &'a wgpu::Buffer,
    /// The sampler of [`fog_sampler`] (bound with [`Filtering::Sampler`] only).
    pub sampler: &'a wgpu::Sampler,
}

/// A fog group (layout from [`fog_layout_entries`] with `filtering`).
pub fn fog_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    filtering: Filtering,
    r: &FogResources<'_>,
) -> wgpu::BindGroup {
    let mut resources = vec![
        (0, r.froxels.as_entire_binding()),
        (1, wgpu::BindingResource::TextureView(r.integrated)),
        (3, r.tail.as_entire_binding()),
        (4, r.view.as_entire_binding()),
    ];
    if filtering == Filtering::Sampler {
        resources.push((2, wgpu::BindingResource::Sampler(r.sampler)));
    }
    bind_group(device, "volfog fog", layout, &resources)
}

/// The sampler the fog group expects: linear filtering, clamp to edge.
pub fn fog_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("volfog integrated volume"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    })
}

/// The blend state that turns the pass output (L, T) into `dst * T + L`.
pub const FOG_BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::SrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The layout entries of the apply pass's group 1: binding 0, the scene depth (2D,
/// unfilterable float view of a depth texture).
pub fn depth_layout_entries() -> [wgpu::BindGroupLayoutEntry; 1] {
    [texture_entry(
        0,
        wgpu::ShaderStages::FRAGMENT,
        wgpu::TextureViewDimension::D2,
        false,
    )]
}

/// The layout entries of the multiview apply pass's group 1: binding 0, the eyes' scene
/// depths (a 2D array, layer i the depth of view i, unfilterable float view of a depth
/// texture).
pub fn depth_array_layout_entries() -> [wgpu::BindGroupLayoutEntry; 1] {
    [texture_entry(
        0,
        wgpu::ShaderStages::FRAGMENT,
        wgpu::TextureViewDimension::D2Array,
        false,
    )]
}

/// The define of the multiview apply variant (stereo fog, both eyes in one draw).
pub const MULTIVIEW_DEFINE: &str = "VOLFOG_APPLY_MULTIVIEW";

/// The view mask of the multiview apply: layers 0 (left eye) and 1 (right eye).
pub const STEREO_VIEW_MASK: NonZeroU32 = NonZeroU32::new(0b11).unwrap();

/// The layout entries of the apply pass's group 1 for an input: the depth (or the
/// resolved layout) at binding 0 and, for [`ApplyInput::FarField`], the shaft texture
/// (2D, unfilterable float) at binding 1.
pub fn input_layout_entries(input: ApplyInput) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut entries = depth_layout_entries().to_vec();
    if input == ApplyInput::FarField {
        entries.push(texture_entry(
            1,
            wgpu::ShaderStages::FRAGMENT,
            wgpu::TextureViewDimension::D2,
            false,
        ));
    }
    entries
}

/// The compiled fullscreen apply pass for one colour format: draws into the caller's
/// render pass with the fog group at group 0 and a depth group at group 1.
#[derive(Debug)]
pub struct ApplyPipeline {
    filtering: Filtering,
    input: ApplyInput,
    format: wgpu::TextureFormat,
    samples: u32,
    /// The view mask of a multiview pipeline ([`ApplyPipeline::multiview`]).
    multiview: Option<NonZeroU32>,
    depth_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The variant without the far-plane tail (`VOLFOG_APPLY_NO_TAIL`), for frames whose
    /// tail is empty; none for [`ApplyInput::FarField`], which shadows the tail.
    no_tail: Option<wgpu::RenderPipeline>,
}

impl ApplyPipeline {
    /// Compiles the pass for fog groups laid out by `fog_layout` (built from
    /// [`fog_layout_entries`] with `filtering`) and a colour target of `format`.
    pub fn new(
        device: &wgpu::Device,
        fog_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
    ) -> Result<Self, CodegenError> {
        Self::with_input(device, fog_layout, filtering, format, ApplyInput::Depth)
    }

    /// As [`ApplyPipeline::new`], reading `input` at group 1 (the scene depth, or the
    /// resolved MSAA fog layout).
    pub fn with_input(
        device: &wgpu::Device,
        fog_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
        input: ApplyInput,
    ) -> Result<Self, CodegenError> {
        Self::with_samples(device, fog_layout, filtering, format, input, 1)
    }

    /// As [`ApplyPipeline::with_input`], drawing into a colour target of `samples`
    /// samples per pixel (a multisampled scene composited before its resolve): the
    /// fragment runs once per pixel and every covered sample blends the pixel's fog
    /// onto its own colour. `samples` must be a count the device supports for
    /// `format` (the count the scene was rendered with);
    /// [`VolumetricFog::create_apply_multisampled`](crate::pipeline::VolumetricFog::create_apply_multisampled)
    /// checks it is 1, 2, 4 or 8.
    pub fn with_samples(
        device: &wgpu::Device,
        fog_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
        input: ApplyInput,
        samples: u32,
    ) -> Result<Self, CodegenError> {
        Self::build(device, fog_layout, filtering, format, input, samples, None)
    }

    /// The multiview apply of stereo fog (`VOLFOG_APPLY_MULTIVIEW`): one draw fogs both
    /// layers of a two-layer colour target of `format` in a multiview render pass of view
    /// mask [`STEREO_VIEW_MASK`], reading the stereo fog group (laid out by
    /// `stereo_layout`, built from [`stereo_fog_layout_entries`] with `filtering`) at
    /// group 0 and the eyes' depths as a two-layer array at group 1
    /// ([`depth_array_layout_entries`]). The device needs `wgpu::Features::MULTIVIEW`
    /// (without it wgpu rejects the pipeline):
    /// [`StereoFog::create_apply_multiview`](crate::pipeline::StereoFog::create_apply_multiview)
    /// checks it and is the usual way to build this.
    pub fn multiview(
        device: &wgpu::Device,
        stereo_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
    ) -> Result<Self, CodegenError> {
        Self::multiview_views(device, stereo_layout, filtering, format, STEREO_VIEW_MASK)
    }

    /// [`ApplyPipeline::multiview`] drawing the views of `view_mask` (bits 0 and 1, the
    /// left and the right eye): `0b11` both eyes; one bit, that eye alone, in its
    /// layer (which needs `wgpu::Features::SELECTIVE_MULTIVIEW`).
    pub fn multiview_views(
        device: &wgpu::Device,
        stereo_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
        view_mask: NonZeroU32,
    ) -> Result<Self, CodegenError> {
        Self::build(
            device,
            stereo_layout,
            filtering,
            format,
            ApplyInput::Depth,
            1,
            Some(view_mask),
        )
    }

    fn build(
        device: &wgpu::Device,
        fog_layout: &wgpu::BindGroupLayout,
        filtering: Filtering,
        format: wgpu::TextureFormat,
        input: ApplyInput,
        samples: u32,
        multiview: Option<NonZeroU32>,
    ) -> Result<Self, CodegenError> {
        let vs = shader_module(device, "fullscreen", &[])?;
        let mut defines = filtering.defines();
        defines.extend(input.defines());
        let depth_entries = match multiview {
            Some(_) => {
                defines.push(MULTIVIEW_DEFINE.to_string());
                depth_array_layout_entries().to_vec()
            }
            None => input_layout_entries(input),
        };
        let depth_layout = bind_group_layout(device, "volfog apply depth", &depth_entries);
        let pipeline = |label: &str, defines: &[String]| {
            let fs = shader_module(device, "apply", defines)?;
            Ok::<_, CodegenError>(render_pipeline_multiview(
                device,
                RenderPipelineDesc {
                    label,
                    vertex: (&vs, "fullscreen_vs"),
                    fragment: (&fs, "apply_fs"),
                    bind_group_layouts: &[Some(fog_layout), Some(&depth_layout)],
                    buffers: &[],
                    primitive: wgpu::PrimitiveState::default(),
                    target: wgpu::ColorTargetState {
                        format,
                        blend: Some(FOG_BLEND),
                        write_mask: wgpu::ColorWrites::ALL,
                    },
                    samples,
                },
                multiview,
            ))
        };
        let with_tail = pipeline("volfog apply", &defines)?;
        let no_tail = match input {
            ApplyInput::FarField => None,
            ApplyInput::Depth | ApplyInput::ResolvedLayout => {
                let mut defines = defines.clone();
                defines.push(NO_TAIL_DEFINE.to_string());
                Some(pipeline("volfog apply without tail", &defines)?)
            }
        };
        Ok(Self {
            filtering,
            input,
            format,
            samples,
            multiview,
            depth_layout,
            pipeline: with_tail,
            no_tail,
        })
    }

    /// The filtering of the fog groups this pipeline reads.
    pub fn filtering(&self) -> Filtering {
        self.filtering
    }

    /// What the pass reads at group 1.
    pub fn input(&self) -> ApplyInput {
        self.input
    }

    /// The colour target format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Samples per pixel of the colour target it draws into.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The view mask of a multiview pipeline ([`ApplyPipeline::multiview`]; `None`
    /// otherwise): record it into a render pass of the same mask.
    pub fn multiview_mask(&self) -> Option<NonZeroU32> {
        self.multiview
    }

    /// The layout of group 1 (the scene depth).
    pub fn depth_bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.depth_layout
    }

    /// Group 1 for a scene depth view (a depth-aspect view of the depth texture, the
    /// size of the colour target; for a multiview pipeline a two-layer `D2Array` view), or with [`ApplyInput::ResolvedLayout`] a view of the
    /// resolved fog layout; build it once per texture.
    pub fn depth_bind_group(
        &self,
        device: &wgpu::Device,
        depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog apply depth",
            &self.depth_layout,
            &[(0, wgpu::BindingResource::TextureView(depth))],
        )
    }

    /// Group 1 of an [`ApplyInput::FarField`] pass: the scene depth view and the shaft
    /// texture's view (`EpipolarShafts::shaft_view`, the same size); build it once per
    /// pair of textures.
    pub fn far_field_bind_group(
        &self,
        device: &wgpu::Device,
        depth: &wgpu::TextureView,
        shafts: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "volfog apply far field",
            &self.depth_layout,
            &[
                (0, wgpu::BindingResource::TextureView(depth)),
                (1, wgpu::BindingResource::TextureView(shafts)),
            ],
        )
    }

    /// Records the fullscreen draw into a render pass whose colour attachment is the
    /// lit scene (loaded, not cleared), reading `fog_group` and `depth_group`, with the
    /// far-plane tail. [`VolumetricFog::draw_apply`](crate::pipeline::VolumetricFog::draw_apply)
    /// draws the variant without it when the prepared frame's tail is empty.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        fog_group: &wgpu::BindGroup,
        depth_group: &wgpu::BindGroup,
    ) {
        self.draw_tail(pass, fog_group, depth_group, Tail::Analytic);
    }

    /// [`ApplyPipeline::draw`] with the tail `tail`: [`Tail::Empty`] draws the variant
    /// without the tail (`VOLFOG_APPLY_NO_TAIL`), which is the same image when the
    /// fog group's tail has density 0, for less work per pixel. A far-field pipeline
    /// always draws its tail.
    pub fn draw_tail(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        fog_group: &wgpu::BindGroup,
        depth_group: &wgpu::BindGroup,
        tail: Tail,
    ) {
        let pipeline = match (tail, &self.no_tail) {
            (Tail::Empty, Some(no_tail)) => no_tail,
            _ => &self.pipeline,
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, fog_group, &[]);
        pass.set_bind_group(1, depth_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Records a render pass that loads `color` and blends the fog onto it (with the
    /// tail, as [`ApplyPipeline::draw`]). For a multiview pipeline the pass has its
    /// view mask and `color` must be a `D2Array` view of as many layers.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        fog_group: &wgpu::BindGroup,
        depth_group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        self.record_tail(
            encoder,
            color,
            fog_group,
            depth_group,
            timestamp_writes,
            Tail::Analytic,
        );
    }

    /// [`ApplyPipeline::record`] with the tail `tail` (see [`ApplyPipeline::draw_tail`]).
    pub fn record_tail(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        fog_group: &wgpu::BindGroup,
        depth_group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        tail: Tail,
    ) {
        let mut pass = composite_pass_multiview(
            encoder,
            "volfog apply",
            color,
            timestamp_writes,
            self.multiview,
        );
        self.draw_tail(&mut pass, fog_group, depth_group, tail);
    }
}

/// The define of the apply variant without the far-plane tail.
pub const NO_TAIL_DEFINE: &str = "VOLFOG_APPLY_NO_TAIL";

/// What lies beyond the far plane in the fog group an apply reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tail {
    /// The analytic height-fog tail (`volfog::apply::fog_tail`), drawn per pixel.
    Analytic,
    /// Nothing: the tail's density is 0 (e.g. `HeightFog::none()`), so the variant
    /// without it draws the same image.
    Empty,
}

impl Tail {
    /// The tail of a frame whose far-plane fog is `tail`.
    pub fn of(tail: &crate::uniforms::HeightFog) -> Self {
        if tail.density == 0.0 {
            Tail::Empty
        } else {
            Tail::Analytic
        }
    }
}

/// A render pass that loads `color` (the lit scene) and stores it, without depth: the
/// pass fullscreen composites draw into.
pub fn composite_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: &wgpu::TextureView,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    composite_pass_multiview(encoder, label, color, timestamp_writes, None)
}

/// [`composite_pass`] as a multiview render pass of view mask `multiview_mask` (`None`:
/// not multiview); `color` is then a `D2Array` view with a layer per view.
pub fn composite_pass_multiview<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: &wgpu::TextureView,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    multiview_mask: Option<NonZeroU32>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask,
    })
}
