//! Every encase struct in `volfog::uniforms` against naga's layout of its WGSL twin in
//! `shaders/volfog/types.wgsl`: member names, order, offsets and sizes, and the struct
//! size. Every WGSL struct in the types module must have a twin here.
//!
//! Rust offsets are measured, not read from encase's metadata: each member in turn is
//! set to a marker value and the bytes that change in the serialised uniform give its
//! offset and size.

use std::collections::BTreeMap;

use glam::{Mat4, UVec3, Vec2, Vec3, Vec4};
use volfog::uniforms::{self, to_uniform_bytes};

trait Marker {
    fn marker() -> Self;
}
impl Marker for f32 {
    fn marker() -> Self {
        1234.5
    }
}
impl Marker for u32 {
    fn marker() -> Self {
        0xDEAD_BEEF
    }
}
impl Marker for i32 {
    fn marker() -> Self {
        -77_777
    }
}
impl Marker for Vec2 {
    fn marker() -> Self {
        Vec2::new(101.0, 102.0)
    }
}
impl Marker for Vec3 {
    fn marker() -> Self {
        Vec3::new(101.0, 102.0, 103.0)
    }
}
impl Marker for Vec4 {
    fn marker() -> Self {
        Vec4::new(101.0, 102.0, 103.0, 104.0)
    }
}
impl Marker for UVec3 {
    fn marker() -> Self {
        UVec3::new(0xA1, 0xA2, 0xA3)
    }
}
impl Marker for [Mat4; 4] {
    fn marker() -> Self {
        std::array::from_fn(|k| {
            Mat4::from_cols_array(&std::array::from_fn(|i| 200.0 + (16 * k + i) as f32))
        })
    }
}
impl<const N: usize> Marker for [Vec4; N] {
    fn marker() -> Self {
        std::array::from_fn(|k| {
            Vec4::from_array(std::array::from_fn(|i| 300.0 + (4 * k + i) as f32))
        })
    }
}
impl Marker for uniforms::DirectionalLight {
    fn marker() -> Self {
        uniforms::DirectionalLight {
            direction: Vec3::marker(),
            fog_intensity: f32::marker(),
            color: Vec3::marker(),
            toward_tint: Vec3::marker(),
            away_tint: Vec3::marker(),
        }
    }
}
impl Marker for Mat4 {
    fn marker() -> Self {
        Mat4::from_cols_array(&std::array::from_fn(|i| 100.0 + i as f32))
    }
}

/// (member name, offset, size) measured from encase, and the struct size.
type Measured = (Vec<(String, u32, u32)>, u32);

macro_rules! measure {
    ($ty:ident { $($field:ident : $fty:ty),* $(,)? }) => {{
        let base = uniforms::$ty::default();
        let base_bytes = to_uniform_bytes(&base);
        let mut members = Vec::new();
        $(
            let mut probe = base;
            probe.$field = <$fty as Marker>::marker();
            let bytes = to_uniform_bytes(&probe);
            let changed: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] != base_bytes[i]).collect();
            let first = (*changed.first().unwrap() / 4 * 4) as u32;
            let last = (changed.last().unwrap() / 4 * 4 + 4) as u32;
            // A nested struct's trailing padding is never written: take its own size.
            let size = (last - first).max(<$fty as encase::ShaderType>::min_size().get() as u32);
            members.push((stringify!($field).to_string(), first, size));
        )*
        (stringify!($ty), (members, base_bytes.len() as u32))
    }};
}

fn rust_layouts() -> BTreeMap<&'static str, Measured> {
    BTreeMap::from([
        measure!(FogHull {
            clip_from_world: Mat4,
            view_from_clip: Mat4,
            camera_position: Vec3,
            reference: f32,
            color: Vec3,
            density: f32,
            quantum: f32,
        }),
        measure!(HeightFog {
            color: Vec3,
            density: f32,
            up: Vec3,
            falloff: f32,
            sun_direction: Vec3,
            base_height: f32,
            sun_color: Vec3,
            sun_g: f32,
            top_height: f32,
            sun_transmittance: u32,
        }),
        measure!(FogVolume {
            local_from_world: Mat4,
            color: Vec3,
            density: f32,
            gradient: Vec3,
            falloff: f32,
            center: Vec3,
            offset: f32,
            shape: u32,
        }),
        measure!(Water {
            normal: Vec3,
            height: f32,
            light: Vec3,
            extinction: f32,
            albedo: Vec3,
            g: f32,
            attenuation: Vec3,
            shore_fade: f32,
        }),
        measure!(SkyAtmosphere {
            sun_direction: Vec3,
            planet_radius: f32,
            rayleigh: Vec3,
            atmosphere_radius: f32,
            sun_intensity: Vec3,
            camera_height: f32,
            rayleigh_height: f32,
            mie: f32,
            mie_height: f32,
            mie_extinction_ratio: f32,
            mie_g: f32,
            view_samples: u32,
            light_samples: u32,
            first_row: u32,
        }),
        measure!(EpipolarFrame {
            view_from_clip: Mat4,
            light_from_view: Mat4,
            light_screen: Vec2,
            screen_size: Vec2,
            rayleigh: Vec3,
            start_depth: f32,
            slices: u32,
            samples: u32,
            initial_step: u32,
            shadow_size: u32,
            cascade: u32,
            downscale: u32,
            fix_steps: u32,
            phase_model: u32,
            depth_threshold: f32,
            max_depth: f32,
            reference_steps: u32,
            depth_bias: f32,
        }),
        measure!(FrustumRays {
            corners: [Vec4; 4],
            camera: Vec4,
            depth_terms: Vec4,
        }),
        measure!(CloudLayer {
            sun_direction: Vec3,
            base_height: f32,
            sun_color: Vec3,
            thickness: f32,
            sky_color: Vec3,
            extinction: f32,
            wind: Vec2,
            map_size: f32,
            time: f32,
            view_samples: u32,
            sun_samples: u32,
            g: f32,
            rim: f32,
        }),
        measure!(FogFrame {
            world_from_view: Mat4,
            clip_from_world: Mat4,
            camera_position: Vec3,
            time: f32,
            jitter: Vec3,
            history_weight: f32,
            index: u32,
            history_enabled: u32,
            checkerboard: u32,
        }),
        measure!(HistoryState {
            clip_from_world: Mat4,
            valid: u32,
        }),
        measure!(FogView {
            view_from_world: Mat4,
        }),
        measure!(FogMedium {
            albedo: Vec3,
            density: f32,
            up: Vec3,
            height_falloff: f32,
            wind: Vec3,
            base_height: f32,
            texture_scale: Vec3,
            noise_strength: f32,
            texture_offset: Vec3,
            noise_scale: f32,
            phase_g: f32,
            local_volume_count: u32,
            emission: Vec3,
            top_height: f32,
            textured: u32,
            particle_count: u32,
        }),
        measure!(LocalVolume {
            local_from_world: Mat4,
            emission: Vec3,
            density: f32,
            edge: f32,
            shape: u32,
            blend: u32,
            texture_offset: Vec3,
            textured: u32,
        }),
        measure!(FogSample {
            albedo: Vec3,
            extinction: f32,
            emission: Vec3,
        }),
        measure!(FogCustomParams { values: [Vec4; 8] }),
        measure!(DirectionalLight {
            direction: Vec3,
            fog_intensity: f32,
            color: Vec3,
            toward_tint: Vec3,
            away_tint: Vec3,
        }),
        measure!(FogLight {
            position: Vec3,
            range: f32,
            color: Vec3,
            fog_intensity: f32,
            direction: Vec3,
            radius: f32,
            cos_outer: f32,
            cos_inner: f32,
            projection: u32,
            flags: u32,
        }),
        measure!(LightProjection {
            light_from_world: Mat4,
            depth_range: f32,
            exponent: f32,
            bias: f32,
            kind: u32,
            layer: u32,
            cookie: u32,
            depth_terms: Vec4,
        }),
        measure!(LocalShadowSource {
            depth_terms: Vec4,
            depth_range: f32,
            exponent: f32,
            source_layer: u32,
            atlas_layer: u32,
            source: u32,
        }),
        measure!(FogLighting {
            sun: uniforms::DirectionalLight,
            ambient_r: Vec4,
            ambient_g: Vec4,
            ambient_b: Vec4,
            light_count: u32,
            transmittance: u32,
        }),
        measure!(ShadowCascades {
            light_from_world: [Mat4; 4],
            splits: Vec4,
            count: u32,
            exponent: f32,
        }),
        measure!(ShadowTaps {
            offsets: [Vec4; 16],
            ray_origin: Vec3,
            count: u32,
            ray_x: Vec3,
            fresh: u32,
            ray_y: Vec3,
            sun_reversed_z: u32,
            camera_depth_terms: Vec4,
            use_scene_depth: u32,
        }),
        measure!(FogParticle {
            position: Vec3,
            radius: f32,
            albedo: Vec3,
            extinction: f32,
            emission: Vec3,
            falloff: f32,
        }),
        measure!(AreaLight {
            center: Vec3,
            shape: u32,
            axis_x: Vec3,
            half_x: f32,
            axis_y: Vec3,
            half_y: f32,
            radiance: Vec3,
            fog_intensity: f32,
            range: f32,
        }),
        measure!(MediumShadow {
            volume_from_world: Mat4,
            world_from_volume: Mat4,
            size: UVec3,
            step: f32,
            march_steps: u32,
            march_length: f32,
        }),
        measure!(TransientLighting {
            camera_position: Vec3,
            count: u32,
            ray_origin: Vec3,
            transmittance: u32,
            ray_x: Vec3,
            ray_y: Vec3,
        }),
        measure!(Froxels {
            clip_from_view: Mat4,
            view_from_clip: Mat4,
            size: UVec3,
            near: f32,
            far: f32,
            curve: f32,
        }),
    ])
}

fn wgsl_layouts() -> BTreeMap<String, Measured> {
    let types = volfog::shaders::MODULES
        .iter()
        .find(|m| m.import_path == "volfog::types")
        .unwrap();
    let source: String = types
        .source
        .lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let module = naga::front::wgsl::parse_str(&source).expect("types.wgsl parses on its own");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let mut out = BTreeMap::new();
    for (handle, ty) in module.types.iter() {
        if let naga::TypeInner::Struct { members, span } = &ty.inner {
            let measured = members
                .iter()
                .map(|m| (m.name.clone().unwrap(), m.offset, layouter[m.ty].size))
                .collect();
            let _ = handle;
            out.insert(ty.name.clone().unwrap(), (measured, *span));
        }
    }
    out
}

#[test]
fn uniform_structs_match_wgsl_layouts() {
    let rust = rust_layouts();
    let wgsl = wgsl_layouts();
    let missing: Vec<&String> = wgsl
        .keys()
        .filter(|k| !rust.contains_key(k.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "WGSL structs without a checked Rust twin: {missing:?}"
    );
    for (name, (members, size)) in &rust {
        let (want_members, want_size) = &wgsl[*name];
        assert_eq!(
            members, want_members,
            "{name}: members (name, offset, size)"
        );
        assert_eq!(size, want_size, "{name}: size");
        eprintln!(
            "{name}: {} members, {size} bytes, layout matches naga",
            members.len()
        );
    }
}

/// With the `serde` feature each struct serializes with its WGSL member names (the
/// names a host in another language finds in the manifest), nested structs as objects.
#[test]
fn uniform_structs_serialize_with_wgsl_member_names() {
    use uniforms::*;
    fn keys<T: serde::Serialize>(value: T) -> Vec<String> {
        let mut keys: Vec<String> = match serde_json::to_value(value).unwrap() {
            serde_json::Value::Object(map) => map.keys().cloned().collect(),
            other => panic!("not an object: {other}"),
        };
        keys.sort();
        keys
    }
    let rust = BTreeMap::from([
        ("FogHull", keys(FogHull::default())),
        ("HeightFog", keys(HeightFog::default())),
        ("FogVolume", keys(FogVolume::default())),
        ("Water", keys(Water::default())),
        ("SkyAtmosphere", keys(SkyAtmosphere::default())),
        ("FrustumRays", keys(FrustumRays::default())),
        ("EpipolarFrame", keys(EpipolarFrame::default())),
        ("CloudLayer", keys(CloudLayer::default())),
        ("FogFrame", keys(FogFrame::default())),
        ("HistoryState", keys(HistoryState::default())),
        ("FogView", keys(FogView::default())),
        ("FogMedium", keys(FogMedium::default())),
        ("LocalVolume", keys(LocalVolume::default())),
        ("FogSample", keys(FogSample::default())),
        ("FogCustomParams", keys(FogCustomParams::default())),
        ("DirectionalLight", keys(DirectionalLight::default())),
        ("FogLight", keys(FogLight::default())),
        ("LightProjection", keys(LightProjection::default())),
        ("LocalShadowSource", keys(LocalShadowSource::default())),
        ("FogLighting", keys(FogLighting::default())),
        ("ShadowCascades", keys(ShadowCascades::default())),
        ("ShadowTaps", keys(ShadowTaps::default())),
        ("TransientLighting", keys(TransientLighting::default())),
        ("AreaLight", keys(AreaLight::default())),
        ("FogParticle", keys(FogParticle::default())),
        ("MediumShadow", keys(MediumShadow::default())),
        ("Froxels", keys(Froxels::default())),
    ]);
    let wgsl = wgsl_layouts();
    assert_eq!(
        rust.keys().collect::<Vec<_>>(),
        wgsl.keys()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .iter()
            .collect::<Vec<_>>(),
        "every WGSL struct has a serialized twin"
    );
    for (name, (members, _)) in &wgsl {
        let mut want: Vec<String> = members.iter().map(|(n, _, _)| n.clone()).collect();
        want.sort();
        assert_eq!(rust[name.as_str()], want, "{name}");
    }
    let light = serde_json::to_value(FogLighting::default()).unwrap();
    assert!(light["sun"].is_object(), "nested struct as an object");
    let froxels = serde_json::to_value(Froxels::default()).unwrap();
    assert_eq!(froxels["clip_from_view"].as_array().unwrap().len(), 16);
}
