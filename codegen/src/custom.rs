//! The user's modules behind a pass's hooks ([`Hook`]; the custom density of inject):
//! each is checked (its import path, the function and its signature, by composing the
//! call the pass makes), added to the composer for one composition and taken out
//! again, so the shared composer never keeps a user's module.
//!
//! ```
//! use volfog_codegen::compose::Defines;
//! use volfog_codegen::custom::{CustomModule, compose_with};
//! use volfog_codegen::manifest::{self, CUSTOM_DENSITY};
//!
//! let density = CustomModule::new(
//!     "slab.wgsl",
//!     "#import volfog::types::{FogSample, FogCustomParams}\n\
//!      fn volfog_custom_density(world: vec3<f32>, time: f32, params: FogCustomParams) -> FogSample {\n\
//!          let inside = abs(world.y - params.values[0].x) < params.values[0].y;\n\
//!          return FogSample(vec3<f32>(0.8), select(0.0, 0.1, inside), vec3<f32>(0.0));\n\
//!      }\n",
//! );
//! let inject = manifest::pass("inject").unwrap();
//! let defines = Defines::parse(inject, &[CUSTOM_DENSITY.define.to_string()])?;
//! let module = compose_with(inject, &defines, &[(&CUSTOM_DENSITY, &density)])?;
//! assert!(module.functions.iter().any(|(_, f)| {
//!     f.name.as_deref().is_some_and(|n| n.starts_with("volfog_custom_density"))
//! }));
//!
//! // A module without the function gets a typed error naming it.
//! let empty = CustomModule::new("empty.wgsl", "fn helper() -> f32 { return 1.0; }\n");
//! let err = compose_with(inject, &defines, &[(&CUSTOM_DENSITY, &empty)]).unwrap_err();
//! assert!(matches!(err, volfog_codegen::CodegenError::CustomFunctionMissing { .. }));
//! # Ok::<(), volfog_codegen::CodegenError>(())
//! ```

use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};

use crate::CodegenError;
use crate::compose::{Defines, compose_pass, declared_import_path, validate, with_shared_composer};
use crate::manifest::{Hook, PassSource};

/// A user's module: its file (named in errors) and its text, in naga_oil's WGSL
/// (`#import volfog::types::FogSample`) or with WESL's import statements (`import
/// volfog::types::FogSample;`, as Bevy's shaders write them), which are read as
/// naga_oil's, line for line.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CustomModule {
    /// The file the source comes from, as errors name it.
    pub file: String,
    /// The WGSL (or WESL) text.
    pub source: String,
}

impl CustomModule {
    /// A module from its file name and text.
    pub fn new(file: impl Into<String>, source: impl Into<String>) -> Self {
        Self {
            file: file.into(),
            source: source.into(),
        }
    }

    /// The source as naga_oil composes it: each WESL `import ...;` statement becomes a
    /// `#import ...` line on its first line (the lines it spanned stay, empty), so
    /// every line and column of the rest is where the user wrote it.
    pub fn naga_oil_source(&self) -> String {
        let mut out: Vec<String> = Vec::new();
        let mut open: Option<(usize, String)> = None;
        for line in self.source.lines() {
            if let Some((first, text)) = open.as_mut() {
                text.push(' ');
                text.push_str(line.trim());
                out.push(String::new());
                if text.ends_with(';') {
                    let statement = text.trim_end_matches(';').to_string();
                    out[*first] = format!("#import {statement}");
                    open = None;
                }
                continue;
            }
            let trimmed = line.trim_start();
            if let Some(rest) = trimmed.strip_prefix("import ") {
                let rest = rest.trim();
                if let Some(statement) = rest.strip_suffix(';') {
                    out.push(format!("#import {}", statement.trim()));
                } else {
                    out.push(String::new());
                    open = Some((out.len() - 1, rest.to_string()));
                }
                continue;
            }
            out.push(line.to_string());
        }
        let mut text = out.join("\n");
        if self.source.ends_with('\n') {
            text.push('\n');
        }
        text
    }
}

/// Where `fn <function>` is defined in `source`: its 1-based line and the column of
/// `fn`, outside `//` comments; `None` when it is not.
pub fn find_function(source: &str, function: &str) -> Option<(usize, usize)> {
    for (i, line) in source.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        let mut from = 0;
        while let Some(at) = code[from..].find("fn") {
            let start = from + at;
            let before_ok = start == 0
                || !code[..start]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_');
            let rest = &code[start + 2..];
            let name = rest.trim_start();
            let spaced = rest.len() > name.len();
            if before_ok
                && spaced
                && name.starts_with(function)
                && !name[function.len()..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            {
                return Some((i + 1, start + 1));
            }
            from = start + 2;
        }
    }
    None
}

/// Adds the user's module for `hook` to the composer at the hook's import path, after
/// checking that it composes and defines the hook's function with its signature (by
/// composing the call the pass makes). On error the composer is as it was.
pub fn add_custom_module(
    composer: &mut Composer,
    hook: &Hook,
    module: &CustomModule,
) -> Result<(), CodegenError> {
    let source = module.naga_oil_source();
    if let Some(found) = declared_import_path(&source)
        && found != hook.import_path
    {
        return Err(CodegenError::ImportPath {
            file: module.file.clone(),
            found: found.to_string(),
            expected: hook.import_path.to_string(),
        });
    }
    let custom_error = |message: String| CodegenError::CustomModule {
        file: module.file.clone(),
        message: at_original_positions(&message, module),
        signature: hook.signature.to_string(),
    };
    if let Err(e) = composer.add_composable_module(ComposableModuleDescriptor {
        source: &source,
        file_path: &module.file,
        as_name: Some(hook.import_path.to_string()),
        ..Default::default()
    }) {
        let message = e.emit_to_string(composer);
        composer.remove_composable_module(hook.import_path);
        return Err(custom_error(message));
    }
    let probe = composer.make_naga_module(NagaModuleDescriptor {
        source: hook.probe,
        file_path: "volfog: the pass's call",
        ..Default::default()
    });
    let Err(e) = probe else {
        return Ok(());
    };
    let in_module = e.source.path(composer) == &module.file;
    let message = e.emit_to_string(composer);
    composer.remove_composable_module(hook.import_path);
    if in_module {
        return Err(custom_error(message));
    }
    match find_function(&module.source, hook.function) {
        None => Err(CodegenError::CustomFunctionMissing {
            file: module.file.clone(),
            function: hook.function.to_string(),
            signature: hook.signature.to_string(),
        }),
        Some((line, column)) => Err(CodegenError::CustomSignature {
            file: module.file.clone(),
            line,
            column,
            function: hook.function.to_string(),
            signature: hook.signature.to_string(),
            message: naga_message(&message),
        }),
    }
}

/// A module path and a name (an item, or the name a module is used by).
type Import = (String, String);

/// What a module imports, as naga_oil substitutes it: (module path, item) for
/// `#import a::b::{x, y}` and `#import a::b::x` (the item used as `x`), and (module
/// path, the name it is used by) for `#import a::b` and `#import a::b as c` (used as
/// `b::x`, `c::x`).
fn imports(source: &str) -> (Vec<Import>, Vec<Import>) {
    let (mut items, mut modules) = (Vec::new(), Vec::new());
    for line in source.lines() {
        let Some(rest) = line.trim().strip_prefix("#import") else {
            continue;
        };
        let rest = rest.trim();
        if let Some((path, list)) = rest.split_once('{') {
            let path = path.trim().trim_end_matches("::").to_string();
            for item in list.trim_end_matches('}').split(',') {
                let item = item.split(" as ").next().unwrap_or("").trim();
                if !item.is_empty() {
                    items.push((path.clone(), item.to_string()));
                }
            }
        } else if let Some((path, alias)) = rest.split_once(" as ") {
            modules.push((path.trim().to_string(), alias.trim().to_string()));
        } else if let Some((module, last)) = rest.rsplit_once("::") {
            // An item, or a module used by its last segment: both are substituted.
            items.push((module.to_string(), last.to_string()));
            modules.push((rest.to_string(), last.to_string()));
        }
    }
    (items, modules)
}

/// `line` cut into segments as naga_oil parses it: (the segment's start and end in the
/// line, in chars; the text naga_oil has there), imported names replaced by their
/// decorated names (`Composer::decorated_name`).
fn decorated_segments(line: &str, source: &str) -> Vec<(usize, usize, String)> {
    let (items, modules) = imports(source);
    let chars: Vec<char> = line.chars().collect();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if !ident(chars[i]) || (i > 0 && ident(chars[i - 1])) {
            out.push((i, i + 1, chars[i].to_string()));
            i += 1;
            continue;
        }
        let mut end = i;
        while end < chars.len() && ident(chars[end]) {
            end += 1;
        }
        let word: String = chars[i..end].iter().collect();
        let after: String = chars[end..].iter().collect();
        let before: String = chars[..i].iter().collect();
        let qualified = before.ends_with("::") || before.ends_with('.');
        // `alias::item` of a module import.
        if let Some((module, _)) = modules.iter().find(|(_, alias)| *alias == word)
            && let Some(rest) = after.strip_prefix("::")
        {
            let item: String = rest.chars().take_while(|c| ident(*c)).collect();
            if !item.is_empty() {
                let stop = end + 2 + item.chars().count();
                out.push((i, stop, Composer::decorated_name(Some(module), &item)));
                i = stop;
                continue;
            }
        }
        match items.iter().find(|(_, item)| *item == word) {
            Some((module, item)) if !qualified => {
                out.push((i, end, Composer::decorated_name(Some(module), item)));
            }
            _ => out.push((i, end, word)),
        }
        i = end;
    }
    out
}

/// The 1-based column in `line` of 1-based column `column` of the line as naga_oil
/// parses it ([`decorated_segments`]).
fn original_column(line: &str, source: &str, column: usize) -> usize {
    let mut at = 0;
    for (start, end, text) in decorated_segments(line, source) {
        let len = text.chars().count();
        if column - 1 < at + len {
            return (start + (column - 1 - at)).min(end - 1) + 1;
        }
        at += len;
    }
    line.chars().count() + 1
}

/// naga_oil's rendered message with its position in the user's module as the user
/// wrote it: naga_oil counts the column in the line with imported names replaced by
/// their decorated names, and shows the line with them qualified
/// (`volfog::types::FogSample`); the `file:line:column` header, the source line and
/// the carets under it are put back on the user's text.
fn at_original_positions(rendered: &str, module: &CustomModule) -> String {
    let original: Vec<&str> = module.source.lines().collect();
    let header = format!("┌─ {}:", module.file);
    let mut at: Option<(usize, usize)> = None; // (line, column) in the user's text
    let mut out: Vec<String> = Vec::new();
    for line in rendered.lines() {
        if let Some(start) = line.find(&header) {
            let position = &line[start + header.len()..];
            let parsed = position.split_once(':').and_then(|(l, c)| {
                Some((
                    l.trim().parse::<usize>().ok()?,
                    c.trim().parse::<usize>().ok()?,
                ))
            });
            match parsed {
                Some((l, c)) if l >= 1 && c >= 1 && l <= original.len() => {
                    let column = original_column(original[l - 1], &module.source, c);
                    out.push(format!(
                        "{}{}:{l}:{column}",
                        &line[..start + "┌─ ".len()],
                        module.file
                    ));
                    at = Some((l, column));
                }
                _ => out.push(line.to_string()),
            }
            continue;
        }
        if let Some((l, column)) = at {
            let marker = format!("{l} │ ");
            if let Some(start) = line.find(&marker) {
                out.push(format!(
                    "{}{}",
                    &line[..start + marker.len()],
                    original[l - 1]
                ));
                continue;
            }
            if let Some(bar) = line.find("│ ")
                && line[bar..].contains('^')
            {
                let (head, tail) = line.split_at(bar + "│ ".len());
                out.push(format!(
                    "{head}{}{}",
                    " ".repeat(column - 1),
                    tail.trim_start()
                ));
                continue;
            }
        }
        out.push(line.to_string());
    }
    out.join("\n")
}

/// The gist of naga_oil's rendered message: its first line and its notes, without the
/// probe's source lines.
fn naga_message(rendered: &str) -> String {
    let mut parts: Vec<&str> = Vec::new();
    for line in rendered.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("error:") {
            parts.push(rest.trim());
        } else if let Some(rest) = t.strip_prefix("= ") {
            parts.push(rest.trim());
        }
    }
    parts.dedup();
    if parts.is_empty() {
        rendered.trim().to_string()
    } else {
        parts.join("; ")
    }
}

/// Runs `f` with the shared composer holding each user's module at its hook's import
/// path (checked as [`add_custom_module`] checks it), and takes them out afterwards,
/// whatever `f` returns.
pub fn with_custom_modules<T>(
    modules: &[(&Hook, &CustomModule)],
    f: impl FnOnce(&mut Composer) -> Result<T, CodegenError>,
) -> Result<T, CodegenError> {
    with_shared_composer(|composer| {
        let mut added: Vec<&str> = Vec::new();
        let mut result = Ok(());
        for (hook, module) in modules {
            result = add_custom_module(composer, hook, module);
            if result.is_err() {
                break;
            }
            added.push(hook.import_path);
        }
        let out = result.and_then(|()| f(composer));
        for path in added {
            composer.remove_composable_module(path);
        }
        out
    })
}

/// Composes a pass under a define set with the users' modules of its hooks, and
/// validates the result (the runtime's module for a hook's define).
pub fn compose_with(
    pass: &PassSource,
    defines: &Defines,
    modules: &[(&Hook, &CustomModule)],
) -> Result<naga::Module, CodegenError> {
    let module = with_custom_modules(modules, |composer| compose_pass(composer, pass, defines))?;
    validate(&module, &defines.variant_name(pass.name))?;
    Ok(module)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wesl_imports_become_naga_oil_imports_line_for_line() {
        let m = CustomModule::new(
            "a.wesl",
            "// density\nimport volfog::types::{FogSample,\n    FogCustomParams};\nfn f() {}\nimport volfog::types::FogSample;\n",
        );
        assert_eq!(
            m.naga_oil_source(),
            "// density\n#import volfog::types::{FogSample, FogCustomParams}\n\nfn f() {}\n#import volfog::types::FogSample\n"
        );
    }

    #[test]
    fn positions_are_moved_back_to_the_users_text() {
        let line = "    return FogSample(vec3<f32>(1.0), oops, vec3<f32>(0.0));";
        let module = CustomModule::new(
            "bad.wgsl",
            format!(
                "#import volfog::types::{{FogSample, FogCustomParams}}\nfn f() -> FogSample {{\n{line}\n}}\n"
            ),
        );
        // As naga_oil renders it: the column in the line with the decorated name, the
        // line shown with the qualified one.
        let decorated = Composer::decorated_name(Some("volfog::types"), "FogSample");
        let col = line.replace("FogSample", &decorated).find("oops").unwrap() + 1;
        let shown = line.replace("FogSample", "volfog::types::FogSample");
        let rendered = format!(
            "error: no definition in scope for identifier: `oops`\n  ┌─ bad.wgsl:3:{col}\n  │\n\
             3 │ {shown}\n  │ {}^^^^ unknown identifier\n",
            " ".repeat(col - 1)
        );
        let fixed = at_original_positions(&rendered, &module);
        let want = line.find("oops").unwrap() + 1;
        assert!(fixed.contains(&format!("┌─ bad.wgsl:3:{want}")), "{fixed}");
        assert!(fixed.contains(&format!("3 │ {line}")), "{fixed}");
        let caret = fixed.lines().find(|l| l.contains('^')).unwrap();
        let start = caret.find('│').unwrap() + '│'.len_utf8() + 1;
        assert_eq!(caret.find('^'), Some(start + want - 1), "{fixed}");
    }

    #[test]
    fn the_function_is_found_where_it_is_defined() {
        let src = "// fn volfog_custom_density in a comment\nfn volfog_custom_density_x() {}\n  fn  volfog_custom_density(world: vec3<f32>)\n";
        assert_eq!(find_function(src, "volfog_custom_density"), Some((3, 3)));
        assert_eq!(
            find_function("fn other() {}", "volfog_custom_density"),
            None
        );
    }
}
