//! Exponential shadow maps on the GPU: the downsample and blur passes against the CPU
//! mirror (linear and log space), and the visibility of a plane occluder against its
//! exact answer (1 in front, below the leak bound 3 / c behind).

use crate::common;

use common::{compose, gpu};
use glam::Vec2;
use naga_oil::compose::ShaderDefValue;
use volfog::cpu::esm::{self, Layer};
use volfog::options::EsmOptions;
use volfog_testkit::selfcheck::run_esm;

fn layer(size: u32, f: impl Fn(u32, u32) -> f32) -> Layer {
    Layer {
        width: size,
        height: size,
        texels: (0..size * size).map(|i| f(i % size, i / size)).collect(),
    }
}

fn options(log_space: bool, blur_radius: u32, reversed_z: bool) -> EsmOptions {
    EsmOptions {
        log_space,
        blur_radius,
        reversed_z,
    }
}

fn cpu_esm(depth: &Layer, exponent: f32, log_space: bool, radius: i32) -> Layer {
    let down = esm::downsample(depth, exponent, log_space);
    let x = esm::blur(&down, radius, 0, log_space);
    esm::blur(&x, radius, 1, log_space)
}

/// A bumpy depth field in [0.05, 0.95] with a hard-edged box occluder.
fn bumpy(size: u32, layer_index: u32) -> Layer {
    layer(size, |x, y| {
        let (u, v) = (x as f32 / size as f32, y as f32 / size as f32);
        let base = 0.5 + 0.3 * ((7.0 * u + layer_index as f32).sin() * (5.0 * v).cos());
        if (0.3..0.55).contains(&u) && (0.2..0.7).contains(&v) {
            0.12
        } else {
            base
        }
    })
}

#[test]
fn filtered_esm_matches_cpu_box_filter() {
    let gpu = gpu();
    let size = 256; // ESM 64 x 64 per cascade
    let depths: Vec<Layer> = (0..2).map(|l| bumpy(size, l)).collect();
    for (log_space, exponent, radius) in [
        (false, 40.0, 5),
        (false, 80.0, 2),
        (true, 40.0, 5),
        (true, 300.0, 5),
    ] {
        let gpu_layers = run_esm(
            gpu,
            &options(log_space, radius as u32, false),
            exponent,
            &depths,
        )
        .unwrap();
        let mut worst = 0.0f32;
        for (g, d) in gpu_layers.iter().zip(&depths) {
            let want = cpu_esm(d, exponent, log_space, radius);
            for (a, b) in g.texels.iter().zip(&want.texels) {
                // Linear values span exp(c d); compare relatively. Log values are
                // exponents: compare absolutely (an error e is a factor exp(e)).
                let err = if log_space {
                    (a - b).abs()
                } else {
                    (a - b).abs() / b.abs()
                };
                assert!(a.is_finite(), "non-finite ESM texel");
                worst = worst.max(err);
            }
        }
        eprintln!(
            "ESM {} c={exponent} radius={radius}: worst {} error vs CPU {worst:e} (bound 1e-4)",
            if log_space { "log-space" } else { "linear" },
            if log_space {
                "absolute (log)"
            } else {
                "relative"
            }
        );
        assert!(worst <= 1e-4, "{worst}");
    }
}

/// A reverse-Z shadow map (`VOLFOG_ESM_REVERSED_Z`, texels 1 - d) filters to the ESM of
/// the standard depths d: against the CPU mirror run on d, in linear and log space.
#[test]
fn reversed_z_shadow_map_matches_standard_depth() {
    let gpu = gpu();
    let depths: Vec<Layer> = (0..2).map(|l| bumpy(128, l)).collect();
    let reversed: Vec<Layer> = depths
        .iter()
        .map(|d| Layer {
            texels: d.texels.iter().map(|t| 1.0 - t).collect(),
            ..d.clone()
        })
        .collect();
    for log_space in [false, true] {
        let exponent = 40.0;
        let gpu_layers = run_esm(gpu, &options(log_space, 3, true), exponent, &reversed).unwrap();
        let mut worst = 0.0f32;
        for (g, d) in gpu_layers.iter().zip(&depths) {
            let want = cpu_esm(d, exponent, log_space, 3);
            for (a, b) in g.texels.iter().zip(&want.texels) {
                let err = if log_space {
                    (a - b).abs()
                } else {
                    (a - b).abs() / b.abs()
                };
                worst = worst.max(err);
            }
        }
        eprintln!(
            "reversed-Z ESM (log space {log_space}): worst error vs CPU on 1 - texel {worst:e} (bound 1e-4)"
        );
        assert!(worst <= 1e-4, "{worst}");
    }
}

const LOOKUP_KERNEL: &str = r#"
#import volfog::esm::{esm_occluder, esm_visibility}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;
@group(0) @binding(2) var esm: texture_2d_array<f32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let q = input[i];
    let occluder = esm_occluder(esm, q.xy, 0u);
    output[i] = esm_visibility(occluder, q.z, q.w);
}
"#;

/// Visibility lookups (uv, receiver depth, exponent) against a filtered ESM layer.
fn lookup(
    gpu: &volfog_testkit::Gpu,
    log_space: bool,
    esm_layer: &Layer,
    queries: &[[f32; 4]],
) -> Vec<f32> {
    use wgpu::util::DeviceExt;
    let defs = if log_space {
        vec![("VOLFOG_ESM_LOG_SPACE", ShaderDefValue::Bool(true))]
    } else {
        vec![]
    };
    let module = gpu.shader_from_naga("esm lookup", compose(LOOKUP_KERNEL, &defs));
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("esm"),
            size: wgpu::Extent3d {
                width: esm_layer.width,
                height: esm_layer.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&esm_layer.texels),
    );
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let bytes = gpu
        .run_kernel_with(
            &module,
            "main",
            bytemuck::cast_slice(queries),
            (queries.len() * 4) as u64,
            queries.len() as u32,
            &[wgpu::BindingResource::TextureView(&view)],
        )
        .unwrap();
    bytemuck::cast_slice(&bytes).to_vec()
}

#[test]
fn plane_occluder_shadows_behind_and_lights_in_front() {
    let gpu = gpu();
    let size = 256;
    let d_occ = 0.4;
    // The left half of the map holds a plane occluder at depth 0.4; the right half
    // sees nothing (depth 1, the far plane).
    let depth = layer(size, |x, _| if x < size / 2 { d_occ } else { 1.0 });
    for (log_space, c) in [
        (false, 40.0f32),
        (false, 80.0),
        (true, 200.0),
        (true, 600.0),
    ] {
        let filtered = &run_esm(
            gpu,
            &options(log_space, 5, false),
            c,
            std::slice::from_ref(&depth),
        )
        .unwrap()[0];
        // Receivers well inside each half (away from the blurred edge): the ESM is 64
        // texels wide, the blur spans 11 texels plus the bilinear footprint.
        let mut queries = Vec::new();
        for u in [0.05f32, 0.15, 0.3, 0.7, 0.85, 0.95] {
            for k in 0..=40 {
                let r = k as f32 / 40.0;
                queries.push([u, 0.37, r, c]);
            }
        }
        let vis = lookup(gpu, log_space, filtered, &queries);
        let cpu_vis: Vec<f32> = queries
            .iter()
            .map(|q| {
                esm::esm_visibility(
                    esm::esm_occluder(filtered, Vec2::new(q[0], q[1]), log_space),
                    q[2],
                    c,
                    log_space,
                )
            })
            .collect();
        let leak_band = 3.0 / c;
        let mut worst_leak = 0.0f32;
        for (i, q) in queries.iter().enumerate() {
            let (u, r, v) = (q[0], q[2], vis[i]);
            assert!(v.is_finite() && (0.0..=1.0).contains(&v), "visibility {v}");
            assert!(
                (v - cpu_vis[i]).abs() <= 1e-4,
                "GPU {v} vs CPU {} at u={u} r={r}",
                cpu_vis[i]
            );
            if u < 0.5 {
                if r <= d_occ {
                    assert!(
                        v >= 0.999,
                        "in front of the occluder (r={r}) visibility {v}"
                    );
                } else if r >= d_occ + leak_band {
                    worst_leak = worst_leak.max(v);
                    assert!(
                        v <= 0.05,
                        "behind the occluder by {} (c={c}): visibility {v}",
                        r - d_occ
                    );
                }
            } else {
                assert!(v >= 0.999, "no occluder at u={u}: visibility {v}");
            }
        }
        eprintln!(
            "plane occluder, {} c={c}: lit 1.0 in front, max leak {worst_leak:.2e} beyond 3/c = {leak_band:.4} behind",
            if log_space { "log-space" } else { "linear" }
        );
    }
}
