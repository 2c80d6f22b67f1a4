//! The package as a whole: one module per manifest module, its features the flags of
//! the naga_oil conditionals, and the imports its header comments document exist.

use std::collections::{BTreeSet, HashMap};

use volfog_codegen::manifest::MODULES;
use volfog_codegen::wesl::{features, translate};

use crate::compile::compile_validated;
use crate::fixtures::{all_features, combinations, naga_oil_source, package, sources};

#[test]
fn package_mirrors_the_manifest() {
    let package = package();
    let names: Vec<&str> = package.iter().map(|m| m.name).collect();
    let stems: Vec<&str> = MODULES
        .iter()
        .map(|m| m.import_path.strip_prefix("volfog::").expect("volfog path"))
        .collect();
    assert_eq!(
        names, stems,
        "one WESL module per manifest module, in order"
    );
    for module in &package {
        let (file, source) = naga_oil_source(module.name);
        assert!(
            !module
                .source
                .lines()
                .any(|l| l.trim_start().starts_with('#')),
            "{file}: a naga_oil directive is left in the WESL module"
        );
        assert!(
            !module.source.contains("#import") && !module.source.contains("#{"),
            "{file}: `#import` or `#{{...}}` is left in the WESL module"
        );
        // The features are exactly the flags naga_oil's conditionals test.
        let flags: BTreeSet<String> = source
            .lines()
            .filter_map(|l| {
                let l = l.trim();
                l.strip_prefix("#ifdef ")
                    .or_else(|| l.strip_prefix("#ifndef "))
                    .map(|f| f.trim().to_string())
            })
            .collect();
        assert_eq!(
            features(module),
            flags.into_iter().collect::<Vec<_>>(),
            "{file}: the flags of its `@if`s"
        );
        assert_eq!(
            translate(file, source).expect("translates"),
            module.source,
            "{file}: the translation is deterministic"
        );
    }
}

#[test]
fn documented_imports_name_existing_items() {
    // The `Use:` lines of the header comments, rewritten to `import volfog::...;`.
    let package = package();
    let modules = sources(&package);
    let mut declared: HashMap<&str, BTreeSet<String>> = HashMap::new();
    for module in &package {
        let all = all_features(&package, module.name);
        let names = declared.entry(module.name).or_default();
        for on in combinations(&all) {
            names.extend(compile_validated(&modules, module.name, &on, &all).own);
        }
    }
    let mut checked = 0;
    for module in &package {
        let comments: String = module
            .source
            .lines()
            .filter_map(|l| l.trim_start().strip_prefix("//"))
            .collect::<Vec<_>>()
            .join("\n");
        for (at, _) in comments.match_indices("import volfog::") {
            let statement = &comments[at + "import volfog::".len()..];
            let end = statement
                .find(';')
                .unwrap_or_else(|| panic!("{}: unterminated `import` in a comment", module.name));
            let path: String = statement[..end]
                .chars()
                .filter(|c| !c.is_whitespace())
                .collect();
            let (target, items) = match path.split_once("::") {
                Some((target, rest)) => {
                    let list = rest.trim_start_matches('{').trim_end_matches('}');
                    (
                        target.to_string(),
                        list.split(',').map(str::to_string).collect(),
                    )
                }
                None => (path.clone(), Vec::new()),
            };
            let names = declared.get(target.as_str()).unwrap_or_else(|| {
                panic!(
                    "{}: `import volfog::{path}`: no module {target}",
                    module.name
                )
            });
            for item in items.iter().filter(|i| *i != "...") {
                assert!(
                    names.contains(item),
                    "{}: `import volfog::{path}`: {target} has no `{item}`",
                    module.name
                );
                checked += 1;
            }
            checked += usize::from(items.is_empty());
        }
    }
    assert!(
        checked > MODULES.len(),
        "the headers document their imports"
    );
}
