//! volfog in a browser. The scene ([`scene`]) and its frame ([`render`]) are plain wgpu
//! and run wherever wgpu does: on the page's WebGPU from wasm (the exports in `page`,
//! the page in `www/`) and natively, where the browser test renders the same frame on
//! lavapipe and compares it with the page's. Without WebGPU the page falls back to the
//! WebGL2 tier ([`analytic`]): the closed-form fog through the GLSL ES snippets. Built
//! and served by `cargo xtask web`.

pub mod analytic;
pub mod readback;
pub mod render;
pub mod scene;

#[cfg(not(target_arch = "wasm32"))]
pub mod serve;

#[cfg(target_arch = "wasm32")]
mod page;
