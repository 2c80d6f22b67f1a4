//! The scene's images as PNG files.

use bevy::math::Vec4;

/// Writes linear rgb as an 8-bit sRGB PNG (Reinhard tone curve).
pub fn write_png(
    path: &std::path::Path,
    width: u32,
    height: u32,
    pixels: &[Vec4],
) -> std::io::Result<()> {
    let file = std::fs::File::create(path)?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
    let srgb = |v: f32| {
        let v = (v / (1.0 + v)).clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5) as u8
    };
    let data: Vec<u8> = pixels
        .iter()
        .flat_map(|p| [srgb(p.x), srgb(p.y), srgb(p.z)])
        .collect();
    writer
        .write_image_data(&data)
        .map_err(std::io::Error::other)
}
