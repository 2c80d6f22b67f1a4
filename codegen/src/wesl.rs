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

use std::collections::{BTreeSet, HashMap};

use crate::CodegenError;
use crate::manifest::MODULES;

/// The package name users import the modules from (`import volfog::apply::...`).
pub const PACKAGE: &str = "volfog";

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

// ---------------------------------------------------------------------------------
// Lexing

/// A piece of a line: code, or (part of) a comment.
struct Piece {
    code: bool,
    range: std::ops::Range<usize>,
}

/// Splits a line into code and comment pieces. `depth` is the nesting of WGSL block
/// comments, carried from line to line.
fn split_comments(line: &str, depth: &mut u32) -> Vec<Piece> {
    let b = line.as_bytes();
    let mut pieces = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < b.len() {
        if *depth > 0 {
            if b[i..].starts_with(b"/*") {
                *depth += 1;
                i += 2;
            } else if b[i..].starts_with(b"*/") {
                *depth -= 1;
                i += 2;
                if *depth == 0 {
                    pieces.push(Piece {
                        code: false,
                        range: start..i,
                    });
                    start = i;
                }
            } else {
                i += 1;
            }
        } else if b[i..].starts_with(b"//") {
            if start < i {
                pieces.push(Piece {
                    code: true,
                    range: start..i,
                });
            }
            start = i;
            i = b.len();
            pieces.push(Piece {
                code: false,
                range: start..i,
            });
            start = i;
        } else if b[i..].starts_with(b"/*") {
            if start < i {
                pieces.push(Piece {
                    code: true,
                    range: start..i,
                });
            }
            start = i;
            *depth = 1;
            i += 2;
        } else {
            i += 1;
        }
    }
    if start < b.len() {
        pieces.push(Piece {
            code: *depth == 0,
            range: start..b.len(),
        });
    }
    pieces
}

/// The tokens the translation needs to follow WGSL's structure.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    /// An identifier or keyword.
    Ident(String),
    /// A number literal.
    Number,
    /// Any other character.
    Punct(char),
}

fn tokens(code: &str) -> Vec<Tok> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Tok::Ident(chars[start..i].iter().collect()));
        } else if c.is_ascii_digit() {
            while i < chars.len()
                && (chars[i].is_alphanumeric() || chars[i] == '_' || chars[i] == '.')
            {
                i += 1;
            }
            out.push(Tok::Number);
        } else {
            out.push(Tok::Punct(c));
            i += 1;
        }
    }
    out
}

fn is_ident(text: &str) -> bool {
    let mut chars = text.chars();
    matches!(chars.next(), Some(c) if c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

fn leading_ws(text: &str) -> &str {
    &text[..text.len() - text.trim_start().len()]
}

// ---------------------------------------------------------------------------------
// Lines and directives

/// A preprocessor directive.
#[derive(Debug, Clone)]
enum Directive {
    DefineImportPath,
    /// The WESL import statement (possibly several lines).
    Import(String),
    If(Lit),
    Else,
    Endif,
}

/// One line of the source, classified.
#[derive(Debug, Clone)]
enum Line {
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
struct Lit {
    flag: String,
    positive: bool,
}

impl Lit {
    fn negated(&self) -> Lit {
        Lit {
            flag: self.flag.clone(),
            positive: !self.positive,
        }
    }
}

fn condition(lits: &[Lit]) -> String {
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

fn error(file: &str, line: usize, message: impl Into<String>) -> CodegenError {
    CodegenError::Wesl {
        file: file.to_string(),
        line: line + 1,
        message: message.into(),
    }
}

/// Classifies every line: directives are parsed, code lines lexed, `#{N}` substituted
/// and `#import volfog::...` in comments rewritten to WESL.
fn classify(file: &str, source: &str) -> Result<Vec<Line>, CodegenError> {
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

/// `#import volfog::x...` (the part after `#import`) as a WESL import statement.
fn translate_import(spec: &str) -> Result<String, String> {
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
fn substitute(code: &str, values: &mut Vec<String>) -> Result<String, String> {
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
fn rewrite_comment(text: &str, pending_brace: &mut bool) -> String {
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

// ---------------------------------------------------------------------------------
// The tree of conditional regions

#[derive(Debug, Clone)]
enum Node {
    /// A code line, by index.
    Code(usize),
    /// An import directive line, by index.
    Import(usize),
    /// A conditional region.
    Cond(Region),
}

#[derive(Debug, Clone)]
struct Region {
    branches: Vec<Branch>,
    /// The line of `#endif`.
    endif: usize,
    /// The last line that belongs to the region: `#endif`, or the last line of code
    /// after it that was copied into the branches.
    end: usize,
}

#[derive(Debug, Clone)]
struct Branch {
    lit: Lit,
    /// The line of the `#ifdef` / `#ifndef` / `#else`.
    directive: usize,
    body: Vec<Node>,
}

fn build_tree(file: &str, lines: &[Line]) -> Result<Vec<Node>, CodegenError> {
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

// ---------------------------------------------------------------------------------
// Following WGSL's structure

/// What an open bracket encloses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frame {
    Params,
    FnBody,
    Block,
    Struct,
    Paren,
    Bracket,
}

/// How far a `fn` or `struct` header has come at module scope.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Header {
    #[default]
    None,
    Fn,
    FnName,
    FnSignature,
    Struct,
    StructName,
}

/// The last significant token.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Prev {
    #[default]
    Start,
    Punct(char),
    Other,
}

/// Where a conditional region stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Context {
    /// Between module-scope declarations.
    Module,
    /// Between statements of a function body or block.
    Statements,
    /// Between function parameters or struct members.
    List,
}

/// The bracket structure of the code read so far.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Scan {
    stack: Vec<Frame>,
    header: Header,
    prev: Prev,
}

impl Scan {
    fn feed(&mut self, tok: &Tok) -> Result<(), String> {
        match tok {
            Tok::Ident(word) => {
                match (self.header, word.as_str()) {
                    (Header::None, "fn") if self.stack.is_empty() => self.header = Header::Fn,
                    (Header::None, "struct") if self.stack.is_empty() => {
                        self.header = Header::Struct
                    }
                    (Header::Fn, _) => self.header = Header::FnName,
                    (Header::Struct, _) => self.header = Header::StructName,
                    _ => {}
                }
                self.prev = Prev::Other;
            }
            Tok::Number => self.prev = Prev::Other,
            Tok::Punct(c) => {
                match c {
                    '(' => {
                        let frame = if self.header == Header::FnName {
                            self.header = Header::None;
                            Frame::Params
                        } else {
                            Frame::Paren
                        };
                        self.stack.push(frame);
                    }
                    ')' => match self.stack.pop() {
                        Some(Frame::Params) => self.header = Header::FnSignature,
                        Some(Frame::Paren) => {}
                        _ => return Err("`)` without a matching `(`".to_string()),
                    },
                    '[' => self.stack.push(Frame::Bracket),
                    ']' => {
                        if self.stack.pop() != Some(Frame::Bracket) {
                            return Err("`]` without a matching `[`".to_string());
                        }
                    }
                    '{' => {
                        let frame = match (self.header, self.stack.last()) {
                            (Header::FnSignature, None) => Frame::FnBody,
                            (Header::StructName, None) => Frame::Struct,
                            (Header::None, Some(Frame::FnBody | Frame::Block)) => Frame::Block,
                            _ => {
                                return Err(
                                    "`{` that opens neither a function body, a struct nor a block"
                                        .to_string(),
                                );
                            }
                        };
                        self.header = Header::None;
                        self.stack.push(frame);
                    }
                    '}' => match self.stack.pop() {
                        Some(Frame::FnBody | Frame::Block | Frame::Struct) => {}
                        _ => return Err("`}` without a matching `{`".to_string()),
                    },
                    ';' if self.stack.is_empty() => self.header = Header::None,
                    _ => {}
                }
                self.prev = Prev::Punct(*c);
            }
        }
        Ok(())
    }

    /// Where a region starting now would stand, if it starts between whole items.
    fn context(&self) -> Option<Context> {
        let after = |ok: &[char]| matches!(self.prev, Prev::Punct(c) if ok.contains(&c));
        match self.stack.last() {
            None if self.header == Header::None
                && (self.prev == Prev::Start || after(&[';', '}'])) =>
            {
                Some(Context::Module)
            }
            Some(Frame::FnBody | Frame::Block) if after(&['{', ';', '}']) => {
                Some(Context::Statements)
            }
            Some(Frame::Params) if after(&['(', ',']) => Some(Context::List),
            Some(Frame::Struct) if after(&['{', ',']) => Some(Context::List),
            _ => None,
        }
    }

    /// Whether two states have the same brackets open.
    fn same_level(&self, other: &Scan) -> bool {
        self.stack == other.stack && self.header == other.header
    }
}

/// What a branch of a region holds at the region's level.
#[derive(Debug, Default)]
struct BranchInfo {
    /// Body index of the line each item starts on.
    starts: Vec<usize>,
    /// Whether a nested region stands between items.
    nested: bool,
    /// Whether an item starts on a line where another ended.
    crowded: bool,
    /// Names declared by `let` / `var` / `const` at the region's level.
    decls: BTreeSet<String>,
}

/// How a region is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// `@if(C)` / `@else` on the single item of each branch.
    Single,
    /// `@if(C) { ... }` / `@else { ... }`.
    Block,
    /// `@if(C)` / `@if(!C)` on every item.
    PerItem,
}

/// The emission context of a node list.
#[derive(Debug, Clone, Default)]
struct Ctx {
    /// Indentation added to every line (inside conditional blocks).
    indent: String,
    /// Conditions that attributes written at stack depth `base` must include.
    attr: Vec<Lit>,
    /// The stack depth at which `attr` applies.
    base: usize,
    /// Every enclosing branch's condition (for `#{N}`).
    scope: Vec<Lit>,
}

struct Translator<'a> {
    file: &'a str,
    lines: &'a [Line],
    out: Vec<String>,
    scan: Scan,
}

impl Translator<'_> {
    fn err(&self, line: usize, message: impl Into<String>) -> CodegenError {
        error(self.file, line, message)
    }

    fn toks(&self, line: usize) -> &[Tok] {
        match &self.lines[line] {
            Line::Code { toks, .. } => toks,
            _ => &[],
        }
    }

    fn text(&self, line: usize) -> &str {
        match &self.lines[line] {
            Line::Code { text, .. } => text,
            _ => "",
        }
    }

    fn comment(&self, line: usize) -> Option<&str> {
        match &self.lines[line] {
            Line::Directive { comment, .. } => comment.as_deref(),
            _ => None,
        }
    }

    fn feed_line(&self, line: usize, scan: &mut Scan) -> Result<(), CodegenError> {
        for tok in self.toks(line) {
            scan.feed(tok).map_err(|m| self.err(line, m))?;
        }
        Ok(())
    }

    /// Whether the first token of `nodes`, past lines of comments only, is `else`.
    fn else_follows(&self, nodes: &[Node]) -> bool {
        for node in nodes {
            let Node::Code(line) = node else {
                return false;
            };
            if let Some(first) = self.toks(*line).first() {
                return *first == Tok::Ident("else".to_string());
            }
        }
        false
    }

    /// Checks that every region leaves the brackets as it found them, copying code
    /// after `#endif` into the branches where they all open a block it closes.
    fn balance(&self, nodes: &mut Vec<Node>, scan: &mut Scan) -> Result<(), CodegenError> {
        let mut i = 0;
        while i < nodes.len() {
            let region = match &mut nodes[i] {
                Node::Code(line) => {
                    self.feed_line(*line, scan)?;
                    i += 1;
                    continue;
                }
                Node::Import(_) => {
                    i += 1;
                    continue;
                }
                Node::Cond(region) => region,
            };
            let first = region.branches[0].directive;
            let start = scan.clone();
            let mut ends = Vec::new();
            for branch in &mut region.branches {
                let mut end = start.clone();
                self.balance(&mut branch.body, &mut end)?;
                ends.push(end);
            }
            if !ends.iter().all(|end| end.same_level(&start)) {
                let opens_block = ends.iter().all(|end| {
                    end.stack.len() > start.stack.len() && end.stack.starts_with(&start.stack)
                });
                if region.branches.len() < 2 || !opens_block {
                    return Err(self.err(
                        first,
                        "the region's branches leave different brackets open; only branches that \
                         all open a block closed after `#endif` are supported",
                    ));
                }
                let tail_start = i + 1;
                let mut tail_len = None;
                for end in &mut ends {
                    let mut k = 0;
                    loop {
                        match nodes.get(tail_start + k) {
                            Some(Node::Code(line)) => self.feed_line(*line, end)?,
                            _ => {
                                return Err(self.err(
                                    first,
                                    "the block the region's branches open is not closed by plain \
                                     code after `#endif`",
                                ));
                            }
                        }
                        k += 1;
                        if end.same_level(&start) && !self.else_follows(&nodes[tail_start + k..]) {
                            break;
                        }
                    }
                    if *tail_len.get_or_insert(k) != k {
                        return Err(self.err(
                            first,
                            "the region's branches close their blocks at different lines",
                        ));
                    }
                }
                let tail_len = tail_len.expect("two branches");
                let tail: Vec<Node> = nodes.drain(tail_start..tail_start + tail_len).collect();
                let Node::Cond(region) = &mut nodes[i] else {
                    unreachable!("the region is still at i");
                };
                if let Some(Node::Code(last)) = tail.last() {
                    region.end = *last;
                }
                for branch in &mut region.branches {
                    branch.body.extend(tail.iter().cloned());
                }
            }
            if self.else_follows(&nodes[i + 1..]) {
                return Err(self.err(
                    first,
                    "`else` after `#endif`: WESL attributes cannot select an `else` clause",
                ));
            }
            *scan = ends.swap_remove(0);
            i += 1;
        }
        Ok(())
    }

    /// The items of a branch at the region's level.
    fn analyse(
        &self,
        body: &[Node],
        start: &Scan,
        context: Context,
    ) -> Result<BranchInfo, CodegenError> {
        #[derive(PartialEq)]
        enum Item {
            Closed,
            Open,
            /// Closed by `}` unless `else` follows.
            MaybeClosed,
        }
        #[derive(PartialEq)]
        enum Decl {
            None,
            Keyword,
            Template,
        }
        let base = start.stack.len();
        let mut scan = start.clone();
        let mut info = BranchInfo::default();
        let mut item = Item::Closed;
        for (index, node) in body.iter().enumerate() {
            let line = match node {
                Node::Code(line) => *line,
                Node::Import(line) => return Err(self.err(*line, "`#import` in a region")),
                Node::Cond(region) => {
                    if scan.stack.len() == base {
                        if item == Item::Open {
                            return Err(self.err(
                                region.branches[0].directive,
                                "a conditional region inside a statement or declaration",
                            ));
                        }
                        item = Item::Closed;
                        info.nested = true;
                        for branch in &region.branches {
                            let nested = self.analyse(&branch.body, &scan, context)?;
                            info.decls.extend(nested.decls);
                        }
                    }
                    continue;
                }
            };
            let mut ended_here = false;
            let mut decl = Decl::None;
            for tok in self.toks(line) {
                let is_else = *tok == Tok::Ident("else".to_string());
                if item == Item::MaybeClosed {
                    item = if is_else { Item::Open } else { Item::Closed };
                }
                if item == Item::Closed {
                    if is_else {
                        return Err(self.err(
                            line,
                            "`else` at the start of a conditional region: WESL attributes \
                             cannot select an `else` clause",
                        ));
                    }
                    item = Item::Open;
                    info.crowded |= ended_here;
                    info.starts.push(index);
                }
                if context == Context::Statements && scan.stack.len() == base {
                    decl = match (decl, tok) {
                        (Decl::None, Tok::Ident(w)) if w == "let" || w == "var" || w == "const" => {
                            Decl::Keyword
                        }
                        (Decl::Keyword, Tok::Punct('<')) => Decl::Template,
                        (Decl::Template, Tok::Punct('>')) => Decl::Keyword,
                        (Decl::Template, _) => Decl::Template,
                        (Decl::Keyword, Tok::Ident(name)) => {
                            info.decls.insert(name.clone());
                            Decl::None
                        }
                        _ => Decl::None,
                    };
                }
                scan.feed(tok).map_err(|m| self.err(line, m))?;
                if scan.stack.len() < base {
                    return Err(self.err(
                        line,
                        "closes a bracket opened before the conditional region",
                    ));
                }
                if scan.stack.len() == base {
                    match (context, tok) {
                        (Context::List, Tok::Punct(','))
                        | (Context::Module | Context::Statements, Tok::Punct(';')) => {
                            item = Item::Closed;
                            ended_here = true;
                        }
                        (Context::Module | Context::Statements, Tok::Punct('}')) => {
                            item = Item::MaybeClosed;
                            ended_here = true;
                        }
                        _ => {}
                    }
                }
            }
        }
        Ok(info)
    }

    /// Whether a name declared in a region is named in the code after it, up to the end
    /// of the enclosing block.
    fn used_after(&self, region: &Region, names: &BTreeSet<String>) -> bool {
        if names.is_empty() {
            return false;
        }
        let mut depth = 0i32;
        for line in region.end + 1..self.lines.len() {
            for tok in self.toks(line) {
                match tok {
                    Tok::Punct('{') => depth += 1,
                    Tok::Punct('}') => {
                        depth -= 1;
                        if depth < 0 {
                            return false;
                        }
                    }
                    Tok::Ident(name) if names.contains(name) => return true,
                    _ => {}
                }
            }
        }
        false
    }

    fn push(&mut self, ctx: &Ctx, text: &str) {
        if text.trim().is_empty() {
            self.out.push(String::new());
        } else {
            self.out.push(format!("{}{text}", ctx.indent));
        }
    }

    /// Writes a node list; `attrs` holds an attribute line to write before the line
    /// at a body index.
    fn seq(
        &mut self,
        nodes: &[Node],
        ctx: &Ctx,
        attrs: &HashMap<usize, String>,
    ) -> Result<(), CodegenError> {
        for (index, node) in nodes.iter().enumerate() {
            match node {
                Node::Code(line) => {
                    let line = *line;
                    if let Line::Code { values, .. } = &self.lines[line] {
                        for name in values {
                            let on = Lit {
                                flag: name.clone(),
                                positive: true,
                            };
                            if !ctx.scope.contains(&on) {
                                return Err(self.err(
                                    line,
                                    format!(
                                        "`#{{{name}}}` outside `#ifdef {name}`: the constant \
                                         `constants::{name}` exists only where the flag is on"
                                    ),
                                ));
                            }
                        }
                    }
                    let text = self.text(line).to_string();
                    if let Some(attr) = attrs.get(&index) {
                        let attr_line = format!("{}{attr}", leading_ws(&text));
                        self.push(ctx, &attr_line);
                    }
                    let mut scan = std::mem::take(&mut self.scan);
                    let fed = self.feed_line(line, &mut scan);
                    self.scan = scan;
                    fed?;
                    self.push(ctx, &text);
                }
                Node::Import(line) => {
                    let Line::Directive {
                        directive: Directive::Import(import),
                        comment,
                    } = &self.lines[*line]
                    else {
                        unreachable!("import nodes are import directives");
                    };
                    let mut text = import.clone();
                    if let Some(comment) = comment {
                        text = format!("{text} {comment}");
                    }
                    for part in text.lines() {
                        self.push(ctx, part);
                    }
                }
                Node::Cond(region) => {
                    let depth = self.scan.stack.len();
                    let sub = Ctx {
                        indent: ctx.indent.clone(),
                        attr: if depth == ctx.base {
                            ctx.attr.clone()
                        } else {
                            Vec::new()
                        },
                        base: depth,
                        scope: ctx.scope.clone(),
                    };
                    self.region(region, &sub)?;
                }
            }
        }
        Ok(())
    }

    /// The indentation of a region's first code line.
    fn region_indent(&self, region: &Region) -> String {
        fn first(t: &Translator<'_>, nodes: &[Node]) -> Option<String> {
            nodes.iter().find_map(|node| match node {
                Node::Code(line) if !t.toks(*line).is_empty() => {
                    Some(leading_ws(t.text(*line)).to_string())
                }
                Node::Cond(region) => region.branches.iter().find_map(|b| first(t, &b.body)),
                _ => None,
            })
        }
        region
            .branches
            .iter()
            .find_map(|b| first(self, &b.body))
            .unwrap_or_default()
    }

    fn region(&mut self, region: &Region, ctx: &Ctx) -> Result<(), CodegenError> {
        let first = region.branches[0].directive;
        let context = self.scan.context().ok_or_else(|| {
            self.err(
                first,
                "a conditional region must enclose whole declarations, statements, parameters \
                 or struct members; this one starts inside an expression or a declaration",
            )
        })?;
        let start = self.scan.clone();
        let infos = region
            .branches
            .iter()
            .map(|b| self.analyse(&b.body, &start, context))
            .collect::<Result<Vec<_>, _>>()?;
        let single = infos.iter().all(|i| i.starts.len() <= 1 && !i.nested);
        let mode = match context {
            Context::List => Mode::PerItem,
            Context::Module if single => Mode::Single,
            Context::Module => Mode::Block,
            Context::Statements if single => Mode::Single,
            Context::Statements => {
                let decls: BTreeSet<String> =
                    infos.iter().flat_map(|i| i.decls.iter().cloned()).collect();
                if self.used_after(region, &decls) {
                    Mode::PerItem
                } else {
                    Mode::Block
                }
            }
        };
        if mode == Mode::PerItem
            && let Some((branch, _)) = region
                .branches
                .iter()
                .zip(&infos)
                .find(|(_, info)| info.crowded)
        {
            return Err(self.err(
                branch.directive,
                "several items on one line in a region whose items each need an `@if`; put \
                 each on its own line",
            ));
        }
        let indent = self.region_indent(region);
        let mut after_first = None;
        let last = region.branches.len() - 1;
        for (b, (branch, info)) in region.branches.iter().zip(&infos).enumerate() {
            self.scan = start.clone();
            let mut lits = ctx.attr.clone();
            lits.push(branch.lit.clone());
            let mut scope = ctx.scope.clone();
            scope.push(branch.lit.clone());
            let comment = self.comment(branch.directive).map(str::to_string);
            let endif_comment = if b == last {
                self.comment(region.endif).map(str::to_string)
            } else {
                None
            };
            let chained = b > 0 && ctx.attr.is_empty();
            match mode {
                Mode::Single | Mode::PerItem => {
                    if let Some(comment) = &comment {
                        self.push(ctx, &format!("{indent}{comment}"));
                    }
                    // A single item per branch chains with `@else`; items that each
                    // carry their own condition cannot.
                    let attr = if mode == Mode::Single && chained && !infos[0].starts.is_empty() {
                        "@else".to_string()
                    } else {
                        format!("@if({})", condition(&lits))
                    };
                    let attrs: HashMap<usize, String> =
                        info.starts.iter().map(|&s| (s, attr.clone())).collect();
                    let sub = Ctx {
                        indent: ctx.indent.clone(),
                        attr: lits,
                        base: start.stack.len(),
                        scope,
                    };
                    self.seq(&branch.body, &sub, &attrs)?;
                    if let Some(comment) = &endif_comment {
                        self.push(ctx, &format!("{indent}{comment}"));
                    }
                }
                Mode::Block => {
                    let head = if chained {
                        "@else {".to_string()
                    } else {
                        format!("@if({}) {{", condition(&lits))
                    };
                    let head = match &comment {
                        Some(comment) => format!("{indent}{head}  {comment}"),
                        None => format!("{indent}{head}"),
                    };
                    self.push(ctx, &head);
                    let sub = Ctx {
                        indent: format!("{}    ", ctx.indent),
                        attr: Vec::new(),
                        base: start.stack.len(),
                        scope,
                    };
                    self.seq(&branch.body, &sub, &HashMap::new())?;
                    let tail = match &endif_comment {
                        Some(comment) => format!("{indent}}}  {comment}"),
                        None => format!("{indent}}}"),
                    };
                    self.push(ctx, &tail);
                }
            }
            if !self.scan.same_level(&start) {
                return Err(self.err(branch.directive, "the branch leaves a bracket open"));
            }
            if b == 0 {
                after_first = Some(self.scan.clone());
            }
        }
        self.scan = after_first.expect("a region has a branch");
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wesl(source: &str) -> String {
        translate("test.wgsl", source).unwrap_or_else(|e| panic!("{e}"))
    }

    fn fails(source: &str) -> String {
        match translate("test.wgsl", source) {
            Ok(text) => panic!("translated:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

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

    #[test]
    fn single_items_get_if_and_else() {
        let text = wesl(
            "fn f() -> f32 {\n#ifdef A\n    // one\n    return 1.0;\n#else\n    return 2.0;\n#endif\n}\n",
        );
        assert_eq!(
            text,
            "fn f() -> f32 {\n    // one\n    @if(A)\n    return 1.0;\n    @else\n    return 2.0;\n}\n"
        );
    }

    #[test]
    fn several_statements_become_blocks() {
        let text = wesl(
            "fn f() -> f32 {\n#ifndef A\n    let x = 1.0;\n    return x;\n#else\n    return 2.0;\n#endif\n}\n",
        );
        assert_eq!(
            text,
            "fn f() -> f32 {\n    @if(!A) {\n        let x = 1.0;\n        return x;\n    }\n    \
             @else {\n        return 2.0;\n    }\n}\n"
        );
    }

    #[test]
    fn declarations_used_later_get_one_attribute_each() {
        let text = wesl(
            "fn f() -> f32 {\n#ifdef A\n    let x = 1.0;\n    let y = x;\n#else\n    let y = 2.0;\n\
             #ifdef B\n    let z = y;\n#endif\n#endif\n    return y;\n}\n",
        );
        assert_eq!(
            text,
            "fn f() -> f32 {\n    @if(A)\n    let x = 1.0;\n    @if(A)\n    let y = x;\n    \
             @if(!A)\n    let y = 2.0;\n    @if(!A && B)\n    let z = y;\n    return y;\n}\n"
        );
    }

    #[test]
    fn parameters_and_nested_module_regions() {
        let text = wesl(
            "fn f(\n    a: f32,\n#ifdef A\n    b: f32,\n#ifndef B\n    c: f32,\n#endif\n#endif\n) {}\n\
             #ifdef G\n@group(#{G}) @binding(0) var<uniform> u: f32;\n#ifdef S\n\
             @group(#{G}) @binding(1) var s: sampler;\n#endif\n#endif\n",
        );
        assert_eq!(
            text,
            "fn f(\n    a: f32,\n    @if(A)\n    b: f32,\n    @if(A && !B)\n    c: f32,\n) {}\n\
             @if(G) {\n    @group(constants::G) @binding(0) var<uniform> u: f32;\n    @if(S)\n    \
             @group(constants::G) @binding(1) var s: sampler;\n}\n"
        );
    }

    #[test]
    fn shared_block_tail_is_copied_into_each_branch() {
        let text = wesl(
            "fn f(a: bool, b: bool) {\n#ifdef A\n    if a && b {\n#else\n    if a {\n#endif\n        \
             return;\n    }\n}\n",
        );
        assert_eq!(
            text,
            "fn f(a: bool, b: bool) {\n    @if(A)\n    if a && b {\n        return;\n    }\n    \
             @else\n    if a {\n        return;\n    }\n}\n"
        );
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
