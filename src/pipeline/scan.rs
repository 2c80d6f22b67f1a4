//! The scan pass: integrates the scattering volume front to back into the
//! integrated volume (`shaders/passes/scan.wgsl`), its variant that adds the frame's
//! transient lights on the way (`VOLFOG_SCAN_TRANSIENT_LIGHTS`), and stereo fog's scan
//! of both eyes in one dispatch, each reading the volume both eyes share at its own
//! froxels' centres (`VOLFOG_SCAN_RESAMPLE`, `volfog::stereo`).

use super::{
    bind_group, bind_group_layout, compute_pipeline, sampler_entry, shader_module,
    storage_buffer_entry, storage_entry, texture_entry, uint_texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
use crate::options::{ScanStep, cull_defines};
use crate::shaders::CodegenError;

/// Workgroup size of the scan (x, y).
pub const WORKGROUP: u32 = 8;

/// Workgroup size in y of the resampling variant, whose workgroups are
/// `WORKGROUP x RESAMPLE_WORKGROUP_Y x 2` (z the eye).
pub const RESAMPLE_WORKGROUP_Y: u32 = 4;

/// The define of the scan variant that adds the frame's transient lights.
pub const TRANSIENT_LIGHTS_DEFINE: &str = "VOLFOG_SCAN_TRANSIENT_LIGHTS";

/// The define of stereo fog's scan of both eyes over the shared volume.
pub const RESAMPLE_DEFINE: &str = "VOLFOG_SCAN_RESAMPLE";

/// The defines of stereo fog's scan of both eyes for a step, with or without depth
/// culling.
pub fn resample_defines(step: ScanStep, cull: bool) -> Vec<String> {
    let mut defines = scan_defines(step, cull, false);
    defines.push(RESAMPLE_DEFINE.to_string());
    defines
}

/// One eye's resources in the resampling variant (the left eye's at bindings 0, 2,
/// 3 and 5, the right eye's at 10, 11, 13 and 12).
#[derive(Debug, Clone, Copy)]
pub struct ResampleEye<'a> {
    /// The eye's `Froxels` uniform.
    pub froxels: &'a wgpu::Buffer,
    /// The eye's `TransientLighting` uniform: its camera position and column rays.
    pub rays: &'a wgpu::Buffer,
    /// The eye's integrated volume (3D rgba16float, written).
    pub integrated: &'a wgpu::TextureView,
    /// The eye's live-slice texture, required by the depth-culling variant (ignored
    /// by the other).
    pub live_slices: Option<&'a wgpu::TextureView>,
}

/// What the resampling variant reads besides the eyes' resources and the shared
/// volume (bindings 7, 8 and 9).
#[derive(Debug, Clone, Copy)]
pub struct ResampleScanResources<'a> {
    /// A filtering, clamp-to-edge sampler for the shared volume.
    pub sampler: &'a wgpu::Sampler,
    /// The shared volume's `FogFrame` uniform (its `clip_from_world`).
    pub shared_frame: &'a wgpu::Buffer,
    /// The shared volume's `Froxels` uniform.
    pub shared_froxels: &'a wgpu::Buffer,
}

/// The defines of the scan variant for a step, with or without depth culling and the
/// transient lights.
pub fn scan_defines(step: ScanStep, cull: bool, transient_lights: bool) -> Vec<String> {
    let mut defines = step.defines();
    defines.extend(cull_defines(cull));
    if transient_lights {
        defines.push(TRANSIENT_LIGHTS_DEFINE.to_string());
    }
    defines
}

/// What the transient variant reads besides the volumes (bindings 4 to 6).
#[derive(Debug, Clone, Copy)]
pub struct TransientScanResources<'a> {
    /// The `FogMedium` uniform (the albedo, the phase and the height profile).
    pub medium: &'a wgpu::Buffer,
    /// The `TransientLighting` uniform.
    pub lighting: &'a wgpu::Buffer,
    /// The transient lights (`FogLight` elements, at least one).
    pub lights: &'a wgpu::Buffer,
}

/// The compiled scan pass.
#[derive(Debug)]
pub struct ScanPass {
    cull: bool,
    transient_lights: bool,
    resample: bool,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl ScanPass {
    /// The bind group layout: 0 `Froxels` uniform, 1 scattering volume (3D float,
    /// read with textureLoad), 2 integrated volume (3D rgba16float, write-only storage),
    /// with depth culling 3 the live-slice texture (2D uint), and with the transient
    /// lights 4 the `FogMedium` uniform, 5 the `TransientLighting` uniform and 6 the
    /// transient lights (read-only storage).
    pub fn layout_entries(cull: bool, transient_lights: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            uniform_entry(0, c),
            texture_entry(1, c, wgpu::TextureViewDimension::D3, false),
            storage_entry(
                2,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
        ];
        if cull {
            entries.push(uint_texture_entry(3));
        }
        if transient_lights {
            entries.extend([
                uniform_entry(4, c),
                uniform_entry(5, c),
                storage_buffer_entry(6, c, true),
            ]);
        }
        entries
    }

    /// The bind group layout of the resampling variant: 0 the left eye's `Froxels`, 1
    /// the shared volume (3D float, filterable), 2 the left eye's integrated volume,
    /// with depth culling 3 the left eye's live-slice texture, 5 the left eye's
    /// `TransientLighting`, 7 a filtering sampler, 8 the shared volume's `FogFrame`, 9
    /// its `Froxels`, then the right eye's `Froxels` (10), integrated volume (11),
    /// `TransientLighting` (12) and, with depth culling, live-slice texture (13).
    pub fn resample_layout_entries(cull: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = Self::layout_entries(cull, false);
        if let wgpu::BindingType::Texture { sample_type, .. } = &mut entries[1].ty {
            *sample_type = wgpu::TextureSampleType::Float { filterable: true };
        }
        entries.extend([
            uniform_entry(5, c),
            sampler_entry(7, c, true),
            uniform_entry(8, c),
            uniform_entry(9, c),
            uniform_entry(10, c),
            storage_entry(
                11,
                wgpu::TextureViewDimension::D3,
                wgpu::TextureFormat::Rgba16Float,
            ),
            uniform_entry(12, c),
        ]);
        if cull {
            entries.push(uint_texture_entry(13));
        }
        entries
    }

    /// Compiles the pass (`cull`: the depth-culling variant, `VOLFOG_FROXEL_CULL`).
    pub fn new(device: &wgpu::Device, step: ScanStep, cull: bool) -> Result<Self, CodegenError> {
        Self::build(device, step, cull, false, false)
    }

    /// Compiles the variant that adds the frame's transient lights
    /// (`VOLFOG_SCAN_TRANSIENT_LIGHTS`).
    pub fn with_transient_lights(
        device: &wgpu::Device,
        step: ScanStep,
        cull: bool,
    ) -> Result<Self, CodegenError> {
        Self::build(device, step, cull, true, false)
    }

    /// Compiles stereo fog's scan of both eyes over the shared volume
    /// (`VOLFOG_SCAN_RESAMPLE`).
    pub fn resampling(
        device: &wgpu::Device,
        step: ScanStep,
        cull: bool,
    ) -> Result<Self, CodegenError> {
        Self::build(device, step, cull, false, true)
    }

    fn build(
        device: &wgpu::Device,
        step: ScanStep,
        cull: bool,
        transient_lights: bool,
        resample: bool,
    ) -> Result<Self, CodegenError> {
        let (defines, entries) = if resample {
            (
                resample_defines(step, cull),
                Self::resample_layout_entries(cull),
            )
        } else {
            (
                scan_defines(step, cull, transient_lights),
                Self::layout_entries(cull, transient_lights),
            )
        };
        let module = shader_module(device, "scan", &defines)?;
        let layout = bind_group_layout(device, "volfog scan", &entries);
        let pipeline = compute_pipeline(device, "volfog scan", &module, "scan", &layout);
        Ok(Self {
            cull,
            transient_lights,
            resample,
            layout,
            pipeline,
        })
    }

    /// The bind group layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A bind group for the given resources; `live_slices` is required by the culling
    /// variant (ignored by the other). For the transient variant see
    /// [`ScanPass::bind_group_with`].
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        scattering: &wgpu::TextureView,
        integrated: &wgpu::TextureView,
        live_slices: Option<&wgpu::TextureView>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        self.bind_group_with(device, froxels, scattering, integrated, live_slices, None)
    }

    /// [`ScanPass::bind_group`] with the transient variant's resources, required by it
    /// (ignored by the others).
    pub fn bind_group_with(
        &self,
        device: &wgpu::Device,
        froxels: &wgpu::Buffer,
        scattering: &wgpu::TextureView,
        integrated: &wgpu::TextureView,
        live_slices: Option<&wgpu::TextureView>,
        transient: Option<TransientScanResources<'_>>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        let mut resources = vec![
            (0, froxels.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(scattering)),
            (2, wgpu::BindingResource::TextureView(integrated)),
        ];
        if self.cull {
            let Some(live) = live_slices else {
                return Err(InvalidValue {
                    field: "ScanPass::bind_group live_slices",
                    value: "None".to_string(),
                    expected: "the live-slice texture for the depth-culling variant".into(),
                });
            };
            resources.push((3, wgpu::BindingResource::TextureView(live)));
        }
        if self.transient_lights {
            let Some(t) = transient else {
                return Err(InvalidValue {
                    field: "ScanPass::bind_group_with transient",
                    value: "None".to_string(),
                    expected: "the medium, transient lighting and light buffers for the \
                               transient-light variant"
                        .into(),
                });
            };
            resources.extend([
                (4, t.medium.as_entire_binding()),
                (5, t.lighting.as_entire_binding()),
                (6, t.lights.as_entire_binding()),
            ]);
        }
        Ok(bind_group(device, "volfog scan", &self.layout, &resources))
    }

    /// A bind group of the resampling variant: the `shared` volume, both eyes'
    /// resources (`eyes[0]` the left eye) and those of [`ResampleScanResources`].
    /// Errors on a pass that is not the resampling variant, or on a missing live-slice
    /// texture for the depth-culling variant.
    pub fn resample_bind_group(
        &self,
        device: &wgpu::Device,
        shared: &wgpu::TextureView,
        eyes: [ResampleEye<'_>; 2],
        r: ResampleScanResources<'_>,
    ) -> Result<wgpu::BindGroup, InvalidValue> {
        if !self.resample {
            return Err(InvalidValue {
                field: "ScanPass::resample_bind_group",
                value: "a scan without VOLFOG_SCAN_RESAMPLE".into(),
                expected: "the pass of ScanPass::resampling".into(),
            });
        }
        let [left, right] = eyes;
        let mut resources = vec![
            (0, left.froxels.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(shared)),
            (2, wgpu::BindingResource::TextureView(left.integrated)),
            (5, left.rays.as_entire_binding()),
            (7, wgpu::BindingResource::Sampler(r.sampler)),
            (8, r.shared_frame.as_entire_binding()),
            (9, r.shared_froxels.as_entire_binding()),
            (10, right.froxels.as_entire_binding()),
            (11, wgpu::BindingResource::TextureView(right.integrated)),
            (12, right.rays.as_entire_binding()),
        ];
        if self.cull {
            for (binding, eye, field) in [
                (
                    3,
                    &left,
                    "ScanPass::resample_bind_group eyes[0].live_slices",
                ),
                (
                    13,
                    &right,
                    "ScanPass::resample_bind_group eyes[1].live_slices",
                ),
            ] {
                let Some(live) = eye.live_slices else {
                    return Err(InvalidValue {
                        field,
                        value: "None".to_string(),
                        expected: "the eye's live-slice texture for the depth-culling variant"
                            .into(),
                    });
                };
                resources.push((binding, wgpu::BindingResource::TextureView(live)));
            }
        }
        Ok(bind_group(
            device,
            "volfog scan resample",
            &self.layout,
            &resources,
        ))
    }

    /// Records the scan of a volume of `size` froxels (x, y); the resampling variant
    /// scans both eyes' volumes of that size.
    pub fn encode(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        bind_group: &wgpu::BindGroup,
        size: [u32; 2],
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        let rows = if self.resample {
            RESAMPLE_WORKGROUP_Y
        } else {
            WORKGROUP
        };
        pass.dispatch_workgroups(size[0].div_ceil(WORKGROUP), size[1].div_ceil(rows), 1);
    }
}
