//! Expressions and statement blocks of the L-system language: parsing into a
//! tree, then compiling into a small stack program with slots for module
//! parameters and local variables.
//!
//! The operators are C's (`+ - * / %`, comparisons, `&& || !`, `?:`) plus `^`
//! (or `**`) for powers, as in cpfg (Prusinkiewicz, Hanan & Měch 2000,
//! "An L-system-based plant modeling language"). Trigonometric functions take
//! and return degrees, as cpfg's do. Statements are `name = expr;`,
//! `if (c) { … } else { … }` and `while (c) { … }`.

use super::text::{Cursor, MAX_NESTING};
use super::vm::{BinOp, Code, Func, Op};
use crate::error::{PlantError, Result, Span};
use std::cell::Cell;
use std::collections::HashMap;

/// An operator joining the terms of a left-associative chain.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Link {
    Bin(BinOp),
    And,
    Or,
}

/// An expression tree.
///
/// Operators of one precedence level are kept as one flat [`Expr::Chain`]
/// (`a + b - c + …`), so a long sum parses, compiles and drops without
/// recursing once per term; everything that nests (parentheses, prefix
/// operators, `^`, `?:`) is limited to [`MAX_NESTING`] levels by the parser.
#[derive(Clone, Debug)]
pub(crate) enum Expr {
    Num(f64),
    Var(String, Span),
    Unary(char, Box<Expr>, Span),
    /// `a ^ b` (right-associative).
    Pow(Box<Expr>, Box<Expr>, Span),
    /// `a op b op c …`: the first term, then each operator, term and the
    /// operator's position, evaluated left to right.
    Chain(Box<Expr>, Vec<(Link, Expr, Span)>),
    Cond(Box<Expr>, Box<Expr>, Box<Expr>),
    Call(String, Vec<Expr>, Span),
    Index(String, Box<Expr>, Span),
}

/// A statement of a block.
#[derive(Clone, Debug)]
pub(crate) enum Stmt {
    Assign(String, Expr, Span),
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    While(Expr, Vec<Stmt>, Span),
}

/// A `#define`: an object-like or function-like macro.
#[derive(Clone, Debug)]
pub(crate) struct Macro {
    pub params: Vec<String>,
    pub body: Expr,
}

/// Names known when an expression is compiled.
#[derive(Debug, Default)]
pub(crate) struct Globals {
    pub macros: HashMap<String, Macro>,
    pub arrays: HashMap<String, u16>,
    /// Operations compiled so far from the whole text (bounded by [`MAX_OPS`]).
    pub compiled: Cell<usize>,
}

/// The most operations the programs of one L-system text may compile to, in
/// all (macros that expand into each other can otherwise grow exponentially).
pub(crate) const MAX_OPS: usize = 1 << 22;

/// The deepest an expression may nest once its macros are expanded.
const MAX_COMPILE_DEPTH: u32 = 4 * MAX_NESTING;

/// Parses an expression, stopping at a character in `stop` at depth 0 (or the end).
pub(crate) fn parse_expr(cur: &mut Cursor<'_>) -> Result<Expr> {
    parse_ternary(cur)
}

fn parse_ternary(cur: &mut Cursor<'_>) -> Result<Expr> {
    cur.enter()?;
    let c = parse_or(cur)?;
    let r = if cur.eat('?') {
        let a = parse_ternary(cur)?;
        cur.expect(':', "in `c ? a : b`")?;
        let b = parse_ternary(cur)?;
        Expr::Cond(Box::new(c), Box::new(a), Box::new(b))
    } else {
        c
    };
    cur.leave();
    Ok(r)
}

/// Parses `term (op term)*` into one flat chain.
fn chain(
    cur: &mut Cursor<'_>,
    term: fn(&mut Cursor<'_>) -> Result<Expr>,
    op: fn(&mut Cursor<'_>) -> Option<(Link, Span)>,
) -> Result<Expr> {
    let first = term(cur)?;
    let mut rest = Vec::new();
    while let Some((link, span)) = op(cur) {
        rest.push((link, term(cur)?, span));
    }
    Ok(if rest.is_empty() {
        first
    } else {
        Expr::Chain(Box::new(first), rest)
    })
}

fn parse_or(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_and, |cur| {
        cur.eat_str("||").then_some((Link::Or, Span::default()))
    })
}

fn parse_and(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_eq, |cur| {
        cur.eat_str("&&").then_some((Link::And, Span::default()))
    })
}

fn parse_eq(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_cmp, |cur| {
        cur.skip_ws();
        let span = cur.span();
        let op = if cur.eat_str("==") {
            BinOp::Eq
        } else if cur.eat_str("!=") {
            BinOp::Ne
        } else {
            return None;
        };
        Some((Link::Bin(op), span))
    })
}

fn parse_cmp(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_add, |cur| {
        cur.skip_ws();
        let span = cur.span();
        let op = if cur.eat_str("<=") || cur.eat_str("≤") {
            BinOp::Le
        } else if cur.eat_str(">=") || cur.eat_str("≥") {
            BinOp::Ge
        } else if cur.peek() == Some('<') {
            cur.bump();
            BinOp::Lt
        } else if cur.peek() == Some('>') {
            cur.bump();
            BinOp::Gt
        } else {
            return None;
        };
        Some((Link::Bin(op), span))
    })
}

fn parse_add(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_mul, |cur| {
        cur.skip_ws();
        let span = cur.span();
        let op = match cur.peek() {
            Some('+') => BinOp::Add,
            Some('-') if cur.peek_at(1) != Some('>') => BinOp::Sub,
            _ => return None,
        };
        cur.bump();
        Some((Link::Bin(op), span))
    })
}

fn parse_mul(cur: &mut Cursor<'_>) -> Result<Expr> {
    chain(cur, parse_unary, |cur| {
        cur.skip_ws();
        let span = cur.span();
        let op = match (cur.peek(), cur.peek_at(1)) {
            (Some('*'), Some('*')) => return None,
            (Some('*'), _) => BinOp::Mul,
            (Some('/'), _) => BinOp::Div,
            (Some('%'), _) => BinOp::Rem,
            _ => return None,
        };
        cur.bump();
        Some((Link::Bin(op), span))
    })
}

fn parse_unary(cur: &mut Cursor<'_>) -> Result<Expr> {
    // Prefix operators are read in a loop, each one a level of nesting.
    let mut prefix = Vec::new();
    let r = loop {
        cur.skip_ws();
        let span = cur.span();
        match cur.peek() {
            Some('-') => prefix.push(('-', span)),
            Some('+') => {
                cur.bump();
                continue;
            }
            Some('!') if cur.peek_at(1) != Some('=') => prefix.push(('!', span)),
            _ => break parse_pow(cur),
        }
        cur.bump();
        if let Err(e) = cur.enter() {
            break Err(e);
        }
    };
    let mut e = r?;
    for (op, span) in prefix.into_iter().rev() {
        e = Expr::Unary(op, Box::new(e), span);
        cur.leave();
    }
    Ok(e)
}

fn parse_pow(cur: &mut Cursor<'_>) -> Result<Expr> {
    let a = parse_postfix(cur)?;
    cur.skip_ws();
    let span = cur.span();
    if cur.eat_str("**") || cur.eat('^') {
        // Right-associative; the exponent may carry a sign.
        cur.enter()?;
        let b = parse_unary(cur)?;
        cur.leave();
        return Ok(Expr::Pow(Box::new(a), Box::new(b), span));
    }
    Ok(a)
}

fn parse_number(cur: &mut Cursor<'_>) -> Result<Expr> {
    let span = cur.span();
    let mut s = String::new();
    while let Some(c) = cur.peek() {
        let exp_sign = (c == '-' || c == '+') && s.ends_with(['e', 'E']);
        if c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E' || exp_sign {
            // `e` only continues a number when a digit or sign follows it.
            if (c == 'e' || c == 'E')
                && !cur
                    .peek_at(1)
                    .is_some_and(|d| d.is_ascii_digit() || d == '-' || d == '+')
            {
                break;
            }
            s.push(c);
            cur.bump();
        } else {
            break;
        }
    }
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .map(Expr::Num)
        .ok_or_else(|| PlantError::syntax(span, format!("malformed number `{s}`")))
}

fn parse_postfix(cur: &mut Cursor<'_>) -> Result<Expr> {
    cur.skip_ws();
    let span = cur.span();
    match cur.peek() {
        Some(c) if c.is_ascii_digit() || c == '.' => parse_number(cur),
        Some('(') => {
            cur.bump();
            let e = parse_expr(cur)?;
            cur.expect(')', "to close `(`")?;
            Ok(e)
        }
        Some('π') => {
            cur.bump();
            Ok(Expr::Num(std::f64::consts::PI))
        }
        Some(_) => {
            let Some(name) = cur.ident() else {
                let c = cur.peek().unwrap_or(' ');
                return Err(PlantError::syntax(
                    span,
                    format!("expected an expression, found `{c}`"),
                ));
            };
            cur.skip_ws();
            if cur.peek() == Some('(') {
                cur.bump();
                let mut args = Vec::new();
                if !cur.eat(')') {
                    loop {
                        args.push(parse_expr(cur)?);
                        if cur.eat(')') {
                            break;
                        }
                        cur.expect(',', "between arguments")?;
                    }
                }
                Ok(Expr::Call(name, args, span))
            } else if cur.peek() == Some('[') {
                cur.bump();
                let i = parse_expr(cur)?;
                cur.expect(']', "to close the array index")?;
                Ok(Expr::Index(name, Box::new(i), span))
            } else {
                Ok(Expr::Var(name, span))
            }
        }
        None => Err(PlantError::syntax(
            span,
            "expected an expression, found end of line",
        )),
    }
}

/// Parses statements up to (not including) a closing `}` or the end.
pub(crate) fn parse_block(cur: &mut Cursor<'_>) -> Result<Vec<Stmt>> {
    let mut out = Vec::new();
    loop {
        cur.skip_ws();
        if cur.peek().is_none() || cur.peek() == Some('}') {
            return Ok(out);
        }
        if cur.eat(';') {
            continue;
        }
        let span = cur.span();
        let save = cur.pos;
        let name = cur.ident().ok_or_else(|| {
            PlantError::syntax(span, "expected a statement (`name = expr;`, `if`, `while`)")
        })?;
        match name.as_str() {
            "if" => {
                cur.expect('(', "after `if`")?;
                let c = parse_expr(cur)?;
                cur.expect(')', "after the condition of `if`")?;
                let then = parse_braced_or_single(cur)?;
                let save2 = cur.pos;
                let els = if cur.ident().as_deref() == Some("else") {
                    parse_braced_or_single(cur)?
                } else {
                    cur.pos = save2;
                    Vec::new()
                };
                out.push(Stmt::If(c, then, els));
            }
            "while" => {
                cur.expect('(', "after `while`")?;
                let c = parse_expr(cur)?;
                cur.expect(')', "after the condition of `while`")?;
                let body = parse_braced_or_single(cur)?;
                out.push(Stmt::While(c, body, span));
            }
            _ => {
                if !cur.eat('=') || cur.peek() == Some('=') {
                    cur.pos = save;
                    return Err(PlantError::syntax(span, format!("expected `{name} = …;`")));
                }
                let e = parse_expr(cur)?;
                out.push(Stmt::Assign(name, e, span));
                cur.skip_ws();
                if cur.peek() != Some('}') && cur.peek().is_some() {
                    cur.expect(';', "after an assignment")?;
                }
            }
        }
    }
}

fn parse_braced_or_single(cur: &mut Cursor<'_>) -> Result<Vec<Stmt>> {
    cur.enter()?;
    let r = braced_or_single(cur);
    cur.leave();
    r
}

fn braced_or_single(cur: &mut Cursor<'_>) -> Result<Vec<Stmt>> {
    if cur.eat('{') {
        let b = parse_block(cur)?;
        cur.expect('}', "to close the block")?;
        Ok(b)
    } else {
        // A single statement.
        let span = cur.span();
        let name = cur
            .ident()
            .ok_or_else(|| PlantError::syntax(span, "expected a statement"))?;
        cur.expect('=', "in an assignment")?;
        let e = parse_expr(cur)?;
        cur.eat(';');
        Ok(vec![Stmt::Assign(name, e, span)])
    }
}

/// The local variables of one production: parameter names first, then locals.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scope {
    pub names: Vec<String>,
}

impl Scope {
    pub fn slot(&self, name: &str) -> Option<u16> {
        self.names.iter().rposition(|n| n == name).map(|i| i as u16)
    }

    pub fn slot_or_new(&mut self, name: &str, span: Span) -> Result<u16> {
        if let Some(s) = self.slot(name) {
            return Ok(s);
        }
        if self.names.len() >= u16::MAX as usize {
            return Err(PlantError::syntax(
                span,
                "too many variables in one production",
            ));
        }
        self.names.push(name.to_string());
        Ok((self.names.len() - 1) as u16)
    }
}

/// The arguments of the macro whose body is being compiled: each parameter
/// is bound to its argument as written at the call, which compiles in the
/// caller's own bindings (so nothing is copied or substituted).
struct Bindings<'e, 'p> {
    params: &'e [String],
    args: &'e [Expr],
    caller: Option<&'p Bindings<'e, 'p>>,
}

impl<'e> Bindings<'e, '_> {
    fn get(&self, name: &str) -> Option<&'e Expr> {
        self.params
            .iter()
            .rposition(|p| p == name)
            .map(|k| &self.args[k])
    }
}

/// Compiles expressions and blocks against a scope and the globals.
#[derive(Debug)]
pub(crate) struct Compiler<'g> {
    pub globals: &'g Globals,
    pub scope: Scope,
    ops: Vec<Op>,
    spans: Vec<Span>,
    /// Macro expansions open.
    depth: u32,
    /// Expression levels being compiled (with macros expanded).
    nest: u32,
}

impl<'g> Compiler<'g> {
    pub fn new(globals: &'g Globals, scope: Scope) -> Self {
        Self {
            globals,
            scope,
            ops: Vec::new(),
            spans: Vec::new(),
            depth: 0,
            nest: 0,
        }
    }

    fn emit(&mut self, op: Op, span: Span) -> usize {
        self.ops.push(op);
        self.spans.push(span);
        self.ops.len() - 1
    }

    fn finish(&mut self, span: Span) -> Code {
        let ops = std::mem::take(&mut self.ops);
        let spans = std::mem::take(&mut self.spans);
        self.globals
            .compiled
            .set(self.globals.compiled.get() + ops.len());
        Code::new(ops, spans, span)
    }

    /// Compiles an expression into a program that leaves one value.
    pub fn expr(&mut self, e: &Expr, span: Span) -> Result<Code> {
        let r = self.lower(e, None, span);
        self.settle(r, span)
    }

    /// Compiles a block into a program that leaves nothing.
    pub fn block(&mut self, b: &[Stmt], span: Span) -> Result<Code> {
        let r = self.gen_block(b, span);
        self.settle(r, span)
    }

    /// Ends a compilation: the depth counters reset, and the program is
    /// taken, or on an error dropped.
    fn settle(&mut self, r: Result<()>, span: Span) -> Result<Code> {
        self.nest = 0;
        self.depth = 0;
        if let Err(err) = r {
            self.ops.clear();
            self.spans.clear();
            return Err(err);
        }
        Ok(self.finish(span))
    }

    fn gen_block(&mut self, b: &[Stmt], at: Span) -> Result<()> {
        for s in b {
            match s {
                Stmt::Assign(name, e, span) => {
                    self.lower(e, None, *span)?;
                    let slot = self.scope.slot_or_new(name, *span)?;
                    self.emit(Op::Store(slot), *span);
                }
                Stmt::If(c, then, els) => {
                    self.lower(c, None, at)?;
                    let jf = self.emit(Op::JumpIfFalse(0), Span::default());
                    self.gen_block(then, at)?;
                    if els.is_empty() {
                        let here = self.ops.len() as u32;
                        self.ops[jf] = Op::JumpIfFalse(here);
                    } else {
                        let j = self.emit(Op::Jump(0), Span::default());
                        self.ops[jf] = Op::JumpIfFalse(self.ops.len() as u32);
                        self.gen_block(els, at)?;
                        let here = self.ops.len() as u32;
                        self.ops[j] = Op::Jump(here);
                    }
                }
                Stmt::While(c, body, span) => {
                    let top = self.ops.len() as u32;
                    self.lower(c, None, *span)?;
                    let jf = self.emit(Op::JumpIfFalse(0), *span);
                    self.gen_block(body, *span)?;
                    self.emit(Op::Loop(top), *span);
                    let here = self.ops.len() as u32;
                    self.ops[jf] = Op::JumpIfFalse(here);
                }
            }
        }
        Ok(())
    }

    /// Compiles `e`; `at` is the nearest position known, for errors.
    fn lower<'e>(&mut self, e: &'e Expr, b: Option<&Bindings<'e, '_>>, at: Span) -> Result<()> {
        let at = match e {
            Expr::Var(_, s)
            | Expr::Unary(_, _, s)
            | Expr::Pow(_, _, s)
            | Expr::Call(_, _, s)
            | Expr::Index(_, _, s) => *s,
            _ => at,
        };
        if self.globals.compiled.get() + self.ops.len() >= MAX_OPS {
            return Err(PlantError::syntax(
                at,
                format!(
                    "the expressions compile to more than {MAX_OPS} operations in all (macros that double at each level?)"
                ),
            ));
        }
        self.nest += 1;
        if self.nest > MAX_COMPILE_DEPTH {
            return Err(PlantError::syntax(
                at,
                format!(
                    "expression nested deeper than {MAX_COMPILE_DEPTH} levels once its macros are expanded"
                ),
            ));
        }
        self.lower_inner(e, b, at)?;
        self.nest -= 1;
        Ok(())
    }

    fn lower_inner<'e>(
        &mut self,
        e: &'e Expr,
        b: Option<&Bindings<'e, '_>>,
        at: Span,
    ) -> Result<()> {
        match e {
            Expr::Num(v) => {
                self.emit(Op::Const(*v), Span::default());
            }
            Expr::Var(name, span) => return self.lower_var(name, b, *span),
            Expr::Unary(op, a, span) => {
                self.lower(a, b, *span)?;
                self.emit(if *op == '-' { Op::Neg } else { Op::Not }, *span);
            }
            Expr::Pow(x, y, span) => {
                self.lower(x, b, *span)?;
                self.lower(y, b, *span)?;
                self.emit(Op::Bin(BinOp::Pow), *span);
            }
            Expr::Chain(first, rest) => {
                self.lower(first, b, at)?;
                for (link, x, span) in rest {
                    self.lower_link(*link, x, b, at, *span)?;
                }
            }
            Expr::Cond(c, x, y) => {
                self.lower(c, b, at)?;
                let jf = self.emit(Op::JumpIfFalse(0), Span::default());
                self.lower(x, b, at)?;
                let j = self.emit(Op::Jump(0), Span::default());
                self.ops[jf] = Op::JumpIfFalse(self.ops.len() as u32);
                self.lower(y, b, at)?;
                let here = self.ops.len() as u32;
                self.ops[j] = Op::Jump(here);
            }
            Expr::Index(name, i, span) => {
                let Some(&arr) = self.globals.arrays.get(name.as_str()) else {
                    return Err(PlantError::Undefined {
                        span: *span,
                        what: "array",
                        name: name.clone(),
                    });
                };
                self.lower(i, b, *span)?;
                self.emit(Op::Index(arr), *span);
            }
            Expr::Call(name, a, span) => return self.lower_call(name, a, b, *span),
        }
        Ok(())
    }

    /// A variable: a bound macro argument, a local slot, a macro without
    /// parameters or a named constant, in that order.
    fn lower_var<'e>(
        &mut self,
        name: &str,
        b: Option<&Bindings<'e, '_>>,
        span: Span,
    ) -> Result<()> {
        let g: &'g Globals = self.globals;
        if let Some(bind) = b
            && let Some(a) = bind.get(name)
        {
            return self.lower(a, bind.caller, span);
        }
        if let Some(slot) = self.scope.slot(name) {
            self.emit(Op::Load(slot), span);
        } else if let Some(m) = g.macros.get(name) {
            if !m.params.is_empty() {
                return Err(PlantError::syntax(
                    span,
                    format!("macro `{name}` takes {} arguments", m.params.len()),
                ));
            }
            self.expand(m, &[], None, span)?;
        } else if let Some(v) = constant(name) {
            self.emit(Op::Const(v), span);
        } else {
            return Err(PlantError::Undefined {
                span,
                what: "variable",
                name: name.to_owned(),
            });
        }
        Ok(())
    }

    /// One link of a chain: a binary operator, or a short-circuit `&&`/`||`
    /// whose jump is patched past the right operand.
    fn lower_link<'e>(
        &mut self,
        link: Link,
        x: &'e Expr,
        b: Option<&Bindings<'e, '_>>,
        at: Span,
        span: Span,
    ) -> Result<()> {
        match link {
            Link::Bin(op) => {
                self.lower(x, b, span)?;
                self.emit(Op::Bin(op), span);
            }
            Link::And | Link::Or => {
                let j = self.emit(
                    if matches!(link, Link::And) {
                        Op::AndJump(0)
                    } else {
                        Op::OrJump(0)
                    },
                    Span::default(),
                );
                self.lower(x, b, at)?;
                self.emit(Op::ToBool, Span::default());
                let here = self.ops.len() as u32;
                self.ops[j] = if matches!(link, Link::And) {
                    Op::AndJump(here)
                } else {
                    Op::OrJump(here)
                };
            }
        }
        Ok(())
    }

    /// A call: a macro with its arguments, or a built-in function of the
    /// right arity.
    fn lower_call<'e>(
        &mut self,
        name: &str,
        a: &'e [Expr],
        b: Option<&Bindings<'e, '_>>,
        span: Span,
    ) -> Result<()> {
        let g: &'g Globals = self.globals;
        if let Some(m) = g.macros.get(name) {
            if m.params.len() != a.len() {
                return Err(PlantError::syntax(
                    span,
                    format!(
                        "macro `{name}` takes {} arguments, {} given",
                        m.params.len(),
                        a.len()
                    ),
                ));
            }
            // Arguments are bound as expressions (C's macro semantics,
            // but hygienic: each argument is one parenthesised operand).
            return self.expand(m, a, b, span);
        }
        let Some((f, arity)) = Func::lookup(name) else {
            return Err(PlantError::Undefined {
                span,
                what: "function",
                name: name.to_owned(),
            });
        };
        if !arity.contains(&a.len()) {
            return Err(PlantError::syntax(
                span,
                format!(
                    "function `{name}` takes {arity:?} arguments, {} given",
                    a.len()
                ),
            ));
        }
        for x in a {
            self.lower(x, b, span)?;
        }
        self.emit(Op::Call(f, a.len() as u8), span);
        Ok(())
    }

    /// Compiles the body of macro `m` with its parameters bound to `args`
    /// (which compile in the caller's bindings `caller`).
    fn expand<'e>(
        &mut self,
        m: &'e Macro,
        args: &'e [Expr],
        caller: Option<&Bindings<'e, '_>>,
        span: Span,
    ) -> Result<()> {
        self.depth += 1;
        if self.depth > 64 {
            return Err(PlantError::syntax(
                span,
                "macro expansion nested deeper than 64 (recursive #define?)",
            ));
        }
        let bind = Bindings {
            params: &m.params,
            args,
            caller,
        };
        let r = self.lower(&m.body, Some(&bind), span);
        self.depth -= 1;
        r
    }
}

/// Named constants of the language.
fn constant(name: &str) -> Option<f64> {
    match name {
        "pi" | "PI" | "M_PI" => Some(std::f64::consts::PI),
        "M_E" => Some(std::f64::consts::E),
        _ => None,
    }
}
