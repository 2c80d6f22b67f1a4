//! GPU memory: `memory_bytes` against what the device allocates, and no growth of GPU
//! objects across repeated frames and reconfigurations.

use super::{live, private_device};
use crate::common::gpu;
use crate::common::scene::{projection, small_config, view};
use glam::UVec3;
use volfog::pipeline::{FogConfig, FrameInputs, VolumetricFog};

/// `memory_bytes` against the texture and buffer memory wgpu's Vulkan backend
/// allocates for the object (its internal counters), the budget of the default
/// configuration, and no history volumes without temporal reprojection.
#[test]
fn memory_matches_what_the_device_allocates() {
    let gpu = gpu();
    let device = private_device(gpu, wgpu::Features::empty(), wgpu::Limits::default());
    let allocated = |config: &FogConfig| {
        let before = live(&device);
        let fog = VolumetricFog::new(&device, config).unwrap();
        let after = live(&device);
        let bytes = (after.3 - before.3) + (after.4 - before.4);
        (fog.memory_bytes(), bytes as u64)
    };
    let (default_bytes, default_allocated) = allocated(&FogConfig::default());
    let (plain_bytes, plain_allocated) = allocated(&FogConfig {
        temporal: false,
        ..FogConfig::default()
    });
    let mib = |b: u64| b as f64 / 1048576.0;
    eprintln!(
        "default configuration: memory_bytes {:.2} MiB, device allocations {:.2} MiB (budget 48 MiB); without temporal {:.2} / {:.2} MiB",
        mib(default_bytes),
        mib(default_allocated),
        mib(plain_bytes),
        mib(plain_allocated)
    );
    assert!(default_bytes <= 48 * 1024 * 1024, "{default_bytes}");
    for (reported, allocated) in [
        (default_bytes, default_allocated),
        (plain_bytes, plain_allocated),
    ] {
        // Allocations pad resources to the backend's alignment (lavapipe pads the 3D
        // volumes by up to a megabyte): within 5 %.
        assert!(
            reported <= allocated && allocated as f64 <= reported as f64 * 1.05,
            "memory_bytes {reported} vs allocated {allocated}"
        );
    }
    // Without temporal reprojection: one volume (and the history states) fewer.
    let volume = 160 * 90 * 128 * 8;
    assert_eq!(default_bytes - plain_bytes, volume + 2 * 80);
    assert!(default_allocated - plain_allocated >= volume);
}

#[test]
fn reconfigure_and_repeated_frames_do_not_grow_gpu_objects() {
    let gpu = gpu();
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("counted"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::default(),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .unwrap();
    let mut fog = VolumetricFog::new(&device, &small_config()).unwrap();
    let frame = |fog: &mut VolumetricFog, t: f32| {
        fog.prepare(&queue, &FrameInputs::new(view(2.0, 0.0), projection(), t))
            .unwrap();
        let mut encoder = device.create_command_encoder(&Default::default());
        fog.encode(&mut encoder).unwrap();
        queue.submit([encoder.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    };
    for i in 0..5 {
        frame(&mut fog, i as f32);
    }
    let baseline = live(&device);
    assert!(
        baseline.3 > 0,
        "the counters are live (wgpu feature `counters`)"
    );
    for i in 0..30 {
        frame(&mut fog, i as f32);
    }
    let after_frames = live(&device);
    // Resize the volume back and forth, then return to the first configuration.
    for size in [
        UVec3::new(64, 36, 64),
        UVec3::new(16, 9, 16),
        small_config().volume_size,
    ] {
        fog.reconfigure(
            &device,
            &FogConfig {
                volume_size: size,
                ..small_config()
            },
        )
        .unwrap();
        for i in 0..3 {
            frame(&mut fog, i as f32);
        }
    }
    let after_resizes = live(&device);
    eprintln!(
        "live (texture views, buffers, bind groups, texture bytes, buffer bytes): after warm-up {baseline:?}, after 30 frames {after_frames:?}, after 3 reconfigurations {after_resizes:?}"
    );
    assert_eq!(
        after_frames, baseline,
        "repeated frames allocate nothing that lives on"
    );
    assert_eq!(
        after_resizes, baseline,
        "reconfiguring releases what it replaces"
    );
}
