//! The compute pipelines of every epipolar pass, compiled from the naga module of the
//! sampling's variant (coloured or not) with their bind group layouts.

use super::EpipolarShafts;
use crate::pipeline::{bind_group_layout, compute_pipeline, shader_module};
use crate::shaders::CodegenError;
use crate::uniforms::EpipolarSampling;

#[derive(Debug)]
pub(super) struct Pipelines {
    pub(super) coords: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) refine: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) tree: (
        wgpu::BindGroupLayout,
        wgpu::ComputePipeline,
        wgpu::ComputePipeline,
    ),
    pub(super) march: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) steps: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) interpolate: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) resolve: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) upscale: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
    pub(super) reference: (wgpu::BindGroupLayout, wgpu::ComputePipeline),
}

impl Pipelines {
    /// Compiles every pass for `s`.
    pub(super) fn new(device: &wgpu::Device, s: &EpipolarSampling) -> Result<Self, CodegenError> {
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
        let tree_layout =
            bind_group_layout(device, "epipolar_tree", &EpipolarShafts::tree_entries());
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
        Ok(Pipelines {
            coords: compute(
                "epipolar_coords",
                &[],
                "epipolar_coords",
                EpipolarShafts::coords_entries(),
            )?,
            refine: compute(
                "epipolar_refine",
                &[],
                "epipolar_refine",
                EpipolarShafts::refine_entries(),
            )?,
            tree: (tree_layout, tree_init, tree_level),
            march: compute(
                "epipolar_march",
                &colored,
                "epipolar_march",
                EpipolarShafts::march_entries(false, s.colored),
            )?,
            steps: compute(
                "epipolar_march",
                &[
                    colored.clone(),
                    vec!["VOLFOG_EPIPOLAR_BRUTE_FORCE".to_string()],
                ]
                .concat(),
                "epipolar_march",
                EpipolarShafts::march_entries(true, s.colored),
            )?,
            interpolate: compute(
                "epipolar_interpolate",
                &[],
                "epipolar_interpolate",
                EpipolarShafts::interpolate_entries(),
            )?,
            resolve: compute(
                "epipolar_resolve",
                &colored,
                "epipolar_resolve",
                EpipolarShafts::resolve_entries(s.colored),
            )?,
            upscale: compute(
                "epipolar_upscale",
                &colored,
                "epipolar_upscale",
                EpipolarShafts::upscale_entries(s.colored),
            )?,
            reference: compute(
                "epipolar_reference",
                &colored,
                "epipolar_reference",
                EpipolarShafts::reference_entries(s.colored),
            )?,
        })
    }
}
