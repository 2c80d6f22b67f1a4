//! `cargo run -p volfog-bevy --example fog_scene [-- --out DIR --width W --height H]`:
//! the fog scene rendered headless with volfog's froxel fog, written to
//! `DIR/fog_scene.png` (default: `out/bevy` at the repository root).

mod scene;

use std::path::PathBuf;

use clap::Parser;
use scene::{FogKind, SceneOptions};

/// Renders the fog scene to a PNG.
#[derive(Parser)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../out/bevy"))]
    out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 960)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 540)]
    height: u32,
    /// Frames rendered before the capture (temporal reprojection settles).
    #[arg(long, default_value_t = 8)]
    frames: u32,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let options = SceneOptions {
        width: args.width,
        height: args.height,
        fog: FogKind::Froxel,
        ..SceneOptions::default()
    };
    let mut app = scene::app(&options);
    let pixels = scene::capture(&mut app, args.frames);
    if pixels.iter().any(|p| !p.is_finite()) {
        return Err("the image has NaN or infinite pixels".into());
    }
    std::fs::create_dir_all(&args.out)?;
    let path = args.out.join("fog_scene.png");
    scene::write_png(&path, args.width, args.height, &pixels)?;
    println!("{}", path.display());
    Ok(())
}
