//! The tests that need no GPU: codegen errors, every variant's translations (snapshots
//! and independent validators), the export folder and its manifest, the uniform
//! layouts against naga, and the WGSL constants against their Rust twins.

mod bind_groups;
mod codegen_errors;
mod constants;
mod exports;
mod layout;
mod snapshots;
mod spirv_pipelines;

/// What the test modules share.
mod common {
    use std::path::{Path, PathBuf};
    use std::sync::OnceLock;

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
            })
            .expect("the export succeeds");
            out
        })
    }
}
