//! volfog's shader modules as a WESL package, for Bevy 0.20 and other WESL users.
//!
//! Every module of [`MODULES`] becomes the module of the same file stem in a package
//! named `volfog` (`volfog::apply` is `apply.wesl`). The translation works on the text
//! and keeps each file's comments and layout; only the preprocessor changes:
//!
//! | naga_oil | WESL |
//! |---|---|
//! | `#define_import_path volfog::x` | dropped: a WESL module's path is its file |
//! | `#import volfog::x::{a, b}` | `import package::x::{a, b};` (likewise `volfog::x::a`, `volfog::x`, `as`) |
//! | `// Use: #import volfog::x::a` | `// Use: import volfog::x::a;` (how a user of the package imports it) |
//! | `#ifdef N` / `#ifndef N` / `#else` / `#endif` | `@if(N)` / `@if(!N)` / `@else`, see below |
//! | `#{N}` inside `#ifdef N` | `constants::N`, from the virtual `constants` package |
//!
//! A conditional region becomes attributes on the declarations, statements or function
//! parameters it encloses:
//!
//! - When every branch holds at most one declaration or statement, that item gets
//!   `@if(N)` (or `@if(!N)`), and the `#else` item `@else`.
//! - When a branch holds more, each branch becomes a conditional block, `@if(N) { ... }`
//!   and `@else { ... }`, its lines indented one level; the WESL compiler splices the
//!   chosen block into the enclosing scope. Inside a function this form is used only when no
//!   `let`, `var` or `const` declared in the region is named after it, so the result
//!   does not depend on whether a WESL translator keeps the block's scope.
//! - Otherwise (such a declaration is used later) every statement of a branch gets its
//!   own `@if`: the branch's condition for the first branch, its negation for `#else`.
//! - Function parameters and struct members always get one `@if` each.
//!
//! Where attributes are written per item, the conditions of enclosing regions that are
//! not already a conditional block are joined in: `@if(A && !B)`. A region whose
//! branches open a block that the code after `#endif` closes (`#ifdef A` / `if x && y {`
//! / `#else` / `if x {` / `#endif` / body / `}`) gets that shared code copied into each
//! branch, so each branch is one whole statement.
//!
//! `#{N}` is the only value substitution naga_oil offers. Bevy declares every integer
//! shader def `N` both as a feature flag and as the constant `constants::N`, so
//! `@group(#{VOLFOG_FOG_GROUP})` under `#ifdef VOLFOG_FOG_GROUP` becomes
//! `@group(constants::VOLFOG_FOG_GROUP)` inside `@if(VOLFOG_FOG_GROUP)`; conditional
//! translation drops that branch before imports are resolved, so without the flag no
//! `constants` package is needed.
//!
//! Flags keep their names. One difference in meaning remains: Bevy turns a flag off for
//! a `ShaderDefVal::Bool(N, false)`, where naga_oil's `#ifdef N` holds for any value of
//! `N`; volfog never defines a flag as false.
//!
//! Anything else (other directives, `#import` of other packages or inside a
//! conditional, a region that starts or ends inside a statement, `::` paths in code,
//! several statements on one line where each needs its own attribute) is a
//! [`CodegenError::Wesl`] naming the file and line.
//!
//! ```
//! let package = volfog_codegen::wesl::wesl_package().unwrap();
//! let scan = package.iter().find(|m| m.name == "scan").unwrap();
//! assert!(scan.source.contains("@if(VOLFOG_SCAN_WRONSKI_STEP)"));
//! assert_eq!(volfog_codegen::wesl::features(scan), ["VOLFOG_SCAN_WRONSKI_STEP"]);
//! ```

mod analysis;
mod attributes;
mod lex;
mod package;
mod regions;
mod scan;

use std::collections::{BTreeSet, HashMap};

use crate::CodegenError;
use crate::manifest::MODULES;

pub use package::PACKAGE;

use analysis::Translator;
use attributes::Ctx;
use lex::{Tok, split_comments, tokens};
use regions::{build_tree, classify};
use scan::Scan;

/// One module of the WESL package.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WeslModule {
    /// The module name, the file stem of the naga_oil module (`apply`): users import it
    /// as `volfog::apply`, other modules of the package as `package::apply`.
    pub name: &'static str,
    /// The WESL source.
    pub source: String,
}

/// The WESL package: one module per entry of [`MODULES`], in the same (dependency)
/// order.
pub fn wesl_package() -> Result<Vec<WeslModule>, CodegenError> {
    MODULES
        .iter()
        .map(|module| {
            let name = module
                .import_path
                .strip_prefix(PACKAGE)
                .and_then(|path| path.strip_prefix("::"))
                .ok_or_else(|| CodegenError::Wesl {
                    file: module.file.to_string(),
                    line: 1,
                    message: format!(
                        "import path {} is not in the volfog package",
                        module.import_path
                    ),
                })?;
            Ok(WeslModule {
                name,
                source: translate(module.file, module.source)?,
            })
        })
        .collect()
}

/// The feature flags a module's `@if` attributes name, sorted.
pub fn features(module: &WeslModule) -> Vec<String> {
    let mut flags = BTreeSet::new();
    let mut depth = 0;
    for line in module.source.lines() {
        for piece in split_comments(line, &mut depth) {
            if !piece.code {
                continue;
            }
            let code = &line[piece.range];
            for (at, _) in code.match_indices('@') {
                let rest = &code[at + 1..];
                let Some(args) = rest
                    .strip_prefix("if(")
                    .or_else(|| rest.strip_prefix("elif("))
                else {
                    continue;
                };
                let end = args.find(')').unwrap_or(args.len());
                for tok in tokens(&args[..end]) {
                    if let Tok::Ident(name) = tok
                        && name != "true"
                        && name != "false"
                    {
                        flags.insert(name);
                    }
                }
            }
        }
    }
    flags.into_iter().collect()
}

/// Translates one naga_oil module (`file` names it in errors) into WESL by the rules of
/// this module's documentation.
pub fn translate(file: &str, source: &str) -> Result<String, CodegenError> {
    let lines = classify(file, source)?;
    let mut tree = build_tree(file, &lines)?;
    let mut translator = Translator {
        file,
        lines: &lines,
        out: Vec::new(),
        scan: Scan::default(),
    };
    translator.balance(&mut tree, &mut Scan::default())?;
    translator.seq(&tree, &Ctx::default(), &HashMap::new())?;
    if !translator.scan.stack.is_empty() {
        return Err(CodegenError::Wesl {
            file: file.to_string(),
            line: lines.len(),
            message: "a block or parenthesis is still open at the end of the file".to_string(),
        });
    }
    let mut text = translator.out.join("\n");
    if source.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn wesl(source: &str) -> String {
        translate("test.wgsl", source).unwrap_or_else(|e| panic!("{e}"))
    }

    fn fails(source: &str) -> String {
        match translate("test.wgsl", source) {
            Ok(text) => panic!("translated:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn features_are_the_flags_of_if_attributes() {
        let module = WeslModule {
            name: "m",
            source: wesl(
                "fn f(\n#ifdef B\n    x: f32,\n#endif\n#ifndef A\n    y: f32,\n#endif\n) {}\n",
            ),
        };
        assert_eq!(features(&module), ["A", "B"]);
    }

    #[test]
    fn unsupported_constructs_name_file_and_line() {
        assert!(fails("fn f() {}\n#if A == 1\n#endif\n").starts_with("test.wgsl:2:"));
        assert!(fails("#import bevy_pbr::x\n").starts_with("test.wgsl:1:"));
        assert!(fails("const X = 1;\n#import volfog::a::b\n").contains("test.wgsl:2:"));
        assert!(fails("fn f() {\n#ifdef A\n    let x = 1.0;\n}\n").contains("without `#endif`"));
        assert!(fails("#else\n").starts_with("test.wgsl:1:"));
        // A region inside an expression.
        assert!(
            fails("fn f() -> f32 {\n    return 1.0 +\n#ifdef A\n    2.0 +\n#endif\n    3.0;\n}\n")
                .starts_with("test.wgsl:3:")
        );
        // `#{N}` outside `#ifdef N`.
        assert!(fails("@group(#{G}) @binding(0) var s: sampler;\n").starts_with("test.wgsl:1:"));
        // naga_oil's qualified paths.
        assert!(fails("fn f() -> f32 { return volfog::x::y(); }\n").contains("qualified name"));
        // An `else` clause selected by a region.
        assert!(
            fails("fn f(a: bool) {\n    if a {\n    }\n#ifdef A\n    else {\n    }\n#endif\n}\n")
                .contains("`else`")
        );
        // A block opened in one branch only.
        assert!(
            fails("fn f(a: bool) {\n#ifdef A\n    if a {\n#endif\n    }\n}\n")
                .starts_with("test.wgsl:2:")
        );
    }
}
