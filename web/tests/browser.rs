//! volfog in a real browser: the page built by `cargo xtask web` (the wasm module on
//! wgpu's WebGPU backend) runs in headless Chromium on its bundled SwiftShader, renders
//! the demo scene's fixed frame (shadowed sun, a point and a spot light, two local
//! volumes, depth culling; no jitter, no history) and posts the integrated fog volume
//! and the fogged image back; the same frame rendered natively by the same Rust code on
//! lavapipe must match it. A page error, an uncaught exception or a WebGPU validation
//! error fails the test with its message.

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use volfog_web::analytic::analytic_scene;
use volfog_web::readback::read_rgba16f;
use volfog_web::render::Renderer;
use volfog_web::scene::Params;
use volfog_web::serve::Server;

const SIZE: (u32, u32) = (320, 180);
const CHROMIUM: &str = "/usr/lib/chromium/chromium";
const INSTALL: &str =
    "cargo xtask web (and apt-get install chromium, which cargo xtask test installs)";

fn page_dir() -> PathBuf {
    std::env::var_os("VOLFOG_WEB_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/web"))
}

/// Chromium headless, WebGL2 on SwiftShader through ANGLE, and with `webgpu` WebGPU
/// on SwiftShader's Vulkan (without it the browser offers no WebGPU adapter); killed
/// when dropped.
struct Browser(Child);

impl Browser {
    fn open(url: &str, webgpu: bool) -> Self {
        let binary = std::env::var("VOLFOG_CHROMIUM").unwrap_or_else(|_| CHROMIUM.to_string());
        // A profile per launch: tests run in parallel, and a second Chromium on the
        // same profile would hand its page to the first and exit.
        static LAUNCHES: AtomicUsize = AtomicUsize::new(0);
        let profile = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!(
            "chromium-{}",
            LAUNCHES.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&profile);
        let gpu_flags: &[&str] = if webgpu {
            &[
                "--enable-unsafe-webgpu",
                "--enable-features=Vulkan",
                "--use-vulkan=swiftshader",
            ]
        } else {
            &["--disable-features=WebGPU,Vulkan"]
        };
        let child = Command::new(&binary)
            .args([
                "--headless=new",
                "--no-sandbox",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader",
                "--enable-logging=stderr",
                "--v=0",
            ])
            .args(gpu_flags)
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg(url)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {binary}: {e}; install it with `{INSTALL}`"));
        Self(child)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn floats(bytes: &[u8]) -> Vec<[f32; 4]> {
    bytes
        .chunks_exact(16)
        .map(|c| {
            let f = |i: usize| f32::from_le_bytes(c[i * 4..i * 4 + 4].try_into().unwrap());
            [f(0), f(1), f(2), f(3)]
        })
        .collect()
}

/// Per texel, the largest |got - want| over max(|want|, floor) of its four channels,
/// sorted; and the mean absolute difference over all channels.
fn relative_errors(got: &[[f32; 4]], want: &[[f32; 4]], floor: f32) -> (Vec<f32>, f32) {
    assert_eq!(got.len(), want.len(), "the page read back another size");
    let mut abs = 0.0f64;
    let mut errors: Vec<f32> = got
        .iter()
        .zip(want)
        .map(|(g, w)| {
            assert!(
                g.iter().all(|v| v.is_finite()),
                "non-finite value from the page: {g:?}"
            );
            (0..4)
                .map(|c| {
                    let d = (g[c] - w[c]).abs();
                    abs += f64::from(d);
                    d / w[c].abs().max(floor)
                })
                .fold(0.0, f32::max)
        })
        .collect();
    errors.sort_by(f32::total_cmp);
    (errors, (abs / (got.len() * 4) as f64) as f32)
}

/// Mean, 99th and 99.9th percentile and worst of sorted errors.
fn summary(sorted: &[f32]) -> [f32; 4] {
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q) as usize];
    let mean = sorted.iter().map(|&e| f64::from(e)).sum::<f64>() / sorted.len() as f64;
    [mean as f32, at(0.99), at(0.999), at(1.0)]
}

/// Opens the page with `query` (`check=WxH`: the check frame; `frames=N`: the demo for
/// N frames) in Chromium, with or without WebGPU, and collects its reports until
/// `done`: the reports by name and `done`'s JSON, or the message of the first error
/// the page reports.
fn open_page(
    webgpu: bool,
    query: &str,
) -> Result<(HashMap<String, Vec<u8>>, serde_json::Value), String> {
    let dir = page_dir();
    let server =
        Server::start(&dir, 0).unwrap_or_else(|e| panic!("{e}; build the page with `{INSTALL}`"));
    let started = Instant::now();
    let browser = Browser::open(&server.url(query), webgpu);
    let mut reports = HashMap::new();
    loop {
        let left = Duration::from_secs(180).saturating_sub(started.elapsed());
        let Some(report) = server.next_report(left) else {
            drop(browser);
            panic!("the page reported nothing within 180 s");
        };
        match report.name.as_str() {
            "error" => return Err(String::from_utf8_lossy(&report.body).into_owned()),
            "done" => {
                let done = serde_json::from_slice(&report.body).expect("JSON");
                println!(
                    "page done {:.1} s after launch",
                    started.elapsed().as_secs_f64()
                );
                return Ok((reports, done));
            }
            name => {
                reports.insert(name.to_string(), report.body);
            }
        }
    }
}

/// [`open_page`] at [`SIZE`], failing with the page's message.
fn run_page(webgpu: bool) -> (HashMap<String, Vec<u8>>, serde_json::Value) {
    open_page(webgpu, &format!("check={}x{}", SIZE.0, SIZE.1))
        .unwrap_or_else(|e| panic!("the page failed: {e}"))
}

#[test]
fn a_page_error_reaches_the_test_with_its_message() {
    // A zero-sized image is refused by the wasm module with a typed error, which the
    // page reports as an uncaught rejection.
    let message = match open_page(true, "check=0x180") {
        Ok((_, done)) => panic!("the page accepted a 0 x 180 image: {done}"),
        Err(message) => message,
    };
    println!("the page reported: {message}");
    assert!(
        message.contains("Renderer.size") && message.contains("1..=8192"),
        "{message}"
    );
}

#[test]
fn the_page_renders_the_native_frame_in_headless_chromium() {
    // The native frame on lavapipe.
    let gpu = volfog_testkit::Gpu::shared();
    let (native_volume, native_image) = gpu
        .checked(|| {
            let mut renderer = Renderer::new(&gpu.device, SIZE, false).expect("the scene builds");
            let commands = renderer
                .frame(&gpu.device, &gpu.queue, &Params::default())
                .expect("a valid frame");
            gpu.queue.submit([commands]);
            let volume = pollster::block_on(read_rgba16f(
                &gpu.device,
                &gpu.queue,
                renderer.fog.integrated_texture(),
            ))
            .expect("readback");
            let image = pollster::block_on(read_rgba16f(&gpu.device, &gpu.queue, &renderer.color))
                .expect("readback");
            (volume, image)
        })
        .expect("no validation error natively");

    // The same frame in the browser.
    let (reports, done) = run_page(true);
    let volume = floats(&reports["integrated"]);
    let image = floats(&reports["image"]);
    assert_eq!(done["tier"], "webgpu", "the page ran another tier: {done}");
    println!(
        "browser WebGPU: {} ({:.0} ms for the frame and its readback); native: {}",
        done["adapter"],
        done["ms"].as_f64().unwrap_or(f64::NAN),
        gpu.describe()
    );

    // Integrated in-scattering and transmittance: fp16 storage rounds each value by
    // 2^-11; the two rasterizers, samplers and exp/pow implementations differ a little
    // more. The largest differences lie behind a pillar's edge, where the two
    // rasterizers put the farthest depth of a screen tile a slice apart, so depth
    // culling ends the column's scan one slice earlier in one of them.
    let (errors, abs) = relative_errors(&volume, &native_volume, 0.05);
    let [mean, p99, p999, worst] = summary(&errors);
    println!(
        "integrated volume, relative (floor 0.05) per froxel: mean {mean:.2e}, p99 {p99:.2e}, \
         p99.9 {p999:.2e}, worst {worst:.2e}; mean |d| {abs:.2e}"
    );
    let (errors, abs) = relative_errors(&image, &native_image, 0.05);
    let [imean, ip99, ip999, iworst] = summary(&errors);
    println!(
        "fogged image, relative (floor 0.05) per pixel: mean {imean:.2e}, p99 {ip99:.2e}, \
         p99.9 {ip999:.2e}, worst {iworst:.2e} (a silhouette pixel); mean |d| {abs:.2e}"
    );
    assert!(mean < 1.5e-3, "volume mean {mean:.2e} >= 1.5e-3");
    assert!(p999 < 5e-3, "volume p99.9 {p999:.2e} >= 5e-3");
    assert!(imean < 5e-3, "image mean {imean:.2e} >= 5e-3");
    assert!(ip99 < 2e-2, "image p99 {ip99:.2e} >= 2e-2");
}

#[test]
fn without_webgpu_the_webgl2_tier_draws_the_analytic_fog_of_the_cpu_mirror() {
    let (reports, done) = run_page(false);
    assert_eq!(done["tier"], "webgl2", "the page ran another tier: {done}");
    let image = floats(&reports["image"]);
    let scene = analytic_scene(&Params::default(), SIZE).expect("a valid scene");
    let pixels: Vec<(u32, u32)> = (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .collect();
    let want: Vec<[f32; 4]> = pixels
        .iter()
        .map(|&(x, y)| scene.pixel(x, y, SIZE).to_array())
        .collect();
    // The fog shapes the image: it hides part of what lies behind it and adds light.
    let (mut hidden, mut added, mut seen) = (0.0f64, 0.0f64, 0.0f64);
    for &(x, y) in &pixels {
        let (surface, fog) = scene.pixel_parts(x, y, SIZE);
        hidden += f64::from(1.0 - fog.w);
        added += f64::from(fog.truncate().element_sum());
        seen += f64::from((surface * fog.w).element_sum());
    }
    let n = pixels.len() as f64;
    println!(
        "the fog hides {:.1} % of the background and adds {:.1} % of the light seen",
        100.0 * hidden / n,
        100.0 * added / (added + seen)
    );
    assert!(hidden / n > 0.1 && added / (added + seen) > 0.1);
    println!(
        "browser WebGL2: {} ({:.0} ms to compile, draw and read back)",
        done["adapter"],
        done["ms"].as_f64().unwrap_or(f64::NAN)
    );
    // Both in f32: the GPU's exp, pow and sqrt against Rust's, through the sky's 64 x 16
    // sample quadrature and the fog's closed forms.
    let (errors, abs) = relative_errors(&image, &want, 0.05);
    let [mean, p99, p999, worst] = summary(&errors);
    println!(
        "WebGL2 image against the CPU mirror, relative (floor 0.05) per pixel: mean {mean:.2e}, \
         p99 {p99:.2e}, p99.9 {p999:.2e}, worst {worst:.2e}; mean |d| {abs:.2e}"
    );
    assert!(mean < 1e-5, "mean {mean:.2e} >= 1e-5");
    assert!(p999 < 1e-4, "p99.9 {p999:.2e} >= 1e-4");
}

#[test]
fn the_demo_animates_its_canvas_on_either_tier() {
    // SwiftShader runs both on the CPU: a dozen frames tell that the loop runs.
    for (webgpu, tier) in [(true, "webgpu"), (false, "webgl2")] {
        let (_, done) = open_page(webgpu, "frames=12")
            .unwrap_or_else(|e| panic!("the {tier} demo failed: {e}"));
        let number = |k: &str| done[k].as_f64().unwrap_or(f64::NAN);
        println!(
            "{tier} demo at {}: {:.0} ms per frame (mean of 11 intervals) on {}; canvas mean \
             {:.1}, deviation {:.1} (8-bit)",
            done["size"],
            number("ms"),
            done["adapter"],
            number("mean"),
            number("deviation")
        );
        assert_eq!(done["tier"], tier);
        assert!(number("ms") > 0.0, "{done}");
        // Neither black nor flat: the scene is drawn.
        let (mean, deviation) = (number("mean"), number("deviation"));
        assert!((20.0..235.0).contains(&mean) && deviation > 5.0, "{done}");
    }
}
