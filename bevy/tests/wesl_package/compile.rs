//! Compiling the package as Bevy does (the WESL compiler with a resolver for the
//! `volfog` and `constants` packages) under every combination of feature flags.

use std::borrow::Cow;
use std::collections::BTreeSet;

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use wesl::syntax::{GlobalDeclaration, ModulePath, PathOrigin};

use crate::fixtures::{Sources, all_features, combinations, label, package, sources};
use crate::{FOG_GROUP, FOG_GROUP_FLAG, group_value};

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

/// Compiles module `name` as Bevy compiles a WESL shader: imports and conditional
/// translation on, visibility off, the main module `volfog::<name>`. Every flag of
/// `all` is set on or off (an `@if` naming any other flag is an error), and the
/// `constants` package (where `constants` is set) holds `VOLFOG_FOG_GROUP = 3` and
/// `VOLFOG_STEREO_FOG_GROUP = 2` for those flags that are on, and does not exist
/// otherwise. Every declaration of the module is kept.
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
        constants: constants.then(|| {
            on.iter()
                .filter_map(|flag| group_value(flag).map(|v| format!("const {flag} = {v};\n")))
                .collect()
        }),
    };
    let main = ModulePath::new(PathOrigin::Package("volfog".into()), vec![name.into()]);
    wesl::compile(&main, &options, &resolver)
}

pub(crate) fn validate(module: &naga::Module, what: &str) -> ModuleInfo {
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: validation failed: {e:?}"))
}

/// A WESL compilation as naga sees it, with the names of the main module's own
/// declarations (the WESL compiler mangles only imported names).
pub(crate) struct Compiled {
    pub(crate) module: naga::Module,
    pub(crate) own: BTreeSet<String>,
}

/// [`compile`] (with the constants package exactly when a group flag is on), the WGSL
/// parsed and validated by naga.
pub(crate) fn compile_validated(
    modules: &Sources,
    name: &str,
    on: &[String],
    all: &[String],
) -> Compiled {
    let what = label(name, on);
    let constants = on.iter().any(|f| group_value(f).is_some());
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
