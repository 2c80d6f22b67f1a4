//! The package's name and references: naga_oil `#import`s as `package::` imports, `#{N}`
//! as `constants::N`, and the imports that comments document as a user's `import volfog::`.

use super::lex::is_ident;

/// The package name users import the modules from (`import volfog::apply::...`).
pub const PACKAGE: &str = "volfog";

/// `#import volfog::x...` (the part after `#import`) as a WESL import statement.
pub(super) fn translate_import(spec: &str) -> Result<String, String> {
    let spec = spec.trim();
    let Some(rest) = spec
        .strip_prefix(PACKAGE)
        .and_then(|path| path.strip_prefix("::"))
    else {
        return Err(format!(
            "`#import {spec}`: only imports of volfog modules can be translated"
        ));
    };
    let allowed = |c: char| c.is_alphanumeric() || "_:{},".contains(c) || c.is_whitespace();
    if rest.is_empty() || !rest.chars().all(allowed) || rest.ends_with("::") {
        return Err(format!("unsupported import syntax `#import {spec}`"));
    }
    Ok(format!("import package::{rest};"))
}

/// Replaces `#{N}` in code with `constants::N` (collecting `N`); any other `#` and any
/// `::` path is an error.
pub(super) fn substitute(code: &str, values: &mut Vec<String>) -> Result<String, String> {
    if let Some(at) = code.find("::") {
        let start = code[..at]
            .rfind(|c: char| !(c.is_alphanumeric() || c == '_'))
            .map_or(0, |p| p + 1);
        let end = code[at..]
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
            .map_or(code.len(), |p| at + p);
        return Err(format!(
            "qualified name `{}` in code: naga_oil module paths are not translated",
            &code[start..end]
        ));
    }
    let mut out = String::new();
    let mut rest = code;
    while let Some(at) = rest.find('#') {
        out.push_str(&rest[..at]);
        let after = &rest[at + 1..];
        let name = after
            .strip_prefix('{')
            .and_then(|a| a.find('}').map(|end| &a[..end]))
            .filter(|n| is_ident(n))
            .ok_or_else(|| {
                format!(
                    "unsupported preprocessor syntax `{}`",
                    rest[at..].split_whitespace().next().unwrap_or("#")
                )
            })?;
        out.push_str("constants::");
        out.push_str(name);
        values.push(name.to_string());
        rest = &after[name.len() + 2..];
    }
    out.push_str(rest);
    Ok(out)
}

/// Rewrites `#import volfog::...` in a comment to the WESL statement a user of the
/// package writes. `pending_brace` carries an import list that continues on the next
/// comment line.
pub(super) fn rewrite_comment(text: &str, pending_brace: &mut bool) -> String {
    let mut out = String::new();
    let mut rest = text;
    if *pending_brace {
        if let Some(end) = rest.find('}') {
            out.push_str(&rest[..=end]);
            out.push(';');
            rest = &rest[end + 1..];
            *pending_brace = false;
        } else {
            return text.to_string();
        }
    }
    while let Some(at) = rest.find("#import volfog::") {
        out.push_str(&rest[..at]);
        out.push_str("import ");
        let path_start = at + "#import ".len();
        let path_len = rest[path_start..]
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
            .unwrap_or(rest.len() - path_start);
        let path_end = path_start + path_len;
        out.push_str(&rest[path_start..path_end]);
        rest = &rest[path_end..];
        if rest.starts_with('{') {
            match rest.find('}') {
                Some(end) => {
                    out.push_str(&rest[..=end]);
                    out.push(';');
                    rest = &rest[end + 1..];
                }
                None => {
                    *pending_brace = true;
                    out.push_str(rest);
                    return out;
                }
            }
        } else {
            out.push(';');
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use crate::wesl::tests::wesl;

    #[test]
    fn imports_and_header() {
        let text = wesl(
            "// Use: #import volfog::a::{x,\n//        y} and #import volfog::b\n\
             #define_import_path volfog::c\n\
             #import volfog::a::{x, y}\n#import volfog::b::z\n#import volfog::b as bee\n\
             fn f() {}\n",
        );
        assert_eq!(
            text,
            "// Use: import volfog::a::{x,\n//        y}; and import volfog::b;\n\
             import package::a::{x, y};\nimport package::b::z;\nimport package::b as bee;\n\
             fn f() {}\n"
        );
    }
}
