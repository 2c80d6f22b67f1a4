//! The memory floor of a pass: the textures its shader reads and writes, found in
//! its composed naga module (from the entry points through every function they call,
//! a texture passed as an argument followed back to its binding), the bytes those
//! textures hold for a configuration and dispatch (the live share of the volume where
//! the pass culls), and the time moving those bytes once takes at a stated bandwidth.
//!
//! It is a floor, not a prediction: each texture's bytes count once per direction, as
//! if the caches caught every re-read of a texel (a trilinear sample's eight texels,
//! the scan's neighbouring slices); storage and uniform buffers (lights, local
//! volumes, uniforms: kilobytes) are left out, and so is arithmetic. A pass far above
//! its floor on a GPU is bound by its arithmetic or its latency, not by memory.

use std::collections::BTreeMap;

use naga::{Block, Expression, Function, GlobalVariable, Handle, Module, Statement};
use serde::Serialize;
use volfog::pipeline::FogConfig;

/// How a shader touches one texture binding: the places in the code that read it
/// (loads and samples) and write it (stores), each call of a function counting its
/// places again, a loop's body once.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct TextureUse {
    /// The binding's name in the WGSL.
    pub name: String,
    /// Places that load or sample it.
    pub read_sites: u32,
    /// Places that store to it.
    pub write_sites: u32,
}

/// The textures entry point `entry` of `module` reads or writes, by binding name.
pub fn texture_uses(module: &Module, entry: &str) -> Vec<TextureUse> {
    let mut uses: BTreeMap<Handle<GlobalVariable>, (u32, u32)> = BTreeMap::new();
    for e in module.entry_points.iter().filter(|e| e.name == entry) {
        walk(module, &e.function, &[], &mut uses);
    }
    uses.into_iter()
        .map(|(g, (read_sites, write_sites))| {
            let name = module.global_variables[g].name.clone().unwrap_or_default();
            let name = volfog_codegen::names::undecorate(&name).map_or(name, |(item, _)| item);
            TextureUse {
                name,
                read_sites,
                write_sites,
            }
        })
        .collect()
}

/// Adds the texture accesses of `function` (its texture arguments bound to `args`)
/// and of every function it calls.
fn walk(
    module: &Module,
    function: &Function,
    args: &[Option<Handle<GlobalVariable>>],
    uses: &mut BTreeMap<Handle<GlobalVariable>, (u32, u32)>,
) {
    let resolve = |e: Handle<Expression>| match function.expressions[e] {
        Expression::GlobalVariable(g) => Some(g),
        Expression::FunctionArgument(i) => args.get(i as usize).copied().flatten(),
        _ => None,
    };
    for (_, expression) in function.expressions.iter() {
        if let Expression::ImageLoad { image, .. } | Expression::ImageSample { image, .. } =
            expression
            && let Some(g) = resolve(*image)
        {
            uses.entry(g).or_default().0 += 1;
        }
    }
    let mut calls = Vec::new();
    statements(&function.body, &mut |s| match s {
        Statement::ImageStore { image, .. } => {
            if let Some(g) = resolve(*image) {
                uses.entry(g).or_default().1 += 1;
            }
        }
        Statement::Call {
            function: callee,
            arguments,
            ..
        } => calls.push((
            *callee,
            arguments.iter().map(|a| resolve(*a)).collect::<Vec<_>>(),
        )),
        _ => {}
    });
    for (callee, bound) in calls {
        walk(module, &module.functions[callee], &bound, uses);
    }
}

/// Visits every statement of a block and of the blocks nested in it.
fn statements(block: &Block, visit: &mut dyn FnMut(&Statement)) {
    for s in block.iter() {
        visit(s);
        match s {
            Statement::Block(b) => statements(b, visit),
            Statement::If { accept, reject, .. } => {
                statements(accept, visit);
                statements(reject, visit);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                statements(body, visit);
                statements(continuing, visit);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    statements(&c.body, visit);
                }
            }
            _ => {}
        }
    }
}

/// One texture's traffic in a pass.
#[derive(Debug, Clone, Serialize)]
pub struct TextureTraffic {
    /// How the shader touches it.
    #[serde(flatten)]
    pub uses: TextureUse,
    /// The bytes it holds that the dispatch covers (read once if read, written once
    /// if written).
    pub bytes: u64,
}

/// The bytes a pass moves at its floor.
#[derive(Debug, Clone, Serialize)]
pub struct Traffic {
    /// The textures it reads and writes.
    pub textures: Vec<TextureTraffic>,
    /// The render target's bytes read by blending (render passes).
    pub target_read_bytes: u64,
    /// The render target's bytes written (render passes).
    pub target_written_bytes: u64,
    /// Bytes read, each texture once.
    pub bytes_read: u64,
    /// Bytes written, each texture once.
    pub bytes_written: u64,
}

impl Traffic {
    /// Bytes read and written.
    pub fn bytes(&self) -> u64 {
        self.bytes_read + self.bytes_written
    }

    /// Moving them once at `bytes_per_second` (ms).
    pub fn floor_ms(&self, bytes_per_second: f64) -> f64 {
        self.bytes() as f64 / bytes_per_second * 1e3
    }
}

/// The traffic of entry points `entries` of `module`: each texture they touch sized
/// by `bytes_of(binding name)`, plus a render target's bytes (read by blending,
/// written).
pub fn traffic(
    module: &Module,
    entries: &[&str],
    bytes_of: &dyn Fn(&str) -> u64,
    target: (u64, u64),
) -> Traffic {
    let mut merged: BTreeMap<String, TextureUse> = BTreeMap::new();
    for entry in entries {
        for u in texture_uses(module, entry) {
            let slot = merged.entry(u.name.clone()).or_insert_with(|| TextureUse {
                name: u.name.clone(),
                ..TextureUse::default()
            });
            slot.read_sites += u.read_sites;
            slot.write_sites += u.write_sites;
        }
    }
    let textures: Vec<TextureTraffic> = merged
        .into_values()
        .map(|uses| TextureTraffic {
            bytes: bytes_of(&uses.name),
            uses,
        })
        .collect();
    let sum = |pick: &dyn Fn(&TextureUse) -> bool| -> u64 {
        textures
            .iter()
            .filter(|t| pick(&t.uses))
            .map(|t| t.bytes)
            .sum()
    };
    Traffic {
        bytes_read: sum(&|u| u.read_sites > 0) + target.0,
        bytes_written: sum(&|u| u.write_sites > 0) + target.1,
        target_read_bytes: target.0,
        target_written_bytes: target.1,
        textures,
    }
}

/// A floor pass's shader: the plainest pass that moves a fog pass's bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FloorShader {
    /// Its path in the repository.
    pub path: &'static str,
    /// Its WGSL (it may import volfog's modules).
    pub source: &'static str,
    /// The entry point that does the work.
    pub entry: &'static str,
}

/// A constant written to every texel of a volume, with inject's dispatch (inject's
/// floor).
pub const WRITE: FloorShader = FloorShader {
    path: "cost/src/shaders/write.wgsl",
    source: include_str!("shaders/write.wgsl"),
    entry: "write_volume",
};
/// A plain copy of a volume with the scan's access pattern (the scan's floor).
pub const COPY: FloorShader = FloorShader {
    path: "cost/src/shaders/copy.wgsl",
    source: include_str!("shaders/copy.wgsl"),
    entry: "copy_volume",
};
/// A fullscreen blit of a texture of the target's size (the apply's floor).
pub const BLIT: FloorShader = FloorShader {
    path: "cost/src/shaders/blit.wgsl",
    source: include_str!("shaders/blit.wgsl"),
    entry: "blit_fs",
};

/// Composes WGSL that may import volfog's modules (`#import volfog::...`) with
/// naga_oil shader defs into a validated naga module; the error is naga_oil's report.
pub fn compose(
    source: &str,
    path: &str,
    defs: &[(&str, naga_oil::compose::ShaderDefValue)],
) -> Result<Module, String> {
    use naga_oil::compose::{Composer, NagaModuleDescriptor};
    let mut composer = Composer::default();
    volfog::shaders::add_to_composer(&mut composer).map_err(|e| e.to_string())?;
    let shader_defs = defs.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path: path,
            shader_defs,
            ..Default::default()
        })
        .map_err(|e| e.emit_to_string(&composer))
}

/// What the froxel pipeline's textures hold for a configuration and a screen, by the
/// names their bindings have in the passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sizes {
    /// One volume (rgba16float), bytes.
    pub volume: u64,
    /// The share of the volume the culling passes cover.
    pub live_fraction: f64,
    /// The live-slice texture (r32uint per column).
    pub live: u64,
    /// The filtered ESM (r32float, one layer per cascade).
    pub esm: u64,
    /// The cascaded shadow map the ESM is downsampled from (Depth32Float, 4x the
    /// ESM's resolution per side).
    pub shadow_map: u64,
    /// The baked noise texture.
    pub noise: u64,
    /// The screen's depth buffer (Depth32Float).
    pub depth: u64,
    /// An rgba16float colour target of the screen.
    pub screen: u64,
}

impl Sizes {
    /// The sizes for `config` behind a `screen` (width, height), where the culling
    /// passes cover `live_fraction` of the volume.
    pub fn new(config: &FogConfig, screen: (u32, u32), live_fraction: f64) -> Self {
        let v = config.volume_size;
        let pixels = u64::from(screen.0) * u64::from(screen.1);
        let esm_texels = u64::from(config.esm_resolution).pow(2) * u64::from(config.cascades);
        Self {
            volume: u64::from(v.x) * u64::from(v.y) * u64::from(v.z) * 8,
            live_fraction,
            live: u64::from(v.x) * u64::from(v.y) * 4,
            esm: esm_texels * 4,
            shadow_map: esm_texels * 16 * 4,
            noise: u64::from(volfog::cpu::noise::NOISE_TEXTURE_SIZE).pow(3) * 8,
            depth: pixels * 4,
            screen: pixels * 8,
        }
    }

    /// The bytes of binding `name` a pass's dispatch covers (`culled`: it runs over
    /// the live blocks only); 0 for a binding this model does not size.
    pub fn of(&self, name: &str, culled: bool) -> u64 {
        let share = |bytes: u64| {
            if culled {
                (bytes as f64 * self.live_fraction).round() as u64
            } else {
                bytes
            }
        };
        match name {
            "scattering" | "integrated" | "current" | "history" | "stabilised" | "destination"
            | "fog_integrated" => share(self.volume),
            "source" if !culled => self.volume,
            "live_slices" | "history_live_slices" => self.live,
            "esm_array" | "esm_out" | "unfiltered" | "filtered" => self.esm,
            "shadow_map" => self.shadow_map,
            "noise_texture" => self.noise,
            "scene_depth" => self.depth,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_texture_passed_to_a_function_counts_at_its_binding() {
        let module = naga::front::wgsl::parse_str(
            "
            @group(0) @binding(0) var source: texture_2d<f32>;
            @group(0) @binding(1) var dest: texture_storage_2d<rgba16float, write>;
            @group(0) @binding(2) var unused: texture_2d<f32>;
            fn fetch(t: texture_2d<f32>, p: vec2<i32>) -> vec4<f32> {
                return textureLoad(t, p, 0);
            }
            @compute @workgroup_size(8, 8)
            fn main(@builtin(global_invocation_id) id: vec3<u32>) {
                let p = vec2<i32>(id.xy);
                let v = fetch(source, p) + fetch(source, p + 1);
                textureStore(dest, p, v);
            }",
        )
        .unwrap();
        let uses = texture_uses(&module, "main");
        assert_eq!(
            uses,
            [
                TextureUse {
                    name: "source".into(),
                    read_sites: 2,
                    write_sites: 0
                },
                TextureUse {
                    name: "dest".into(),
                    read_sites: 0,
                    write_sites: 1
                },
            ]
        );
        let t = traffic(
            &module,
            &["main"],
            &|n| if n == "source" { 100 } else { 40 },
            (5, 7),
        );
        assert_eq!((t.bytes_read, t.bytes_written), (105, 47));
        assert_eq!(t.floor_ms(152.0e3), 1.0);
    }

    #[test]
    fn sizes_of_the_default_configuration() {
        let config = FogConfig::default();
        let s = Sizes::new(&config, (1920, 1080), 0.5);
        assert_eq!(s.of("integrated", false), 160 * 90 * 128 * 8);
        assert_eq!(s.of("integrated", true), 160 * 90 * 128 * 4);
        assert_eq!(s.of("filtered", false), 256 * 256 * 4 * 4);
        assert_eq!(s.of("shadow_map", false), 1024 * 1024 * 4 * 4);
        assert_eq!(s.of("scene_depth", false), 1920 * 1080 * 4);
        assert_eq!(s.of("lights", false), 0);
    }
}
