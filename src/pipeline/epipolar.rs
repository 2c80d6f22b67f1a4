//! Epipolar sun shafts (Yusov 2012; `volfog::epipolar`): [`EpipolarShafts`] owns the
//! epipolar textures, the min/max trees and the passes, and turns a depth buffer and a
//! cascaded shadow map into a shaft texture: alone, composited by its own fullscreen
//! pass ([`EpipolarApply`]), or as the far field of a
//! [`VolumetricFog`](super::VolumetricFog) (`VolumetricFog::create_apply_far_field`).

use wgpu::util::DeviceExt;

use super::apply::FOG_BLEND;
use super::{
    RenderPipelineDesc, TimestampError, TimestampPairs, bind_group, bind_group_layout,
    compute_pipeline, render_pipeline, shader_module, storage_buffer_entry, storage_entry,
    texture_entry, uint_texture_entry, uniform_entry,
};
use crate::limits::InvalidValue;
use crate::shaders::CodegenError;
use crate::uniforms::{self, EpipolarFrame, EpipolarSampling, EpipolarView, HeightFog};

/// Format of the shaft texture: rgb the lit fraction F in [0, 1] per colour channel (the
/// share of the medium's sun in-scattering along the pixel's ray that the sun reaches:
/// 1 unshadowed; the light's colour after stained glass for coloured shafts), a the
/// view depth (m).
pub const SHAFT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Formats the depth buffer may have (read as unfilterable float).
pub const DEPTH_FORMATS: [wgpu::TextureFormat; 5] = super::SCENE_DEPTH_FORMATS;
/// Formats the shadow map may have (read as unfilterable float, like the ESM passes).
pub const SHADOW_FORMATS: [wgpu::TextureFormat; 3] = super::SHADOW_MAP_FORMATS;

const COORD_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const SOURCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const TREE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const TERM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Stride of the per-level uniforms of the tree build (the uniform offset alignment).
const LEVEL_STRIDE: u64 = 256;

/// Errors of [`EpipolarShafts`].
#[derive(Debug, thiserror::Error)]
pub enum EpipolarError {
    /// A value is out of range.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// A shader failed to compose.
    #[error(transparent)]
    Shader(#[from] CodegenError),
    /// An input texture does not fit the sampling.
    #[error("{texture}: {property} is {found}, expected {expected}")]
    Texture {
        /// Which texture.
        texture: &'static str,
        /// The property that does not fit.
        property: &'static str,
        /// What it is.
        found: String,
        /// What it must be.
        expected: String,
    },
    /// `encode` or `create_apply` before `set_inputs`, or `encode` before `prepare`.
    #[error("EpipolarShafts: {0} first")]
    NotReady(&'static str),
    /// Reading timestamps or counters failed.
    #[error(transparent)]
    Timestamp(#[from] TimestampError),
}

/// Which march fills the shaft texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EpipolarMode {
    /// Epipolar sampling with the min/max tree march (Yusov's Algorithm 2).
    #[default]
    Tree,
    /// Epipolar sampling, each ray-marching sample visiting every section of its
    /// slice's height map in the shadow map (Algorithm 1; the same result, slower).
    Steps,
    /// No epipolar sampling: every pixel marched with `reference_steps` fixed steps.
    Reference,
}

/// The passes of [`EpipolarShafts`], in the order of [`EpipolarShafts::read_timings`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EpipolarPass {
    /// `epipolar_coords`: the coordinate texture.
    Coords,
    /// `epipolar_refine`: the ray-marching samples and interpolation sources.
    Refine,
    /// `epipolar_tree`: the 1D min/max trees (every level).
    Tree,
    /// `epipolar_march`: the march of the ray-marching samples.
    March,
    /// `epipolar_interpolate`: the other samples.
    Interpolate,
    /// `epipolar_resolve`: back to the (downscaled) screen.
    Resolve,
    /// `epipolar_upscale`: to full resolution (downscale > 1).
    Upscale,
    /// `epipolar_reference`: the per-pixel brute-force march.
    Reference,
}

impl EpipolarPass {
    /// Every pass, in timing order.
    pub const ALL: [EpipolarPass; 8] = [
        Self::Coords,
        Self::Refine,
        Self::Tree,
        Self::March,
        Self::Interpolate,
        Self::Resolve,
        Self::Upscale,
        Self::Reference,
    ];

    /// The pass's name (its WGSL file).
    pub fn name(self) -> &'static str {
        match self {
            Self::Coords => "epipolar_coords",
            Self::Refine => "epipolar_refine",
            Self::Tree => "epipolar_tree",
            Self::March => "epipolar_march",
            Self::Interpolate => "epipolar_interpolate",
            Self::Resolve => "epipolar_resolve",
            Self::Upscale => "epipolar_upscale",
            Self::Reference => "epipolar_reference",
        }
    }

    /// The passes `mode` runs, in order, for a resolve downscaled by `downscale`.
    pub fn of(mode: EpipolarMode, downscale: u32) -> Vec<EpipolarPass> {
        match mode {
            EpipolarMode::Reference => vec![Self::Reference],
            EpipolarMode::Tree | EpipolarMode::Steps => Self::ALL[..7]
                .iter()
                .copied()
                .filter(|p| !(*p == Self::Tree && mode == EpipolarMode::Steps))
                .filter(|p| !(*p == Self::Upscale && downscale == 1))
                .collect(),
        }
    }
}

#[derive(Debug)]
struct Pipelines {
    coords: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    refine: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    tree: (
        wgpu::BindGroupLayout,
        wgpu::ComputePipeline,
        wgpu::ComputePipeline,
    ),
    march: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    steps: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    interpolate: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    resolve: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    upscale: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    reference: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
}

#[derive(Debug)]
struct Groups {
    coords: wgpu::BindGroup,
    refine: wgpu::BindGroup,
    tree: Vec<wgpu::BindGroup>,
    march: wgpu::BindGroup,
    steps: wgpu::BindGroup,
    interpolate: wgpu::BindGroup,
    resolve: wgpu::BindGroup,
    upscale: Option<wgpu::BindGroup>,
    reference: wgpu::BindGroup,
    depth: wgpu::TextureView,
}

#[derive(Debug)]
struct Textures {
    coords: wgpu::Texture,
    sources: wgpu::Texture,
    /// Every level of every slice's tree, two nodes per texel.
    tree: wgpu::Texture,
    /// One level while it is built (copied into `tree`).
    scratch: wgpu::Texture,
    marched: wgpu::Texture,
    interpolated: wgpu::Texture,
    low: Option<wgpu::Texture>,
    shafts: wgpu::Texture,
}

/// Epipolar sun shafts for one camera and target size.
///
/// ```no_run
/// # fn f(device: &wgpu::Device, queue: &wgpu::Queue, depth: &wgpu::Texture, shadow: &wgpu::Texture, color: &wgpu::TextureView) -> Result<(), volfog::pipeline::epipolar::EpipolarError> {
/// use glam::{Mat4, Vec3};
/// use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
/// use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
///
/// let mut shafts = EpipolarShafts::new(device, EpipolarSampling::new(1920, 1080, 2048))?;
/// shafts.set_inputs(device, depth, shadow)?; // again when either texture is recreated
/// let apply = shafts.create_apply(device, wgpu::TextureFormat::Rgba16Float)?;
/// let sun = Vec3::new(0.3, 0.4, -0.87).normalize();
/// let medium = HeightFog::new(Vec3::splat(0.02), 0.01, Vec3::Y, 0.0, 0.0)?
///     .with_sun(sun, Vec3::splat(2.0), 0.6)?;
/// let view = EpipolarView {
///     view_from_world: Mat4::IDENTITY,
///     clip_from_view: glam::camera::rh::proj::directx::perspective(1.0, 1.78, 0.1, 500.0),
///     // the cascade's matrix, as for VolumetricFog's ShadowCascades
///     light_from_world: volfog::pipeline::cascade_projection(sun, Vec3::ZERO, 100.0, 400.0),
///     cascade: 0,
///     rayleigh: Vec3::ZERO,
///     phase: EpipolarPhase::HenyeyGreenstein,
///     start_depth: 0.0,
///     max_depth: 500.0,
///     depth_bias: 0.001,
/// };
/// shafts.prepare(queue, &view, &medium)?;
/// let mut encoder = device.create_command_encoder(&Default::default());
/// shafts.encode(&mut encoder, EpipolarMode::Tree)?;
/// shafts.record_apply(&mut encoder, &apply, color);
/// queue.submit([encoder.finish()]);
/// # Ok(()) }
/// ```
#[derive(Debug)]
pub struct EpipolarShafts {
    sampling: EpipolarSampling,
    prepared: bool,
    frame: wgpu::Buffer,
    medium: wgpu::Buffer,
    levels: wgpu::Buffer,
    counters: wgpu::Buffer,
    counters_readback: wgpu::Buffer,
    textures: Textures,
    pipelines: Pipelines,
    groups: Option<Groups>,
    timestamps: Option<TimestampPairs>,
}

fn storage_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

const C: wgpu::ShaderStages = wgpu::ShaderStages::COMPUTE;
const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;

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

    /// Allocates the textures and compiles the passes for `sampling`.
    pub fn new(device: &wgpu::Device, sampling: EpipolarSampling) -> Result<Self, EpipolarError> {
        sampling.validate()?;
        let s = &sampling;
        let epi = (s.samples, s.slices);
        let textures = Textures {
            coords: storage_texture(device, "volfog epipolar coordinates", epi, COORD_FORMAT),
            sources: storage_texture(device, "volfog epipolar sources", epi, SOURCE_FORMAT),
            tree: storage_texture(
                device,
                "volfog epipolar tree",
                (s.shadow_size, s.slices),
                TREE_FORMAT,
            ),
            scratch: storage_texture(
                device,
                "volfog epipolar tree scratch",
                (s.shadow_size / 4, s.slices),
                TREE_FORMAT,
            ),
            marched: storage_texture(device, "volfog epipolar marched", epi, TERM_FORMAT),
            interpolated: storage_texture(device, "volfog epipolar interpolated", epi, TERM_FORMAT),
            low: (s.downscale > 1).then(|| {
                storage_texture(
                    device,
                    "volfog epipolar resolved",
                    s.resolved_size(),
                    SHAFT_FORMAT,
                )
            }),
            shafts: storage_texture(
                device,
                "volfog epipolar shafts",
                (s.width, s.height),
                SHAFT_FORMAT,
            ),
        };
        let compute = |pass: &str, defines: &[String], entry: &str, entries: Vec<_>| {
            let layout = bind_group_layout(device, pass, &entries);
            let module = shader_module(device, pass, defines)?;
            let pipeline = compute_pipeline(device, entry, &module, entry, &layout);
            Ok::<_, CodegenError>((layout, pipeline))
        };
        let colored: Vec<String> = if s.colored {
            vec!["VOLFOG_EPIPOLAR_COLORED".to_string()]
        } else {
            Vec::new()
        };
        let tree_layout = bind_group_layout(device, "epipolar_tree", &Self::tree_entries());
        let tree_module = shader_module(device, "epipolar_tree", &[])?;
        let tree_init = compute_pipeline(
            device,
            "epipolar_tree_init",
            &tree_module,
            "epipolar_tree_init",
            &tree_layout,
        );
        let tree_level = compute_pipeline(
            device,
            "epipolar_tree_level",
            &tree_module,
            "epipolar_tree_level",
            &tree_layout,
        );
        let pipelines = Pipelines {
            coords: compute(
                "epipolar_coords",
                &[],
                "epipolar_coords",
                Self::coords_entries(),
            )?,
            refine: compute(
                "epipolar_refine",
                &[],
                "epipolar_refine",
                Self::refine_entries(),
            )?,
            tree: (tree_layout, tree_init, tree_level),
            march: compute(
                "epipolar_march",
                &colored,
                "epipolar_march",
                Self::march_entries(false, s.colored),
            )?,
            steps: compute(
                "epipolar_march",
                &[
                    colored.clone(),
                    vec!["VOLFOG_EPIPOLAR_BRUTE_FORCE".to_string()],
                ]
                .concat(),
                "epipolar_march",
                Self::march_entries(true, s.colored),
            )?,
            interpolate: compute(
                "epipolar_interpolate",
                &[],
                "epipolar_interpolate",
                Self::interpolate_entries(),
            )?,
            resolve: compute(
                "epipolar_resolve",
                &colored,
                "epipolar_resolve",
                Self::resolve_entries(s.colored),
            )?,
            upscale: compute(
                "epipolar_upscale",
                &colored,
                "epipolar_upscale",
                Self::upscale_entries(s.colored),
            )?,
            reference: compute(
                "epipolar_reference",
                &colored,
                "epipolar_reference",
                Self::reference_entries(s.colored),
            )?,
        };
        let uniform = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let top = s.shadow_size.trailing_zeros();
        let mut level_bytes = vec![0u8; (LEVEL_STRIDE * u64::from(top + 1)) as usize];
        for l in 0..=top {
            let at = (LEVEL_STRIDE * u64::from(l)) as usize;
            level_bytes[at..at + 4].copy_from_slice(&l.to_le_bytes());
        }
        let levels = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("volfog epipolar tree levels"),
            contents: &level_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog epipolar counters"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let counters_readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("volfog epipolar counters readback"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let timestamps = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| {
                TimestampPairs::new(
                    device,
                    "volfog epipolar timestamps",
                    EpipolarPass::ALL.len() as u32,
                )
            });
        Ok(Self {
            sampling,
            prepared: false,
            frame: uniform(
                "volfog epipolar frame",
                uniforms::to_uniform_bytes(&EpipolarFrame::default()).len() as u64,
            ),
            medium: uniform(
                "volfog epipolar medium",
                HeightFog::default().to_bytes().len() as u64,
            ),
            levels,
            counters,
            counters_readback,
            textures,
            pipelines,
            groups: None,
            timestamps,
        })
    }

    /// The sampling this object was made for.
    pub fn sampling(&self) -> &EpipolarSampling {
        &self.sampling
    }

    /// Binds the scene depth buffer (`width` x `height`, one of [`DEPTH_FORMATS`],
    /// single-sampled) and the cascaded shadow map (a 2D texture of side
    /// `shadow_size`, one layer per cascade, one of [`SHADOW_FORMATS`]); both need
    /// `TEXTURE_BINDING` usage. Call again when either is recreated. With
    /// `EpipolarSampling::colored`, see [`EpipolarShafts::set_inputs_colored`].
    pub fn set_inputs(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
    ) -> Result<(), EpipolarError> {
        self.bind(device, depth, shadow, None)
    }

    /// [`EpipolarShafts::set_inputs`] for coloured shafts (`EpipolarSampling::colored`):
    /// `colors` is the light-space colour texture, the light's colour after stained
    /// glass as the cascade sees it (2D, `shadow_size` texels square, texel-aligned with
    /// the cascade; a float format, rgb used), with `TEXTURE_BINDING` usage.
    pub fn set_inputs_colored(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
        colors: &wgpu::Texture,
    ) -> Result<(), EpipolarError> {
        self.bind(device, depth, shadow, Some(colors))
    }

    fn bind(
        &mut self,
        device: &wgpu::Device,
        depth: &wgpu::Texture,
        shadow: &wgpu::Texture,
        colors: Option<&wgpu::Texture>,
    ) -> Result<(), EpipolarError> {
        let s = self.sampling;
        if s.colored != colors.is_some() {
            return Err(EpipolarError::Texture {
                texture: "the light colours",
                property: "presence",
                found: if colors.is_some() { "given" } else { "missing" }.into(),
                expected: if s.colored {
                    "a colour texture: EpipolarSampling::colored is set (set_inputs_colored)"
                } else {
                    "none: EpipolarSampling::colored is not set (set_inputs)"
                }
                .into(),
            });
        }
        if let Some(c) = colors {
            let float = matches!(
                c.format().sample_type(None, Some(device.features())),
                Some(wgpu::TextureSampleType::Float { .. })
            );
            if !float {
                return Err(EpipolarError::Texture {
                    texture: "the light colours",
                    property: "format",
                    found: format!("{:?}", c.format()),
                    expected: "a float format (rgba8unorm, rgba16float, ...)".into(),
                });
            }
            check_texture(
                "the light colours",
                c,
                &[c.format()],
                (s.shadow_size, s.shadow_size),
            )?;
        }
        check_texture(
            "the depth buffer",
            depth,
            &DEPTH_FORMATS,
            (s.width, s.height),
        )?;
        check_texture(
            "the shadow map",
            shadow,
            &SHADOW_FORMATS,
            (s.shadow_size, s.shadow_size),
        )?;
        let aspect = |t: &wgpu::Texture| {
            if t.format().has_depth_aspect() {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            }
        };
        let depth_view = depth.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(D2),
            aspect: aspect(depth),
            ..Default::default()
        });
        let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            aspect: aspect(shadow),
            ..Default::default()
        });
        let t = &self.textures;
        let p = &self.pipelines;
        let (coords, sources, marched, interpolated, shafts) = (
            view(&t.coords),
            view(&t.sources),
            view(&t.marched),
            view(&t.interpolated),
            view(&t.shafts),
        );
        let (tree, scratch) = (view(&t.tree), view(&t.scratch));
        use wgpu::BindingResource as R;
        let frame = self.frame.as_entire_binding();
        let medium = self.medium.as_entire_binding();
        let counters = self.counters.as_entire_binding();
        let top = s.shadow_size.trailing_zeros();
        let tree_groups = (0..=top)
            .map(|l| {
                // Level 0 is written into the tree; level l > 0 is read from the tree
                // into the scratch texture, then copied into the tree.
                let (src, dst) = if l == 0 {
                    (&scratch, &tree)
                } else {
                    (&tree, &scratch)
                };
                bind_group(
                    device,
                    "epipolar_tree",
                    &p.tree.0,
                    &[
                        (0, frame.clone()),
                        (1, R::TextureView(&shadow_view)),
                        (2, R::TextureView(src)),
                        (3, R::TextureView(dst)),
                        (
                            4,
                            R::Buffer(wgpu::BufferBinding {
                                buffer: &self.levels,
                                offset: LEVEL_STRIDE * u64::from(l),
                                size: wgpu::BufferSize::new(16),
                            }),
                        ),
                    ],
                )
            })
            .collect();
        let low = t.low.as_ref().map(view);
        let resolve_target = low.as_ref().unwrap_or(&shafts);
        let color_view = colors.map(view);
        let color = |binding: u32| color_view.as_ref().map(|v| (binding, R::TextureView(v)));
        let groups = Groups {
            coords: bind_group(
                device,
                "epipolar_coords",
                &p.coords.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&depth_view)),
                    (2, R::TextureView(&coords)),
                ],
            ),
            refine: bind_group(
                device,
                "epipolar_refine",
                &p.refine.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&coords)),
                    (2, R::TextureView(&sources)),
                ],
            ),
            tree: tree_groups,
            march: bind_group(
                device,
                "epipolar_march",
                &p.march.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&coords)),
                    (3, R::TextureView(&sources)),
                    (4, R::TextureView(&tree)),
                    (5, R::TextureView(&marched)),
                ]
                .into_iter()
                .chain(color(6))
                .collect::<Vec<_>>(),
            ),
            steps: bind_group(
                device,
                "epipolar_march steps",
                &p.steps.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&coords)),
                    (3, R::TextureView(&sources)),
                    (4, R::TextureView(&shadow_view)),
                    (5, R::TextureView(&marched)),
                ]
                .into_iter()
                .chain(color(6))
                .collect::<Vec<_>>(),
            ),
            interpolate: bind_group(
                device,
                "epipolar_interpolate",
                &p.interpolate.0,
                &[
                    (0, frame.clone()),
                    (1, R::TextureView(&sources)),
                    (2, R::TextureView(&marched)),
                    (3, R::TextureView(&interpolated)),
                ],
            ),
            resolve: bind_group(
                device,
                "epipolar_resolve",
                &p.resolve.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&depth_view)),
                    (3, R::TextureView(&coords)),
                    (4, R::TextureView(&interpolated)),
                    (5, R::TextureView(&shadow_view)),
                    (6, R::TextureView(resolve_target)),
                    (7, counters.clone()),
                ]
                .into_iter()
                .chain(color(8))
                .collect::<Vec<_>>(),
            ),
            upscale: low.as_ref().map(|low| {
                bind_group(
                    device,
                    "epipolar_upscale",
                    &p.upscale.0,
                    &[
                        (0, frame.clone()),
                        (1, medium.clone()),
                        (2, R::TextureView(&depth_view)),
                        (3, R::TextureView(low)),
                        (4, R::TextureView(&shadow_view)),
                        (5, R::TextureView(&shafts)),
                        (6, counters.clone()),
                    ]
                    .into_iter()
                    .chain(color(7))
                    .collect::<Vec<_>>(),
                )
            }),
            reference: bind_group(
                device,
                "epipolar_reference",
                &p.reference.0,
                &[
                    (0, frame.clone()),
                    (1, medium.clone()),
                    (2, R::TextureView(&depth_view)),
                    (3, R::TextureView(&shadow_view)),
                    (4, R::TextureView(&shafts)),
                ]
                .into_iter()
                .chain(color(5))
                .collect::<Vec<_>>(),
            ),
            depth: depth_view,
        };
        self.groups = Some(groups);
        Ok(())
    }

    /// Writes the frame: the camera and cascade in `view`, the medium `medium` in
    /// world space (its `sun_direction` is the light's; uniform fog has falloff 0).
    /// Returns the frame written.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        view: &EpipolarView,
        medium: &HeightFog,
    ) -> Result<EpipolarFrame, EpipolarError> {
        let frame = EpipolarFrame::new(&self.sampling, view, medium.sun_direction)?;
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(&frame));
        queue.write_buffer(
            &self.medium,
            0,
            &EpipolarFrame::medium(medium, view.view_from_world).to_bytes(),
        );
        self.prepared = true;
        Ok(frame)
    }

    /// Writes a frame built by hand (for example with the epipole placed exactly on
    /// the screen's edge) and the medium already in view space. The frame's sampling
    /// fields must be this object's.
    pub fn prepare_frame(
        &mut self,
        queue: &wgpu::Queue,
        frame: &EpipolarFrame,
        medium_in_view: &HeightFog,
    ) -> Result<(), EpipolarError> {
        let s = &self.sampling;
        crate::limits::check(
            (
                frame.slices,
                frame.samples,
                frame.initial_step,
                frame.shadow_size,
                frame.downscale,
            ) == (
                s.slices,
                s.samples,
                s.initial_step,
                s.shadow_size,
                s.downscale,
            ) && frame.screen_size == glam::Vec2::new(s.width as f32, s.height as f32),
            "EpipolarFrame",
            (
                frame.slices,
                frame.samples,
                frame.initial_step,
                frame.shadow_size,
                frame.downscale,
            ),
            "the sampling of this EpipolarShafts (slices, samples, initial_step, shadow_size, downscale, screen_size)",
        )?;
        crate::limits::check(
            frame.light_screen.is_finite()
                && frame.light_screen.abs().max_element() <= uniforms::EPIPOLE_LIMIT,
            "EpipolarFrame.light_screen",
            frame.light_screen,
            "finite, |x|, |y| <= EPIPOLE_LIMIT",
        )?;
        medium_in_view.validate()?;
        queue.write_buffer(&self.frame, 0, &uniforms::to_uniform_bytes(frame));
        queue.write_buffer(&self.medium, 0, &medium_in_view.to_bytes());
        self.prepared = true;
        Ok(())
    }

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

    /// The shaft texture ([`SHAFT_FORMAT`], `width` x `height`): r the lit fraction F.
    pub fn shaft_texture(&self) -> &wgpu::Texture {
        &self.textures.shafts
    }

    /// A view of the shaft texture (bind it as unfilterable float).
    pub fn shaft_view(&self) -> wgpu::TextureView {
        view(&self.textures.shafts)
    }

    /// The coordinate texture (rgba32float, samples x slices), for inspection.
    pub fn coordinate_texture(&self) -> &wgpu::Texture {
        &self.textures.coords
    }

    /// The interpolation sources (r32uint, two u16 sample indices, samples x slices),
    /// for inspection.
    pub fn source_texture(&self) -> &wgpu::Texture {
        &self.textures.sources
    }

    /// The marched lit fractions (r32float, samples x slices; 1 at samples that are not
    /// marched), for inspection.
    pub fn marched_texture(&self) -> &wgpu::Texture {
        &self.textures.marched
    }

    /// Bytes of every texture and buffer this object owns.
    pub fn memory_bytes(&self) -> u64 {
        let t = &self.textures;
        let textures = [
            &t.coords,
            &t.sources,
            &t.tree,
            &t.scratch,
            &t.marched,
            &t.interpolated,
            &t.shafts,
        ]
        .into_iter()
        .chain(t.low.as_ref())
        .map(super::fog::texture_bytes)
        .sum::<u64>();
        textures
            + self.frame.size()
            + self.medium.size()
            + self.levels.size()
            + self.counters.size()
            + self.counters_readback.size()
            + self
                .timestamps
                .as_ref()
                .map_or(0, TimestampPairs::buffer_bytes)
    }

    /// Pixels the last `encode` corrected by a march: (in the resolve, in the upscale).
    /// Blocks until the GPU is done.
    pub fn read_corrected(&self, device: &wgpu::Device) -> Result<(u32, u32), EpipolarError> {
        let slice = self.counters_readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let fail =
            |e: &dyn std::fmt::Display| EpipolarError::Timestamp(TimestampError(e.to_string()));
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| fail(&e))?;
        rx.recv().map_err(|e| fail(&e))?.map_err(|e| fail(&e))?;
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
        let mut pass = super::apply::composite_pass(encoder, "volfog epipolar apply", color, None);
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

fn check_texture(
    what: &'static str,
    texture: &wgpu::Texture,
    formats: &[wgpu::TextureFormat],
    (width, height): (u32, u32),
) -> Result<(), EpipolarError> {
    let fail = |property, found: String, expected: String| {
        Err(EpipolarError::Texture {
            texture: what,
            property,
            found,
            expected,
        })
    };
    let size = texture.size();
    if texture.dimension() != wgpu::TextureDimension::D2 {
        return fail(
            "dimension",
            format!("{:?}", texture.dimension()),
            "D2".into(),
        );
    }
    if (size.width, size.height) != (width, height) {
        return fail(
            "size",
            format!("{} x {}", size.width, size.height),
            format!("{width} x {height} (EpipolarSampling)"),
        );
    }
    if !formats.contains(&texture.format()) {
        return fail(
            "format",
            format!("{:?}", texture.format()),
            format!("one of {formats:?}"),
        );
    }
    if texture.sample_count() != 1 {
        return fail(
            "sample count",
            texture.sample_count().to_string(),
            "1".into(),
        );
    }
    if !texture
        .usage()
        .contains(wgpu::TextureUsages::TEXTURE_BINDING)
    {
        return fail(
            "usage",
            format!("{:?}", texture.usage()),
            "TEXTURE_BINDING".into(),
        );
    }
    Ok(())
}
