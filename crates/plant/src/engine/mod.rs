//! The derivation engine: parallel rewriting of the module string.
//!
//! One derivation step rewrites every module of the string at once (Měch &
//! Prusinkiewicz 1996, §4): contexts and conditions read the *old* string,
//! successors go to a second buffer, and the buffers swap. In the
//! deterministic case the first production that matches applies; when a
//! predecessor has stochastic productions, every matching production is a
//! candidate and one is chosen with probability proportional to its
//! (possibly parameter-dependent) weight. Random numbers come from a
//! counter-based stream keyed by the seed, the step and the module's index,
//! so a derivation is reproducible and independent of evaluation order.
//!
//! After a production applies, its successor modules are decomposed
//! (decomposition rules, applied recursively up to the maximum depth), and
//! after the step the cut symbol `%` erases the rest of its branch.

mod context;

use crate::error::{PlantError, Result};
use crate::lang::vm::{Env, Rng};
use crate::lang::{LSystem, Production, RuleSet};
use crate::string::ModuleString;
use crate::symbols::{CUT, LBRACKET, RBRACKET};

pub(crate) use context::{bind_pred, match_left, match_right};

/// Limits that stop runaway growth and runaway work with an error instead
/// of exhausting memory or time.
///
/// A string never holds more than `max_modules` modules and `max_params`
/// parameters: a step, a decomposition or the interpretation rules that
/// would go past either stop with [`PlantError::Growth`] before the module
/// is written, and the buffers grow no further than the limits. At the
/// defaults, everything a derivation and the interpretation of its string
/// hold (see [`Limits::memory_bound`]) stays under 2.5 GB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Limits {
    /// The most modules a string may hold.
    pub max_modules: usize,
    /// The most parameters a string may hold in all.
    pub max_params: usize,
    /// The most work a derivation may do in all, in units of one module read
    /// or written; every step costs [`Limits::STEP_COST`] units more, so a
    /// long derivation of a short string ends too.
    pub max_work: u64,
}

impl Default for Limits {
    /// 16 Mi modules, 64 Mi parameters and 2³³ units of work: at most
    /// 2.22 GB of memory ([`Limits::memory_bound`]), and a few seconds to a
    /// few minutes of work.
    fn default() -> Self {
        Self {
            max_modules: 16 << 20,
            max_params: 64 << 20,
            max_work: 1 << 33,
        }
    }
}

impl Limits {
    /// Units of work every derivation step costs besides its modules.
    pub const STEP_COST: u64 = 64;

    /// The most bytes the strings of a derivation and of the interpretation
    /// of its string can hold at these limits: the derivation's two buffers
    /// (a `u32` symbol and a `u32` offset per module, an `f64` per
    /// parameter), its bracket scratch (two `u32` per module), and the
    /// output of the interpretation rules with the origin of each of its
    /// modules (`u32`).
    #[must_use]
    pub fn memory_bound(&self) -> u64 {
        let m = self.max_modules as u64 + 1;
        let p = self.max_params as u64;
        let string = 8 * m + 8 * p;
        2 * string + 8 * m + string + 4 * m
    }
}

/// Scratch memory reused across steps (no allocation per module).
#[derive(Debug, Default)]
struct Scratch {
    partners: Vec<u32>,
    stack: Vec<u32>,
    slots: Vec<f64>,
    estack: Vec<f64>,
    /// Stochastic candidates: (rule, weight, offset of its slots in `cand_slots`).
    cand: Vec<(u32, f64, usize)>,
    cand_slots: Vec<f64>,
    /// Slots and parameter buffers per decomposition depth.
    dslots: Vec<Vec<f64>>,
    dparams: Vec<Vec<f64>>,
}

/// A derivation in progress: the current string, the step count and the seed.
#[derive(Debug)]
pub struct Derivation<'a> {
    pub(crate) lsys: &'a LSystem,
    pub(crate) cur: ModuleString,
    next: ModuleString,
    step: u32,
    seed: u64,
    limits: Limits,
    scratch: Scratch,
    /// Work done so far (see [`Limits::max_work`]).
    work: u64,
}

impl<'a> Derivation<'a> {
    /// Starts a derivation of `lsys` from its axiom (decomposed) with `seed`
    /// (the L-system's `seed:` directive, if any, is only a default for callers).
    ///
    /// # Errors
    ///
    /// [`PlantError::Eval`] or [`PlantError::Depth`] if decomposing the axiom fails.
    pub fn new(lsys: &'a LSystem, seed: u64) -> Result<Self> {
        Self::with_limits(lsys, seed, Limits::default())
    }

    /// As [`Derivation::new`] with explicit growth limits.
    ///
    /// # Errors
    ///
    /// As [`Derivation::new`]; [`PlantError::Growth`] if the axiom, or its
    /// decomposition, exceeds the limits.
    pub fn with_limits(lsys: &'a LSystem, seed: u64, limits: Limits) -> Result<Self> {
        let nslots = max_slots(&lsys.productions)
            .max(max_slots(&lsys.decompositions))
            .max(1);
        let mut d = Self {
            lsys,
            cur: ModuleString::new(),
            next: ModuleString::new(),
            step: 0,
            seed,
            limits,
            scratch: Scratch {
                slots: vec![0.0; nslots],
                ..Scratch::default()
            },
            work: 0,
        };
        if lsys.axiom.len() > limits.max_modules || lsys.axiom.param_count() > limits.max_params {
            return Err(d.growth_error(&lsys.axiom));
        }
        if lsys.decompositions.is_empty() {
            d.cur = lsys.axiom.clone();
        } else {
            let mut out = ModuleString::new();
            for i in 0..lsys.axiom.len() {
                let env = Env {
                    arrays: &lsys.arrays,
                    user: &lsys.user,
                    rng: Rng::for_module(seed, 0, i as u64),
                };
                let mut env = env;
                decompose(
                    lsys,
                    lsys.axiom.symbol(i),
                    lsys.axiom.params(i),
                    0,
                    &mut out,
                    &mut d.scratch,
                    &mut env,
                    &Cap::new(&limits, 0),
                )?;
            }
            d.cur = out;
        }
        d.work = d.cur.len() as u64;
        // A cut in the axiom erases the rest of its branch, as one in a successor does.
        if d.cur.symbols().contains(&CUT) {
            apply_cuts(&d.cur, &mut d.next);
            std::mem::swap(&mut d.cur, &mut d.next);
            d.next.clear();
        }
        Ok(d)
    }

    /// The current string.
    #[must_use]
    pub fn string(&self) -> &ModuleString {
        &self.cur
    }

    /// The current string, mutably (to set parameters between steps, as an environment would).
    pub fn string_mut(&mut self) -> &mut ModuleString {
        &mut self.cur
    }

    /// Consumes the derivation and returns the current string.
    #[must_use]
    pub fn into_string(self) -> ModuleString {
        self.cur
    }

    /// Number of steps performed.
    #[must_use]
    pub fn steps(&self) -> u32 {
        self.step
    }

    /// The L-system being derived.
    #[must_use]
    pub fn lsystem(&self) -> &'a LSystem {
        self.lsys
    }

    /// Bytes held by the two string buffers.
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.cur.memory_bytes() + self.next.memory_bytes()
    }

    /// Work done so far, in the units of [`Limits::max_work`].
    #[must_use]
    pub fn work(&self) -> u64 {
        self.work
    }

    /// The limits in force.
    #[must_use]
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The growth error for a string that is already too large (the axiom).
    fn growth_error(&self, s: &ModuleString) -> PlantError {
        Cap::new(&self.limits, self.step).error(s.len(), s.param_count())
    }

    /// Performs `n` derivation steps.
    ///
    /// # Errors
    ///
    /// As [`Derivation::step`].
    pub fn derive(&mut self, n: u32) -> Result<()> {
        for _ in 0..n {
            self.step()?;
        }
        Ok(())
    }

    /// Performs one derivation step: every module rewritten in parallel, the
    /// successors decomposed, then cuts applied.
    ///
    /// # Errors
    ///
    /// [`PlantError::Eval`] if a condition, block, probability or successor
    /// parameter fails (division by zero, NaN, array index out of range),
    /// [`PlantError::Depth`] if decomposition recurses past the maximum depth,
    /// [`PlantError::Growth`] if the string would exceed the limits,
    /// [`PlantError::Work`] if the step would take the derivation's work past
    /// [`Limits::max_work`]. On error the current string is left as it was
    /// before the step.
    pub fn step(&mut self) -> Result<()> {
        let l = self.lsys;
        let Self {
            cur,
            next,
            scratch,
            step,
            seed,
            limits,
            work,
            ..
        } = self;
        let cost = Limits::STEP_COST + cur.len() as u64;
        if work.saturating_add(cost) > limits.max_work {
            return Err(PlantError::Work {
                step: *step + 1,
                work: work.saturating_add(cost),
                max_work: limits.max_work,
            });
        }
        let cap = Cap::new(limits, *step + 1);
        next.clear();
        let old: &ModuleString = cur;
        if l.any_context {
            old.bracket_partners(&mut scratch.partners, &mut scratch.stack);
        }
        let rules = &l.productions;
        let mut has_cut = false;
        let decompose_on = !l.decompositions.is_empty();
        let r = (|| {
            for i in 0..old.len() {
                let s = old.symbol(i);
                let cands = rules.for_symbol(s);
                if cands.is_empty() {
                    cap.room(next, 1, old.arity(i))?;
                    next.push_from(old, i);
                    continue;
                }
                let mut env = Env {
                    arrays: &l.arrays,
                    user: &l.user,
                    rng: Rng::default(),
                };
                let chosen = if rules.stochastic[s as usize] {
                    env.rng = Rng::for_module(*seed, *step, i as u64);
                    choose_stochastic(l, old, i, cands, scratch, &mut env)?
                } else {
                    choose_first(l, old, i, cands, scratch, &mut env, *seed, *step)?
                };
                let Some(r) = chosen else {
                    cap.room(next, 1, old.arity(i))?;
                    next.push_from(old, i);
                    continue;
                };
                let rule = &rules.rules[r as usize];
                if decompose_on {
                    has_cut |= emit_decomposed(l, rule, next, scratch, &mut env, &cap)?;
                } else {
                    let params = rule.succ.iter().map(|m| m.params.len()).sum();
                    cap.room(next, rule.succ.len(), params)?;
                    has_cut |= emit(l, rule, next, scratch, &mut env)?;
                }
            }
            Ok(())
        })();
        if let Err(e) = r {
            next.clear();
            return Err(e);
        }
        *work = work.saturating_add(cost + next.len() as u64);
        if has_cut {
            apply_cuts(next, cur);
        } else {
            std::mem::swap(cur, next);
        }
        *step += 1;
        Ok(())
    }
}

/// The growth limits while one string is written, and the step it belongs to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cap {
    max_modules: usize,
    max_params: usize,
    step: u32,
}

impl Cap {
    /// The limits of `l` for derivation step `step` (0: the axiom or the
    /// interpretation rules).
    pub(crate) fn new(l: &Limits, step: u32) -> Self {
        Self {
            max_modules: l.max_modules,
            max_params: l.max_params,
            step,
        }
    }

    /// Makes room in `out` for `modules` more modules holding `params`
    /// parameters, or returns the growth error if they would pass the limits.
    #[inline]
    pub(crate) fn room(&self, out: &mut ModuleString, modules: usize, params: usize) -> Result<()> {
        let (m, p) = (out.len() + modules, out.param_count() + params);
        if m > self.max_modules || p > self.max_params {
            return Err(self.error(m, p));
        }
        out.reserve_within(modules, params, self.max_modules, self.max_params);
        Ok(())
    }

    pub(crate) fn error(&self, modules: usize, params: usize) -> PlantError {
        PlantError::Growth {
            step: self.step,
            modules,
            params,
            max_modules: self.max_modules,
            max_params: self.max_params,
            bytes: modules * 8 + params * 8,
        }
    }
}

fn max_slots(r: &RuleSet) -> usize {
    r.rules.iter().map(|p| p.nslots).max().unwrap_or(0)
}

/// Binds predecessor and contexts of `rule` at module `i`; true if they match.
#[inline]
fn matches(l: &LSystem, rule: &Production, old: &ModuleString, i: usize, sc: &mut Scratch) -> bool {
    if !bind_pred(&rule.pred, old, i, &mut sc.slots) {
        return false;
    }
    if !rule.left.is_empty()
        && !match_left(&rule.left, old, i, &sc.partners, &l.visible, &mut sc.slots)
    {
        return false;
    }
    if !rule.right.is_empty()
        && !match_right(&rule.right, old, i, &sc.partners, &l.visible, &mut sc.slots)
    {
        return false;
    }
    true
}

/// Runs the blocks and the condition of `rule` on bound slots.
#[inline]
fn guard(
    l: &LSystem,
    rule: &Production,
    slots: &mut [f64],
    estack: &mut Vec<f64>,
    env: &mut Env<'_>,
) -> Result<bool> {
    if let Some(b) = &rule.pre {
        b.exec(slots, estack, env)
            .map_err(|f| l.eval_error(f, &rule.name))?;
    }
    if let Some(c) = &rule.cond {
        let v = c
            .eval(slots, estack, env)
            .map_err(|f| l.eval_error(f, &rule.name))?;
        if v == 0.0 {
            return Ok(false);
        }
    }
    if let Some(b) = &rule.post {
        b.exec(slots, estack, env)
            .map_err(|f| l.eval_error(f, &rule.name))?;
    }
    Ok(true)
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn choose_first(
    l: &LSystem,
    old: &ModuleString,
    i: usize,
    cands: &[u32],
    sc: &mut Scratch,
    env: &mut Env<'_>,
    seed: u64,
    step: u32,
) -> Result<Option<u32>> {
    for &r in cands {
        let rule = &l.productions.rules[r as usize];
        if !matches(l, rule, old, i, sc) {
            continue;
        }
        if rule.uses_random {
            env.rng = Rng::for_module(seed, step, i as u64);
        }
        // Locals start at zero in every application.
        sc.slots[rule.nparams..rule.nslots]
            .iter_mut()
            .for_each(|v| *v = 0.0);
        if guard(l, rule, &mut sc.slots, &mut sc.estack, env)? {
            return Ok(Some(r));
        }
    }
    Ok(None)
}

fn choose_stochastic(
    l: &LSystem,
    old: &ModuleString,
    i: usize,
    cands: &[u32],
    sc: &mut Scratch,
    env: &mut Env<'_>,
) -> Result<Option<u32>> {
    sc.cand.clear();
    sc.cand_slots.clear();
    let mut total = 0.0;
    for &r in cands {
        let rule = &l.productions.rules[r as usize];
        if !matches(l, rule, old, i, sc) {
            continue;
        }
        if !guard(l, rule, &mut sc.slots, &mut sc.estack, env)? {
            continue;
        }
        let w = match &rule.prob {
            Some(p) => p
                .eval(&mut sc.slots, &mut sc.estack, env)
                .map_err(|f| l.eval_error(f, &rule.name))?,
            None => 1.0,
        };
        if w < 0.0 {
            return Err(PlantError::Eval {
                span: rule.prob.as_ref().map_or(rule.span, |p| p.span),
                production: rule.name.clone(),
                message: format!("probability {w} is negative"),
            });
        }
        total += w;
        sc.cand.push((r, w, sc.cand_slots.len()));
        sc.cand_slots.extend_from_slice(&sc.slots[..rule.nslots]);
    }
    if sc.cand.is_empty() || total <= 0.0 {
        return Ok(None);
    }
    let mut u = env.rng.uniform() * total;
    let mut pick = sc.cand.len() - 1;
    for (k, &(_, w, _)) in sc.cand.iter().enumerate() {
        if u < w {
            pick = k;
            break;
        }
        u -= w;
    }
    let (r, _, off) = sc.cand[pick];
    let n = l.productions.rules[r as usize].nslots;
    sc.slots[..n].copy_from_slice(&sc.cand_slots[off..off + n]);
    Ok(Some(r))
}

/// Writes the successor of `rule` (slots bound) to `out`; true if it holds a cut.
#[inline]
fn emit(
    l: &LSystem,
    rule: &Production,
    out: &mut ModuleString,
    sc: &mut Scratch,
    env: &mut Env<'_>,
) -> Result<bool> {
    let mut cut = false;
    for m in &rule.succ {
        out.begin_module(m.sym);
        for c in &m.params {
            match c.eval(&mut sc.slots, &mut sc.estack, env) {
                Ok(v) => out.push_param(v),
                Err(f) => {
                    out.end_module();
                    return Err(l.eval_error(f, &rule.name));
                }
            }
        }
        out.end_module();
        cut |= m.sym == CUT;
    }
    Ok(cut)
}

/// As [`emit`], decomposing every successor module.
fn emit_decomposed(
    l: &LSystem,
    rule: &Production,
    out: &mut ModuleString,
    sc: &mut Scratch,
    env: &mut Env<'_>,
    cap: &Cap,
) -> Result<bool> {
    let mut cut = false;
    let mut params = std::mem::take(&mut sc.dparams);
    if params.is_empty() {
        params.push(Vec::new());
    }
    for m in &rule.succ {
        params[0].clear();
        for c in &m.params {
            let v = c
                .eval(&mut sc.slots, &mut sc.estack, env)
                .map_err(|f| l.eval_error(f, &rule.name))?;
            params[0].push(v);
        }
        let p = std::mem::take(&mut params[0]);
        let before = out.len();
        let r = decompose(l, m.sym, &p, 0, out, sc, env, cap);
        params[0] = p;
        r?;
        cut |= out.symbols()[before..].contains(&CUT);
    }
    sc.dparams = params;
    Ok(cut)
}

/// Writes module (`sym`, `params`) to `out`, applying decomposition rules
/// recursively (depth counts the rules applied above this module).
#[allow(clippy::too_many_arguments)]
fn decompose(
    l: &LSystem,
    sym: u32,
    params: &[f64],
    depth: u32,
    out: &mut ModuleString,
    sc: &mut Scratch,
    env: &mut Env<'_>,
    cap: &Cap,
) -> Result<()> {
    expand(
        l,
        &l.decompositions,
        sym,
        params,
        depth,
        out,
        &mut sc.dslots,
        &mut sc.estack,
        env,
        cap,
    )
}

/// Applies the first matching context-free rule of `set` recursively, up to
/// the L-system's maximum depth. Shared by decomposition and interpretation.
#[allow(clippy::too_many_arguments)]
pub(crate) fn expand(
    l: &LSystem,
    set: &RuleSet,
    sym: u32,
    params: &[f64],
    depth: u32,
    out: &mut ModuleString,
    dslots: &mut Vec<Vec<f64>>,
    estack: &mut Vec<f64>,
    env: &mut Env<'_>,
    cap: &Cap,
) -> Result<()> {
    let cands = set.for_symbol(sym);
    let d = depth as usize;
    while dslots.len() <= d {
        dslots.push(Vec::new());
    }
    for &r in cands {
        let rule = &set.rules[r as usize];
        if rule.pred.arity as usize != params.len() {
            continue;
        }
        let mut slots = std::mem::take(&mut dslots[d]);
        slots.clear();
        slots.resize(rule.nslots.max(1), 0.0);
        slots[..params.len()].copy_from_slice(params);
        let ok = guard(l, rule, &mut slots, estack, env);
        let ok = match ok {
            Ok(v) => v,
            Err(e) => {
                dslots[d] = slots;
                return Err(e);
            }
        };
        if !ok {
            dslots[d] = slots;
            continue;
        }
        if depth >= l.max_depth {
            dslots[d] = slots;
            return Err(PlantError::Depth {
                span: rule.span,
                production: rule.name.clone(),
                depth: l.max_depth,
            });
        }
        let mut vals: Vec<f64> = Vec::new();
        for m in &rule.succ {
            vals.clear();
            for c in &m.params {
                match c.eval(&mut slots, estack, env) {
                    Ok(v) => vals.push(v),
                    Err(f) => {
                        dslots[d] = slots;
                        return Err(l.eval_error(f, &rule.name));
                    }
                }
            }
            if let Err(e) = expand(
                l,
                set,
                m.sym,
                &vals,
                depth + 1,
                out,
                dslots,
                estack,
                env,
                cap,
            ) {
                dslots[d] = slots;
                return Err(e);
            }
        }
        dslots[d] = slots;
        return Ok(());
    }
    cap.room(out, 1, params.len())?;
    out.push(sym, params);
    Ok(())
}

/// Copies `src` to `dst` without the cut regions: each `%` and everything
/// after it up to the end of its branch (the closing `]` stays).
fn apply_cuts(src: &ModuleString, dst: &mut ModuleString) {
    dst.clear();
    // The result is no longer than `src`: room for that, and no more.
    dst.reserve_within(src.len(), src.param_count(), src.len(), src.param_count());
    let syms = src.symbols();
    let n = syms.len();
    let mut i = 0;
    let mut run = 0;
    while i < n {
        if syms[i] == CUT {
            dst.extend_from_range(src, run, i);
            let mut depth = 0usize;
            while i < n {
                let s = syms[i];
                if s == LBRACKET {
                    depth += 1;
                } else if s == RBRACKET {
                    if depth == 0 {
                        break;
                    }
                    depth -= 1;
                }
                i += 1;
            }
            run = i;
            continue;
        }
        i += 1;
    }
    dst.extend_from_range(src, run, n);
}
