//! The inject pass through `VolumetricFog`: against the CPU mirror for a full scene,
//! against closed forms (homogeneous fog lit by the sun, with and without an occluder),
//! against numerical integration (a height-fog column), and with lights placed exactly
//! at froxel centres; the density-texture variant, the culling of local volumes,
//! directional fog lights and squared spot cones, the blend modes of local volumes, your
//! own density in WGSL, and typed errors for bad frame inputs.

mod blend_modes;
mod closed_form;
mod custom_density;
mod inputs;
mod light_kinds;
mod local_volumes;
mod mirror;
mod textured_volumes;

/// An R16Float 3D density texture of `size` texels from `value(x, y, z)`, and the CPU
/// mirror's copy of its values as the texture stores them (rounded to f16).
fn density_texture(
    size: [u32; 3],
    value: impl Fn(u32, u32, u32) -> f32,
) -> (wgpu::Texture, volfog::cpu::inject::DensityTexture) {
    use wgpu::util::DeviceExt;
    let gpu = crate::common::gpu();
    let [w, h, d] = size;
    let halfs: Vec<half::f16> = (0..w * h * d)
        .map(|i| half::f16::from_f32(value(i % w, (i / w) % h, i / (w * h))))
        .collect();
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("density"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: d,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D3,
            format: wgpu::TextureFormat::R16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&halfs),
    );
    let reference = volfog::cpu::inject::DensityTexture {
        size,
        texels: halfs.iter().map(|h| h.to_f32()).collect(),
    };
    (texture, reference)
}
