//! The L-system language: text in the cpfg / L-Py convention, parsed into
//! typed modules and compiled productions.
//!
//! ```text
//! #define r1 0.94                      /* object-like macro                */
//! #define ProbB(x) (0.12 + x*0.42)     /* function-like macro              */
//! #ignore: + - F                       /* or  Consider: ?E [ ] L           */
//! derivation length: 5
//! angle: 22.5                          /* default turn, degrees            */
//! tropism: 0, 0, -1, 0.22              /* vector T and susceptibility e    */
//! axiom: A(1)B(3)A(5)                  /* also  ω:  or  Axiom:             */
//! p1: A(x) -> A(x+1) : 0.4             /* label, successor, probability    */
//! p3: A(x) < B(y) > A(z) : y < 4 -> B(x+z)[A(y)]
//! A(s) : { t = s*2; } t < 9 { u = t+1; } -> B(u)   /* blocks around the condition */
//! decomposition:                       /* applied after every step         */
//! maximum depth: 8
//! B(x) -> C(x)D
//! homomorphism:                        /* applied only when interpreted    */
//! C(x) -> F(x)
//! ```
//!
//! Modules are one character (`A`, `+`, `[`) or a prefix `?`, `@`, `~`
//! followed by one character (`?E`, `@o`, `~L`), optionally followed by
//! parameters in parentheses. The production format is Měch & Prusinkiewicz
//! 1996, §4: `id : lc < pred > rc : cond → succ : prob`; the arrows `->`,
//! `-->`, `→`, `⇝` and `=>` are synonyms. `ε` or `*` is the empty successor.
//! Condition blocks follow Prusinkiewicz et al. 2001, §2, eq. 1.
//! A production continues on the next line while a `(` or `{` is open or
//! while the next line holds no arrow and no directive. A UTF-8 byte-order
//! mark at the start of the text is skipped.
//!
//! The brackets `[` `]` of the axiom and of each successor must balance.
//!
//! ## Limits
//!
//! Text is refused with a [`PlantError::Syntax`] naming the line and column,
//! never parsed into unbounded work or memory, when it is longer than
//! [`MAX_SOURCE_BYTES`] (16 MiB); when parentheses, prefix operators, `^`,
//! `?:` or `if` / `while` blocks nest deeper than 256 levels (a flat
//! `a + b + …` of any length is fine); when its expressions, with their
//! `#define`s expanded, compile to more than 2²² operations in all; when an
//! array has more than 10⁷ values or all arrays more than 2²⁴; when
//! `maximum depth:` is above 256; or when `step:` is outside `0 ..= 1e12` or a
//! value of `tropism:` outside `±1e6`. A derivation is bounded by its
//! [`crate::Limits`] (modules, parameters and total work).

mod consts;
pub(crate) mod expr;
pub mod funcs;
mod parser;
pub(crate) mod text;
pub(crate) mod vm;

use crate::error::{PlantError, Result, Span};
use crate::string::ModuleString;
use crate::symbols::SymbolTable;
pub use funcs::{Curve, Function, UserFns};
pub use text::MAX_SOURCE_BYTES;
use vm::Code;

/// A module of a predecessor or context: symbol, arity and the first slot its
/// parameters bind to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pattern {
    pub sym: u32,
    pub arity: u16,
    pub slot: u16,
}

/// An element of a right context: a module, or a bracket.
#[derive(Clone, Copy, Debug)]
pub(crate) enum RightElem {
    Module(Pattern),
    Open,
    Close,
}

/// A module of a successor: its symbol and one program per parameter.
#[derive(Clone, Debug)]
pub(crate) struct SuccModule {
    pub sym: u32,
    pub params: Vec<Code>,
}

/// A compiled production.
#[derive(Clone, Debug)]
pub(crate) struct Production {
    /// `"production p3"` or `"production at line 7"`.
    pub name: String,
    pub span: Span,
    pub pred: Pattern,
    /// Left context, in text order.
    pub left: Vec<Pattern>,
    pub right: Vec<RightElem>,
    pub pre: Option<Code>,
    pub cond: Option<Code>,
    pub post: Option<Code>,
    pub succ: Vec<SuccModule>,
    pub prob: Option<Code>,
    /// Slots needed: parameters, then locals.
    pub nslots: usize,
    /// Slots bound by the predecessor and the contexts (locals follow).
    pub nparams: usize,
    pub uses_random: bool,
}

impl Production {
    pub fn has_context(&self) -> bool {
        !self.left.is_empty() || !self.right.is_empty()
    }
}

/// Productions of one kind, indexed by predecessor symbol (text order kept).
#[derive(Clone, Debug, Default)]
pub(crate) struct RuleSet {
    pub rules: Vec<Production>,
    /// `order[start[s]..start[s+1]]` are the productions whose predecessor is `s`.
    pub order: Vec<u32>,
    pub start: Vec<u32>,
    /// Per symbol: some production of it has a probability.
    pub stochastic: Vec<bool>,
}

impl RuleSet {
    pub fn build(rules: Vec<Production>, nsyms: usize) -> Self {
        let mut by: Vec<Vec<u32>> = vec![Vec::new(); nsyms];
        let mut stochastic = vec![false; nsyms];
        for (k, r) in rules.iter().enumerate() {
            by[r.pred.sym as usize].push(k as u32);
            if r.prob.is_some() {
                stochastic[r.pred.sym as usize] = true;
            }
        }
        let mut order = Vec::with_capacity(rules.len());
        let mut start = Vec::with_capacity(nsyms + 1);
        for v in by {
            start.push(order.len() as u32);
            order.extend(v);
        }
        start.push(order.len() as u32);
        Self {
            rules,
            order,
            start,
            stochastic,
        }
    }

    #[inline]
    pub fn for_symbol(&self, s: u32) -> &[u32] {
        let s = s as usize;
        if s + 1 >= self.start.len() {
            return &[];
        }
        &self.order[self.start[s] as usize..self.start[s + 1] as usize]
    }

    pub fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }
}

/// A parsed and compiled L-system.
///
/// Build one with [`LSystem::parse`]; derive it with
/// [`crate::Derivation`].
#[derive(Clone, Debug)]
pub struct LSystem {
    pub(crate) symbols: SymbolTable,
    pub(crate) axiom: ModuleString,
    pub(crate) productions: RuleSet,
    pub(crate) decompositions: RuleSet,
    pub(crate) homomorphisms: RuleSet,
    pub(crate) derivation_length: u32,
    pub(crate) max_depth: u32,
    /// Per symbol: seen by context matching (`#ignore` / `Consider:`).
    pub(crate) visible: Vec<bool>,
    pub(crate) arrays: Vec<Vec<f64>>,
    pub(crate) user: UserFns,
    pub(crate) angle: Option<f64>,
    pub(crate) step: Option<f64>,
    pub(crate) seed: Option<u64>,
    /// `tropism: x, y, z, e`: the vector `T` and the susceptibility `e`.
    pub(crate) tropism: Option<([f64; 3], f64)>,
    pub(crate) any_context: bool,
}

impl LSystem {
    /// Parses L-system text (see the [module documentation](self) for the language).
    ///
    /// # Errors
    ///
    /// [`PlantError::Syntax`] for malformed text, [`PlantError::Undefined`] for
    /// an undefined variable, function, array or macro, and
    /// [`PlantError::Eval`] if a constant expression (the axiom's parameters,
    /// an array's values, the derivation length) fails; each names the line
    /// and column. Text past the language's limits (see the
    /// [module documentation](self#limits)) is a [`PlantError::Syntax`].
    pub fn parse(text: &str) -> Result<Self> {
        parser::parse(text)
    }

    /// The symbol table (module names by id).
    #[must_use]
    pub fn symbols(&self) -> &SymbolTable {
        &self.symbols
    }

    /// The axiom.
    #[must_use]
    pub fn axiom(&self) -> &ModuleString {
        &self.axiom
    }

    /// The derivation length given by `derivation length:` (0 if absent).
    #[must_use]
    pub fn derivation_length(&self) -> u32 {
        self.derivation_length
    }

    /// The maximum depth of decomposition and interpretation rules (`maximum depth:`, default 16).
    #[must_use]
    pub fn max_depth(&self) -> u32 {
        self.max_depth
    }

    /// The default turning angle in degrees given by `angle:`, if any.
    #[must_use]
    pub fn angle(&self) -> Option<f64> {
        self.angle
    }

    /// The default step length given by `step:`, if any.
    #[must_use]
    pub fn step(&self) -> Option<f64> {
        self.step
    }

    /// The seed given by `seed:`, if any.
    #[must_use]
    pub fn seed(&self) -> Option<u64> {
        self.seed
    }

    /// The tropism vector `T` and susceptibility `e` given by
    /// `tropism: x, y, z, e`, if any.
    #[must_use]
    pub fn tropism(&self) -> Option<([f64; 3], f64)> {
        self.tropism
    }

    /// Number of productions (not counting decomposition and interpretation rules).
    #[must_use]
    pub fn production_count(&self) -> usize {
        self.productions.rules.len()
    }

    /// True if the L-system has homomorphism (interpretation) rules.
    #[must_use]
    pub fn has_homomorphism(&self) -> bool {
        !self.homomorphisms.is_empty()
    }

    /// Makes `f` callable in expressions as `func(id, x)`.
    pub fn set_function(&mut self, id: u32, f: Function) {
        self.user.set_function(id, f);
    }

    /// Makes `c` callable in expressions as `curveX(id, s)`, `tanX(id, s)`, `curveLen(id)`, ….
    pub fn set_curve(&mut self, id: u32, c: Curve) {
        self.user.set_curve(id, c);
    }

    /// Returns the id of module `name`, if the L-system mentions it.
    #[must_use]
    pub fn symbol(&self, name: &str) -> Option<u32> {
        self.symbols.get(name)
    }

    /// Parses a module string (constant parameters) with this L-system's symbols.
    ///
    /// # Errors
    ///
    /// As [`LSystem::parse`]; a module not known to the L-system is an
    /// [`PlantError::Undefined`] error.
    pub fn parse_string(&self, text: &str) -> Result<ModuleString> {
        parser::parse_constant_string(self, text)
    }

    pub(crate) fn eval_error(&self, f: vm::Fault, production: &str) -> PlantError {
        PlantError::Eval {
            span: f.span,
            production: production.to_string(),
            message: f.message,
        }
    }
}
