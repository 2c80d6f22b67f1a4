//! Following WGSL's structure: the brackets a line opens and closes, and where a
//! conditional region starting at a point stands (module scope, statements, a list).

use super::lex::Tok;

/// What an open bracket encloses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Frame {
    Params,
    FnBody,
    Block,
    Struct,
    Paren,
    Bracket,
}

/// How far a `fn` or `struct` header has come at module scope.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) enum Header {
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
pub(super) enum Prev {
    #[default]
    Start,
    Punct(char),
    Other,
}

/// Where a conditional region stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Context {
    /// Between module-scope declarations.
    Module,
    /// Between statements of a function body or block.
    Statements,
    /// Between function parameters or struct members.
    List,
}

/// The bracket structure of the code read so far.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct Scan {
    pub(super) stack: Vec<Frame>,
    header: Header,
    prev: Prev,
}

impl Scan {
    pub(super) fn feed(&mut self, tok: &Tok) -> Result<(), String> {
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
                    ']' => match self.stack.pop() {
                        Some(Frame::Bracket) => {}
                        _ => return Err("`]` without a matching `[`".to_string()),
                    },
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
    pub(super) fn context(&self) -> Option<Context> {
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
    pub(super) fn same_level(&self, other: &Scan) -> bool {
        self.stack == other.stack && self.header == other.header
    }
}
