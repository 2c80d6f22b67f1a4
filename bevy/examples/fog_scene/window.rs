//! The fog scene in a window, with a fly camera: hold the right mouse button and move
//! the mouse to look around, W A S D to move, E and Q to rise and sink, Shift to move
//! faster, Escape to quit.

use bevy::camera::RenderTarget;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::input::mouse::AccumulatedMouseMotion;
use bevy::prelude::*;
use bevy::render::render_resource::TextureFormat;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::WindowRef;
use std::path::PathBuf;

use crate::scene::{self, SceneCamera, SceneOptions};

/// Metres per second of the fly camera (four times that with Shift).
const SPEED: f32 = 4.0;
/// Radians per pixel of mouse motion.
const LOOK: f32 = 0.003;

/// Whether a display to open a window on exists (an X11 display; Wayland sessions
/// offer one through Xwayland).
pub fn display_exists() -> bool {
    std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
}

/// Frames to run before quitting (`None`: until the window closes), and where to save
/// a screenshot of the window then.
#[derive(Resource)]
struct ExitAfter {
    frames: Option<u32>,
    screenshot: Option<PathBuf>,
    /// The screenshot was requested; the app quits once it is saved.
    requested: bool,
}

/// Runs the scene in a window of `options`' size until it is closed (or for
/// `exit_after` frames, then saving a screenshot of the window to `screenshot` as a
/// PNG when given).
pub fn run(
    options: &SceneOptions,
    exit_after: Option<u32>,
    screenshot: Option<PathBuf>,
) -> AppExit {
    let window = Window {
        title: "volfog: fog_scene".into(),
        resolution: (options.width, options.height).into(),
        ..Default::default()
    };
    let mut app = scene::build_app(options, Some(window));
    app.insert_resource(ExitAfter {
        frames: exit_after,
        screenshot,
        requested: false,
    })
    .add_systems(PostStartup, to_window)
    .add_systems(Update, (fly, quit));
    app.run()
}

/// The scene camera renders into the window, tone mapped for the screen.
fn to_window(mut commands: Commands, cameras: Query<Entity, With<SceneCamera>>) {
    for camera in &cameras {
        commands.entity(camera).insert((
            RenderTarget::Window(WindowRef::Primary),
            Tonemapping::ReinhardLuminance,
        ));
    }
}

fn fly(
    time: Res<Time>,
    keys: Res<ButtonInput<KeyCode>>,
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    mut cameras: Query<&mut Transform, With<SceneCamera>>,
) {
    for mut transform in &mut cameras {
        if buttons.pressed(MouseButton::Right) && motion.delta != Vec2::ZERO {
            let (yaw, pitch, _) = transform.rotation.to_euler(EulerRot::YXZ);
            let yaw = yaw - motion.delta.x * LOOK;
            let pitch = (pitch - motion.delta.y * LOOK).clamp(-1.5, 1.5);
            transform.rotation = Quat::from_euler(EulerRot::YXZ, yaw, pitch, 0.0);
        }
        let axis = |plus: KeyCode, minus: KeyCode| {
            f32::from(u8::from(keys.pressed(plus))) - f32::from(u8::from(keys.pressed(minus)))
        };
        let local = Vec3::new(
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::KeyE, KeyCode::KeyQ),
            axis(KeyCode::KeyS, KeyCode::KeyW),
        );
        if local == Vec3::ZERO {
            continue;
        }
        let fast = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
        let speed = SPEED * if fast { 4.0 } else { 1.0 };
        let step = transform.rotation * local.normalize() * speed * time.delta_secs();
        transform.translation += step;
    }
}

fn quit(
    mut commands: Commands,
    keys: Res<ButtonInput<KeyCode>>,
    mut left: ResMut<ExitAfter>,
    mut exit: MessageWriter<AppExit>,
) {
    if keys.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
        return;
    }
    match &mut left.frames {
        Some(0) => {}
        Some(n) => {
            *n -= 1;
            return;
        }
        None => return,
    }
    let Some(path) = left.screenshot.clone() else {
        exit.write(AppExit::Success);
        return;
    };
    if !left.requested {
        left.requested = true;
        commands.spawn(Screenshot::primary_window()).observe(
            move |captured: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                match save_png(&captured.image, &path) {
                    Ok(()) => {
                        println!("{}", path.display());
                        exit.write(AppExit::Success);
                    }
                    Err(error) => {
                        eprintln!("screenshot {}: {error}", path.display());
                        exit.write(AppExit::error());
                    }
                }
            },
        );
    }
}

/// Writes an 8-bit RGBA or BGRA screenshot as an RGB PNG.
fn save_png(image: &Image, path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let format = image.texture_descriptor.format;
    let bgra = matches!(
        format,
        TextureFormat::Bgra8Unorm | TextureFormat::Bgra8UnormSrgb
    );
    if !bgra
        && !matches!(
            format,
            TextureFormat::Rgba8Unorm | TextureFormat::Rgba8UnormSrgb
        )
    {
        return Err(format!("unexpected window format {format:?}").into());
    }
    let data = image.data.as_ref().ok_or("the screenshot holds no data")?;
    let rgb: Vec<u8> = data
        .chunks_exact(4)
        .flat_map(|p| {
            if bgra {
                [p[2], p[1], p[0]]
            } else {
                [p[0], p[1], p[2]]
            }
        })
        .collect();
    // A drawn scene: neither black nor one flat colour.
    let luma: Vec<f32> = rgb
        .chunks_exact(3)
        .map(|p| 0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2]))
        .collect();
    let mean = luma.iter().sum::<f32>() / luma.len() as f32;
    let deviation =
        (luma.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / luma.len() as f32).sqrt();
    println!("window: 8-bit luminance mean {mean:.1}, deviation {deviation:.1}");
    if !(8.0..=247.0).contains(&mean) || deviation < 4.0 {
        return Err(format!(
            "the window is not drawn: luminance mean {mean:.1}, deviation {deviation:.1}"
        )
        .into());
    }
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let size = image.texture_descriptor.size;
    let mut encoder = png::Encoder::new(file, size.width, size.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(&rgb)?;
    Ok(())
}
