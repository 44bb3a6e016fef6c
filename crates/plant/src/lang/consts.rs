//! Constants of an L-system file: `#define` macros, constant arrays, and
//! the values of directives (`angle`, `step`, `seed`, `tropism`, counts),
//! evaluated once when the file is parsed.

use super::UserFns;
use super::expr::{self, Compiler, Expr, Globals, Macro, Scope};
use super::text::{Ch, Cursor, Stmt};
use super::vm::{Code, Env, Rng};
use crate::error::{PlantError, Result, Span};

/// The largest magnitude of each value of `tropism:` (a rotation of
/// `e · |H × T|` radians per step is meaningless long before).
pub(crate) const MAX_TROPISM: f64 = 1e6;

/// The largest size of one array.
pub(crate) const MAX_ARRAY_SIZE: usize = 10_000_000;

/// The most values all the arrays of one L-system may hold together (128 MiB of values).
pub(crate) const MAX_ARRAY_VALUES: usize = 1 << 24;

pub(super) fn define(st: &Stmt, off: usize, g: &mut Globals) -> Result<()> {
    let mut cur = Cursor::new(&st.chars[off..]).end_at(st.end());
    let span = cur.span();
    let name = cur
        .ident()
        .ok_or_else(|| PlantError::syntax(span, "expected a name after `#define`"))?;
    let mut params = Vec::new();
    if cur.peek() == Some('(') {
        cur.bump();
        if !cur.eat(')') {
            loop {
                let s = cur.span();
                params.push(
                    cur.ident()
                        .ok_or_else(|| PlantError::syntax(s, "expected a macro parameter name"))?,
                );
                if cur.eat(')') {
                    break;
                }
                cur.expect(',', "between macro parameters")?;
            }
        }
    }
    if cur.at_end() {
        return Err(PlantError::syntax(
            cur.span(),
            format!("`#define {name}` has no value"),
        ));
    }
    let body = expr::parse_expr(&mut cur)?;
    if !cur.at_end() {
        return Err(PlantError::syntax(
            cur.span(),
            "unexpected text after the macro's value",
        ));
    }
    g.macros.insert(name, Macro { params, body });
    Ok(())
}

/// `array Name[N] = {v, …}, Name2[M] = {…}` (also inside `Define: { … }`).
pub(super) fn define_arrays(
    chars: &[Ch],
    end: Span,
    g: &mut Globals,
    arrays: &mut Vec<Vec<f64>>,
) -> Result<()> {
    let mut cur = Cursor::new(chars).end_at(end);
    let braced = cur.eat('{');
    loop {
        if cur.at_end() || (braced && cur.eat('}')) {
            break;
        }
        if cur.eat(',') || cur.eat(';') {
            continue;
        }
        let span = cur.span();
        let mut name = cur
            .ident()
            .ok_or_else(|| PlantError::syntax(span, "expected `array Name[size] = {…}`"))?;
        if name == "array" {
            let s = cur.span();
            name = cur
                .ident()
                .ok_or_else(|| PlantError::syntax(s, "expected an array name"))?;
        }
        cur.expect('[', "after the array name")?;
        let size_span = cur.span();
        let size_e = expr::parse_expr(&mut cur)?;
        cur.expect(']', "after the array size")?;
        cur.expect('=', "before the array's values")?;
        cur.expect('{', "to open the array's values")?;
        let mut vals = Vec::new();
        if !cur.eat('}') {
            loop {
                let s = cur.span();
                let e = expr::parse_expr(&mut cur)?;
                vals.push(eval_const(&e, g, arrays, s)?);
                if cur.eat('}') {
                    break;
                }
                cur.expect(',', "between array values")?;
            }
        }
        let size = eval_const(&size_e, g, arrays, size_span)?;
        if !(size >= 1.0 && size.fract() == 0.0 && size <= MAX_ARRAY_SIZE as f64) {
            return Err(PlantError::syntax(
                size_span,
                format!("array `{name}` size {size} is not an integer in 1..={MAX_ARRAY_SIZE}"),
            ));
        }
        let held: usize = arrays.iter().map(Vec::len).sum();
        if held + size as usize > MAX_ARRAY_VALUES {
            return Err(PlantError::syntax(
                size_span,
                format!(
                    "array `{name}` of size {size} brings the arrays to {} values, more than the {MAX_ARRAY_VALUES} allowed in all",
                    held + size as usize
                ),
            ));
        }
        if vals.len() > size as usize {
            return Err(PlantError::syntax(
                span,
                format!("array `{name}` has {} values for size {size}", vals.len()),
            ));
        }
        vals.resize(size as usize, 0.0);
        if arrays.len() >= u16::MAX as usize {
            return Err(PlantError::syntax(span, "too many arrays"));
        }
        g.arrays.insert(name, arrays.len() as u16);
        arrays.push(vals);
    }
    Ok(())
}

fn eval_const(e: &Expr, g: &Globals, arrays: &[Vec<f64>], span: Span) -> Result<f64> {
    let mut c = Compiler::new(g, Scope::default());
    let code = c.expr(e, span)?;
    run_const(&code, arrays, &UserFns::default(), "a constant expression")
}

pub(super) fn run_const(
    code: &Code,
    arrays: &[Vec<f64>],
    user: &UserFns,
    what: &str,
) -> Result<f64> {
    let mut env = Env {
        arrays,
        user,
        rng: Rng::default(),
    };
    let mut slots = [0.0; 0];
    code.eval(&mut slots, &mut Vec::new(), &mut env)
        .map_err(|f| PlantError::Eval {
            span: f.span,
            production: what.to_string(),
            message: f.message,
        })
}

pub(super) fn const_value(
    rest: &[Ch],
    g: &Globals,
    arrays: &[Vec<f64>],
    span: Span,
) -> Result<f64> {
    let mut cur = Cursor::new(rest).end_at(span);
    let s = cur.span();
    if cur.at_end() {
        return Err(PlantError::syntax(span, "expected a value"));
    }
    let e = expr::parse_expr(&mut cur)?;
    if !cur.at_end() {
        return Err(PlantError::syntax(
            cur.span(),
            "unexpected text after the value",
        ));
    }
    eval_const(&e, g, arrays, s)
}

/// `tropism: x, y, z, e`: four constant expressions, the tropism vector and the
/// susceptibility. The vector must be non-zero and every value finite.
pub(super) fn tropism_values(
    rest: &[Ch],
    g: &Globals,
    arrays: &[Vec<f64>],
    end: Span,
) -> Result<([f64; 3], f64)> {
    const USAGE: &str = "`tropism:` takes four comma-separated values `x, y, z, e`";
    let mut cur = Cursor::new(rest).end_at(end);
    cur.skip_ws();
    let first = cur.span();
    let mut v = [0.0; 4];
    for (k, slot) in v.iter_mut().enumerate() {
        if (k > 0 && !cur.eat(',')) || cur.at_end() {
            return Err(PlantError::syntax(cur.span(), USAGE));
        }
        let at = cur.span();
        let e = expr::parse_expr(&mut cur)?;
        let x = eval_const(&e, g, arrays, at)?;
        if x.is_nan() || x.abs() > MAX_TROPISM {
            return Err(PlantError::syntax(
                at,
                format!(
                    "`tropism:` value {} is outside the range -{MAX_TROPISM:e} ..= {MAX_TROPISM:e}",
                    crate::turtle::num(x)
                ),
            ));
        }
        *slot = x;
    }
    if !cur.at_end() {
        return Err(PlantError::syntax(
            cur.span(),
            "unexpected text after the tropism's four values",
        ));
    }
    if v[..3].iter().all(|&c| c == 0.0) {
        return Err(PlantError::syntax(first, "the tropism vector is zero"));
    }
    Ok(([v[0], v[1], v[2]], v[3]))
}

pub(super) fn const_count(
    rest: &[Ch],
    g: &Globals,
    arrays: &[Vec<f64>],
    what: &str,
    span: Span,
) -> Result<u32> {
    let v = const_value(rest, g, arrays, span)?;
    if v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) {
        Ok(v as u32)
    } else {
        Err(PlantError::syntax(
            span,
            format!("{what} {v} is not a non-negative integer"),
        ))
    }
}
