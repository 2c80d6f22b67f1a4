//! GPU self-check: runs the passes on the selected adapter and compares them with
//! independent answers (closed forms) and with the CPU mirror. `volfog selfcheck`
//! prints the report; the tests call the same runners with their own bounds.

use glam::{Mat4, UVec3, Vec2, Vec3, Vec4};
use wgpu::util::DeviceExt;

use volfog::cpu;
use volfog::cpu::apply::Volume;
use volfog::cpu::scan::SCAN_START;
use volfog::options::{EsmOptions, Filtering, ScanStep};
use volfog::pipeline::apply::{
    ApplyPipeline, FogResources, fog_bind_group, fog_layout_entries, fog_sampler,
};
use volfog::pipeline::scan::ScanPass;
use volfog::uniforms::Froxels;

use crate::gpu::{Gpu, GpuError};

/// The camera used by the self-check: 60 degree vertical field of view, 16:9,
/// standard depth with near 0.1 m and far 1000 m.
pub fn test_projection() -> Mat4 {
    glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 0.1, 1000.0)
}

/// A froxel placement over `test_projection` with `slices` exponential slices from
/// 0.5 m to 128 m and `xy` froxels across the screen.
pub fn test_froxels(xy: [u32; 2], slices: u32) -> Froxels {
    Froxels::new(
        test_projection(),
        UVec3::new(xy[0], xy[1], slices),
        0.5,
        128.0,
        (128.0f32 / 0.5).ln(),
    )
    .expect("valid test froxels")
}

/// Rounds each component to the nearest f16, as an rgba16float texture stores it.
pub fn round_f16(v: Vec4) -> Vec4 {
    Vec4::from_array(v.to_array().map(|c| half::f16::from_f32(c).to_f32()))
}

fn uniform_buffer(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// Runs the scan pass over a scattering volume (rgb = sigma_s L_in, a = sigma_t; x
/// fastest) and returns the integrated volume.
pub fn run_scan(
    gpu: &Gpu,
    step: ScanStep,
    froxels: &Froxels,
    medium: &[Vec4],
) -> Result<Vec<Vec4>, GpuError> {
    run_scan_culled(gpu, step, froxels, medium, None)
}

/// A live-slice texture of `columns` holding `values` (x fastest).
pub fn live_slices_texture(gpu: &Gpu, columns: [u32; 2], values: &[u32]) -> wgpu::Texture {
    let texture = volfog::pipeline::cull::live_slices_texture(&gpu.device, "live", columns);
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * columns[0]),
            rows_per_image: Some(columns[1]),
        },
        texture.size(),
    );
    texture
}

/// [`run_scan`] of the depth-culling variant when `live` holds the live slices per
/// column (x fastest; `size.x * size.y` values).
pub fn run_scan_culled(
    gpu: &Gpu,
    step: ScanStep,
    froxels: &Froxels,
    medium: &[Vec4],
    live: Option<&[u32]>,
) -> Result<Vec<Vec4>, GpuError> {
    let size = froxels.size.to_array();
    let pass = gpu
        .checked(|| ScanPass::new(&gpu.device, step, live.is_some()))?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let froxel_buffer = uniform_buffer(gpu, "froxels", &froxels.to_bytes());
    let scattering = gpu.texture_3d_rgba16f("scattering", size, medium);
    let integrated = gpu.texture_3d_rgba16f("integrated", size, &[]);
    let live_texture = live.map(|values| {
        live_slices_texture(gpu, [size[0], size[1]], values).create_view(&Default::default())
    });
    let bind_group = gpu
        .checked(|| {
            pass.bind_group(
                &gpu.device,
                &froxel_buffer,
                &scattering.create_view(&Default::default()),
                &integrated.create_view(&Default::default()),
                live_texture.as_ref(),
            )
        })?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut compute = encoder.begin_compute_pass(&Default::default());
        pass.encode(&mut compute, &bind_group, [size[0], size[1]]);
    }
    gpu.queue.submit([encoder.finish()]);
    gpu.read_texture_rgba16f(&integrated)
}

/// A homogeneous medium of extinction `sigma_t`, albedo `albedo` and in-scattered
/// radiance `light` filling every froxel.
pub fn homogeneous(froxels: &Froxels, sigma_t: f32, albedo: f32, light: Vec3) -> Vec<Vec4> {
    let count = (froxels.size.x * froxels.size.y * froxels.size.z) as usize;
    vec![(light * albedo * sigma_t).extend(sigma_t); count]
}

/// Closed form for a homogeneous medium after path length `d` (m):
/// `L = (sigma_s / sigma_t) L_in (1 - exp(-sigma_t d))`, `T = exp(-sigma_t d)`.
pub fn homogeneous_closed_form(sigma_t: f32, albedo: f32, light: Vec3, d: f32) -> Vec4 {
    let t = (-(sigma_t as f64) * d as f64).exp();
    (light * albedo * (1.0 - t) as f32).extend(t as f32)
}

/// Largest relative errors of a scan against the closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanError {
    /// Slices in the volume.
    pub slices: u32,
    /// Step used.
    pub step: ScanStep,
    /// Largest relative error of the in-scattered radiance (any channel, any froxel).
    pub inscatter: f32,
    /// Largest relative error of the transmittance.
    pub transmittance: f32,
}

/// Scans a homogeneous medium on the GPU and compares every froxel with the closed
/// form at the back of its slice, along the column's own ray (relative errors with a
/// denominator floor of 1e-3 of the medium's final value).
pub fn scan_vs_closed_form(
    gpu: &Gpu,
    step: ScanStep,
    slices: u32,
    sigma_t: f32,
) -> Result<ScanError, GpuError> {
    let froxels = test_froxels([16, 9], slices);
    let (albedo, light) = (0.7, Vec3::new(2.0, 1.6, 1.0));
    let out = run_scan(
        gpu,
        step,
        &froxels,
        &homogeneous(&froxels, sigma_t, albedo, light),
    )?;
    let mut err = ScanError {
        slices,
        step,
        inscatter: 0.0,
        transmittance: 0.0,
    };
    let [sx, sy, sz] = froxels.size.to_array();
    for z in 0..sz {
        let back = cpu::froxel::slice_depth(
            (z + 1) as f32 / sz as f32,
            froxels.near,
            froxels.far,
            froxels.curve,
        );
        for y in 0..sy {
            for x in 0..sx {
                let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(sx as f32, sy as f32);
                let d = (back - froxels.near) * cpu::froxel::ray_scale(uv, froxels.view_from_clip);
                let want = homogeneous_closed_form(sigma_t, albedo, light, d);
                let got = out[((z * sy + y) * sx + x) as usize];
                for c in 0..3 {
                    let e = (got[c] - want[c]).abs() / want[c].max(1e-3 * light[c] * albedo);
                    err.inscatter = err.inscatter.max(e);
                }
                let e = (got.w - want.w).abs() / want.w.max(1e-3);
                err.transmittance = err.transmittance.max(e);
            }
        }
    }
    Ok(err)
}

/// The CPU mirror of the scan pass over the same (fp16-rounded) input.
pub fn cpu_scan(step: ScanStep, froxels: &Froxels, medium: &[Vec4]) -> Vec<Vec4> {
    let [sx, sy, sz] = froxels.size.to_array();
    let mut out = vec![Vec4::ZERO; medium.len()];
    for y in 0..sy {
        for x in 0..sx {
            let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(sx as f32, sy as f32);
            let scale = cpu::froxel::ray_scale(uv, froxels.view_from_clip);
            let mut acc = SCAN_START;
            let mut front = froxels.near;
            for z in 0..sz {
                let back = cpu::froxel::slice_depth(
                    (z + 1) as f32 / sz as f32,
                    froxels.near,
                    froxels.far,
                    froxels.curve,
                );
                let i = ((z * sy + y) * sx + x) as usize;
                acc = cpu::scan::scan_step(acc, round_f16(medium[i]), (back - front) * scale, step);
                out[i] = acc.min(Vec4::splat(volfog::cpu::inject::HALF_MAX));
                front = back;
            }
        }
    }
    out
}

/// Inputs of an apply run: a colour image, a depth image and an integrated volume.
#[derive(Debug, Clone)]
pub struct ApplyCase {
    /// Froxel placement.
    pub froxels: Froxels,
    /// Image size in pixels.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Lit colour per pixel (rgb, a ignored), row-major from the top.
    pub color: Vec<Vec4>,
    /// Depth-buffer value per pixel (standard depth, [0, 1]).
    pub depth: Vec<f32>,
    /// The integrated volume (x fastest).
    pub volume: Vec<Vec4>,
    /// The analytic tail beyond the far plane, in view space.
    pub tail: volfog::uniforms::HeightFog,
}

impl ApplyCase {
    /// A deterministic case: a smooth volume whose in-scatter and transmittance
    /// vary along every axis, depths spanning the near plane to beyond far, and a
    /// colour gradient.
    pub fn synthetic(width: u32, height: u32) -> Self {
        let froxels = test_froxels([20, 12], 32);
        let [sx, sy, sz] = froxels.size.to_array();
        let mut volume = Vec::with_capacity((sx * sy * sz) as usize);
        for z in 0..sz {
            for y in 0..sy {
                for x in 0..sx {
                    let (fx, fy, fz) = (
                        x as f32 / sx as f32,
                        y as f32 / sy as f32,
                        (z + 1) as f32 / sz as f32,
                    );
                    let t = (-2.5 * fz * (1.0 + 0.3 * fx)).exp();
                    let l = Vec3::new(0.8 + 0.2 * fy, 0.6 + 0.3 * fx, 0.5) * (1.0 - t);
                    volume.push(l.extend(t));
                }
            }
        }
        let proj = froxels.clip_from_view;
        let mut color = Vec::new();
        let mut depth = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let v = (y as f32 + 0.5) / height as f32;
                color.push(Vec4::new(u, v, 1.0 - u, 1.0));
                // View depth from 0.2 m (in front of near) to 400 m (beyond far).
                let view_depth = 0.2 * (2000.0f32).powf((u + v * 0.37).fract());
                let clip = proj * Vec4::new(0.0, 0.0, -view_depth, 1.0);
                depth.push(clip.z / clip.w);
            }
        }
        Self {
            froxels,
            width,
            height,
            color,
            depth,
            volume,
            tail: volfog::uniforms::HeightFog::new(
                Vec3::new(0.5, 0.6, 0.7),
                0.01,
                Vec3::Y,
                0.05,
                -2.0,
            )
            .and_then(|f| {
                f.with_sun(
                    Vec3::new(0.3, 0.5, -0.8).normalize(),
                    Vec3::new(0.4, 0.3, 0.2),
                    0.6,
                )
            })
            .expect("valid tail"),
        }
    }

    /// The CPU answer: `color * T + L` with the fog at each pixel's centre.
    pub fn expected(&self) -> Vec<Vec4> {
        let volume = Volume {
            size: self.froxels.size.to_array(),
            texels: self.volume.iter().map(|t| round_f16(*t)).collect(),
        };
        let mut out = Vec::with_capacity(self.color.len());
        for y in 0..self.height {
            for x in 0..self.width {
                let i = (y * self.width + x) as usize;
                let uv = Vec2::new(
                    (x as f32 + 0.5) / self.width as f32,
                    (y as f32 + 0.5) / self.height as f32,
                );
                let ndc = cpu::froxel::ndc_from_uv(uv).extend(self.depth[i]);
                let view = cpu::froxel::view_from_ndc(ndc, self.froxels.view_from_clip);
                let fog = volume.fog(cpu::apply::fog_coord(uv, view.z.abs(), &self.froxels));
                let fog = cpu::apply::fog_with_tail(
                    fog,
                    cpu::apply::fog_tail(&self.froxels, &self.tail, view),
                );
                let color = round_f16(self.color[i]);
                out.push(cpu::apply::apply_fog(color.truncate(), fog).extend(color.w));
            }
        }
        out
    }
}

/// Writes depth values into a Depth32Float texture (which cannot be a copy
/// destination) by drawing a fullscreen triangle that outputs `frag_depth`.
pub fn depth_texture(
    gpu: &Gpu,
    width: u32,
    height: u32,
    values: &[f32],
) -> Result<wgpu::Texture, GpuError> {
    depth_array_texture(gpu, width, height, &[values])
}

/// Writes one slice of depth values per layer into a Depth32Float 2D array texture
/// (one layer is a plain 2D texture).
pub fn depth_array_texture(
    gpu: &Gpu,
    width: u32,
    height: u32,
    layers: &[&[f32]],
) -> Result<wgpu::Texture, GpuError> {
    const WRITE_DEPTH: &str = r#"
#import volfog::fullscreen::fullscreen_position
@group(0) @binding(0) var values: texture_2d<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(i);
}
@fragment fn fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(values, vec2<i32>(p.xy), 0).r;
}
"#;
    let extent = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: layers.len() as u32,
    };
    let texture = |format, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let source = texture(
        wgpu::TextureFormat::R32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let depth = texture(
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let module = gpu.shader_from_naga("write depth", crate::kernel::compose(WRITE_DEPTH, &[]));
    let pipeline = gpu.checked(|| {
        gpu.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("write depth"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
    })?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for (layer, values) in layers.iter().enumerate() {
        let layer = layer as u32;
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &source,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: layer,
                },
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(values),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 4),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        let layer_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("write depth"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&layer_view(&source)),
            }],
        });
        let view = layer_view(&depth);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("write depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    Ok(depth)
}

/// Runs the ESM passes (downsample, blur x, blur y) over a cascaded shadow map given
/// as depth layers of `4 * size` texels per side (stored as given: reversed depth when
/// `options.reversed_z`), and returns the filtered ESM layers.
pub fn run_esm(
    gpu: &Gpu,
    options: &EsmOptions,
    exponent: f32,
    depth_layers: &[volfog::cpu::esm::Layer],
) -> Result<Vec<volfog::cpu::esm::Layer>, GpuError> {
    use volfog::pipeline::esm::EsmPasses;
    let layers = depth_layers.len() as u32;
    let full = depth_layers[0].width;
    let size = full / 4;
    let passes =
        EsmPasses::new(&gpu.device, options).map_err(|e| GpuError::Operation(e.to_string()))?;
    let slices: Vec<&[f32]> = depth_layers.iter().map(|l| l.texels.as_slice()).collect();
    let shadow = depth_array_texture(gpu, full, full, &slices)?;
    let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        aspect: wgpu::TextureAspect::DepthOnly,
        ..Default::default()
    });
    let cascades = volfog::uniforms::ShadowCascades {
        exponent,
        count: layers,
        ..Default::default()
    };
    let cascade_buffer = uniform_buffer(
        gpu,
        "cascades",
        &volfog::uniforms::to_uniform_bytes(&cascades),
    );
    let esm_texture = |label| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: volfog::pipeline::esm::ESM_FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let (a, b) = (esm_texture("esm a"), esm_texture("esm b"));
    let array = |t: &wgpu::Texture| {
        t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    };
    let (av, bv) = (array(&a), array(&b));
    let groups = gpu.checked(|| {
        (
            passes.downsample_bind_group(&gpu.device, &cascade_buffer, &shadow_view, &av),
            passes.blur_bind_group(&gpu.device, &av, &bv),
            passes.blur_bind_group(&gpu.device, &bv, &av),
        )
    })?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_downsample(&mut pass, &groups.0, size, layers);
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_blur(&mut pass, &groups.1, 0, size, layers);
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        passes.encode_blur(&mut pass, &groups.2, 1, size, layers);
    }
    gpu.queue.submit([encoder.finish()]);
    let raw = gpu.read_texture_raw(&a, 4)?;
    let values: &[f32] = bytemuck::cast_slice(&raw);
    Ok(values
        .chunks_exact((size * size) as usize)
        .map(|c| volfog::cpu::esm::Layer {
            width: size,
            height: size,
            texels: c.to_vec(),
        })
        .collect())
}

/// Runs the fullscreen apply pass on an `ApplyCase` into an rgba16float target
/// (blending onto the case's colour) and returns the fogged image.
pub fn run_apply(gpu: &Gpu, filtering: Filtering, case: &ApplyCase) -> Result<Vec<Vec4>, GpuError> {
    let format = wgpu::TextureFormat::Rgba16Float;
    let fog_layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fog group"),
            entries: &fog_layout_entries(filtering, wgpu::ShaderStages::FRAGMENT),
        });
    let pass = gpu
        .checked(|| ApplyPipeline::new(&gpu.device, &fog_layout, filtering, format))?
        .map_err(|e| GpuError::Operation(e.to_string()))?;
    let froxel_buffer = uniform_buffer(gpu, "froxels", &case.froxels.to_bytes());
    let tail_buffer = uniform_buffer(gpu, "tail", &case.tail.to_bytes());
    let view_buffer = uniform_buffer(
        gpu,
        "view",
        &volfog::uniforms::to_uniform_bytes(&volfog::uniforms::FogView::default()),
    );
    let volume = gpu.texture_3d_rgba16f("integrated", case.froxels.size.to_array(), &case.volume);
    let depth = depth_texture(gpu, case.width, case.height, &case.depth)?;
    let color = gpu.texture_2d_rgba16f("scene colour", [case.width, case.height], &case.color);
    let (fog_group, depth_group) = gpu.checked(|| {
        (
            fog_bind_group(
                &gpu.device,
                &fog_layout,
                filtering,
                &FogResources {
                    froxels: &froxel_buffer,
                    integrated: &volume.create_view(&Default::default()),
                    tail: &tail_buffer,
                    view: &view_buffer,
                    sampler: &fog_sampler(&gpu.device),
                },
            ),
            pass.depth_bind_group(
                &gpu.device,
                &depth.create_view(&wgpu::TextureViewDescriptor {
                    aspect: wgpu::TextureAspect::DepthOnly,
                    ..Default::default()
                }),
            ),
        )
    })?;
    let color_view = color.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &color_view, &fog_group, &depth_group, None);
    gpu.queue.submit([encoder.finish()]);
    gpu.read_texture_rgba16f(&color)
}

/// Largest absolute difference between two images.
pub fn max_abs_diff(a: &[Vec4], b: &[Vec4]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f32::max)
}

/// Epipolar sun shafts on a 160x90 screen (ground plane at 1-80 m, 256² shadow map):
/// unshadowed, the lit fraction is 1 everywhere (the fog is then the closed-form
/// height fog); with a half-plane of the shadow map in shadow, the tree march gives
/// the march over every section.
#[derive(Debug, Clone, Copy)]
pub struct EpipolarCheck {
    /// Unshadowed: max |F - 1| over the screen (rgba16float: 1e-3 is its rounding).
    pub unshadowed: f32,
    /// Half shadowed: max |F(tree) - F(every section)| over the ray-marching samples.
    pub tree_vs_steps: f32,
    /// Half shadowed: ray-marching samples neither fully lit nor fully shadowed.
    pub partly_shadowed: usize,
}

/// Runs [`EpipolarCheck`].
pub fn epipolar_check(gpu: &Gpu) -> Result<EpipolarCheck, GpuError> {
    use volfog::pipeline::epipolar::{EpipolarMode, EpipolarShafts};
    use volfog::uniforms::{EpipolarPhase, EpipolarSampling, EpipolarView, HeightFog};
    let fail = |e: &dyn std::fmt::Display| GpuError::Operation(e.to_string());
    let (w, h, size) = (160u32, 90u32, 256u32);
    let projection = test_projection();
    let view_from_world = glam::camera::rh::view::look_to_mat4(
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(0.0, -0.05, -1.0),
        Vec3::Y,
    );
    let sun = Vec3::new(0.3, 0.4, -1.0).normalize();
    // Depth: the ground seen by each pixel, clamped to 1..80 m of view depth.
    let view_from_clip = projection.inverse();
    let world_from_view = view_from_world.inverse();
    let depths: Vec<f32> = (0..w * h)
        .map(|i| {
            let ndc = Vec2::new(
                ((i % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - ((i / w) as f32 + 0.5) / h as f32 * 2.0,
            );
            let ray = view_from_clip.project_point3(ndc.extend(0.5));
            let dir = world_from_view.transform_vector3(ray / ray.z.abs());
            let z = if dir.y < -1e-4 {
                (3.0 / -dir.y).clamp(1.0, 80.0)
            } else {
                80.0
            };
            let clip = projection * Vec4::new(0.0, 0.0, -z, 1.0);
            clip.z / clip.w
        })
        .collect();
    let depth = depth_texture(gpu, w, h, &depths)?;
    let light_from_world =
        volfog::pipeline::cascade_projection(sun, Vec3::new(0.0, 0.0, -40.0), 60.0, 200.0);
    let medium = HeightFog::new(Vec3::splat(0.02), 0.03, Vec3::Y, 0.05, 0.0)
        .and_then(|f| f.with_sun(sun, Vec3::splat(2.0), 0.5))
        .map_err(|e| fail(&e))?;
    let view = EpipolarView {
        view_from_world,
        clip_from_view: projection,
        light_from_world,
        cascade: 0,
        rayleigh: Vec3::ZERO,
        phase: EpipolarPhase::HenyeyGreenstein,
        start_depth: 0.0,
        max_depth: 80.0,
        depth_bias: 0.0,
    };
    let sampling = EpipolarSampling {
        slices: 128,
        samples: 128,
        downscale: 1,
        ..EpipolarSampling::new(w, h, size)
    };
    // (shaft texture, marched lit fractions, packed interpolation sources)
    type Run = (Vec<Vec4>, Vec<f32>, Vec<u32>);
    let run = |shadow: &[f32], mode| -> Result<Run, GpuError> {
        let shadow = depth_texture(gpu, size, size, shadow)?;
        let mut shafts = EpipolarShafts::new(&gpu.device, sampling).map_err(|e| fail(&e))?;
        shafts
            .set_inputs(&gpu.device, &depth, &shadow)
            .map_err(|e| fail(&e))?;
        shafts
            .prepare(&gpu.queue, &view, &medium)
            .map_err(|e| fail(&e))?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        shafts.encode(&mut encoder, mode).map_err(|e| fail(&e))?;
        gpu.queue.submit([encoder.finish()]);
        let image = gpu.read_texture_rgba16f(shafts.shaft_texture())?;
        // The marched lit fraction is rgba32float: keep its first channel.
        let marched = gpu.read_texture_raw(shafts.marched_texture(), 16)?;
        let sources = gpu.read_texture_raw(shafts.source_texture(), 4)?;
        Ok((
            image,
            bytemuck::cast_slice::<u8, f32>(&marched)
                .iter()
                .step_by(4)
                .copied()
                .collect(),
            bytemuck::cast_slice(&sources).to_vec(),
        ))
    };
    let open = vec![1.0f32; (size * size) as usize];
    let (image, _, _) = run(&open, EpipolarMode::Tree)?;
    let unshadowed = image
        .iter()
        .map(|p| (p.x - 1.0).abs())
        .fold(0.0f32, f32::max);
    let half: Vec<f32> = (0..size * size)
        .map(|t| if (t % size) < size / 2 { 0.0 } else { 1.0 })
        .collect();
    let (_, tree, sources) = run(&half, EpipolarMode::Tree)?;
    let (_, steps, _) = run(&half, EpipolarMode::Steps)?;
    let marching = |i: &usize| sources[*i] & 0xffff == sources[*i] >> 16;
    let tree_vs_steps = (0..tree.len())
        .filter(marching)
        .map(|i| (tree[i] - steps[i]).abs())
        .fold(0.0f32, f32::max);
    let partly_shadowed = (0..tree.len())
        .filter(marching)
        .filter(|&i| steps[i] > 0.01 && steps[i] < 0.99)
        .count();
    Ok(EpipolarCheck {
        unshadowed,
        tree_vs_steps,
        partly_shadowed,
    })
}

/// The self-check report.
#[derive(Debug, Clone)]
pub struct Report {
    /// Adapter description.
    pub adapter: String,
    /// Scan errors against the closed form, per slice count and step.
    pub scan: Vec<ScanError>,
    /// Apply pass (sampler) vs CPU: largest absolute difference.
    pub apply_sampler: f32,
    /// Apply pass (manual filtering) vs CPU: largest absolute difference.
    pub apply_manual: f32,
    /// Epipolar sun shafts.
    pub epipolar: EpipolarCheck,
}

/// Runs the self-check on an adapter.
pub fn run(gpu: &Gpu) -> Result<Report, GpuError> {
    let mut scan = Vec::new();
    for slices in [32, 64, 128] {
        for step in [ScanStep::EnergyConserving, ScanStep::Wronski] {
            scan.push(scan_vs_closed_form(gpu, step, slices, 0.03)?);
        }
    }
    let case = ApplyCase::synthetic(96, 54);
    let expected = case.expected();
    let apply_sampler = max_abs_diff(&run_apply(gpu, Filtering::Sampler, &case)?, &expected);
    let apply_manual = max_abs_diff(&run_apply(gpu, Filtering::Manual, &case)?, &expected);
    Ok(Report {
        adapter: gpu.describe(),
        scan,
        apply_sampler,
        apply_manual,
        epipolar: epipolar_check(gpu)?,
    })
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "adapter: {}", self.adapter)?;
        writeln!(
            f,
            "scan of homogeneous fog (sigma_t = 0.03/m, 0.5..128 m) vs closed form, max relative error:"
        )?;
        writeln!(f, "  slices  step               in-scatter   transmittance")?;
        for e in &self.scan {
            writeln!(
                f,
                "  {:>6}  {:<17}  {:>9.4}%  {:>12.4}%",
                e.slices,
                format!("{:?}", e.step),
                e.inscatter * 100.0,
                e.transmittance * 100.0
            )?;
        }
        writeln!(
            f,
            "apply pass vs CPU (color * T + L), max abs difference: sampler {:.2e}, manual filtering {:.2e}",
            self.apply_sampler, self.apply_manual
        )?;
        let e = &self.epipolar;
        writeln!(
            f,
            "epipolar shafts: unshadowed lit fraction vs 1, max {:.2e}; tree march vs every section, max {:.2e} over {} partly shadowed samples",
            e.unshadowed, e.tree_vs_steps, e.partly_shadowed
        )
    }
}
