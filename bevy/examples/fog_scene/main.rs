//! `cargo run -p volfog-bevy --example fog_scene [-- --width W --height H]`: the fog
//! scene with volfog's froxel fog in a window with a fly camera when a display exists
//! (right mouse button to look, W A S D E Q to move, Shift faster, Escape to quit);
//! headless otherwise or with `--headless`: rendered into an image and written to
//! `DIR/fog_scene.png` (`--out DIR`, default: `out/bevy` at the repository root).

mod scene;
mod window;

use std::path::PathBuf;

use bevy::app::AppExit;
use clap::Parser;
use scene::{FogKind, SceneOptions};

/// Shows the fog scene in a window, or renders it to a PNG.
#[derive(Parser)]
struct Args {
    /// Render headless to a PNG even when a display exists.
    #[arg(long)]
    headless: bool,
    /// In a window: quit after this many frames.
    #[arg(long)]
    exit_after: Option<u32>,
    /// In a window, with --exit-after: save a screenshot of the window as a PNG then.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../out/bevy"))]
    out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 960)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 540)]
    height: u32,
    /// Headless: frames rendered before the capture (temporal reprojection settles).
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
    if !args.headless && window::display_exists() {
        return match window::run(&options, args.exit_after, args.screenshot.clone()) {
            AppExit::Success => Ok(()),
            AppExit::Error(code) => Err(format!("the app exited with code {code}").into()),
        };
    }
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
