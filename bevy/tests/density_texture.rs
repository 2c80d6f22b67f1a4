//! A `FogVolume`'s density texture under `BevyFogCompat`: it becomes the volume's
//! `FroxelFogVolumeTexture`, the extracted fog reads a density texture and marks the
//! volume textured with Bevy's offset, and the texture shapes the fog on screen: a
//! texture of ones gives the uniform volume's image, one of zeros takes the volume's
//! fog away, and one that is 1 in half of the volume and 0 in the other leaves part of
//! the fog (the `fog_scene` scene at 160 x 90, noise and temporal off).

#[path = "../examples/fog_scene/scene.rs"]
mod scene;

use bevy::asset::RenderAssetUsages;
use bevy::light::FogVolume;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use scene::{FogKind, SceneOptions};
use volfog_bevy::{ExtractedFroxelFog, FroxelFogVolumeTexture};

/// A 16 x 4 x 4 R8Unorm image whose texels along x are `value(x)`.
fn texture(value: impl Fn(u32) -> u8) -> Image {
    let data: Vec<u8> = (0..16 * 4 * 4).map(|i| value(i % 16)).collect();
    Image::new(
        Extent3d {
            width: 16,
            height: 4,
            depth_or_array_layers: 4,
        },
        TextureDimension::D3,
        data,
        TextureFormat::R8Unorm,
        RenderAssetUsages::RENDER_WORLD,
    )
}

/// The compat scene with its `FogVolume` given `image` (none: uniform) scrolled by
/// `offset`: the captured image and the fog the render world extracted.
fn render(image: Option<Image>, offset: Vec3) -> (Vec<Vec4>, ExtractedFroxelFog, bool) {
    let mut app = scene::app(&SceneOptions::still(160, 90, FogKind::BevyCompat));
    app.update();
    let handle = image.map(|i| app.world_mut().resource_mut::<Assets<Image>>().add(i));
    let world = app.world_mut();
    let mut volumes = world.query::<(Entity, &mut FogVolume)>();
    let (entity, mut volume) = volumes.single_mut(world).expect("the scene's FogVolume");
    volume.density_texture = handle;
    volume.density_texture_offset = offset;
    let pixels = scene::capture(&mut app, 8);
    let textured = app.world().get::<FroxelFogVolumeTexture>(entity).is_some();
    let render = app.sub_app_mut(RenderApp).world_mut();
    let mut q = render.query::<&ExtractedFroxelFog>();
    let fog = q.single(render).expect("one fog view").clone();
    (pixels, fog, textured)
}

/// Mean over the pixels of the absolute difference of the rgb sums.
fn mean_difference(a: &[Vec4], b: &[Vec4]) -> f32 {
    let d: f32 = a
        .iter()
        .zip(b)
        .map(|(a, b)| (a.truncate().element_sum() - b.truncate().element_sum()).abs())
        .sum();
    d / a.len() as f32
}

#[test]
fn a_fog_volume_density_texture_shapes_the_fog() {
    let offset = Vec3::new(0.1, 0.0, 0.0);
    let (uniform, plain_fog, plain_textured) = render(None, Vec3::ZERO);
    let (ones, ones_fog, ones_textured) = render(Some(texture(|_| 255)), offset);
    let (zeros, ..) = render(Some(texture(|_| 0)), offset);
    // The camera stands near the volume's middle in x (local x 0.48): the texture's
    // left half fogs what lies to its left, the right half nothing.
    let (half, ..) = render(Some(texture(|x| if x < 8 { 255 } else { 0 })), Vec3::ZERO);

    assert!(!plain_textured && plain_fog.density_texture.is_none());
    assert!(!plain_fog.config.density_texture);
    assert!(
        ones_textured,
        "the FogVolume's texture becomes its FroxelFogVolumeTexture"
    );
    assert!(ones_fog.config.density_texture && ones_fog.density_texture.is_some());
    let textured: Vec<_> = ones_fog
        .volumes
        .iter()
        .filter(|v| v.textured == 1)
        .collect();
    assert_eq!(textured.len(), 1, "the volume reads the density texture");
    assert_eq!(textured[0].texture_offset.to_array(), offset.to_array());
    assert_eq!(
        ones_fog.medium.textured, 0,
        "the texture is the volumes': FroxelFog's own medium never reads it"
    );

    // How much the volume's fog changes the image, and how much of it each texture
    // leaves.
    let fog = mean_difference(&uniform, &zeros);
    let ones_vs_uniform = mean_difference(&ones, &uniform);
    let half_share = mean_difference(&half, &zeros) / fog;
    eprintln!(
        "density texture: the volume's fog moves a pixel's rgb sum by {fog:.4} on average; a \
         texture of ones differs from the uniform volume by {:.2e} of that (bound 1e-2); one \
         that is 1 in half of the volume leaves {:.0} % of the fog's change",
        ones_vs_uniform / fog,
        100.0 * half_share
    );
    assert!(fog > 0.05, "the volume's fog shows: {fog}");
    assert!(ones_vs_uniform < 1e-2 * fog, "{ones_vs_uniform}");
    assert!(
        half_share > 0.1 && half_share < 0.9,
        "half a texture leaves part of the fog: {half_share}"
    );
    assert!(half.iter().all(|p| p.is_finite()));
}
