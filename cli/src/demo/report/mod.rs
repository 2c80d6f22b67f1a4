//! What the demo reports: the printed table of per-pass GPU times (median, min and
//! max over the frames), the PNGs and linear float files it writes, and the probe.

mod probe;

use std::path::Path;

use glam::Vec4;

pub use probe::{write_probe, write_underwater_probe};

use super::DemoError;
use super::passes::{PASS_COUNT, PASS_NAMES};

pub fn median(values: &mut [f64]) -> f64 {
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

pub fn write_error(path: &Path, e: impl std::fmt::Display) -> DemoError {
    DemoError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), DemoError> {
    let file = std::fs::File::create(path).map_err(|e| write_error(path, e))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(|e| write_error(path, e))?;
    writer
        .write_image_data(rgba)
        .map_err(|e| write_error(path, e))?;
    writer.finish().map_err(|e| write_error(path, e))
}

pub fn write_f32(path: &Path, values: &[f32]) -> Result<(), DemoError> {
    std::fs::write(path, bytemuck::cast_slice(values)).map_err(|e| write_error(path, e))
}

pub fn flat(v: &[Vec4]) -> Vec<f32> {
    v.iter().flat_map(|t| t.to_array()).collect()
}

pub fn print_timings(times: &[[f64; PASS_COUNT]], frames: u32) {
    if times.is_empty() {
        println!("per-pass GPU times: unavailable (the adapter lacks TIMESTAMP_QUERY)");
        return;
    }
    // The first frame pays for pipeline compilation and first use: leave it out when
    // there are others.
    let measured = if times.len() > 1 { &times[1..] } else { times };
    println!(
        "\nper-pass GPU time, median of {} frame(s) (of {frames}):",
        measured.len()
    );
    println!(
        "  {:<16} {:>10} {:>10} {:>10}",
        "pass", "median ms", "min ms", "max ms"
    );
    let mut total = 0.0;
    for (i, name) in PASS_NAMES.iter().enumerate() {
        let mut v: Vec<f64> = measured.iter().map(|t| t[i]).collect();
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = v.iter().copied().fold(0.0, f64::max);
        let m = median(&mut v);
        total += m;
        println!("  {name:<16} {m:>10.3} {min:>10.3} {max:>10.3}");
    }
    println!("  {:<16} {:>10.3}", "total", total);
}
