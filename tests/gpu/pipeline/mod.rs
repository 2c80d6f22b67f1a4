//! `VolumetricFog` as an object: typed errors for every invalid configuration field,
//! input and texture and for a device without a needed capability, the frame contract
//! (no encoding before `prepare`, shadow maps checked against the cascades,
//! `reconfigure` keeping what the user set), memory measured by wgpu's own counters,
//! and no growth of GPU objects across reconfigurations and repeated frames. Here: a
//! device of a test's own and its live-object counters.

mod config;
mod frames;
mod inputs;
mod memory;

use volfog_testkit::Gpu;

/// A device of its own (wgpu's counters are per device, and the shared device is busy
/// with other tests), with `features`.
fn private_device(gpu: &Gpu, features: wgpu::Features, limits: wgpu::Limits) -> wgpu::Device {
    pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("private"),
        required_features: features,
        required_limits: limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap()
    .0
}

/// Live GPU objects: (texture views, buffers, bind groups, texture bytes, buffer bytes).
/// wgpu's Vulkan backend counts texture memory but not textures themselves.
fn live(device: &wgpu::Device) -> (isize, isize, isize, isize, isize) {
    let c = device.get_internal_counters().hal;
    (
        c.texture_views.read(),
        c.buffers.read(),
        c.bind_groups.read(),
        c.texture_memory.read(),
        c.buffer_memory.read(),
    )
}
