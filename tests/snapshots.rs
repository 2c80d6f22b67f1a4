//! Snapshots of every prebuilt (variant, entry point, target) translation and of the
//! binding manifest, under `snapshots/`. SPIR-V is stored as disassembly. Snapshot
//! files that no translation references fail the test, like
//! `cargo insta test --unreferenced=reject`.

use std::collections::BTreeSet;
use std::path::Path;

use rspirv::binary::Disassemble;
use volfog::shaders::{self, Target};

fn disassemble(words: &[u32]) -> String {
    let module = rspirv::dr::load_words(words).expect("naga's SPIR-V parses");
    module.disassemble()
}

#[test]
fn translations_and_manifest() {
    let snapshot_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("snapshots");
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path(&snapshot_dir);
    settings.set_prepend_module_to_snapshot(false);
    settings.set_omit_expression(true);
    let mut referenced = BTreeSet::new();
    settings.bind(|| {
        for v in shaders::variants() {
            for e in v.entries {
                for target in Target::ALL {
                    let name = format!(
                        "{}.{}.{}.{}",
                        v.name,
                        e.entry,
                        e.stage.short(),
                        target.extension()
                    );
                    let text = match e.text(target) {
                        Some(t) => t.to_string(),
                        None => disassemble(&e.spirv_words()),
                    };
                    insta::assert_snapshot!(name.clone(), text);
                    referenced.insert(format!("{name}.snap"));
                }
            }
        }
        let outputs: Vec<_> = shaders::variants().iter().map(|v| v.to_output()).collect();
        let manifest = volfog::export::manifest_json(&outputs, &Target::ALL);
        insta::assert_snapshot!("manifest.json", manifest);
        referenced.insert("manifest.json.snap".to_string());
    });
    let unreferenced: Vec<String> = std::fs::read_dir(&snapshot_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".snap") && !referenced.contains(n))
        .collect();
    assert!(
        unreferenced.is_empty(),
        "unreferenced snapshots: {unreferenced:?}"
    );
}
