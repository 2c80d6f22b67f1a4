//! The WESL compilation compared item by item with the naga_oil composition of the same
//! module under the same defines, so a misplaced `@if` fails.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog_codegen::names::undecorate;
use wesl::Mangler;

use crate::compile::{Compiled, compile_validated, validate};
use crate::fixtures::{
    Sources, all_features, combinations, label, naga_oil_source, package, sources,
};
use crate::group_value;

/// naga_oil's composition of a source as the top-level module, under the same flags
/// (the fog groups as the integer defines `VOLFOG_FOG_GROUP=3` and
/// `VOLFOG_STEREO_FOG_GROUP=2`).
fn compose(
    composer: &mut Composer,
    file: &str,
    source: &str,
    on: &[String],
    what: &str,
) -> naga::Module {
    let shader_defs = on
        .iter()
        .map(|flag| {
            let value = group_value(flag).map_or(ShaderDefValue::Bool(true), ShaderDefValue::UInt);
            (flag.clone(), value)
        })
        .collect();
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path: file,
            shader_defs,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(composer)));
    validate(&module, what);
    module
}

/// Renames every named item of a module to `base(name)`.
fn rename(module: &mut naga::Module, base: &dyn Fn(&str) -> String) {
    let types: Vec<_> = module.types.iter().map(|(h, t)| (h, t.clone())).collect();
    for (h, t) in types {
        if let Some(name) = t.name.as_deref().filter(|n| base(n) != *n) {
            module.types.replace(
                h,
                naga::Type {
                    name: Some(base(name)),
                    inner: t.inner.clone(),
                },
            );
        }
    }
    for (_, c) in module.constants.iter_mut() {
        c.name = c.name.as_deref().map(base);
    }
    for (_, o) in module.overrides.iter_mut() {
        o.name = o.name.as_deref().map(base);
    }
    for (_, g) in module.global_variables.iter_mut() {
        g.name = g.name.as_deref().map(base);
    }
    for (_, f) in module.functions.iter_mut() {
        f.name = f.name.as_deref().map(base);
    }
}

/// Makes naga's generated names independent of the rest of the module: naga names
/// unnamed expressions by arena index (`_e12`) and makes every name unique in the
/// module with a suffix (`ndc_1`, `h0_` for a name ending in a digit); here an item's
/// first `_e` name is `_e0`, the next `_e1`, and `_<digits>` and `_` suffixes are
/// dropped.
fn normalize(item: &str) -> String {
    let mut out = String::new();
    let mut expressions: HashMap<String, usize> = HashMap::new();
    let chars: Vec<char> = item.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let is_expression = word.len() > 2
                && word.starts_with("_e")
                && word[2..].chars().all(|c| c.is_ascii_digit());
            if is_expression {
                let next = expressions.len();
                let n = *expressions.entry(word).or_insert(next);
                out.push_str(&format!("_e{n}"));
            } else {
                let mut base = word.as_str();
                while let Some((stem, n)) = base.rsplit_once('_')
                    && !stem.is_empty()
                    && n.chars().all(|c| c.is_ascii_digit())
                {
                    base = stem;
                }
                out.push_str(base);
            }
        } else if c.is_ascii_digit() {
            // A number with its suffix (`1f`, `0.5f`, `1e-3`), copied as is.
            while i < chars.len()
                && (chars[i].is_alphanumeric() || chars[i] == '.' || chars[i] == '_')
            {
                out.push(chars[i]);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The name a WGSL declaration declares.
fn declared_name(decl: &str) -> Option<String> {
    let words: Vec<&str> = decl
        .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == '<' || c == '>'))
        .filter(|w| !w.is_empty())
        .collect();
    let at = words.iter().position(|w| {
        ["fn", "struct", "const", "override", "alias"].contains(w) || w.starts_with("var")
    })?;
    words.get(at + 1).map(|w| w.to_string())
}

/// A module's own items (functions with their bodies, structs with their members,
/// constants, global variables with their group and binding) as naga writes them in
/// WGSL, by name: every item is first renamed to `base(name)`, and only items whose
/// name is then in `own` count.
fn items(
    mut module: naga::Module,
    base: &dyn Fn(&str) -> String,
    own: &BTreeSet<String>,
    what: &str,
) -> BTreeMap<String, String> {
    rename(&mut module, base);
    let info = validate(&module, what);
    let text =
        naga::back::wgsl::write_string(&module, &info, naga::back::wgsl::WriterFlags::empty())
            .unwrap_or_else(|e| panic!("{what}: naga cannot write WGSL: {e}"));
    // naga starts every declaration at column 0; a global's attributes come on the
    // line before it.
    let mut chunks: Vec<String> = Vec::new();
    let mut attributes = String::new();
    for line in text.lines().filter(|l| !l.is_empty()) {
        let starts = !line.starts_with(char::is_whitespace) && !line.starts_with('}');
        if starts && line.starts_with('@') && declared_name(line).is_none() {
            attributes.push_str(line);
            attributes.push('\n');
        } else if starts {
            chunks.push(std::mem::take(&mut attributes) + line + "\n");
        } else if let Some(last) = chunks.last_mut() {
            last.push_str(line);
            last.push('\n');
        }
    }
    let mut out = BTreeMap::new();
    for chunk in chunks {
        let name = declared_name(&chunk).unwrap_or_else(|| panic!("{what}: no name in\n{chunk}"));
        if own.contains(&name) {
            out.insert(name, normalize(&chunk));
        }
    }
    out
}

/// The WESL compilation's own items (imported names unmangled).
fn wesl_items(compiled: Compiled, what: &str) -> BTreeMap<String, String> {
    let Compiled { module, own } = compiled;
    let base = |name: &str| {
        if own.contains(name) {
            name.to_string()
        } else {
            wesl::mangler::EscapeMangler
                .unmangle(name)
                .map_or_else(|| name.to_string(), |(_, item)| item)
        }
    };
    items(module, &base, &own, what)
}

/// The naga_oil composition's own items (the names naga_oil does not decorate).
fn naga_oil_items(module: naga::Module, what: &str) -> BTreeMap<String, String> {
    let own: BTreeSet<String> = module
        .types
        .iter()
        .filter_map(|(_, t)| t.name.clone())
        .chain(module.constants.iter().filter_map(|(_, c)| c.name.clone()))
        .chain(module.overrides.iter().filter_map(|(_, o)| o.name.clone()))
        .chain(
            module
                .global_variables
                .iter()
                .filter_map(|(_, g)| g.name.clone()),
        )
        .chain(module.functions.iter().filter_map(|(_, f)| f.name.clone()))
        .filter(|n| undecorate(n).is_none())
        .collect();
    let base = |name: &str| undecorate(name).map_or_else(|| name.to_string(), |(item, _)| item);
    items(module, &base, &own, what)
}

/// `Err` listing every item that differs between the two compositions.
fn compare(
    wesl: &BTreeMap<String, String>,
    naga_oil: &BTreeMap<String, String>,
    what: &str,
) -> Result<usize, String> {
    let names: BTreeSet<&String> = wesl.keys().chain(naga_oil.keys()).collect();
    let mut report = String::new();
    for name in names {
        let (a, b) = (wesl.get(name), naga_oil.get(name));
        if a != b {
            report.push_str(&format!(
                "--- {what}: `{name}`\nWESL:\n{}\nnaga_oil:\n{}\n",
                a.map_or("(missing)", String::as_str),
                b.map_or("(missing)", String::as_str),
            ));
        }
    }
    if report.is_empty() {
        Ok(wesl.len())
    } else {
        Err(report)
    }
}

/// Compares module `name` of `modules` (WESL) with the naga_oil source under every
/// combination of its features; returns (combinations, items compared) or the report
/// of the differences.
pub(crate) fn check_equivalence(
    composer: &mut Composer,
    modules: &Sources,
    name: &str,
    all: &[String],
    (file, source): (&str, &str),
) -> Result<(usize, usize), String> {
    let mut counts = (0, 0);
    let mut report = String::new();
    for on in combinations(all) {
        let what = label(name, &on);
        let wesl = wesl_items(compile_validated(modules, name, &on, all), &what);
        let naga_oil = naga_oil_items(compose(composer, file, source, &on, &what), &what);
        match compare(&wesl, &naga_oil, &what) {
            Ok(n) => {
                counts.0 += 1;
                counts.1 += n;
            }
            Err(diff) => report.push_str(&diff),
        }
    }
    if report.is_empty() {
        Ok(counts)
    } else {
        Err(report)
    }
}

#[test]
fn wesl_matches_naga_oil_under_every_feature_combination() {
    let package = package();
    let modules = sources(&package);
    let mut composer = volfog_codegen::compose::composer().unwrap_or_else(|e| panic!("{e}"));
    let (mut combos, mut items) = (0, 0);
    let mut report = String::new();
    for module in &package {
        let all = all_features(&package, module.name);
        match check_equivalence(
            &mut composer,
            &modules,
            module.name,
            &all,
            naga_oil_source(module.name),
        ) {
            Ok((c, n)) => {
                combos += c;
                items += n;
            }
            Err(diff) => report.push_str(&diff),
        }
    }
    assert!(report.is_empty(), "WESL and naga_oil differ:\n{report}");
    println!("{combos} module x feature combinations, {items} items equal");
}

#[test]
fn a_misplaced_if_is_detected() {
    // esm_encode with the two returns exchanged: valid WESL, wrong under both settings.
    let package = package();
    let mut modules = sources(&package);
    let esm = modules.get_mut("esm").expect("esm");
    let right = "    @if(VOLFOG_ESM_LOG_SPACE)\n    return exponent * depth;\n    @else\n    return exp(exponent * depth);\n";
    let wrong = "    @if(VOLFOG_ESM_LOG_SPACE)\n    return exp(exponent * depth);\n    @else\n    return exponent * depth;\n";
    assert!(esm.contains(right), "esm_encode as expected:\n{esm}");
    *esm = esm.replace(right, wrong);
    let mut composer = volfog_codegen::compose::composer().unwrap_or_else(|e| panic!("{e}"));
    let all = all_features(&package, "esm");
    let report = check_equivalence(&mut composer, &modules, "esm", &all, naga_oil_source("esm"))
        .expect_err("the exchanged branches differ from naga_oil");
    assert_eq!(report.matches("`esm_encode`").count(), 2, "{report}");
}
