//! Snapshots a reviewer reads, under `snapshots/<pass>/`:
//! - the default variant of every pass in WGSL, GLSL, HLSL and MSL, one file per
//!   (entry point, target);
//! - for every define of every axis, the variant with that define as a unified diff
//!   against the default (`….diff.snap`), so a define's effect is read directly and a
//!   change to shared code touches only the default's files;
//! - `spirv.snap`: the SHA-256 of each of those entry points' SPIR-V (the binary is
//!   checked by the validators in the export tests, not read as disassembly);
//! - `manifest.snap`: the manifest entries of those variants; `snapshots/manifest.snap`
//!   holds the manifest's conventions and targets;
//! - `snapshots/snippets/`: the include snippets (`volfog_all`, every definition once)
//!   in each language, and `snapshots/volfog_layout.h.snap` the C/C++ layout header;
//! - `snapshots/wesl/`: every module of the WESL package (`volfog_codegen::wesl`, what
//!   Bevy shaders import), as generated.
//!
//! naga names the temporaries it bakes after their expression index (`_e102`), so one
//! added expression renumbers every later one; in the snapshots each is renamed after
//! its defining expression instead (`_e` and four hex digits of a hash of the text to
//! the right of its `=`), so a diff shows the lines that changed. The exported files
//! keep naga's names.
//!
//! Every other variant is composed, validated and translated by the export tests.
//! Snapshot files that no test references fail the test, like
//! `cargo insta test --unreferenced=reject`.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use volfog_codegen::Target;
use volfog_codegen::export::manifest_value;
use volfog_codegen::manifest::{self, PASSES};
use volfog_codegen::reflect::HlslSamplers;
use volfog_codegen::translate::VariantOutput;

/// The text targets that are snapshotted.
const TEXT_TARGETS: [Target; 4] = [Target::Wgsl, Target::Glsl, Target::Hlsl, Target::Msl];

/// The default variant of a pass and, per choice of its axes (a define, or the defines
/// of an `Axis::Together`), the variant with it.
fn snapshotted(pass: &str) -> (&'static VariantOutput, Vec<&'static VariantOutput>) {
    let find = |name: &str| {
        crate::common::variants()
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("variant {name}"))
    };
    let p = manifest::pass(pass).unwrap();
    let axis_variants = p
        .axes
        .iter()
        .flat_map(|a| a.choices())
        .map(|choice| find(&manifest::variant_name(pass, &choice)))
        .collect();
    (find(&manifest::variant_name(pass, &[])), axis_variants)
}

fn with_snapshot_path<T>(dir: &Path, f: impl FnOnce() -> T) -> T {
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path(dir);
    settings.set_prepend_module_to_snapshot(false);
    settings.set_omit_expression(true);
    settings.bind(f)
}

/// Whether `bytes[i..]` starts a `_e<digits>` token (not inside a longer identifier).
fn temporary_at(line: &str, i: usize) -> Option<usize> {
    let bytes = line.as_bytes();
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    if !line[i..].starts_with("_e") || (i > 0 && ident(bytes[i - 1])) {
        return None;
    }
    let digits = bytes[i + 2..]
        .iter()
        .take_while(|b| b.is_ascii_digit())
        .count();
    let end = i + 2 + digits;
    (digits > 0 && (end == bytes.len() || !ident(bytes[end]))).then_some(end)
}

/// Replaces every `_e<digits>` token of `line` through `map`.
fn rename_temporaries(line: &str, map: &std::collections::HashMap<String, String>) -> String {
    let mut out = String::with_capacity(line.len());
    let mut i = 0;
    while i < line.len() {
        if let Some(end) = temporary_at(line, i) {
            let token = &line[i..end];
            out.push_str(map.get(token).map_or(token, String::as_str));
            i = end;
        } else {
            let c = line[i..].chars().next().unwrap();
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

/// naga's numbered temporaries renamed after their defining expressions.
fn stable_temporaries(text: &str) -> String {
    use std::collections::HashMap;
    let mut map: HashMap<String, String> = HashMap::new();
    let mut taken: HashMap<String, usize> = HashMap::new();
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        if let Some(eq) = line.find(" = ") {
            let left = line[..eq].trim_end();
            let start = left
                .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .map_or(0, |p| p + 1);
            if temporary_at(left, start) == Some(left.len()) {
                let rhs = rename_temporaries(&line[eq + 3..], &map);
                let hash = Sha256::digest(rhs.trim().as_bytes());
                let base = format!("_e{:02x}{:02x}", hash[0], hash[1]);
                let n = taken.entry(base.clone()).or_insert(0);
                *n += 1;
                let name = if *n == 1 { base } else { format!("{base}_{n}") };
                map.insert(left[start..].to_string(), name);
            }
        }
        out.push_str(&rename_temporaries(line, &map));
        out.push('\n');
    }
    out
}

fn unified_diff(old: &str, new: &str, old_name: &str, new_name: &str) -> String {
    similar::TextDiff::from_lines(old, new)
        .unified_diff()
        .context_radius(3)
        .header(old_name, new_name)
        .to_string()
}

#[test]
fn translations_and_manifest() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("snapshots");
    let mut referenced: BTreeSet<PathBuf> = BTreeSet::new();
    for pass in PASSES {
        let dir = root.join(pass.name);
        let (default, axis_variants) = snapshotted(pass.name);
        let mut digests = String::new();
        with_snapshot_path(&dir, || {
            for (i, entry) in default.entries.iter().enumerate() {
                for target in TEXT_TARGETS {
                    let name = entry.file_name(&default.name, target);
                    let text = stable_temporaries(&String::from_utf8(entry.bytes(target)).unwrap());
                    insta::assert_snapshot!(name.clone(), text);
                    referenced.insert(dir.join(format!("{name}.snap")));
                    for v in &axis_variants {
                        let variant_entry = &v.entries[i];
                        assert_eq!(variant_entry.entry, entry.entry);
                        let other = stable_temporaries(
                            &String::from_utf8(variant_entry.bytes(target)).unwrap(),
                        );
                        let diff_name =
                            format!("{}.diff", variant_entry.file_name(&v.name, target));
                        let diff = unified_diff(
                            &text,
                            &other,
                            &name,
                            &variant_entry.file_name(&v.name, target),
                        );
                        insta::assert_snapshot!(diff_name.clone(), diff);
                        referenced.insert(dir.join(format!("{diff_name}.snap")));
                    }
                }
            }
            for v in std::iter::once(&default).chain(&axis_variants) {
                for entry in &v.entries {
                    let hash = Sha256::digest(entry.bytes(Target::Spirv));
                    let hex: String = hash.iter().map(|b| format!("{b:02x}")).collect();
                    writeln!(
                        digests,
                        "{}  sha256 {hex}  {} words",
                        entry.file_name(&v.name, Target::Spirv),
                        entry.spirv.len()
                    )
                    .unwrap();
                }
            }
            insta::assert_snapshot!("spirv", digests);
            referenced.insert(dir.join("spirv.snap"));
            let variants: Vec<VariantOutput> = std::iter::once(default)
                .chain(axis_variants.iter().copied())
                .cloned()
                .collect();
            let manifest = manifest_value(&variants, &[], &Target::ALL, HlslSamplers::Classic);
            insta::assert_snapshot!(
                "manifest",
                serde_json::to_string_pretty(&manifest["variants"]).unwrap()
            );
            referenced.insert(dir.join("manifest.snap"));
        });
    }
    with_snapshot_path(&root, || {
        let mut manifest = manifest_value(&[], &[], &Target::ALL, HlslSamplers::Classic);
        manifest.as_object_mut().unwrap().remove("variants");
        insta::assert_snapshot!("manifest", serde_json::to_string_pretty(&manifest).unwrap());
        let header = volfog_codegen::c_header::c_header(
            &volfog_codegen::export::header_structs(
                crate::common::variants(),
                crate::common::snippets(),
            )
            .unwrap(),
        )
        .unwrap();
        insta::assert_snapshot!("volfog_layout.h", header);
    });
    referenced.insert(root.join("manifest.snap"));
    referenced.insert(root.join("volfog_layout.h.snap"));
    // The snippets, every definition once (`volfog_all`), in each language.
    let snippet_dir = root.join("snippets");
    let all = crate::common::snippets()
        .iter()
        .find(|s| s.name == volfog_codegen::snippets::ALL_SNIPPETS)
        .unwrap();
    with_snapshot_path(&snippet_dir, || {
        for language in volfog_codegen::snippets::SnippetLanguage::ALL {
            let name = all.file_name(language);
            insta::assert_snapshot!(name.clone(), stable_temporaries(all.text(language)));
            referenced.insert(snippet_dir.join(format!("{name}.snap")));
        }
    });
    // The WESL package, one module per file.
    let wesl_dir = root.join("wesl");
    with_snapshot_path(&wesl_dir, || {
        for module in volfog_codegen::wesl::wesl_package().unwrap() {
            let name = format!("{}.wesl", module.name);
            insta::assert_snapshot!(name.clone(), module.source);
            referenced.insert(wesl_dir.join(format!("{name}.snap")));
        }
    });

    let mut on_disk = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|x| x == "snap") {
                on_disk.push(path);
            }
        }
    }
    let unreferenced: Vec<&PathBuf> = on_disk
        .iter()
        .filter(|p| !referenced.contains(*p))
        .collect();
    assert!(
        unreferenced.is_empty(),
        "unreferenced snapshots: {unreferenced:?}"
    );
}
