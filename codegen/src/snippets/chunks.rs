//! Generated text as top-level definitions (chunks): splitting, naming, the renaming of
//! naga's invented names, and the chunks of a rendered snippet.

use super::{ENTRY, SnippetLanguage};

/// A top-level definition of generated text: its name (`None` for preprocessor lines
/// and `using` declarations) and its lines.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Chunk {
    pub(super) name: Option<String>,
    pub(super) text: String,
}

/// Splits generated text into top-level definitions, drops the snippet entry point and
/// what only it needs (GLSL's `#version`, extensions and workgroup layout, GLSL ES's
/// default precisions and fragment output, naga's comments), and gives naga's anonymous types (`type_N`) names of this module.
pub(super) fn chunks(text: &str, module: &str) -> Vec<Chunk> {
    let text = rename_anonymous_types(text, module);
    // naga's `// language:` note and GLSL's compute-stage extension belong to the
    // removed entry point's file, not to an include.
    let kept: String = text
        .lines()
        .filter(|l| !(l.starts_with("//") || l.starts_with("#extension")))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut out = split_top_level(&kept);
    out.retain(|c| {
        let text = c.text.trim_start();
        !(c.text.contains(ENTRY)
            || text.starts_with("void main(")
            || text.starts_with("#version")
            || text.starts_with("precision ")
            // The fragment entry point's output (naga names them `_fs2p_*`).
            || text.contains("_fs2p_")
            || text.starts_with("layout(local_size"))
    });
    for c in &mut out {
        let trimmed = c.text.trim_end().to_string();
        c.text = trimmed + "\n";
    }
    out
}

/// Splits text into top-level definitions: one starts at each line that begins in the
/// first column with something other than a closing bracket; attribute lines (HLSL
/// `[numthreads(..)]`, WGSL `@...`) belong to the definition after them.
fn split_top_level(text: &str) -> Vec<Chunk> {
    let mut out: Vec<Chunk> = Vec::new();
    let mut pending_attribute = String::new();
    for line in text.lines() {
        let top = line
            .chars()
            .next()
            .is_some_and(|c| !c.is_whitespace() && c != '{' && c != '}' && c != ')');
        if line.starts_with('[') || line.starts_with('@') {
            pending_attribute.push_str(line);
            pending_attribute.push('\n');
            continue;
        }
        if top {
            out.push(Chunk {
                name: chunk_name(line),
                text: std::mem::take(&mut pending_attribute),
            });
        }
        if let Some(last) = out.last_mut() {
            last.text.push_str(line);
            last.text.push('\n');
        }
    }
    out
}

/// Gives the names naga invents module-independent meaning: anonymous types
/// (`type_N`) become `volfog_<module>_type_N`, helpers (`naga_*`, `Naga*`) `volfog_*`;
/// and gives back the WGSL name of a global that ends in a digit, to which naga's namer
/// appends `_` (`volfog_phase_hg_sh_l1_` -> `volfog_phase_hg_sh_l1`): the namer's own
/// collision suffixes are `_N`, so the shorter name stays unique.
fn rename_anonymous_types(text: &str, module: &str) -> String {
    rename_identifiers(text, |ident| {
        let anonymous = ident
            .strip_prefix("type_")
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
        if anonymous {
            Some(format!("volfog_{module}_{ident}"))
        } else if ident.starts_with("naga_") || ident.starts_with("Naga") {
            Some(format!("volfog_{ident}"))
        } else if ident.starts_with("volfog_")
            && ident
                .strip_suffix('_')
                .is_some_and(|stem| stem.ends_with(|c: char| c.is_ascii_digit()))
        {
            Some(ident[..ident.len() - 1].to_string())
        } else {
            None
        }
    })
}

/// Replaces every identifier `rename` returns a new name for.
fn rename_identifiers(text: &str, rename: impl Fn(&str) -> Option<String>) -> String {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(ident) {
        out.push_str(&rest[..start]);
        let len = rest[start..]
            .find(|c: char| !ident(c))
            .unwrap_or(rest.len() - start);
        let word = &rest[start..start + len];
        match rename(word).filter(|_| !word.starts_with(|c: char| c.is_ascii_digit())) {
            Some(new) => out.push_str(&new),
            None => out.push_str(word),
        }
        rest = &rest[start + len..];
    }
    out.push_str(rest);
    out
}

/// The name a top-level line defines.
fn chunk_name(line: &str) -> Option<String> {
    let line = line.trim();
    if line.starts_with('#') || line.starts_with("using ") {
        return None;
    }
    let ident = |s: &str| {
        let s = s.trim();
        let start = s
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |p| p + 1);
        (!s[start..].is_empty()).then(|| s[start..].to_string())
    };
    if let Some(rest) = line.strip_prefix("struct ") {
        return ident(rest.split([' ', '{']).next()?);
    }
    if let Some((decl, _)) = line.split_once(" = ") {
        // WGSL declares `const NAME: TYPE = ...`; the C family `TYPE NAME = ...`.
        return ident(decl.split_once(": ").map_or(decl, |(name, _)| name));
    }
    if let Some((head, _)) = line.split_once('(') {
        return ident(head);
    }
    ident(line.trim_end_matches(';'))
}

/// The chunks of a rendered snippet body (guards removed).
pub(super) fn split_rendered(body: &str, language: SnippetLanguage) -> Vec<Chunk> {
    if !language.guarded() {
        return split_top_level(body)
            .into_iter()
            .map(|c| Chunk {
                text: c.text.trim_end().to_string() + "\n",
                ..c
            })
            .collect();
    }
    let mut out = Vec::new();
    let mut lines = body.lines().peekable();
    while let Some(line) = lines.next() {
        if let Some(name) = line.strip_prefix("#ifndef VOLFOG_HAVE_") {
            lines.next();
            let mut text = String::new();
            for l in lines.by_ref() {
                if l == "#endif" {
                    break;
                }
                text.push_str(l);
                text.push('\n');
            }
            out.push(Chunk {
                name: Some(name.to_string()),
                text,
            });
        } else if !line.trim().is_empty() {
            out.push(Chunk {
                name: None,
                text: format!("{line}\n"),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_level_names() {
        assert_eq!(
            chunk_name("struct volfog_Froxels {").as_deref(),
            Some("volfog_Froxels")
        );
        assert_eq!(
            chunk_name("float volfog_phase_hg(float cos_theta, float g)").as_deref(),
            Some("volfog_phase_hg")
        );
        assert_eq!(
            chunk_name("static const float volfog_PI = 3.1415927;").as_deref(),
            Some("volfog_PI")
        );
        assert_eq!(
            chunk_name("const volfog_PI: f32 = 3.1415927f;").as_deref(),
            Some("volfog_PI")
        );
        assert_eq!(
            chunk_name("fn volfog_phase_hg(cos_theta: f32, g: f32) -> f32 {").as_deref(),
            Some("volfog_phase_hg")
        );
        assert_eq!(
            chunk_name("constant metal::float4 volfog_FOG_NONE = metal::float4(0.0);").as_deref(),
            Some("volfog_FOG_NONE")
        );
        assert_eq!(chunk_name("#include <metal_stdlib>"), None);
        assert_eq!(chunk_name("using metal::uint;"), None);
    }

    #[test]
    fn invented_names_are_prefixed() {
        assert_eq!(
            rename_anonymous_types(
                "struct type_5 { float inner[3]; }; type_50 x; my_type_5; naga_f2i32(v); NagaDimensions3D(t); 1.0e5",
                "phase"
            ),
            "struct volfog_phase_type_5 { float inner[3]; }; volfog_phase_type_50 x; my_type_5; \
             volfog_naga_f2i32(v); volfog_NagaDimensions3D(t); 1.0e5"
        );
        assert_eq!(
            rename_anonymous_types("volfog_sh_l1_(d); volfog_SH_Y0_; g0_; volfog_x_", "phase"),
            "volfog_sh_l1(d); volfog_SH_Y0; g0_; volfog_x_"
        );
    }
}
