//! Expressions and statement blocks of the L-system language: parsing into a
//! tree, then compiling into a small stack program with slots for module
//! parameters and local variables.
//!
//! The operators are C's (`+ - * / %`, comparisons, `&& || !`, `?:`) plus `^`
//! (or `**`) for powers, as in cpfg (Prusinkiewicz, Hanan & Měch 2000,
//! "An L-system-based plant modeling language"). Trigonometric functions take
//! and return degrees, as cpfg's do. Statements are `name = expr;`,
//! `if (c) { … } else { … }` and `while (c) { … }`.

use super::text::Cursor;
use super::vm::{BinOp, Code, Func, Op};
use crate::error::{PlantError, Result, Span};
use std::collections::HashMap;

/// An expression tree.
#[derive(Clone, Debug)]
pub(crate) enum Expr {
    Num(f64),
    Var(String, Span),
    Unary(char, Box<Expr>, Span),
    Bin(BinOp, Box<Expr>, Box<Expr>, Span),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
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
}

/// Parses an expression, stopping at a character in `stop` at depth 0 (or the end).
pub(crate) fn parse_expr(cur: &mut Cursor<'_>) -> Result<Expr> {
    parse_ternary(cur)
}

fn parse_ternary(cur: &mut Cursor<'_>) -> Result<Expr> {
    let c = parse_or(cur)?;
    if cur.eat('?') {
        let a = parse_ternary(cur)?;
        cur.expect(':', "in `c ? a : b`")?;
        let b = parse_ternary(cur)?;
        return Ok(Expr::Cond(Box::new(c), Box::new(a), Box::new(b)));
    }
    Ok(c)
}

fn parse_or(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_and(cur)?;
    while cur.eat_str("||") {
        let b = parse_and(cur)?;
        a = Expr::Or(Box::new(a), Box::new(b));
    }
    Ok(a)
}

fn parse_and(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_eq(cur)?;
    while cur.eat_str("&&") {
        let b = parse_eq(cur)?;
        a = Expr::And(Box::new(a), Box::new(b));
    }
    Ok(a)
}

fn parse_eq(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_cmp(cur)?;
    loop {
        let span = {
            cur.skip_ws();
            cur.span()
        };
        let op = if cur.eat_str("==") {
            BinOp::Eq
        } else if cur.eat_str("!=") {
            BinOp::Ne
        } else {
            return Ok(a);
        };
        let b = parse_cmp(cur)?;
        a = Expr::Bin(op, Box::new(a), Box::new(b), span);
    }
}

fn parse_cmp(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_add(cur)?;
    loop {
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
            return Ok(a);
        };
        let b = parse_add(cur)?;
        a = Expr::Bin(op, Box::new(a), Box::new(b), span);
    }
}

fn parse_add(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_mul(cur)?;
    loop {
        cur.skip_ws();
        let span = cur.span();
        let op = match cur.peek() {
            Some('+') => BinOp::Add,
            Some('-') if cur.peek_at(1) != Some('>') => BinOp::Sub,
            _ => return Ok(a),
        };
        cur.bump();
        let b = parse_mul(cur)?;
        a = Expr::Bin(op, Box::new(a), Box::new(b), span);
    }
}

fn parse_mul(cur: &mut Cursor<'_>) -> Result<Expr> {
    let mut a = parse_unary(cur)?;
    loop {
        cur.skip_ws();
        let span = cur.span();
        let op = match (cur.peek(), cur.peek_at(1)) {
            (Some('*'), Some('*')) => return Ok(a),
            (Some('*'), _) => BinOp::Mul,
            (Some('/'), _) => BinOp::Div,
            (Some('%'), _) => BinOp::Rem,
            _ => return Ok(a),
        };
        cur.bump();
        let b = parse_unary(cur)?;
        a = Expr::Bin(op, Box::new(a), Box::new(b), span);
    }
}

fn parse_unary(cur: &mut Cursor<'_>) -> Result<Expr> {
    cur.skip_ws();
    let span = cur.span();
    match cur.peek() {
        Some('-') => {
            cur.bump();
            Ok(Expr::Unary('-', Box::new(parse_unary(cur)?), span))
        }
        Some('+') => {
            cur.bump();
            parse_unary(cur)
        }
        Some('!') if cur.peek_at(1) != Some('=') => {
            cur.bump();
            Ok(Expr::Unary('!', Box::new(parse_unary(cur)?), span))
        }
        _ => parse_pow(cur),
    }
}

fn parse_pow(cur: &mut Cursor<'_>) -> Result<Expr> {
    let a = parse_postfix(cur)?;
    cur.skip_ws();
    let span = cur.span();
    if cur.eat_str("**") || cur.eat('^') {
        // Right-associative; the exponent may carry a sign.
        let b = parse_unary(cur)?;
        return Ok(Expr::Bin(BinOp::Pow, Box::new(a), Box::new(b), span));
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

/// Compiles expressions and blocks against a scope and the globals.
#[derive(Debug)]
pub(crate) struct Compiler<'g> {
    pub globals: &'g Globals,
    pub scope: Scope,
    ops: Vec<Op>,
    spans: Vec<Span>,
    depth: u32,
}

impl<'g> Compiler<'g> {
    pub fn new(globals: &'g Globals, scope: Scope) -> Self {
        Self {
            globals,
            scope,
            ops: Vec::new(),
            spans: Vec::new(),
            depth: 0,
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
        Code::new(ops, spans, span)
    }

    /// Compiles an expression into a program that leaves one value.
    pub fn expr(&mut self, e: &Expr, span: Span) -> Result<Code> {
        self.lower(e, &HashMap::new())?;
        Ok(self.finish(span))
    }

    /// Compiles a block into a program that leaves nothing.
    pub fn block(&mut self, b: &[Stmt], span: Span) -> Result<Code> {
        self.gen_block(b)?;
        Ok(self.finish(span))
    }

    fn gen_block(&mut self, b: &[Stmt]) -> Result<()> {
        let none = HashMap::new();
        for s in b {
            match s {
                Stmt::Assign(name, e, span) => {
                    self.lower(e, &none)?;
                    let slot = self.scope.slot_or_new(name, *span)?;
                    self.emit(Op::Store(slot), *span);
                }
                Stmt::If(c, then, els) => {
                    self.lower(c, &none)?;
                    let jf = self.emit(Op::JumpIfFalse(0), Span::default());
                    self.gen_block(then)?;
                    if els.is_empty() {
                        let here = self.ops.len() as u32;
                        self.ops[jf] = Op::JumpIfFalse(here);
                    } else {
                        let j = self.emit(Op::Jump(0), Span::default());
                        self.ops[jf] = Op::JumpIfFalse(self.ops.len() as u32);
                        self.gen_block(els)?;
                        let here = self.ops.len() as u32;
                        self.ops[j] = Op::Jump(here);
                    }
                }
                Stmt::While(c, body, span) => {
                    let top = self.ops.len() as u32;
                    self.lower(c, &none)?;
                    let jf = self.emit(Op::JumpIfFalse(0), *span);
                    self.gen_block(body)?;
                    self.emit(Op::Loop(top), *span);
                    let here = self.ops.len() as u32;
                    self.ops[jf] = Op::JumpIfFalse(here);
                }
            }
        }
        Ok(())
    }

    fn lower(&mut self, e: &Expr, args: &HashMap<String, Expr>) -> Result<()> {
        match e {
            Expr::Num(v) => {
                self.emit(Op::Const(*v), Span::default());
            }
            Expr::Var(name, span) => {
                if let Some(a) = args.get(name) {
                    let a = a.clone();
                    return self.lower(&a, &HashMap::new());
                }
                if let Some(slot) = self.scope.slot(name) {
                    self.emit(Op::Load(slot), *span);
                } else if let Some(m) = self.globals.macros.get(name.as_str()) {
                    if !m.params.is_empty() {
                        return Err(PlantError::syntax(
                            *span,
                            format!("macro `{name}` takes {} arguments", m.params.len()),
                        ));
                    }
                    self.expand(&m.body.clone(), HashMap::new(), *span)?;
                } else if let Some(v) = constant(name) {
                    self.emit(Op::Const(v), *span);
                } else {
                    return Err(PlantError::Undefined {
                        span: *span,
                        what: "variable",
                        name: name.clone(),
                    });
                }
            }
            Expr::Unary(op, a, span) => {
                self.lower(a, args)?;
                self.emit(if *op == '-' { Op::Neg } else { Op::Not }, *span);
            }
            Expr::Bin(op, a, b, span) => {
                self.lower(a, args)?;
                self.lower(b, args)?;
                self.emit(Op::Bin(*op), *span);
            }
            Expr::And(a, b) => {
                self.lower(a, args)?;
                let j = self.emit(Op::AndJump(0), Span::default());
                self.lower(b, args)?;
                self.emit(Op::ToBool, Span::default());
                let here = self.ops.len() as u32;
                self.ops[j] = Op::AndJump(here);
            }
            Expr::Or(a, b) => {
                self.lower(a, args)?;
                let j = self.emit(Op::OrJump(0), Span::default());
                self.lower(b, args)?;
                self.emit(Op::ToBool, Span::default());
                let here = self.ops.len() as u32;
                self.ops[j] = Op::OrJump(here);
            }
            Expr::Cond(c, a, b) => {
                self.lower(c, args)?;
                let jf = self.emit(Op::JumpIfFalse(0), Span::default());
                self.lower(a, args)?;
                let j = self.emit(Op::Jump(0), Span::default());
                self.ops[jf] = Op::JumpIfFalse(self.ops.len() as u32);
                self.lower(b, args)?;
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
                self.lower(i, args)?;
                self.emit(Op::Index(arr), *span);
            }
            Expr::Call(name, a, span) => {
                if let Some(m) = self.globals.macros.get(name.as_str()) {
                    if m.params.len() != a.len() {
                        return Err(PlantError::syntax(
                            *span,
                            format!(
                                "macro `{name}` takes {} arguments, {} given",
                                m.params.len(),
                                a.len()
                            ),
                        ));
                    }
                    // Arguments are substituted as expressions (C's macro semantics,
                    // but hygienic: each argument is one parenthesised operand).
                    let mut bind = HashMap::new();
                    for (p, x) in m.params.iter().zip(a) {
                        bind.insert(p.clone(), substitute(x, args));
                    }
                    return self.expand(&m.body.clone(), bind, *span);
                }
                let Some((f, arity)) = Func::lookup(name) else {
                    return Err(PlantError::Undefined {
                        span: *span,
                        what: "function",
                        name: name.clone(),
                    });
                };
                if !arity.contains(&a.len()) {
                    return Err(PlantError::syntax(
                        *span,
                        format!(
                            "function `{name}` takes {arity:?} arguments, {} given",
                            a.len()
                        ),
                    ));
                }
                for x in a {
                    self.lower(x, args)?;
                }
                self.emit(Op::Call(f, a.len() as u8), *span);
            }
        }
        Ok(())
    }

    fn expand(&mut self, body: &Expr, bind: HashMap<String, Expr>, span: Span) -> Result<()> {
        self.depth += 1;
        if self.depth > 64 {
            return Err(PlantError::syntax(
                span,
                "macro expansion nested deeper than 64 (recursive #define?)",
            ));
        }
        let r = self.lower(body, &bind);
        self.depth -= 1;
        r
    }
}

/// Replaces macro parameters inside a macro argument by the enclosing bindings.
fn substitute(e: &Expr, args: &HashMap<String, Expr>) -> Expr {
    if args.is_empty() {
        return e.clone();
    }
    match e {
        Expr::Var(n, _) => args.get(n).cloned().unwrap_or_else(|| e.clone()),
        Expr::Num(_) => e.clone(),
        Expr::Unary(o, a, s) => Expr::Unary(*o, Box::new(substitute(a, args)), *s),
        Expr::Bin(o, a, b, s) => Expr::Bin(
            *o,
            Box::new(substitute(a, args)),
            Box::new(substitute(b, args)),
            *s,
        ),
        Expr::And(a, b) => Expr::And(Box::new(substitute(a, args)), Box::new(substitute(b, args))),
        Expr::Or(a, b) => Expr::Or(Box::new(substitute(a, args)), Box::new(substitute(b, args))),
        Expr::Cond(c, a, b) => Expr::Cond(
            Box::new(substitute(c, args)),
            Box::new(substitute(a, args)),
            Box::new(substitute(b, args)),
        ),
        Expr::Call(n, a, s) => Expr::Call(
            n.clone(),
            a.iter().map(|x| substitute(x, args)).collect(),
            *s,
        ),
        Expr::Index(n, i, s) => Expr::Index(n.clone(), Box::new(substitute(i, args)), *s),
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
