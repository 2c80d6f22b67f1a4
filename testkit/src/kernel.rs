//! Test kernels: WGSL that imports volfog modules, composed with naga_oil and run as
//! compute shaders.

use std::collections::HashMap;

use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};

use crate::gpu::Gpu;

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

/// Runs a kernel (see [`Gpu::run_kernel`]) on f32 inputs and returns f32 outputs.
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
