//! Writing a region's branches as WESL `@if` / `@else` attributes: one per item, one per
//! branch, or a conditional block per branch, with the enclosing conditions joined in.

use std::collections::{BTreeSet, HashMap};

use crate::CodegenError;

use super::analysis::Translator;
use super::lex::leading_ws;
use super::regions::{Directive, Line, Lit, Node, Region, condition};
use super::scan::Context;

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
pub(super) struct Ctx {
    /// Indentation added to every line (inside conditional blocks).
    indent: String,
    /// Conditions that attributes written at stack depth `base` must include.
    attr: Vec<Lit>,
    /// The stack depth at which `attr` applies.
    base: usize,
    /// Every enclosing branch's condition (for `#{N}`).
    scope: Vec<Lit>,
}

impl Translator<'_> {
    fn push(&mut self, ctx: &Ctx, text: &str) {
        if text.trim().is_empty() {
            self.out.push(String::new());
        } else {
            self.out.push(format!("{}{text}", ctx.indent));
        }
    }

    /// Writes a node list; `attrs` holds an attribute line to write before the line
    /// at a body index.
    pub(super) fn seq(
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
    use crate::wesl::tests::wesl;

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
}
