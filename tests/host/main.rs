//! The tests of what volfog hands to other compilers and engines: codegen errors, every
//! variant's translations (snapshots and independent validators), the export folder and
//! its manifest, the exports and the include snippets through independent compilers
//! (Slang, Mesa's OpenGL driver, Dawn/Tint, glslang, the Khronos validation layer) and
//! their numbers on lavapipe, the uniform layouts against naga, and the WGSL constants
//! against their Rust twins.

mod bind_groups;
mod codegen_errors;
mod compilers;
mod constants;
mod custom_density;
mod exports;
mod foreign_numbers;
mod guides;
mod layout;
mod snapshots;
mod snippet_hosts;
mod spirv_pipelines;
mod tools;

/// What the test modules share.
mod common {
    use std::path::{Path, PathBuf};
    use std::sync::OnceLock;

    use serde_json::Value;

    use volfog_codegen::export::{ExportRequest, export};
    use volfog_codegen::reflect::HlslSamplers;
    use volfog_codegen::translate::{VariantOutput, generate_variant};
    use volfog_codegen::{Target, manifest};

    /// Every variant of the manifest, translated to every target (once per process).
    pub fn variants() -> &'static [VariantOutput] {
        static ALL: OnceLock<Vec<VariantOutput>> = OnceLock::new();
        ALL.get_or_init(|| {
            manifest::variants()
                .iter()
                .map(|v| {
                    generate_variant(v, HlslSamplers::Classic)
                        .unwrap_or_else(|e| panic!("{}: {e}", v.name))
                })
                .collect()
        })
    }

    /// Every include snippet (once per process).
    pub fn snippets() -> &'static [volfog_codegen::snippets::Snippet] {
        static ALL: OnceLock<Vec<volfog_codegen::snippets::Snippet>> = OnceLock::new();
        ALL.get_or_init(|| volfog_codegen::snippets::all().expect("snippets generate"))
    }

    /// A fresh folder under the test target directory.
    pub fn scratch(name: &str) -> PathBuf {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    /// An export of every variant in every target (once per process).
    pub fn exported() -> &'static Path {
        static DIR: OnceLock<PathBuf> = OnceLock::new();
        DIR.get_or_init(|| {
            let out = scratch("export-all");
            export(&ExportRequest {
                out: out.clone(),
                targets: Target::ALL.to_vec(),
                variants: vec![],
                defines: vec![],
                hlsl_samplers: HlslSamplers::Classic,
                snippets: Some(vec![]),
                custom_density: None,
            })
            .expect("the export succeeds");
            out
        })
    }

    /// The manifest of [`exported`] (once per process).
    pub fn manifest() -> &'static Value {
        static MANIFEST: OnceLock<Value> = OnceLock::new();
        MANIFEST.get_or_init(|| {
            let text = std::fs::read_to_string(exported().join("manifest.json")).unwrap();
            serde_json::from_str(&text).unwrap()
        })
    }

    /// Every entry point of the manifest with its variant's name.
    pub fn entry_points() -> Vec<(&'static str, &'static Value)> {
        manifest()["variants"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|v| {
                let name = v["name"].as_str().unwrap();
                v["entry_points"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(move |e| (name, e))
            })
            .collect()
    }

    /// The vertex entry point the manifest pairs a fragment entry point with, and its
    /// variant's name.
    pub fn vertex_of(fragment: &Value) -> (&'static str, &'static Value) {
        let (variant, entry) = (&fragment["vertex"]["variant"], &fragment["vertex"]["entry"]);
        entry_points()
            .into_iter()
            .find(|(v, e)| *v == variant && &e["name"] == entry && e["stage"] == "vertex")
            .unwrap_or_else(|| panic!("no vertex entry point {variant}.{entry}"))
    }
}
