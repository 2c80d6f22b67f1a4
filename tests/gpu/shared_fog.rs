//! `SharedFog`: one fog group read by the forward shaders of two cameras in one
//! command buffer. Each camera's `encode_share` puts its fog there before its own
//! forward work, so a shader reading the shared group gets, bit for bit, what it gets
//! from that camera's own group; before any copy the shared group holds no fog; a fog
//! of another volume size is a typed error.

use crate::common::gpu;
use crate::common::scene::{projection, small_config, view};
use glam::{UVec3, Vec4};
use volfog::options::Filtering;
use volfog::pipeline::apply::{FogResources, fog_bind_group, fog_layout_entries};
use volfog::pipeline::{FogError, FrameInputs, SharedFog, VolumetricFog};
use volfog::uniforms::{FogMedium, HeightFog};
use wgpu::util::DeviceExt;

/// A forward shader reduced to its fog look-up: the fog (tail included) between the
/// camera of the fog group and each world point.
const FORWARD: &str = r#"
#import volfog::bindings
#import volfog::apply::{fog_coord_from_world, fog_view_position, fog_sample, fog_tail, fog_with_tail}

@group(1) @binding(0) var<storage, read> points: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> fogs: array<vec4<f32>>;

@compute @workgroup_size(64)
fn forward(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&points) {
        return;
    }
    let world = points[id.x].xyz;
    let view_from_world = bindings::fog_view.view_from_world;
    let coord = fog_coord_from_world(world, view_from_world, bindings::fog_froxels);
    let view_pos = fog_view_position(world, view_from_world);
    fogs[id.x] = fog_with_tail(
        fog_sample(bindings::fog_integrated, bindings::fog_sampler, coord),
        fog_tail(bindings::fog_froxels, bindings::fog_far_tail, view_pos),
    );
}
"#;

/// World points in front of both cameras, near and far (beyond the volume, in the
/// tail).
fn points() -> Vec<Vec4> {
    let mut p = Vec::new();
    for i in 0..16 {
        for j in 0..8 {
            let x = -6.0 + 0.8 * i as f32;
            let z = -2.0 - 12.0 * j as f32;
            p.push(Vec4::new(x, 0.5 + 0.3 * j as f32, z, 1.0));
        }
    }
    p
}

struct Forward {
    pipeline: wgpu::ComputePipeline,
    fog_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
    points: wgpu::Buffer,
    count: u32,
}

impl Forward {
    fn new(device: &wgpu::Device) -> Self {
        let module = crate::common::compose(FORWARD, &[]);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shared fog forward"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        });
        let fog_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fog"),
            entries: &fog_layout_entries(Filtering::Sampler, wgpu::ShaderStages::COMPUTE),
        });
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let io_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("io"),
            entries: &[storage(0, true), storage(1, false)],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&fog_layout), Some(&io_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("shared fog forward"),
            layout: Some(&layout),
            module: &shader,
            entry_point: Some("forward"),
            compilation_options: Default::default(),
            cache: None,
        });
        let p = points();
        let points = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("points"),
            contents: bytemuck::cast_slice(&p),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Self {
            pipeline,
            fog_layout,
            io_layout,
            points,
            count: p.len() as u32,
        }
    }

    fn fog_group(&self, device: &wgpu::Device, r: &FogResources<'_>) -> wgpu::BindGroup {
        fog_bind_group(device, &self.fog_layout, Filtering::Sampler, r)
    }

    /// Records the look-up through `fog_group` into a new output buffer.
    fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        fog_group: &wgpu::BindGroup,
    ) -> wgpu::Buffer {
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fogs"),
            size: u64::from(self.count) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.io_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.points.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: out.as_entire_binding(),
                },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, fog_group, &[]);
        pass.set_bind_group(1, &io, &[]);
        pass.dispatch_workgroups(self.count.div_ceil(64), 1, 1);
        drop(pass);
        out
    }
}

fn read(buffer: &wgpu::Buffer) -> Vec<Vec4> {
    bytemuck::cast_slice(&gpu().read_buffer(buffer).unwrap()).to_vec()
}

/// Two cameras: the second higher, looking down, in a fog three times as dense with a
/// tail beyond its far plane.
fn cameras() -> [(VolumetricFog, FrameInputs<'static>); 2] {
    let gpu = gpu();
    let config = small_config();
    let a = FrameInputs::new(view(2.0, 0.0), projection(), 0.0);
    let medium = FogMedium {
        density: 3.0 * a.medium.density,
        ..a.medium
    };
    let b = FrameInputs {
        medium,
        tail: HeightFog {
            density: 0.02,
            ..HeightFog::none()
        },
        ..FrameInputs::new(view(6.0, -0.2), projection(), 0.0)
    };
    [a, b].map(|inputs| {
        let mut fog = VolumetricFog::new(&gpu.device, &config).unwrap();
        fog.prepare(&gpu.queue, &inputs).unwrap();
        (fog, inputs)
    })
}

#[test]
fn each_camera_reads_its_own_fog_through_the_shared_group() {
    let gpu = gpu();
    let device = &gpu.device;
    let forward = Forward::new(device);
    let [(a, _), (b, _)] = cameras();
    let shared = SharedFog::new(device, &gpu.queue, small_config().volume_size).unwrap();
    let shared_group = forward.fog_group(device, &shared.resources());
    let own = [a.fog_resources(), b.fog_resources()].map(|r| forward.fog_group(device, &r));

    // One command buffer, as an engine records its cameras one after the other.
    let mut encoder = device.create_command_encoder(&Default::default());
    let before = forward.record(device, &mut encoder, &shared_group);
    a.encode(&mut encoder).unwrap();
    a.encode_share(&mut encoder, &shared).unwrap();
    let through_a = forward.record(device, &mut encoder, &shared_group);
    b.encode(&mut encoder).unwrap();
    b.encode_share(&mut encoder, &shared).unwrap();
    let through_b = forward.record(device, &mut encoder, &shared_group);
    let own_a = forward.record(device, &mut encoder, &own[0]);
    let own_b = forward.record(device, &mut encoder, &own[1]);
    gpu.queue.submit([encoder.finish()]);

    let [before, through_a, through_b, own_a, own_b] =
        [before, through_a, through_b, own_a, own_b].map(|b| read(&b));
    assert!(
        before.iter().all(|f| *f == Vec4::new(0.0, 0.0, 0.0, 1.0)),
        "before any copy the shared group holds no fog"
    );
    assert_eq!(through_a, own_a, "camera A's pass reads A's fog");
    assert_eq!(through_b, own_b, "camera B's pass reads B's fog");
    // The two fogs differ, so reading the other camera's fog would fail above.
    let differ = own_a
        .iter()
        .zip(&own_b)
        .filter(|(x, y)| (**x - **y).abs().max_element() > 0.05 * x.max_element().max(0.01))
        .count();
    let fogged = own_b.iter().filter(|f| f.w < 0.95).count();
    eprintln!(
        "shared fog: {} points, bit-identical to each camera's own group; the two fogs differ by more than 5 % at {differ}, camera B's transmittance is below 0.95 at {fogged}",
        own_a.len()
    );
    assert!(differ * 2 >= own_a.len(), "{differ} of {}", own_a.len());
    assert!(fogged * 2 >= own_b.len(), "{fogged} of {}", own_b.len());
    assert!(through_b.iter().all(|f| f.is_finite()));
}

#[test]
fn a_fog_of_another_size_is_a_typed_error() {
    let gpu = gpu();
    let [(a, _), _] = cameras();
    let shared = SharedFog::new(&gpu.device, &gpu.queue, UVec3::new(16, 9, 48)).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let error = a.encode_share(&mut encoder, &shared).unwrap_err();
    assert!(matches!(error, FogError::Texture { .. }), "{error}");
    let message = error.to_string();
    assert!(
        message.contains("16, 9, 48") && message.contains("32, 18, 48"),
        "{message}"
    );
    // Out-of-range sizes name the field.
    let error = SharedFog::new(&gpu.device, &gpu.queue, UVec3::new(0, 9, 48)).unwrap_err();
    assert!(
        error.to_string().contains("SharedFog.volume_size"),
        "{error}"
    );
    // Before prepare there is nothing to share.
    let unprepared = VolumetricFog::new(&gpu.device, &small_config()).unwrap();
    assert!(matches!(
        unprepared.encode_share(&mut encoder, &shared),
        Err(FogError::NotPrepared)
    ));
}
