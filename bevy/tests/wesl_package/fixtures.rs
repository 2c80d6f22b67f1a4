//! The package under test and what the tests run over: its modules as sources, the
//! naga_oil source of each module, the features each module sees and their
//! combinations.

use std::collections::{BTreeSet, HashMap};

use volfog_codegen::manifest::MODULES;
use volfog_codegen::wesl::{WeslModule, features, wesl_package};

/// WESL sources by module name, all in package `volfog`.
pub(crate) type Sources = HashMap<String, String>;

pub(crate) fn package() -> Vec<WeslModule> {
    wesl_package().unwrap_or_else(|e| panic!("{e}"))
}

pub(crate) fn sources(package: &[WeslModule]) -> Sources {
    package
        .iter()
        .map(|m| (m.name.to_string(), m.source.clone()))
        .collect()
}

/// The naga_oil source of a module.
pub(crate) fn naga_oil_source(name: &str) -> (&'static str, &'static str) {
    let module = MODULES
        .iter()
        .find(|m| m.import_path == format!("volfog::{name}"))
        .expect("a manifest module");
    (module.file, module.source)
}

/// The features of a module and of every module it imports, sorted.
pub(crate) fn all_features(package: &[WeslModule], name: &str) -> Vec<String> {
    let mut flags = BTreeSet::new();
    let mut todo = vec![name.to_string()];
    let mut seen = BTreeSet::new();
    while let Some(name) = todo.pop() {
        if !seen.insert(name.clone()) {
            continue;
        }
        let module = package.iter().find(|m| m.name == name).expect("a module");
        flags.extend(features(module));
        for line in module.source.lines() {
            if let Some(rest) = line.strip_prefix("import package::") {
                let end = rest
                    .find("::")
                    .or_else(|| rest.find(';'))
                    .expect("an import");
                todo.push(rest[..end].to_string());
            }
        }
    }
    flags.into_iter().collect()
}

/// Every subset of `flags` (the flags that are on), each sorted like `flags`.
pub(crate) fn combinations(flags: &[String]) -> Vec<Vec<String>> {
    (0..1usize << flags.len())
        .map(|bits| {
            flags
                .iter()
                .enumerate()
                .filter(|(i, _)| bits & (1 << i) != 0)
                .map(|(_, f)| f.clone())
                .collect()
        })
        .collect()
}

pub(crate) fn label(name: &str, on: &[String]) -> String {
    if on.is_empty() {
        format!("{name}@default")
    } else {
        format!("{name}@{}", on.join("+"))
    }
}
