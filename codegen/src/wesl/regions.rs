//! Parsing a naga_oil module into classified lines (directives, imports, code) and the
//! tree of its `#ifdef` / `#ifndef` / `#else` / `#endif` regions.

use crate::CodegenError;

use super::lex::{Tok, is_ident, split_comments, tokens};
use super::package::{rewrite_comment, substitute, translate_import};

/// A preprocessor directive.
#[derive(Debug, Clone)]
pub(super) enum Directive {
    DefineImportPath,
    /// The WESL import statement (possibly several lines).
    Import(String),
    If(Lit),
    Else,
    Endif,
}

/// One line of the source, classified.
#[derive(Debug, Clone)]
pub(super) enum Line {
    /// A line of WGSL (or only comments).
    Code {
        /// The output text: comments rewritten, `#{N}` substituted.
        text: String,
        /// Its code tokens.
        toks: Vec<Tok>,
        /// The `N` of every `#{N}` on the line.
        values: Vec<String>,
    },
    /// A directive with its trailing `//` comment, if any.
    Directive {
        directive: Directive,
        comment: Option<String>,
    },
    /// A continuation line of a multi-line `#import`.
    Continued,
}

/// A flag or its negation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Lit {
    pub(super) flag: String,
    pub(super) positive: bool,
}

impl Lit {
    fn negated(&self) -> Lit {
        Lit {
            flag: self.flag.clone(),
            positive: !self.positive,
        }
    }
}

pub(super) fn condition(lits: &[Lit]) -> String {
    lits.iter()
        .map(|l| {
            if l.positive {
                l.flag.clone()
            } else {
                format!("!{}", l.flag)
            }
        })
        .collect::<Vec<_>>()
        .join(" && ")
}

pub(super) fn error(file: &str, line: usize, message: impl Into<String>) -> CodegenError {
    CodegenError::Wesl {
        file: file.to_string(),
        line: line + 1,
        message: message.into(),
    }
}

/// Classifies every line: directives are parsed, code lines lexed, `#{N}` substituted
/// and `#import volfog::...` in comments rewritten to WESL.
pub(super) fn classify(file: &str, source: &str) -> Result<Vec<Line>, CodegenError> {
    let raw: Vec<&str> = source.lines().collect();
    let mut lines = Vec::with_capacity(raw.len());
    let mut depth = 0;
    let mut pending_brace = false;
    let mut i = 0;
    while i < raw.len() {
        let line = raw[i];
        let trimmed = line.trim_start();
        if depth == 0 && trimmed.starts_with('#') {
            let (body, comment) = match trimmed.find("//") {
                Some(at) => (
                    trimmed[..at].trim_end(),
                    Some(trimmed[at..].trim_end().to_string()),
                ),
                None => (trimmed.trim_end(), None),
            };
            let word_end = body.find(|c: char| c.is_whitespace()).unwrap_or(body.len());
            let (word, rest) = (&body[..word_end], body[word_end..].trim());
            let directive = match word {
                "#define_import_path" => Directive::DefineImportPath,
                "#import" => {
                    // naga_oil lets a braced import list run over several lines.
                    let mut spec = rest.to_string();
                    let mut continued = 0;
                    while spec.matches('{').count() > spec.matches('}').count() {
                        continued += 1;
                        let Some(next) = raw.get(i + continued) else {
                            return Err(error(file, i, "`#import` list is not closed"));
                        };
                        spec.push('\n');
                        spec.push_str(next);
                    }
                    let import = translate_import(&spec).map_err(|m| error(file, i, m))?;
                    lines.push(Line::Directive {
                        directive: Directive::Import(import),
                        comment,
                    });
                    for _ in 0..continued {
                        lines.push(Line::Continued);
                    }
                    i += 1 + continued;
                    continue;
                }
                "#ifdef" | "#ifndef" => {
                    if !is_ident(rest) {
                        return Err(error(
                            file,
                            i,
                            format!("`{word}` needs exactly one flag name, found `{rest}`"),
                        ));
                    }
                    Directive::If(Lit {
                        flag: rest.to_string(),
                        positive: word == "#ifdef",
                    })
                }
                "#else" | "#endif" => {
                    if !rest.is_empty() {
                        return Err(error(
                            file,
                            i,
                            format!("`{word} {rest}` is not supported (only plain `{word}`)"),
                        ));
                    }
                    if word == "#else" {
                        Directive::Else
                    } else {
                        Directive::Endif
                    }
                }
                _ => {
                    return Err(error(
                        file,
                        i,
                        format!("unsupported preprocessor directive `{word}`"),
                    ));
                }
            };
            lines.push(Line::Directive { directive, comment });
            i += 1;
            continue;
        }

        let mut text = String::new();
        let mut toks = Vec::new();
        let mut values = Vec::new();
        for piece in split_comments(line, &mut depth) {
            let part = &line[piece.range];
            if piece.code {
                let code = substitute(part, &mut values).map_err(|m| error(file, i, m))?;
                toks.extend(tokens(&code));
                text.push_str(&code);
            } else {
                text.push_str(&rewrite_comment(part, &mut pending_brace));
            }
        }
        lines.push(Line::Code { text, toks, values });
        i += 1;
    }
    Ok(lines)
}

#[derive(Debug, Clone)]
pub(super) enum Node {
    /// A code line, by index.
    Code(usize),
    /// An import directive line, by index.
    Import(usize),
    /// A conditional region.
    Cond(Region),
}

#[derive(Debug, Clone)]
pub(super) struct Region {
    pub(super) branches: Vec<Branch>,
    /// The line of `#endif`.
    pub(super) endif: usize,
    /// The last line that belongs to the region: `#endif`, or the last line of code
    /// after it that was copied into the branches.
    pub(super) end: usize,
}

#[derive(Debug, Clone)]
pub(super) struct Branch {
    pub(super) lit: Lit,
    /// The line of the `#ifdef` / `#ifndef` / `#else`.
    pub(super) directive: usize,
    pub(super) body: Vec<Node>,
}

pub(super) fn build_tree(file: &str, lines: &[Line]) -> Result<Vec<Node>, CodegenError> {
    let mut root = Vec::new();
    let mut open: Vec<Region> = Vec::new();
    let mut seen_code = false;
    for (i, line) in lines.iter().enumerate() {
        let target = match open.last_mut() {
            Some(region) => &mut region.branches.last_mut().expect("a branch").body,
            None => &mut root,
        };
        match line {
            Line::Continued => {}
            Line::Code { toks, .. } => {
                seen_code |= !toks.is_empty();
                target.push(Node::Code(i));
            }
            Line::Directive { directive, .. } => match directive {
                Directive::DefineImportPath | Directive::Import(_) if !open.is_empty() => {
                    return Err(error(
                        file,
                        i,
                        "`#define_import_path` and `#import` inside a conditional region are not supported",
                    ));
                }
                Directive::DefineImportPath => {}
                Directive::Import(_) => {
                    if seen_code {
                        return Err(error(
                            file,
                            i,
                            "`#import` after a declaration: WESL imports precede all declarations",
                        ));
                    }
                    root.push(Node::Import(i));
                }
                Directive::If(lit) => open.push(Region {
                    branches: vec![Branch {
                        lit: lit.clone(),
                        directive: i,
                        body: Vec::new(),
                    }],
                    endif: 0,
                    end: 0,
                }),
                Directive::Else => {
                    let Some(region) = open.last_mut() else {
                        return Err(error(file, i, "`#else` without `#ifdef` / `#ifndef`"));
                    };
                    if region.branches.len() > 1 {
                        return Err(error(file, i, "a second `#else` in one region"));
                    }
                    let lit = region.branches[0].lit.negated();
                    region.branches.push(Branch {
                        lit,
                        directive: i,
                        body: Vec::new(),
                    });
                }
                Directive::Endif => {
                    let Some(mut region) = open.pop() else {
                        return Err(error(file, i, "`#endif` without `#ifdef` / `#ifndef`"));
                    };
                    region.endif = i;
                    region.end = i;
                    match open.last_mut() {
                        Some(outer) => outer
                            .branches
                            .last_mut()
                            .expect("a branch")
                            .body
                            .push(Node::Cond(region)),
                        None => root.push(Node::Cond(region)),
                    }
                }
            },
        }
    }
    if let Some(region) = open.last() {
        return Err(error(
            file,
            region.branches[0].directive,
            "conditional region without `#endif`",
        ));
    }
    Ok(root)
}
