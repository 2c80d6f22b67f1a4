//! Shared test helpers: the GPU (failing loudly when there is none) and composition of
//! test kernels that import volfog modules.
#![allow(dead_code)]

use std::collections::HashMap;

use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog::gpu::Gpu;

/// The GPU every test uses; panics with the install command when no adapter exists.
pub fn gpu() -> Gpu {
    match Gpu::new() {
        Ok(gpu) => {
            eprintln!("adapter: {}", gpu.describe());
            gpu
        }
        Err(e) => panic!("{e}"),
    }
}

/// Composes a test shader that imports volfog modules; panics with naga_oil's report.
pub fn compose(source: &str, defs: &[(&str, ShaderDefValue)]) -> naga::Module {
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).expect("volfog modules compose");
    let shader_defs: HashMap<String, ShaderDefValue> =
        defs.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    match composer.make_naga_module(NagaModuleDescriptor {
        source,
        file_path: "test_kernel.wgsl",
        shader_defs,
        ..Default::default()
    }) {
        Ok(m) => m,
        Err(e) => panic!("{}", e.emit_to_string(&composer)),
    }
}

/// Runs a kernel (see `Gpu::run_kernel`) on f32 inputs and returns f32 outputs.
pub fn run_f32(gpu: &Gpu, source: &str, inputs: &[f32], outputs: usize, count: u32) -> Vec<f32> {
    let module = gpu.shader_from_naga("test kernel", compose(source, &[]));
    let bytes = gpu
        .run_kernel(
            &module,
            "main",
            bytemuck::cast_slice(inputs),
            (outputs * 4) as u64,
            count,
        )
        .expect("kernel runs");
    bytemuck::cast_slice(&bytes).to_vec()
}

/// Relative error with a floor on the denominator.
pub fn rel_err(got: f32, want: f32, floor: f32) -> f32 {
    (got - want).abs() / want.abs().max(floor)
}
