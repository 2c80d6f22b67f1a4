//! The loops of a shader in naga's IR: where they are, how they nest (through calls
//! too), a readable label for each (`froxel_scattering: i < tile_light_count`), and
//! the module with one of them taken out, which the time model compiles to measure
//! what the loop costs in ACO's figures.

use std::collections::HashMap;

use naga::{BinaryOperator, Block, Expression, Function, Handle, Module, Statement};

/// A function of a module: an entry point's or a free one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FunctionRef {
    /// The entry point at this index.
    Entry(usize),
    /// A function.
    Function(Handle<Function>),
}

/// A loop: its function and its ordinal among that function's loops (pre-order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LoopId {
    /// The function whose body holds it.
    pub function: FunctionRef,
    /// Its ordinal in that function.
    pub ordinal: usize,
}

/// One loop reachable from an entry point.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoopInfo {
    /// Where it is.
    pub id: LoopId,
    /// `function: condition`, unique within the entry point.
    pub label: String,
    /// The loop it runs in (index into the list), through calls too.
    pub parent: Option<usize>,
    /// Call paths from the entry point that reach it (each is a copy once inlined).
    pub sites: usize,
    /// Whether two paths reach it from different enclosing loops.
    pub ambiguous: bool,
}

fn function(module: &Module, f: FunctionRef) -> &Function {
    match f {
        FunctionRef::Entry(i) => &module.entry_points[i].function,
        FunctionRef::Function(h) => &module.functions[h],
    }
}

fn function_mut(module: &mut Module, f: FunctionRef) -> &mut Function {
    match f {
        FunctionRef::Entry(i) => &mut module.entry_points[i].function,
        FunctionRef::Function(h) => &mut module.functions[h],
    }
}

/// A name as written in the WGSL (naga_oil's decoration taken off).
fn plain(name: &str) -> String {
    volfog_codegen::names::undecorate(name).map_or_else(|| name.to_string(), |(item, _)| item)
}

fn function_name(module: &Module, f: FunctionRef) -> String {
    match f {
        FunctionRef::Entry(i) => module.entry_points[i].name.clone(),
        FunctionRef::Function(h) => plain(module.functions[h].name.as_deref().unwrap_or("?")),
    }
}

fn operator(op: BinaryOperator) -> &'static str {
    use BinaryOperator as B;
    match op {
        B::Add => "+",
        B::Subtract => "-",
        B::Multiply => "*",
        B::Divide => "/",
        B::Modulo => "%",
        B::Equal => "==",
        B::NotEqual => "!=",
        B::Less => "<",
        B::LessEqual => "<=",
        B::Greater => ">",
        B::GreaterEqual => ">=",
        B::And => "&",
        B::ExclusiveOr => "^",
        B::InclusiveOr => "|",
        B::LogicalAnd => "&&",
        B::LogicalOr => "||",
        B::ShiftLeft => "<<",
        B::ShiftRight => ">>",
    }
}

/// A short text for an expression: names where the WGSL gave one.
fn describe(module: &Module, f: &Function, e: Handle<Expression>, depth: u32) -> String {
    if let Some(name) = f.named_expressions.get(&e) {
        return plain(name);
    }
    if depth == 0 {
        return "..".to_string();
    }
    let d = |e| describe(module, f, e, depth - 1);
    match &f.expressions[e] {
        Expression::Literal(l) => match l {
            naga::Literal::U32(v) => format!("{v}u"),
            naga::Literal::I32(v) => format!("{v}"),
            naga::Literal::F32(v) => format!("{v}"),
            naga::Literal::Bool(v) => format!("{v}"),
            other => format!("{other:?}"),
        },
        Expression::Constant(c) => plain(module.constants[*c].name.as_deref().unwrap_or("const")),
        Expression::FunctionArgument(i) => f.arguments[*i as usize]
            .name
            .clone()
            .unwrap_or_else(|| format!("arg{i}")),
        // An unnamed local: what the frontend keeps a short-circuit condition in.
        Expression::LocalVariable(v) => f.local_variables[*v]
            .name
            .clone()
            .unwrap_or_else(|| "cond".to_string()),
        Expression::GlobalVariable(g) => plain(
            module.global_variables[*g]
                .name
                .as_deref()
                .unwrap_or("global"),
        ),
        Expression::Load { pointer } => d(*pointer),
        Expression::Binary { op, left, right } => {
            format!("{} {} {}", d(*left), operator(*op), d(*right))
        }
        Expression::Unary { expr, .. } => format!("!({})", d(*expr)),
        Expression::AccessIndex { base, index } => format!("{}.{index}", d(*base)),
        Expression::Access { base, index } => format!("{}[{}]", d(*base), d(*index)),
        Expression::Math { fun, arg, arg1, .. } => {
            let mut args = vec![d(*arg)];
            args.extend(arg1.map(d));
            format!("{}({})", format!("{fun:?}").to_lowercase(), args.join(", "))
        }
        Expression::ArrayLength(e) => format!("arrayLength({})", d(*e)),
        Expression::As { expr, .. } => d(*expr),
        Expression::CallResult(callee) => format!(
            "{}(..)",
            plain(module.functions[*callee].name.as_deref().unwrap_or("?"))
        ),
        _ => "..".to_string(),
    }
}

/// The loop's condition: the first `if` of its body that breaks out of it.
fn condition(module: &Module, f: &Function, body: &Block) -> String {
    let breaks = |b: &Block| matches!(b.iter().as_slice(), [Statement::Break]);
    for s in body.iter() {
        if let Statement::If {
            condition,
            accept,
            reject,
        } = s
        {
            if breaks(reject) && accept.is_empty() {
                return describe(module, f, *condition, 4);
            }
            if breaks(accept) && reject.is_empty() {
                return format!("until {}", describe(module, f, *condition, 4));
            }
        }
    }
    "loop".to_string()
}

struct Walk<'m> {
    module: &'m Module,
    loops: Vec<LoopInfo>,
    index: HashMap<LoopId, usize>,
    stack: Vec<usize>,
}

impl Walk<'_> {
    fn function(&mut self, f: FunctionRef) {
        let mut ordinal = 0;
        let body = &function(self.module, f).body;
        self.block(f, body, &mut ordinal);
    }

    fn block(&mut self, f: FunctionRef, block: &Block, ordinal: &mut usize) {
        for s in block.iter() {
            match s {
                Statement::Loop {
                    body, continuing, ..
                } => {
                    let id = LoopId {
                        function: f,
                        ordinal: *ordinal,
                    };
                    *ordinal += 1;
                    let parent = self.stack.last().copied();
                    let i = match self.index.get(&id) {
                        Some(&i) => {
                            self.loops[i].sites += 1;
                            if self.loops[i].parent != parent {
                                self.loops[i].ambiguous = true;
                            }
                            i
                        }
                        None => {
                            let func = function(self.module, f);
                            let label = format!(
                                "{}: {}",
                                function_name(self.module, f),
                                condition(self.module, func, body)
                            );
                            self.loops.push(LoopInfo {
                                id,
                                label,
                                parent,
                                sites: 1,
                                ambiguous: false,
                            });
                            self.index.insert(id, self.loops.len() - 1);
                            self.loops.len() - 1
                        }
                    };
                    self.stack.push(i);
                    self.block(f, body, ordinal);
                    self.block(f, continuing, ordinal);
                    self.stack.pop();
                }
                Statement::Block(b) => self.block(f, b, ordinal),
                Statement::If { accept, reject, .. } => {
                    self.block(f, accept, ordinal);
                    self.block(f, reject, ordinal);
                }
                Statement::Switch { cases, .. } => {
                    for c in cases {
                        self.block(f, &c.body, ordinal);
                    }
                }
                Statement::Call {
                    function: callee, ..
                } => {
                    self.function(FunctionRef::Function(*callee));
                }
                _ => {}
            }
        }
    }
}

/// Redirects every call of `block` (and of the functions it calls, recursively) so
/// that no function is called from two places: a function already called elsewhere
/// is copied for this call. `seen` holds the functions called so far.
fn unshare_block(module: &mut Module, f: FunctionRef, seen: &mut Vec<Handle<Function>>) {
    // The calls of this function, in order: (callee, result expression).
    let mut calls = Vec::new();
    collect_calls(&function(module, f).body, &mut calls);
    let mut redirects = Vec::new();
    for (callee, result) in calls {
        let target = if seen.contains(&callee) {
            let copy = module.functions[callee].clone();
            module.functions.append(copy, naga::Span::UNDEFINED)
        } else {
            callee
        };
        seen.push(target);
        redirects.push((callee, target, result));
    }
    let func = function_mut(module, f);
    let mut next = 0;
    redirect_calls(&mut func.body, &redirects, &mut next);
    for (_, target, result) in &redirects {
        if let Some(r) = result {
            func.expressions[*r] = Expression::CallResult(*target);
        }
    }
    for (_, target, _) in redirects {
        unshare_block(module, FunctionRef::Function(target), seen);
    }
}

type Call = (Handle<Function>, Option<Handle<Expression>>);
/// A call redirected: its callee, the function it calls now, its result expression.
type Redirect = (
    Handle<Function>,
    Handle<Function>,
    Option<Handle<Expression>>,
);

fn collect_calls(block: &Block, calls: &mut Vec<Call>) {
    for s in block.iter() {
        match s {
            Statement::Call {
                function, result, ..
            } => calls.push((*function, *result)),
            Statement::Block(b) => collect_calls(b, calls),
            Statement::If { accept, reject, .. } => {
                collect_calls(accept, calls);
                collect_calls(reject, calls);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                collect_calls(body, calls);
                collect_calls(continuing, calls);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    collect_calls(&c.body, calls);
                }
            }
            _ => {}
        }
    }
}

fn redirect_calls(block: &mut Block, redirects: &[Redirect], next: &mut usize) {
    for s in block.iter_mut() {
        match s {
            Statement::Call { function, .. } => {
                *function = redirects[*next].1;
                *next += 1;
            }
            Statement::Block(b) => redirect_calls(b, redirects, next),
            Statement::If { accept, reject, .. } => {
                redirect_calls(accept, redirects, next);
                redirect_calls(reject, redirects, next);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                redirect_calls(body, redirects, next);
                redirect_calls(continuing, redirects, next);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    redirect_calls(&mut c.body, redirects, next);
                }
            }
            _ => {}
        }
    }
}

/// `module` with every function that entry point `entry` reaches from two call sites
/// copied, so each call site has a function of its own (the driver inlines every
/// call, so the compiled code is the same): a loop in a function called twice is
/// then two loops, each in its own place. `None` when there is no such entry point.
pub fn unshare(module: &Module, entry: &str) -> Option<Module> {
    let index = module.entry_points.iter().position(|e| e.name == entry)?;
    let mut m = module.clone();
    unshare_block(&mut m, FunctionRef::Entry(index), &mut Vec::new());
    callees_first(&mut m);
    Some(m)
}

/// Reorders the functions so each comes after every function it calls (naga's
/// validator wants no call to a later function), remapping the calls.
fn callees_first(module: &mut Module) {
    fn visit(
        module: &Module,
        h: Handle<Function>,
        done: &mut HashMap<Handle<Function>, bool>,
        order: &mut Vec<Handle<Function>>,
    ) {
        if done.contains_key(&h) {
            return;
        }
        done.insert(h, true);
        let mut calls = Vec::new();
        collect_calls(&module.functions[h].body, &mut calls);
        for (callee, _) in calls {
            visit(module, callee, done, order);
        }
        order.push(h);
    }
    let mut done = HashMap::new();
    let mut order = Vec::new();
    let handles: Vec<Handle<Function>> = module.functions.iter().map(|(h, _)| h).collect();
    for h in handles {
        visit(module, h, &mut done, &mut order);
    }
    let mut arena = naga::Arena::new();
    let mut map = HashMap::new();
    for h in order {
        let span = module.functions.get_span(h);
        map.insert(h, arena.append(module.functions[h].clone(), span));
    }
    let remap = |f: &mut Function| {
        remap_block(&mut f.body, &map);
        for (_, e) in f.expressions.iter_mut() {
            if let Expression::CallResult(h) = e {
                *h = map[h];
            }
        }
    };
    for (_, f) in arena.iter_mut() {
        remap(f);
    }
    for ep in &mut module.entry_points {
        remap(&mut ep.function);
    }
    module.functions = arena;
}

fn remap_block(block: &mut Block, map: &HashMap<Handle<Function>, Handle<Function>>) {
    for s in block.iter_mut() {
        match s {
            Statement::Call { function, .. } => *function = map[function],
            Statement::Block(b) => remap_block(b, map),
            Statement::If { accept, reject, .. } => {
                remap_block(accept, map);
                remap_block(reject, map);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                remap_block(body, map);
                remap_block(continuing, map);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    remap_block(&mut c.body, map);
                }
            }
            _ => {}
        }
    }
}

/// Every loop reachable from entry point `entry` (its body and every function it
/// calls), in the order first reached; `None` when there is no such entry point.
pub fn loops(module: &Module, entry: &str) -> Option<Vec<LoopInfo>> {
    let index = module.entry_points.iter().position(|e| e.name == entry)?;
    let mut walk = Walk {
        module,
        loops: Vec::new(),
        index: HashMap::new(),
        stack: Vec::new(),
    };
    walk.function(FunctionRef::Entry(index));
    // Labels unique within the entry point.
    let mut seen: HashMap<String, usize> = HashMap::new();
    for l in &mut walk.loops {
        let n = seen.entry(l.label.clone()).or_insert(0);
        *n += 1;
        if *n > 1 {
            l.label = format!("{} #{n}", l.label);
        }
    }
    Some(walk.loops)
}

/// Puts loop number `target` (counting down) of `block` under `if never { }`.
fn take_out(block: &mut Block, target: &mut usize, never: Handle<Expression>) -> bool {
    for s in block.iter_mut() {
        let found = match s {
            Statement::Loop {
                body, continuing, ..
            } => {
                if *target == 0 {
                    let taken = std::mem::replace(s, Statement::Block(Block::new()));
                    *s = Statement::If {
                        condition: never,
                        accept: Block::from_vec(vec![taken]),
                        reject: Block::new(),
                    };
                    return true;
                }
                *target -= 1;
                take_out(body, target, never) || take_out(continuing, target, never)
            }
            Statement::Block(b) => take_out(b, target, never),
            Statement::If { accept, reject, .. } => {
                take_out(accept, target, never) || take_out(reject, target, never)
            }
            Statement::Switch { cases, .. } => cases
                .iter_mut()
                .any(|c| take_out(&mut c.body, target, never)),
            _ => false,
        };
        if found {
            return true;
        }
    }
    false
}

/// `module` with loop `id` taken out: it runs under `if false { }`, which the driver's
/// compiler folds away, so the code after it sees the variables it would have written
/// as they were before it (the loop stays in naga's IR, whose validator wants every
/// expression it evaluates). `None` when the function has no such loop.
pub fn without(module: &Module, id: LoopId) -> Option<Module> {
    let mut m = module.clone();
    let f = function_mut(&mut m, id.function);
    let never = f.expressions.append(
        Expression::Literal(naga::Literal::Bool(false)),
        naga::Span::UNDEFINED,
    );
    let mut target = id.ordinal;
    take_out(&mut f.body, &mut target, never).then_some(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: &str = "
        @group(0) @binding(0) var<storage, read_write> data: array<f32>;
        @group(0) @binding(1) var<uniform> count: vec4<u32>;

        fn inner(x: f32, n: u32) -> f32 {
            var y = x;
            for (var k = 0u; k < n; k++) {
                y = y * 1.5 + 0.25;
            }
            return y;
        }

        @compute @workgroup_size(64)
        fn main(@builtin(global_invocation_id) id: vec3<u32>) {
            var x = data[id.x];
            let steps = count.x;
            for (var i = 0u; i < steps; i++) {
                x = inner(x, count.y);
            }
            var j = 0u;
            while j < 3u {
                x += 1.0;
                j++;
            }
            data[id.x] = inner(x, 2u);
        }
    ";

    #[test]
    fn loops_nest_through_calls_and_are_labelled() {
        let module = naga::front::wgsl::parse_str(SOURCE).unwrap();
        let found = loops(&module, "main").unwrap();
        let labels: Vec<&str> = found.iter().map(|l| l.label.as_str()).collect();
        assert_eq!(labels, ["main: i < steps", "inner: k < n", "main: j < 3u"]);
        // `inner`'s loop is reached from inside the steps loop and from the top level.
        assert_eq!(found[0].parent, None);
        assert_eq!(found[1].parent, Some(0));
        assert_eq!(found[1].sites, 2);
        assert!(found[1].ambiguous);
        assert!(!found[0].ambiguous && !found[2].ambiguous);
        assert!(loops(&module, "nope").is_none());
    }

    /// Counts loops directly under an `if` whose condition is the literal `false`.
    fn count_guarded(block: &Block, n: &mut usize) {
        for s in block.iter() {
            match s {
                Statement::If { accept, reject, .. } => {
                    if matches!(accept.iter().as_slice(), [Statement::Loop { .. }])
                        && reject.is_empty()
                    {
                        *n += 1;
                    }
                    count_guarded(accept, n);
                    count_guarded(reject, n);
                }
                Statement::Loop {
                    body, continuing, ..
                } => {
                    count_guarded(body, n);
                    count_guarded(continuing, n);
                }
                Statement::Block(b) => count_guarded(b, n),
                _ => {}
            }
        }
    }

    #[test]
    fn unshared_functions_give_each_call_its_own_loop() {
        let module = naga::front::wgsl::parse_str(SOURCE).unwrap();
        let m = unshare(&module, "main").unwrap();
        crate::pipeline::validate(&m, "unshared").unwrap();
        let found = loops(&m, "main").unwrap();
        let labels: Vec<&str> = found.iter().map(|l| l.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "main: i < steps",
                "inner: k < n",
                "main: j < 3u",
                "inner: k < n #2"
            ]
        );
        assert!(found.iter().all(|l| l.sites == 1 && !l.ambiguous));
        assert_eq!(found[1].parent, Some(0));
        assert_eq!(found[3].parent, None);
    }

    #[test]
    fn a_loop_taken_out_leaves_a_valid_module_without_it() {
        let module = naga::front::wgsl::parse_str(SOURCE).unwrap();
        let found = loops(&module, "main").unwrap();
        for l in &found {
            let m = without(&module, l.id).unwrap();
            crate::pipeline::validate(&m, &l.label).unwrap();
            // The loop now sits under `if false`, first thing in its place.
            let body = &super::function(&m, l.id.function).body;
            let mut guarded = 0;
            count_guarded(body, &mut guarded);
            assert_eq!(guarded, 1, "{}", l.label);
        }
        let missing = LoopId {
            ordinal: 7,
            ..found[0].id
        };
        assert!(without(&module, missing).is_none());
    }
}
