//! What the page calls (wasm-bindgen exports): the animated demo in a canvas and the
//! browser test's fixed frame. Every failure reaches the page as a JS `Error` with its
//! message; WebGPU's uncaptured errors go to the page's `volfogError` handler.

use std::sync::Arc;

use wasm_bindgen::prelude::*;

use crate::analytic::analytic_scene;
use crate::readback::read_rgba16f;
use crate::render::{Display, Renderer};
use crate::scene::{Params, SLIDERS};

#[wasm_bindgen]
extern "C" {
    /// The page's error sink (`window.volfogError(message)`).
    #[wasm_bindgen(js_namespace = window, js_name = volfogError)]
    fn report_error(message: &str);
}

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

async fn device(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), JsError> {
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        })
        .await
        .map_err(|e| js_error(format!("no WebGPU adapter: {e}")))?;
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("volfog web"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
            ..Default::default()
        })
        .await
        .map_err(js_error)?;
    device.on_uncaptured_error(Arc::new(|e| report_error(&e.to_string())));
    Ok((adapter, device, queue))
}

fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::BROWSER_WEBGPU;
    wgpu::Instance::new(desc)
}

fn adapter_name(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    format!("{} ({:?})", info.name, info.backend)
}

/// Installs the panic hook that prints Rust panics to the console.
#[wasm_bindgen(start)]
pub fn init() {
    console_error_panic_hook::set_once();
}

/// The sliders as `[{name, min, max, value}]`, values at their defaults.
#[wasm_bindgen]
pub fn sliders() -> js_sys::Array {
    let d = Params::default();
    let values = [d.density, d.phase_g, d.sun_elevation];
    SLIDERS
        .iter()
        .zip(values)
        .map(|(s, v)| {
            let o = js_sys::Object::new();
            for (k, x) in [
                ("name", JsValue::from_str(s.name)),
                ("min", s.min.into()),
                ("max", s.max.into()),
                ("value", v.into()),
            ] {
                let _ = js_sys::Reflect::set(&o, &k.into(), &x);
            }
            JsValue::from(o)
        })
        .collect()
}

/// The animated demo: the scene with jittered, temporally reprojected fog in a canvas.
#[wasm_bindgen]
pub struct Demo {
    device: wgpu::Device,
    queue: wgpu::Queue,
    surface: wgpu::Surface<'static>,
    view_format: wgpu::TextureFormat,
    renderer: Renderer,
    display: Display,
    params: Params,
    adapter: String,
}

#[wasm_bindgen]
impl Demo {
    /// Starts the demo in `canvas` at its current size.
    pub async fn create(canvas: web_sys::HtmlCanvasElement) -> Result<Demo, JsError> {
        let size = (canvas.width().max(1), canvas.height().max(1));
        let instance = instance();
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
            .map_err(js_error)?;
        let (adapter, device, queue) = device(&instance, Some(&surface)).await?;
        let caps = surface.get_capabilities(&adapter);
        let format = *caps
            .formats
            .first()
            .ok_or_else(|| js_error("the canvas offers no format"))?;
        let view_format = format.add_srgb_suffix();
        surface.configure(
            &device,
            &wgpu::SurfaceConfiguration {
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                format,
                width: size.0,
                height: size.1,
                present_mode: wgpu::PresentMode::Fifo,
                desired_maximum_frame_latency: 2,
                alpha_mode: wgpu::CompositeAlphaMode::Opaque,
                view_formats: vec![view_format],
                color_space: wgpu::SurfaceColorSpace::Auto,
            },
        );
        let renderer = Renderer::new(&device, size, true).map_err(js_error)?;
        let display = Display::new(&device, &renderer, view_format);
        Ok(Demo {
            adapter: adapter_name(&adapter),
            device,
            queue,
            surface,
            view_format,
            renderer,
            display,
            params: Params::default(),
        })
    }

    /// The adapter's name and backend.
    pub fn adapter(&self) -> String {
        self.adapter.clone()
    }

    /// Sets slider `name` (see [`sliders`]); the value is clamped to its range.
    pub fn set(&mut self, name: &str, value: f32) -> Result<(), JsError> {
        match name {
            "density" => self.params.density = value,
            "phase_g" => self.params.phase_g = value,
            "sun_elevation" => self.params.sun_elevation = value,
            _ => return Err(js_error(format!("no slider named {name:?}"))),
        }
        self.params = self.params.clamped();
        Ok(())
    }

    /// Renders and presents one frame at `time` seconds.
    pub fn frame(&mut self, time: f32) -> Result<(), JsError> {
        self.params.time = time;
        let frame = self.surface.get_current_texture();
        let frame = match frame {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            other => return Err(js_error(format!("the canvas gave no texture: {other:?}"))),
        };
        let fog = self
            .renderer
            .frame(&self.device, &self.queue, &self.params)
            .map_err(js_error)?;
        let view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.display.record(&mut encoder, &view);
        self.queue.submit([fog, encoder.finish()]);
        self.queue.present(frame);
        Ok(())
    }
}

/// The browser test's frame: the scene with its default parameters at
/// `width` x `height`, no jitter and no history, read back. Returns `{adapter,
/// volume_size, integrated, image}` (the integrated fog volume and the fogged image
/// as rgba `Float32Array`s).
#[wasm_bindgen]
pub async fn check(width: u32, height: u32) -> Result<js_sys::Object, JsError> {
    let instance = instance();
    let (adapter, device, queue) = device(&instance, None).await?;
    let mut renderer = Renderer::new(&device, (width, height), false).map_err(js_error)?;
    let commands = renderer
        .frame(&device, &queue, &Params::default())
        .map_err(js_error)?;
    queue.submit([commands]);
    let integrated = read_rgba16f(&device, &queue, renderer.fog.integrated_texture())
        .await
        .map_err(js_error)?;
    let image = read_rgba16f(&device, &queue, &renderer.color)
        .await
        .map_err(js_error)?;
    let flat = |v: Vec<[f32; 4]>| js_sys::Float32Array::from(v.concat().as_slice());
    let size = renderer.fog.integrated_texture().size();
    let o = js_sys::Object::new();
    let volume_size = js_sys::Array::of3(
        &size.width.into(),
        &size.height.into(),
        &size.depth_or_array_layers.into(),
    );
    for (k, v) in [
        ("adapter", JsValue::from_str(&adapter_name(&adapter))),
        ("volume_size", volume_size.into()),
        ("integrated", flat(integrated).into()),
        ("image", flat(image).into()),
    ] {
        js_sys::Reflect::set(&o, &k.into(), &v).map_err(|_| js_error("Reflect.set"))?;
    }
    Ok(o)
}

/// The WebGL2 tier's uniform block (`Scene` in `webgl2.js`, std140) for the sliders'
/// values at `width` x `height` pixels.
#[wasm_bindgen]
pub fn analytic_block(
    width: u32,
    height: u32,
    density: f32,
    phase_g: f32,
    sun_elevation: f32,
) -> Result<js_sys::Uint8Array, JsError> {
    let params = Params {
        density,
        phase_g,
        sun_elevation,
        ..Params::default()
    };
    let scene = analytic_scene(&params, (width.max(1), height.max(1))).map_err(js_error)?;
    Ok(js_sys::Uint8Array::from(scene.to_std140().as_slice()))
}
