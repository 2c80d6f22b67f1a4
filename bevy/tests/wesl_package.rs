//! The WESL package of `volfog_codegen::wesl`, compiled with the WESL compiler of Bevy
//! 0.20 (wesl 0.6) the way Bevy compiles shaders, under every combination of each
//! module's feature flags; validated with naga; and compared item by item with the
//! naga_oil composition of the same module under the same defines, so a misplaced
//! `@if` fails here.

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet, HashMap};

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue};
use volfog_codegen::manifest::MODULES;
use volfog_codegen::names::undecorate;
use volfog_codegen::wesl::{WeslModule, features, translate, wesl_package};
use wesl::Mangler;
use wesl::syntax::{GlobalDeclaration, ModulePath, PathOrigin};

/// The bind group the tests give `VOLFOG_FOG_GROUP`.
const FOG_GROUP: u32 = 3;

/// The flag that is also an integer define (`#{VOLFOG_FOG_GROUP}`).
const FOG_GROUP_FLAG: &str = "VOLFOG_FOG_GROUP";

/// WESL sources by module name, all in package `volfog`.
type Sources = HashMap<String, String>;

/// Resolves `volfog::<module>` to the sources and Bevy's virtual `constants` package to
/// the integer defines that are on, as Bevy's shader cache does.
struct Resolver<'a> {
    modules: &'a Sources,
    constants: Option<String>,
}

impl wesl::Resolver for Resolver<'_> {
    fn resolve_source<'b>(
        &'b self,
        path: &ModulePath,
    ) -> Result<Cow<'b, str>, wesl::error::ResolveError> {
        let found = match (&path.origin, path.components.as_slice()) {
            (PathOrigin::Package(package), []) if package == "constants" => {
                self.constants.as_deref()
            }
            (PathOrigin::Package(package), [module]) if package == "volfog" => {
                self.modules.get(module).map(String::as_str)
            }
            _ => None,
        };
        found.map(Cow::Borrowed).ok_or_else(|| {
            wesl::error::ResolveError::ModuleNotFound(
                path.clone(),
                "not in the test package".to_string(),
            )
        })
    }

    /// The WESL compiler names a package referenced from inside package `volfog` as
    /// `volfog/<package>`; Bevy's resolver maps it back to `<package>`, and so does this.
    fn canonical_path(&self, path: &ModulePath) -> ModulePath {
        match &path.origin {
            PathOrigin::Package(package) if package.contains('/') => ModulePath::new(
                PathOrigin::Package(package.rsplit('/').next().unwrap_or(package).to_string()),
                path.components.clone(),
            ),
            _ => path.clone(),
        }
    }
}

fn package() -> Vec<WeslModule> {
    wesl_package().unwrap_or_else(|e| panic!("{e}"))
}

fn sources(package: &[WeslModule]) -> Sources {
    package
        .iter()
        .map(|m| (m.name.to_string(), m.source.clone()))
        .collect()
}

/// The naga_oil source of a module.
fn naga_oil_source(name: &str) -> (&'static str, &'static str) {
    let module = MODULES
        .iter()
        .find(|m| m.import_path == format!("volfog::{name}"))
        .expect("a manifest module");
    (module.file, module.source)
}

/// The features of a module and of every module it imports, sorted.
fn all_features(package: &[WeslModule], name: &str) -> Vec<String> {
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
fn combinations(flags: &[String]) -> Vec<Vec<String>> {
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

fn label(name: &str, on: &[String]) -> String {
    if on.is_empty() {
        format!("{name}@default")
    } else {
        format!("{name}@{}", on.join("+"))
    }
}

/// Compiles module `name` as Bevy compiles a WESL shader: imports and conditional
/// translation on, visibility off, the main module `volfog::<name>`. Every flag of
/// `all` is set on or off (an `@if` naming any other flag is an error), and the
/// `constants` package holds `VOLFOG_FOG_GROUP = 3` when that flag is on and does not
/// exist otherwise. Every declaration of the module is kept.
fn compile(
    modules: &Sources,
    name: &str,
    on: &[String],
    all: &[String],
    constants: bool,
) -> Result<wesl::CompileResult, wesl::Error> {
    let mut options = wesl::CompileOptions {
        imports: true,
        condcomp: true,
        visibility: false,
        keep_main: true,
        ..Default::default()
    };
    options.features.default = wesl::Feature::Error;
    for flag in all {
        options.features.set(flag, on.contains(flag));
    }
    let resolver = Resolver {
        modules,
        constants: constants.then(|| format!("const {FOG_GROUP_FLAG} = {FOG_GROUP};\n")),
    };
    let main = ModulePath::new(PathOrigin::Package("volfog".into()), vec![name.into()]);
    wesl::compile(&main, &options, &resolver)
}

fn validate(module: &naga::Module, what: &str) -> ModuleInfo {
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: validation failed: {e:?}"))
}

/// A WESL compilation as naga sees it, with the names of the main module's own
/// declarations (the WESL compiler mangles only imported names).
struct Compiled {
    module: naga::Module,
    own: BTreeSet<String>,
}

/// [`compile`] (with the constants package exactly when the fog group flag is on), the
/// WGSL parsed and validated by naga.
fn compile_validated(modules: &Sources, name: &str, on: &[String], all: &[String]) -> Compiled {
    let what = label(name, on);
    let constants = on.iter().any(|f| f == FOG_GROUP_FLAG);
    let result = compile(modules, name, on, all, constants)
        .unwrap_or_else(|e| panic!("{what}: WESL compilation failed:\n{e}"));
    let wgsl = result.to_string();
    let module = naga::front::wgsl::parse_str(&wgsl).unwrap_or_else(|e| {
        panic!(
            "{what}: naga rejects the WGSL:\n{}\n{wgsl}",
            e.emit_to_string(&wgsl)
        )
    });
    validate(&module, &what);
    let main = result
        .modules
        .iter()
        .find(|m| m.path.components == [name.to_string()])
        .expect("the main module");
    let own = main
        .syntax
        .global_declarations
        .iter()
        .filter_map(|decl| match decl.node() {
            GlobalDeclaration::Declaration(d) => Some(d.ident.name().clone()),
            GlobalDeclaration::TypeAlias(d) => Some(d.ident.name().clone()),
            GlobalDeclaration::Struct(d) => Some(d.ident.name().clone()),
            GlobalDeclaration::Function(d) => Some(d.ident.name().clone()),
            _ => None,
        })
        .collect();
    Compiled { module, own }
}

/// naga_oil's composition of a source as the top-level module, under the same flags
/// (the fog group as the integer define `VOLFOG_FOG_GROUP=3`).
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
            let value = if flag == FOG_GROUP_FLAG {
                ShaderDefValue::UInt(FOG_GROUP)
            } else {
                ShaderDefValue::Bool(true)
            };
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
fn check_equivalence(
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
fn every_module_compiles_under_every_feature_combination() {
    let package = package();
    let modules = sources(&package);
    let mut compiled = 0;
    for module in &package {
        let all = all_features(&package, module.name);
        for on in combinations(&all) {
            compile_validated(&modules, module.name, &on, &all);
            compiled += 1;
        }
    }
    println!(
        "{} modules, {compiled} module x feature combinations compiled and validated",
        package.len()
    );
    assert!(compiled > package.len(), "some modules have features");
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

#[test]
fn fog_group_comes_from_bevy_constants() {
    let package = package();
    let modules = sources(&package);
    let bindings = &modules["bindings"];
    assert!(bindings.contains("@if(VOLFOG_FOG_GROUP) {"));
    assert!(
        bindings
            .contains("@group(constants::VOLFOG_FOG_GROUP) @binding(0) var<uniform> fog_froxels")
    );
    assert!(bindings.contains("@else {\n    @group(0) @binding(0) var<uniform> fog_froxels"));
    let all = all_features(&package, "bindings");
    for on in combinations(&all) {
        let what = label("bindings", &on);
        let group = if on.iter().any(|f| f == FOG_GROUP_FLAG) {
            FOG_GROUP
        } else {
            0
        };
        let sampler = !on.iter().any(|f| f == "VOLFOG_BINDINGS_NO_SAMPLER");
        // Without the flag the resolver has no `constants` package at all.
        let compiled = compile_validated(&modules, "bindings", &on, &all);
        let mut bound: Vec<(String, u32, u32)> = compiled
            .module
            .global_variables
            .iter()
            .map(|(_, g)| {
                let b = g.binding.as_ref().expect("a bound global");
                (g.name.clone().expect("named"), b.group, b.binding)
            })
            .collect();
        bound.sort_by_key(|(_, _, binding)| *binding);
        let mut expected = vec![
            ("fog_froxels", 0),
            ("fog_integrated", 1),
            ("fog_sampler", 2),
            ("fog_far_tail", 3),
            ("fog_view", 4),
        ];
        expected.retain(|(name, _)| sampler || *name != "fog_sampler");
        let expected: Vec<(String, u32, u32)> = expected
            .into_iter()
            .map(|(name, binding)| (name.to_string(), group, binding))
            .collect();
        assert_eq!(bound, expected, "{what}");
        // With the flag, the group is the constant: no constants package, no module.
        if group == FOG_GROUP {
            assert!(
                compile(&modules, "bindings", &on, &all, false).is_err(),
                "{what}: compiles without the constants package"
            );
        }
    }
}

/// A naga_oil module with every form of the translation that volfog's own modules do
/// not use: conditional struct members, nested conditional parameters, declarations
/// used after their region (one `@if` per statement, nested conditions joined), a
/// block-opening `if` header per branch, and several declarations per module-scope
/// branch.
const SYNTHETIC: &str = "\
struct Sample {
    value: f32,
#ifdef A
    weight: f32,
#endif
}

fn pick(
    x: f32,
#ifdef A
    a: f32,
#ifndef B
    b: f32,
#endif
#endif
) -> f32 {
#ifdef A
    let base = x * a;
#ifndef B
    let scale = b;
#else
    let scale = 2.0;
#endif
#else
    let base = x;
    let scale = 3.0;
#endif
    var total = base * scale;
#ifdef B
    if total > 1.0 && x > 0.0 {
#else
    if total > 1.0 {
#endif
        total -= 1.0;
    }
    return total;
}

#ifdef B
fn helper() -> f32 {
    return 1.0;
}

fn helper_twice() -> f32 {
    return helper() * 2.0;
}
#else
fn helper() -> f32 {
    return 0.5;
}
#endif

fn weighted(s: Sample) -> f32 {
#ifdef A
    return s.value * s.weight * helper();
#else
    return s.value * helper();
#endif
}
";

#[test]
fn synthetic_forms_compile_and_match_naga_oil() {
    let wesl = translate("synthetic.wgsl", SYNTHETIC).unwrap_or_else(|e| panic!("{e}"));
    for form in [
        "    @if(A)\n    weight: f32,",
        "    @if(A)\n    a: f32,\n    @if(A && !B)\n    b: f32,",
        "    @if(A)\n    let base = x * a;\n    @if(A && !B)\n    let scale = b;\n    @if(A && B)\n    let scale = 2.0;\n    @if(!A)\n    let base = x;\n    @if(!A)\n    let scale = 3.0;",
        "    @if(B)\n    if total > 1.0 && x > 0.0 {\n        total -= 1.0;\n    }\n    @else\n    if total > 1.0 {\n        total -= 1.0;\n    }",
        "@if(B) {\n    fn helper() -> f32 {",
        "}\n@else {\n    fn helper() -> f32 {\n        return 0.5;\n    }\n}",
    ] {
        assert!(wesl.contains(form), "missing\n{form}\nin\n{wesl}");
    }
    let modules: Sources = [("synthetic".to_string(), wesl)].into();
    let all = vec!["A".to_string(), "B".to_string()];
    let mut composer = Composer::default();
    let (combos, items) = check_equivalence(
        &mut composer,
        &modules,
        "synthetic",
        &all,
        ("synthetic.wgsl", SYNTHETIC),
    )
    .unwrap_or_else(|report| panic!("WESL and naga_oil differ:\n{report}"));
    // Sample, pick, helper and weighted, and helper_twice where B is on.
    assert_eq!((combos, items), (4, 4 * 4 + 2));
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
