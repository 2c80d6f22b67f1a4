//! Lexing: a line's code and comment pieces, and the tokens of its code.

/// A piece of a line: code, or (part of) a comment.
pub(super) struct Piece {
    pub(super) code: bool,
    pub(super) range: std::ops::Range<usize>,
}

/// Splits a line into code and comment pieces. `depth` is the nesting of WGSL block
/// comments, carried from line to line.
pub(super) fn split_comments(line: &str, depth: &mut u32) -> Vec<Piece> {
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
pub(super) enum Tok {
    /// An identifier or keyword.
    Ident(String),
    /// A number literal.
    Number,
    /// Any other character.
    Punct(char),
}

pub(super) fn tokens(code: &str) -> Vec<Tok> {
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

pub(super) fn is_ident(text: &str) -> bool {
    let mut chars = text.chars();
    matches!(chars.next(), Some(c) if c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

pub(super) fn leading_ws(text: &str) -> &str {
    &text[..text.len() - text.trim_start().len()]
}
