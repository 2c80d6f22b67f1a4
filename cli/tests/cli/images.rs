//! The images of the guides are what the current code renders: `docs/demo.png` and
//! `docs/underwater.png` against a run of the command that makes them (`volfog demo`
//! at its defaults, as `cargo xtask demo` runs it), on the test adapter.
//!
//! Tolerance: the same code on the same adapter renders the same image up to the
//! rounding of its 8-bit PNG and the order of floating-point sums a software rasterizer
//! may change between machines: a mean absolute difference of at most 0.5 / 255 per
//! channel and at most 0.5 % of the pixels more than 8 / 255 apart in a channel. An
//! image left from older code misses by far more (the demo image of a fog a third as
//! dense differed by 24 / 255 on average). To renew the images, run `cargo xtask demo`
//! and copy `out/demo/demo.png` and `out/demo/underwater.png` into `docs/`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Decodes an RGBA8 PNG: its size and pixels.
fn read_png(path: &Path) -> ((u32, u32), Vec<u8>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut pixels = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut pixels).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgba, "{}", path.display());
    pixels.truncate(info.buffer_size());
    ((info.width, info.height), pixels)
}

/// The mean absolute difference per colour channel (in 8-bit steps) and the share of
/// pixels with a channel more than `far` steps apart.
fn difference(a: &[u8], b: &[u8], far: u8) -> (f64, f64) {
    let (mut sum, mut outliers) = (0u64, 0usize);
    for (p, q) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        let d: Vec<u8> = (0..3).map(|c| p[c].abs_diff(q[c])).collect();
        sum += d.iter().map(|&x| u64::from(x)).sum::<u64>();
        outliers += usize::from(d.iter().any(|&x| x > far));
    }
    let pixels = a.len() / 4;
    (
        sum as f64 / (3 * pixels) as f64,
        outliers as f64 / pixels as f64,
    )
}

#[test]
fn the_guides_demo_images_are_what_the_demo_renders() {
    let out: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("images_demo");
    let _ = std::fs::remove_dir_all(&out);
    let output = Command::new(env!("CARGO_BIN_EXE_volfog"))
        .args(["demo", "--out"])
        .arg(&out)
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .output()
        .expect("the volfog binary starts");
    assert!(
        output.status.success(),
        "volfog demo failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
    for name in ["demo.png", "underwater.png"] {
        let (size, rendered) = read_png(&out.join(name));
        let (doc_size, doc) = read_png(&docs.join(name));
        assert_eq!(
            doc_size, size,
            "docs/{name} has another size than the demo's"
        );
        let (mean, outliers) = difference(&rendered, &doc, 8);
        eprintln!(
            "docs/{name} against the demo's render: mean absolute difference {:.3} / 255 per channel (bound 0.5), {:.3} % of the pixels more than 8 / 255 apart (bound 0.5 %)",
            mean,
            100.0 * outliers
        );
        assert!(
            mean <= 0.5 && outliers <= 0.005,
            "docs/{name} is not what the demo renders: run `cargo xtask demo` and copy out/demo/{name} into docs/"
        );
    }
}
