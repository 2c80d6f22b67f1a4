//! The baked noise texture: the bake pass against the CPU bake, and the fractal sum,
//! tiled noise and animation sampled from it against the CPU mirror.

use super::Rng;
use crate::common::{self, gpu};
use glam::Vec3;
use volfog::cpu::inject::DensityTexture;
use volfog::cpu::noise::{
    NOISE_TEXTURE_SIZE, bake_noise_texture, noise_animated_texture, noise_fbm_texture,
    perlin_noise_tiled,
};
use volfog::pipeline::noise::{NOISE_TEXTURE_BYTES, NoiseBake, noise_sampler};
use volfog_testkit::Gpu;

/// perlin_noise_tiled, noise_fbm_texture and noise_animated_texture per point: input
/// (x, y, z, octaves), three outputs; the noise texture and its sampler at bindings 2
/// and 3. The animation uses the wind (2, -0.5, 1.25) m/s, time 3 s and scale 0.5 / m
/// (dyadic: the advected point is exact in f32).
pub(super) const TEXTURE_KERNEL: &str = r#"
#import volfog::noise::{perlin_noise_tiled, noise_fbm_texture, noise_animated_texture, NOISE_TEXTURE_PERIOD}

@group(0) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> output: array<f32>;
@group(0) @binding(2) var noise_texture: texture_3d<f32>;
@group(0) @binding(3) var noise_sampler: sampler;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&input) { return; }
    let p = input[i].xyz;
    let octaves = u32(input[i].w);
    output[3u * i] = perlin_noise_tiled(p, NOISE_TEXTURE_PERIOD);
    output[3u * i + 1u] = noise_fbm_texture(noise_texture, noise_sampler, p, octaves);
    output[3u * i + 2u] = noise_animated_texture(
        noise_texture, noise_sampler, p, 0.5, vec3<f32>(2.0, -0.5, 1.25), 3.0, octaves);
}
"#;

/// The wind, time and scale of TEXTURE_KERNEL's noise_animated_texture.
const TEXTURE_KERNEL_ANIMATION: (Vec3, f32, f32) = (Vec3::new(2.0, -0.5, 1.25), 3.0, 0.5);

/// Runs TEXTURE_KERNEL with `texture` (sampled with the runtime's noise sampler):
/// (perlin_noise_tiled(p, 16), noise_fbm_texture(p, octaves),
/// noise_animated_texture(p, ..., octaves)) per point.
fn eval_texture_gpu(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    points: &[(Vec3, u32)],
) -> Vec<(f32, f32, f32)> {
    let inputs: Vec<f32> = points
        .iter()
        .flat_map(|(p, o)| [p.x, p.y, p.z, *o as f32])
        .collect();
    let module = gpu.shader_from_naga("noise texture kernel", common::compose(TEXTURE_KERNEL, &[]));
    let view = texture.create_view(&Default::default());
    let sampler = noise_sampler(&gpu.device);
    let bytes = gpu
        .run_kernel_with(
            &module,
            "main",
            bytemuck::cast_slice(&inputs),
            (3 * 4 * points.len()) as u64,
            points.len() as u32,
            &[
                wgpu::BindingResource::TextureView(&view),
                wgpu::BindingResource::Sampler(&sampler),
            ],
        )
        .expect("kernel runs");
    let out: &[f32] = bytemuck::cast_slice(&bytes);
    out.chunks(3).map(|c| (c[0], c[1], c[2])).collect()
}

/// Bakes the noise texture on the GPU and reads it back: the texture and its red
/// channel as a CPU texture (x fastest).
fn baked_noise(gpu: &Gpu) -> (wgpu::Texture, Vec<glam::Vec4>) {
    let texture = NoiseBake::bake(&gpu.device, &gpu.queue).expect("the bake pass compiles");
    let texels = common::scene::read_volume(gpu, &texture);
    (texture, texels)
}

/// The bake pass writes perlin_noise_tiled on the texel lattice: the texture read back
/// against the CPU bake. The values are in [-1, 1], where an f16 has an ulp of at most
/// 2^-11 below 1 (and 1 is exact): the store rounds to nearest (half an ulp, 2^-12) or,
/// as Vulkan also allows, toward zero (a whole ulp, 2^-11 = 4.9e-4); 5e-4 allows either
/// plus the f32 difference of the two evaluations (~1e-7).
#[test]
fn noise_bake_matches_cpu_bake() {
    let gpu = gpu();
    let (texture, texels) = baked_noise(gpu);
    let n = NOISE_TEXTURE_SIZE;
    assert_eq!(
        (texture.size().width, texture.size().height),
        (n, n),
        "{:?}",
        texture.size()
    );
    assert_eq!(texture.size().depth_or_array_layers, n);
    assert_eq!(texture.format(), wgpu::TextureFormat::Rgba16Float);
    assert_eq!(
        texture.usage(),
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
    );
    assert_eq!(NOISE_TEXTURE_BYTES, u64::from(n).pow(3) * 8);
    assert_eq!(NOISE_TEXTURE_BYTES, 2 << 20);
    let cpu = bake_noise_texture();
    assert_eq!(texels.len(), cpu.texels.len());
    let tol = 5e-4f32;
    let (mut worst, mut nearest, mut toward_zero) = (0.0f32, 0usize, 0usize);
    for (k, (t, &want)) in texels.iter().zip(&cpu.texels).enumerate() {
        let e = (t.x - want).abs();
        worst = worst.max(e);
        // The two roundings Vulkan allows: to nearest, and toward zero (one f16 step
        // closer to zero when the nearest one is farther from zero than the value).
        let rte = half::f16::from_f32(want);
        let rtz = if rte.to_f32().abs() > want.abs() {
            half::f16::from_bits(rte.to_bits() - 1)
        } else {
            rte
        };
        nearest += usize::from(t.x == rte.to_f32());
        toward_zero += usize::from(t.x == rtz.to_f32());
        assert!(e <= tol, "texel {k}: gpu {} cpu {want}", t.x);
        assert_eq!((t.y, t.z, t.w), (0.0, 0.0, 1.0), "texel {k}");
    }
    eprintln!(
        "noise bake: {n}^3 texels, max |gpu - cpu| {worst:e} (bound {tol:e}); of {}, {nearest} \
         equal the CPU value rounded to the nearest f16 and {toward_zero} rounded toward zero",
        texels.len()
    );
}

/// Test points for the texture form: random near the origin, in the first tiles, far
/// away, and on the texel lattice and the tile seams; octaves 0..=9 (clamped to 1..=8).
fn texture_points() -> Vec<(Vec3, u32)> {
    let mut rng = Rng(61);
    let mut pts = Vec::new();
    for i in 0..40_000u32 {
        let span = [16.0f32, 40.0, 1.0e3, 1.0e4][(i % 4) as usize];
        pts.push((
            rng.vec(-span, span),
            [1, 2, 4, 8, 3, 0, 9, 1][(i % 8) as usize],
        ));
    }
    for _ in 0..2000 {
        // Texel centres (quarter lattice units) and tile seams (multiples of 16).
        let q = Vec3::new(
            rng.int(-128, 128) as f32,
            rng.int(-128, 128) as f32,
            rng.int(-128, 128) as f32,
        ) * 0.25;
        pts.push((q, 1));
        let mut seam = rng.vec(-40.0, 40.0);
        seam.x = 16.0 * rng.int(-2, 2) as f32 + rng.range(-1e-3, 1e-3);
        pts.push((seam, 2));
    }
    pts
}

/// noise_fbm_texture sampled on the GPU from the GPU-baked texture against the CPU
/// mirror on the CPU bake, and against the CPU mirror on the texels read back (which
/// isolates the sampler's filtering), plus perlin_noise_tiled and
/// noise_animated_texture.
///
/// Bound: the texels differ by at most 5e-4 (see noise_bake_matches_cpu_bake), and a
/// trilinear filter is a convex combination, so that carries over to each octave and to
/// the normalised sum. The sampler computes its weights in reduced precision (lavapipe:
/// 8-bit fixed point, as Vulkan's subTexelPrecisionBits = 8 minimum allows): a weight off
/// by up to 2^-8 moves a sample by that times the difference of the two texels it
/// blends, at most D = the largest difference of neighbouring texels, on each of the
/// three axes: 5e-4 + 3 * 2^-8 * D.
#[test]
fn noise_fbm_texture_matches_cpu_mirror() {
    let gpu = gpu();
    let (texture, texels) = baked_noise(gpu);
    let cpu = bake_noise_texture();
    let read_back = DensityTexture {
        size: cpu.size,
        texels: texels.iter().map(|t| t.x).collect(),
    };
    let n = NOISE_TEXTURE_SIZE as i32;
    let at = |x: i32, y: i32, z: i32| {
        let w = |v: i32| v.rem_euclid(n) as usize;
        cpu.texels[(w(z) * n as usize + w(y)) * n as usize + w(x)]
    };
    let mut neighbour = 0.0f32;
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let here = at(x, y, z);
                for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    neighbour = neighbour.max((at(x + dx, y + dy, z + dz) - here).abs());
                }
            }
        }
    }
    let tol = 5e-4 + 3.0 * neighbour / 256.0;
    let pts = texture_points();
    let out = eval_texture_gpu(gpu, &texture, &pts);
    let (wind, time, scale) = TEXTURE_KERNEL_ANIMATION;
    let (mut worst_tiled, mut worst_bake, mut worst_filter, mut worst_anim) =
        (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut sum2 = 0.0f64;
    for (&(p, o), &(tiled, fbm, anim)) in pts.iter().zip(&out) {
        let e = (tiled - perlin_noise_tiled(p, 16)).abs();
        worst_tiled = worst_tiled.max(e);
        assert!(e <= 1e-5, "perlin_noise_tiled({p}): gpu {tiled}");
        let want = noise_fbm_texture(&cpu, p, o);
        let e = (fbm - want).abs();
        worst_bake = worst_bake.max(e);
        sum2 += f64::from(e) * f64::from(e);
        assert!(
            e <= tol,
            "noise_fbm_texture({p}, {o}): gpu {fbm} cpu {want}"
        );
        let e = (fbm - noise_fbm_texture(&read_back, p, o)).abs();
        worst_filter = worst_filter.max(e);
        let want = noise_animated_texture(&cpu, p, scale, wind, time, o);
        let e = (anim - want).abs();
        worst_anim = worst_anim.max(e);
        assert!(
            e <= tol,
            "noise_animated_texture({p}, {o}): gpu {anim} cpu {want}"
        );
    }
    // Octaves clamp to 1..=8 as in noise_fbm.
    let probe = Vec3::new(1.3, -2.7, 5.1);
    let clamp = eval_texture_gpu(
        gpu,
        &texture,
        &[(probe, 0), (probe, 1), (probe, 9), (probe, 8)],
    );
    assert_eq!(clamp[0].1, clamp[1].1);
    assert_eq!(clamp[2].1, clamp[3].1);
    eprintln!(
        "noise texture sampling: {} points; noise_fbm_texture |gpu - cpu bake| max {worst_bake:e} \
         RMS {:.2e} (bound 5e-4 + 3 * 2^-8 * {neighbour:.4} = {tol:.2e}); |gpu - cpu on the \
         texels read back| max {worst_filter:e} (the filtering alone); noise_animated_texture \
         max {worst_anim:e}; perlin_noise_tiled |gpu - cpu| max {worst_tiled:e} (bound 1e-5)",
        pts.len(),
        (sum2 / pts.len() as f64).sqrt()
    );
}
