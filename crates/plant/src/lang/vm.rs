//! The stack machine that evaluates compiled expressions and blocks.
//!
//! Programs are short (`x+1`, `v*r2`), so the common shapes (a constant, a
//! slot, a slot combined with a constant) are recognised when compiled and
//! evaluated without the loop; everything else runs through [`Code::eval`].

use super::funcs::UserFns;
use crate::error::Span;
use natura_core::{mix64, unit_f64};

/// A binary arithmetic or comparison operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

/// A built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sqrt,
    Exp,
    Log,
    Log10,
    Floor,
    Ceil,
    Trunc,
    Round,
    Abs,
    Sign,
    Pow,
    Min,
    Max,
    Fmod,
    Clamp,
    Ran,
    Nran,
    Plot,
    CurveX,
    CurveY,
    CurveZ,
    TanX,
    TanY,
    TanZ,
    CurveLen,
}

impl Func {
    /// Returns the function called `name` and the argument counts it accepts.
    pub fn lookup(name: &str) -> Option<(Func, std::ops::RangeInclusive<usize>)> {
        Some(match name {
            "sin" => (Func::Sin, 1..=1),
            "cos" => (Func::Cos, 1..=1),
            "tan" => (Func::Tan, 1..=1),
            "asin" => (Func::Asin, 1..=1),
            "acos" => (Func::Acos, 1..=1),
            "atan" => (Func::Atan, 1..=1),
            "atan2" => (Func::Atan2, 2..=2),
            "sqrt" => (Func::Sqrt, 1..=1),
            "exp" => (Func::Exp, 1..=1),
            "log" | "ln" => (Func::Log, 1..=1),
            "log10" => (Func::Log10, 1..=1),
            "floor" => (Func::Floor, 1..=1),
            "ceil" => (Func::Ceil, 1..=1),
            "trunc" => (Func::Trunc, 1..=1),
            "round" => (Func::Round, 1..=1),
            "abs" | "fabs" => (Func::Abs, 1..=1),
            "sign" => (Func::Sign, 1..=1),
            "pow" => (Func::Pow, 2..=2),
            "min" => (Func::Min, 2..=2),
            "max" => (Func::Max, 2..=2),
            "fmod" => (Func::Fmod, 2..=2),
            "clamp" => (Func::Clamp, 3..=3),
            "ran" | "uniform" => (Func::Ran, 1..=2),
            "nran" | "normal" => (Func::Nran, 2..=2),
            "func" => (Func::Plot, 2..=2),
            "curveX" => (Func::CurveX, 2..=2),
            "curveY" => (Func::CurveY, 2..=2),
            "curveZ" => (Func::CurveZ, 2..=2),
            "tanX" => (Func::TanX, 2..=2),
            "tanY" => (Func::TanY, 2..=2),
            "tanZ" => (Func::TanZ, 2..=2),
            "curveLen" => (Func::CurveLen, 1..=1),
            _ => return None,
        })
    }

    fn is_pure(self) -> bool {
        !matches!(self, Func::Ran | Func::Nran)
            && !matches!(
                self,
                Func::Plot
                    | Func::CurveX
                    | Func::CurveY
                    | Func::CurveZ
                    | Func::TanX
                    | Func::TanY
                    | Func::TanZ
                    | Func::CurveLen
            )
    }
}

/// One instruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Const(f64),
    Load(u16),
    Store(u16),
    Bin(BinOp),
    Neg,
    Not,
    ToBool,
    Call(Func, u8),
    Index(u16),
    Jump(u32),
    /// A backward jump of a `while` loop (counted, to stop runaway loops).
    Loop(u32),
    JumpIfFalse(u32),
    AndJump(u32),
    OrJump(u32),
}

/// A compiled program with its fast shape.
#[derive(Clone, Debug)]
pub(crate) struct Code {
    shape: Shape,
    ops: Box<[Op]>,
    spans: Box<[Span]>,
    /// Where the expression starts in the text.
    pub span: Span,
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    Const(f64),
    Load(u16),
    LoadConst(u16, BinOp, f64),
    General,
}

/// A failure while evaluating: where, and what.
#[derive(Clone, Debug)]
pub(crate) struct Fault {
    pub span: Span,
    pub message: String,
}

/// A counter-based random stream: splitmix64 over a per-module key, so a
/// module's draws do not depend on the order modules are rewritten in.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Rng {
    state: u64,
}

impl Rng {
    /// The stream for module `index` at derivation step `step` under `seed`.
    pub fn for_module(seed: u64, step: u32, index: u64) -> Self {
        Self {
            state: mix64(seed ^ mix64(u64::from(step).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ index)),
        }
    }

    /// A uniform number in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        unit_f64(mix64(self.state))
    }

    /// A standard normal number (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// What evaluation may read besides the slots.
#[derive(Debug)]
pub(crate) struct Env<'a> {
    pub arrays: &'a [Vec<f64>],
    pub user: &'a UserFns,
    pub rng: Rng,
}

/// The largest number of loop iterations one block may run.
const MAX_LOOP: u64 = 10_000_000;

#[inline]
fn bin(op: BinOp, a: f64, b: f64) -> Result<f64, &'static str> {
    Ok(match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => {
            if b == 0.0 {
                return Err("division by zero");
            }
            a / b
        }
        BinOp::Rem => {
            if b == 0.0 {
                return Err("remainder by zero");
            }
            a % b
        }
        BinOp::Pow => a.powf(b),
        BinOp::Lt => f64::from(u8::from(a < b)),
        BinOp::Le => f64::from(u8::from(a <= b)),
        BinOp::Gt => f64::from(u8::from(a > b)),
        BinOp::Ge => f64::from(u8::from(a >= b)),
        BinOp::Eq => f64::from(u8::from(a == b)),
        BinOp::Ne => f64::from(u8::from(a != b)),
    })
}

fn call(f: Func, a: &[f64], env: &mut Env<'_>) -> Result<f64, String> {
    let d = std::f64::consts::PI / 180.0;
    let x = a.first().copied().unwrap_or(0.0);
    let y = a.get(1).copied().unwrap_or(0.0);
    let id = |v: f64| -> Result<u32, String> {
        if v >= 0.0 && v.fract() == 0.0 && v < f64::from(u32::MAX) {
            Ok(v as u32)
        } else {
            Err(format!(
                "function or curve id {v} is not a non-negative integer"
            ))
        }
    };
    Ok(match f {
        Func::Sin => (x * d).sin(),
        Func::Cos => (x * d).cos(),
        Func::Tan => (x * d).tan(),
        Func::Asin => x.asin() / d,
        Func::Acos => x.acos() / d,
        Func::Atan => x.atan() / d,
        Func::Atan2 => x.atan2(y) / d,
        Func::Sqrt => x.sqrt(),
        Func::Exp => x.exp(),
        Func::Log => x.ln(),
        Func::Log10 => x.log10(),
        Func::Floor => x.floor(),
        Func::Ceil => x.ceil(),
        Func::Trunc => x.trunc(),
        Func::Round => x.round(),
        Func::Abs => x.abs(),
        Func::Sign => {
            if x > 0.0 {
                1.0
            } else if x < 0.0 {
                -1.0
            } else {
                0.0
            }
        }
        Func::Pow => x.powf(y),
        Func::Min => x.min(y),
        Func::Max => x.max(y),
        Func::Fmod => {
            if y == 0.0 {
                return Err("fmod by zero".into());
            }
            x % y
        }
        Func::Clamp => {
            let hi = a.get(2).copied().unwrap_or(0.0);
            if y.is_nan() || hi.is_nan() || y > hi {
                return Err(format!("clamp bounds [{y}, {hi}] are empty"));
            }
            x.clamp(y, hi)
        }
        Func::Ran => {
            let u = env.rng.uniform();
            if a.len() == 2 { x + (y - x) * u } else { x * u }
        }
        Func::Nran => x + y * env.rng.normal(),
        Func::Plot => env.user.func(id(x)?, y)?,
        Func::CurveX => env.user.curve_point(id(x)?, y)?.x,
        Func::CurveY => env.user.curve_point(id(x)?, y)?.y,
        Func::CurveZ => env.user.curve_point(id(x)?, y)?.z,
        Func::TanX => env.user.curve_tangent(id(x)?, y)?.x,
        Func::TanY => env.user.curve_tangent(id(x)?, y)?.y,
        Func::TanZ => env.user.curve_tangent(id(x)?, y)?.z,
        Func::CurveLen => env.user.curve_len(id(x)?)?,
    })
}

impl Code {
    pub fn new(ops: Vec<Op>, spans: Vec<Span>, span: Span) -> Self {
        let shape = match ops.as_slice() {
            [Op::Const(v)] => Shape::Const(*v),
            [Op::Load(s)] => Shape::Load(*s),
            [Op::Load(s), Op::Const(v), Op::Bin(op)] if !matches!(op, BinOp::Div | BinOp::Rem) => {
                Shape::LoadConst(*s, *op, *v)
            }
            [Op::Load(s), Op::Const(v), Op::Bin(op)] if *v != 0.0 => Shape::LoadConst(*s, *op, *v),
            _ => Shape::General,
        };
        let mut code = Self {
            shape,
            ops: ops.into(),
            spans: spans.into(),
            span,
        };
        code.fold();
        code
    }

    /// Folds a program without slots, arrays or impure calls into a constant.
    fn fold(&mut self) {
        if !matches!(self.shape, Shape::General) {
            return;
        }
        let pure = self.ops.iter().all(|op| match op {
            Op::Load(_) | Op::Store(_) | Op::Index(_) | Op::Loop(_) => false,
            Op::Call(f, _) => f.is_pure(),
            _ => true,
        });
        if !pure {
            return;
        }
        let user = UserFns::default();
        let mut env = Env {
            arrays: &[],
            user: &user,
            rng: Rng::default(),
        };
        let mut stack = Vec::new();
        if let Ok(v) = self.run(&mut [], &mut stack, &mut env)
            && v.is_finite()
            && stack.is_empty()
        {
            self.shape = Shape::Const(v);
        }
    }

    /// True if the program draws random numbers.
    pub fn uses_random(&self) -> bool {
        self.ops
            .iter()
            .any(|op| matches!(op, Op::Call(Func::Ran | Func::Nran, _)))
    }

    /// Evaluates an expression program; a non-finite result is a fault.
    #[inline]
    pub fn eval(
        &self,
        slots: &mut [f64],
        stack: &mut Vec<f64>,
        env: &mut Env<'_>,
    ) -> Result<f64, Fault> {
        let v = match self.shape {
            Shape::Const(v) => return Ok(v),
            Shape::Load(s) => slots[s as usize],
            Shape::LoadConst(s, op, c) => {
                bin(op, slots[s as usize], c).map_err(|m| self.fault(2, m.to_string()))?
            }
            Shape::General => {
                stack.clear();
                self.run(slots, stack, env)?
            }
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(Fault {
                span: self.span,
                message: format!("expression evaluates to {v}"),
            })
        }
    }

    /// Runs a block (a program that leaves nothing).
    pub fn exec(
        &self,
        slots: &mut [f64],
        stack: &mut Vec<f64>,
        env: &mut Env<'_>,
    ) -> Result<(), Fault> {
        stack.clear();
        self.run(slots, stack, env).map(|_| ())
    }

    fn fault(&self, pc: usize, message: String) -> Fault {
        let span = self
            .spans
            .get(pc)
            .copied()
            .filter(|s| s.line > 0)
            .unwrap_or(self.span);
        Fault { span, message }
    }

    fn run(
        &self,
        slots: &mut [f64],
        stack: &mut Vec<f64>,
        env: &mut Env<'_>,
    ) -> Result<f64, Fault> {
        let mut pc = 0usize;
        let mut loops = 0u64;
        let ops = &self.ops;
        while pc < ops.len() {
            match ops[pc] {
                Op::Const(v) => stack.push(v),
                Op::Load(s) => stack.push(slots[s as usize]),
                Op::Store(s) => {
                    let v = stack.pop().unwrap_or(0.0);
                    if !v.is_finite() {
                        return Err(self.fault(pc, format!("assigned value is {v}")));
                    }
                    slots[s as usize] = v;
                }
                Op::Bin(op) => {
                    let b = stack.pop().unwrap_or(0.0);
                    let a = stack.pop().unwrap_or(0.0);
                    stack.push(bin(op, a, b).map_err(|m| self.fault(pc, m.to_string()))?);
                }
                Op::Neg => {
                    if let Some(v) = stack.last_mut() {
                        *v = -*v;
                    }
                }
                Op::Not => {
                    if let Some(v) = stack.last_mut() {
                        *v = f64::from(u8::from(*v == 0.0));
                    }
                }
                Op::ToBool => {
                    if let Some(v) = stack.last_mut() {
                        *v = f64::from(u8::from(*v != 0.0));
                    }
                }
                Op::Call(f, n) => {
                    let n = n as usize;
                    let base = stack.len().saturating_sub(n);
                    let v = call(f, &stack[base..], env).map_err(|m| self.fault(pc, m))?;
                    stack.truncate(base);
                    stack.push(v);
                }
                Op::Index(a) => {
                    let i = stack.pop().unwrap_or(0.0);
                    let arr = &env.arrays[a as usize];
                    if !(i >= 0.0 && i.fract() == 0.0 && (i as usize) < arr.len()) {
                        return Err(self
                            .fault(pc, format!("array index {i} out of range 0..{}", arr.len())));
                    }
                    stack.push(arr[i as usize]);
                }
                Op::Jump(t) => {
                    pc = t as usize;
                    continue;
                }
                Op::Loop(t) => {
                    loops += 1;
                    if loops > MAX_LOOP {
                        return Err(self.fault(pc, format!("loop ran more than {MAX_LOOP} times")));
                    }
                    pc = t as usize;
                    continue;
                }
                Op::JumpIfFalse(t) => {
                    if stack.pop().unwrap_or(0.0) == 0.0 {
                        pc = t as usize;
                        continue;
                    }
                }
                Op::AndJump(t) => {
                    if stack.last().copied().unwrap_or(0.0) == 0.0 {
                        if let Some(v) = stack.last_mut() {
                            *v = 0.0;
                        }
                        pc = t as usize;
                        continue;
                    }
                    stack.pop();
                }
                Op::OrJump(t) => {
                    if stack.last().copied().unwrap_or(0.0) != 0.0 {
                        if let Some(v) = stack.last_mut() {
                            *v = 1.0;
                        }
                        pc = t as usize;
                        continue;
                    }
                    stack.pop();
                }
            }
            pc += 1;
        }
        Ok(stack.pop().unwrap_or(0.0))
    }
}
