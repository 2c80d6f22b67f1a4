//! Typed errors of stereo fog: each names the field or texture and what is valid, and a
//! rejected frame changes nothing.

use super::*;
use volfog::pipeline::FogError;
use volfog::uniforms::FogLight;

fn field(err: FogError) -> &'static str {
    match err {
        FogError::Invalid(e) => e.field,
        other => panic!("not an invalid value: {other}"),
    }
}

#[test]
fn bad_eyes_and_targets_are_typed_errors() {
    let gpu = gpu();
    let config = config();
    let good = eyes(head(), 0.064);
    let mut fog = StereoFog::new(&gpu.device, &config).unwrap();
    let inputs = FrameInputs::new(good[0].view_from_world, good[0].clip_from_view, 0.0);

    let mut nan = good;
    nan[1].clip_from_view.y_axis.y = f32::NAN;
    assert_eq!(
        field(fog.prepare(&gpu.queue, &nan, &inputs).unwrap_err()),
        "StereoEye.clip_from_view (right)"
    );
    let mut singular = good;
    singular[0].view_from_world = Mat4::ZERO;
    assert_eq!(
        field(fog.prepare(&gpu.queue, &singular, &inputs).unwrap_err()),
        "StereoEye.view_from_world (left)"
    );
    let mut canted = good;
    canted[1].view_from_world = Mat4::from_rotation_y(0.1) * canted[1].view_from_world;
    assert_eq!(
        field(fog.prepare(&gpu.queue, &canted, &inputs).unwrap_err()),
        "StereoEye.view_from_world (right)"
    );
    let mut ortho = good;
    ortho[0].clip_from_view =
        glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0);
    assert_eq!(
        field(fog.prepare(&gpu.queue, &ortho, &inputs).unwrap_err()),
        "StereoEye.clip_from_view (left)"
    );
    let flash = [FogLight::point(
        Vec3::new(0.0, 2.0, -3.0),
        Vec3::splat(10.0),
        5.0,
    )];
    let with_flash = FrameInputs {
        transient_lights: &flash,
        ..inputs.clone()
    };
    assert_eq!(
        field(fog.prepare(&gpu.queue, &good, &with_flash).unwrap_err()),
        "FrameInputs.transient_lights"
    );
    // Nothing was prepared by the rejected frames.
    assert!(fog.centre_eye().is_none());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(matches!(
        fog.encode(&mut encoder),
        Err(FogError::NotPrepared)
    ));
    assert_eq!(
        field(fog.eye_fog_bind_group(2).unwrap_err()),
        "StereoFog eye"
    );

    fog.prepare(&gpu.queue, &good, &inputs).unwrap();
    let apply = fog
        .shared()
        .create_apply(&gpu.device, wgpu::TextureFormat::Rgba16Float)
        .unwrap();
    let depth = far_depth(gpu, 2);
    let groups = [0, 1].map(|i| apply.depth_bind_group(&gpu.device, &depth_layer(&depth, i)));
    let groups = [&groups[0], &groups[1]];
    // One layer where the eyes need two.
    let single = target(gpu, 1);
    match fog.record_apply(&mut encoder, &apply, &single, groups) {
        Err(FogError::Texture {
            property, found, ..
        }) => {
            assert_eq!((property, found.as_str()), ("array layers", "1"));
        }
        other => panic!("{other:?}"),
    }
    // Eyes at different resolutions.
    let small = gpu.texture_2d_rgba16f("small", [IMAGE[0] / 2, IMAGE[1]], &[]);
    match fog.record_apply_eyes(&mut encoder, &apply, [&single, &small], [0, 0], groups) {
        Err(FogError::Texture {
            texture, property, ..
        }) => assert_eq!((texture, property), ("the right eye's target", "size")),
        other => panic!("{other:?}"),
    }
    // A layer the target lacks.
    match fog.record_apply_eyes(&mut encoder, &apply, [&single, &single], [0, 1], groups) {
        Err(FogError::Texture {
            texture, property, ..
        }) => assert_eq!(
            (texture, property),
            ("the right eye's target", "array layer")
        ),
        other => panic!("{other:?}"),
    }
    // The frame still records.
    fog.encode(&mut encoder).unwrap();
    gpu.queue.submit([encoder.finish()]);
}
