//! The translator over a module's classified lines, and what the branches of a region
//! hold: balanced brackets (copying a shared block tail into each branch), the items at
//! the region's level, and declarations used after it.

use std::collections::BTreeSet;

use crate::CodegenError;

use super::lex::Tok;
use super::regions::{Line, Node, Region, error};
use super::scan::{Context, Scan};

/// What a branch of a region holds at the region's level.
#[derive(Debug, Default)]
pub(super) struct BranchInfo {
    /// Body index of the line each item starts on.
    pub(super) starts: Vec<usize>,
    /// Whether a nested region stands between items.
    pub(super) nested: bool,
    /// Whether an item starts on a line where another ended.
    pub(super) crowded: bool,
    /// Names declared by `let` / `var` / `const` at the region's level.
    pub(super) decls: BTreeSet<String>,
}

/// Translates one module: its classified lines, the output written so far and the
/// bracket structure of the code written so far.
pub(super) struct Translator<'a> {
    pub(super) file: &'a str,
    pub(super) lines: &'a [Line],
    pub(super) out: Vec<String>,
    pub(super) scan: Scan,
}

impl Translator<'_> {
    pub(super) fn err(&self, line: usize, message: impl Into<String>) -> CodegenError {
        error(self.file, line, message)
    }

    pub(super) fn toks(&self, line: usize) -> &[Tok] {
        match &self.lines[line] {
            Line::Code { toks, .. } => toks,
            _ => &[],
        }
    }

    pub(super) fn text(&self, line: usize) -> &str {
        match &self.lines[line] {
            Line::Code { text, .. } => text,
            _ => "",
        }
    }

    pub(super) fn comment(&self, line: usize) -> Option<&str> {
        match &self.lines[line] {
            Line::Directive { comment, .. } => comment.as_deref(),
            _ => None,
        }
    }

    pub(super) fn feed_line(&self, line: usize, scan: &mut Scan) -> Result<(), CodegenError> {
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
    pub(super) fn balance(
        &self,
        nodes: &mut Vec<Node>,
        scan: &mut Scan,
    ) -> Result<(), CodegenError> {
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
    pub(super) fn analyse(
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
    pub(super) fn used_after(&self, region: &Region, names: &BTreeSet<String>) -> bool {
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
}

#[cfg(test)]
mod tests {
    use crate::wesl::tests::wesl;

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
}
