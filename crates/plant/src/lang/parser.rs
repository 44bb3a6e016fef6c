//! The parser: statements → directives, axiom and compiled productions.

use super::consts::{const_count, const_value, define, define_arrays, run_const, tropism_values};
use super::expr::{self, Compiler, Expr, Globals, Scope};
use super::text::{self, Ch, Cursor, Stmt};
use super::vm::Code;
use super::{LSystem, Pattern, Production, RightElem, RuleSet, SuccModule, UserFns};
use crate::error::{PlantError, Result, Span};
use crate::string::ModuleString;
use crate::symbols::{LBRACKET, RBRACKET, SymbolTable};
use crate::turtle::{MAX_EXTENT, num};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Section {
    Productions,
    Decomposition,
    Homomorphism,
}

#[derive(Debug)]
enum Filter {
    None,
    Ignore(Vec<u32>),
    Consider(Vec<u32>),
}

/// A module as written: name, span and its parameter expressions.
#[derive(Debug)]
struct RawModule {
    name: String,
    span: Span,
    params: Vec<Expr>,
}

/// The largest `maximum depth:` of decomposition and interpretation rules.
pub(crate) const MAX_DEPTH: u32 = 256;

/// Directive keywords (lower case) in the order they are tried.
const KEYWORDS: &[&str] = &[
    "#define",
    "#ignore",
    "#consider",
    "#include",
    "derivation length",
    "maximum depth",
    "max depth",
    "axiom",
    "ω",
    "lsystem",
    "endlsystem",
    "productions",
    "production",
    "decomposition",
    "homomorphism",
    "interpretation",
    "endgroup",
    "group",
    "ignore",
    "consider",
    "define",
    "array",
    "angle",
    "step",
    "seed",
    "tropism",
];

/// Returns the directive keyword a statement starts with and the character
/// offset after it (and after an optional `:`).
fn keyword(st: &Stmt) -> Option<(&'static str, usize)> {
    let lead = st.chars.iter().take_while(|c| c.c == ' ').count();
    let rest: String = st.chars[lead..].iter().map(|c| c.c).collect();
    let lower = rest.to_lowercase();
    for &k in KEYWORDS {
        if lower.starts_with(k) {
            let n = k.chars().count();
            // A keyword must end the word (`step:` but not `steps`).
            let next = rest.chars().nth(n);
            if next.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            // Bare `#define`-less words need a colon to count as directives,
            // except the section headers and end markers.
            let mut off = lead + n;
            while st.chars.get(off).is_some_and(|c| c.c == ' ') {
                off += 1;
            }
            let colon = st.chars.get(off).is_some_and(|c| c.c == ':');
            if colon {
                off += 1;
            } else if !k.starts_with('#') && !matches!(k, "endlsystem" | "endgroup" | "array") {
                continue;
            }
            return Some((k, off));
        }
    }
    None
}

pub(crate) fn parse(src: &str) -> Result<LSystem> {
    let stmts = text::statements(src)?;
    // Pass 1: macros and arrays, which may be used anywhere.
    let mut globals = Globals::default();
    let mut arrays: Vec<Vec<f64>> = Vec::new();
    for st in &stmts {
        if let Some((k, off)) = keyword(st) {
            match k {
                "#define" => define(st, off, &mut globals)?,
                "define" => define_arrays(&st.chars[off..], st.end(), &mut globals, &mut arrays)?,
                "array" => define_arrays(&st.chars, st.end(), &mut globals, &mut arrays)?,
                _ => {}
            }
        }
    }
    // Pass 2: directives and productions, in the order written.
    let consts = Consts {
        globals: &globals,
        arrays: &arrays,
    };
    let mut symbols = SymbolTable::new();
    let mut head = Directives::default();
    let mut section = Section::Productions;
    let mut rules: [Vec<Production>; 3] = [Vec::new(), Vec::new(), Vec::new()];
    for st in &stmts {
        match keyword(st) {
            None => {
                let r = production(st, &globals, &mut symbols, section)?;
                rules[section as usize].push(r);
            }
            Some(("productions" | "production", _)) => section = Section::Productions,
            Some(("decomposition", _)) => section = Section::Decomposition,
            Some(("homomorphism" | "interpretation", _)) => section = Section::Homomorphism,
            Some((k, off)) => head.directive(k, st, &st.chars[off..], &consts, &mut symbols)?,
        }
    }
    let user = UserFns::default();
    let Some(raw_axiom) = head.axiom.take() else {
        return Err(PlantError::syntax(
            Span::new(1, 1),
            "no axiom (`axiom: …` or `ω: …`)",
        ));
    };
    let axiom = constant_string(&raw_axiom, &globals, &arrays, &mut symbols, &user)?;
    let nsyms = symbols.len();
    let visible = head.filter.visibility(nsyms);
    let [p, d, h] = rules;
    let any_context = p.iter().any(Production::has_context);
    Ok(LSystem {
        symbols,
        axiom,
        productions: RuleSet::build(p, nsyms),
        decompositions: RuleSet::build(d, nsyms),
        homomorphisms: RuleSet::build(h, nsyms),
        derivation_length: head.derivation_length,
        max_depth: head.max_depth,
        visible,
        arrays,
        user,
        angle: head.angle,
        step: head.step,
        seed: head.seed,
        tropism: head.tropism,
        any_context,
    })
}

/// The constants directives may use: `#define`d macros and arrays.
struct Consts<'c> {
    globals: &'c Globals,
    arrays: &'c [Vec<f64>],
}

/// The directives of an L-system file (cpfg's header keywords).
struct Directives {
    derivation_length: u32,
    max_depth: u32,
    filter: Filter,
    angle: Option<f64>,
    step: Option<f64>,
    seed: Option<u64>,
    tropism: Option<([f64; 3], f64)>,
    axiom: Option<Vec<RawModule>>,
}

impl Default for Directives {
    /// No derivation, decomposition and interpretation 16 levels deep (cpfg's
    /// default), nothing else set.
    fn default() -> Self {
        Self {
            derivation_length: 0,
            max_depth: 16,
            filter: Filter::None,
            angle: None,
            step: None,
            seed: None,
            tropism: None,
            axiom: None,
        }
    }
}

impl Directives {
    /// Reads directive `k` of statement `st`, whose text after the keyword
    /// is `rest`.
    fn directive(
        &mut self,
        k: &str,
        st: &Stmt,
        rest: &[Ch],
        c: &Consts<'_>,
        symbols: &mut SymbolTable,
    ) -> Result<()> {
        let (g, arrays) = (c.globals, c.arrays);
        match k {
            "#define" | "define" | "array" | "lsystem" | "endlsystem" | "endgroup" | "group" => {}
            "#include" => {
                return Err(PlantError::syntax(
                    st.span(),
                    "`#include` is not supported; paste the file in",
                ));
            }
            "derivation length" => {
                self.derivation_length =
                    const_count(rest, g, arrays, "derivation length", st.span())?;
            }
            "maximum depth" | "max depth" => {
                let depth = const_count(rest, g, arrays, "maximum depth", st.span())?;
                if depth > MAX_DEPTH {
                    return Err(PlantError::syntax(
                        st.span(),
                        format!(
                            "`maximum depth: {depth}` is more than the {MAX_DEPTH} levels decomposition and interpretation rules may nest"
                        ),
                    ));
                }
                self.max_depth = depth;
            }
            "angle" => self.angle = Some(const_value(rest, g, arrays, st.span())?),
            "step" => {
                let v = const_value(rest, g, arrays, st.span())?;
                if !(0.0..=MAX_EXTENT).contains(&v) {
                    return Err(PlantError::syntax(
                        st.span(),
                        format!(
                            "`step: {}` is outside the range 0 ..= {} a step length may take",
                            num(v),
                            num(MAX_EXTENT)
                        ),
                    ));
                }
                self.step = Some(v);
            }
            "seed" => {
                let seed = const_count(rest, g, arrays, "seed", st.span())?;
                self.seed = Some(u64::from(seed));
            }
            "tropism" => {
                if self.tropism.is_some() {
                    return Err(PlantError::syntax(
                        st.span(),
                        "a second `tropism:` directive",
                    ));
                }
                self.tropism = Some(tropism_values(rest, g, arrays, st.end())?);
            }
            "axiom" | "ω" => {
                let mut cur = Cursor::new(rest).end_at(st.end());
                let raw = module_list(&mut cur, ModCtx::String)?;
                check_brackets(&raw, "the axiom")?;
                self.axiom = Some(raw);
            }
            "#ignore" | "ignore" | "#consider" | "consider" => {
                let mut cur = Cursor::new(rest).end_at(st.end());
                let raw = module_list(&mut cur, ModCtx::Names)?;
                let ids: Vec<u32> = raw
                    .iter()
                    .filter(|m| m.name != "[" && m.name != "]")
                    .map(|m| symbols.intern(&m.name))
                    .collect();
                let filter = std::mem::replace(&mut self.filter, Filter::None);
                self.filter = filter.extend(ids, k.contains("consider"), st.span())?;
            }
            _ => unreachable!("every keyword is handled"),
        }
        Ok(())
    }
}

impl Filter {
    /// This filter with `ids` added to its ignore list (or, with
    /// `consider`, to its consider list); a file may have one kind only.
    fn extend(self, ids: Vec<u32>, consider: bool, span: Span) -> Result<Self> {
        Ok(match (self, consider) {
            (Filter::None, false) => Filter::Ignore(ids),
            (Filter::None, true) => Filter::Consider(ids),
            (Filter::Ignore(mut v), false) => {
                v.extend(ids);
                Filter::Ignore(v)
            }
            (Filter::Consider(mut v), true) => {
                v.extend(ids);
                Filter::Consider(v)
            }
            _ => {
                return Err(PlantError::syntax(
                    span,
                    "both an ignore list and a consider list",
                ));
            }
        })
    }

    /// Which of `nsyms` symbols context matching sees; brackets always.
    fn visibility(&self, nsyms: usize) -> Vec<bool> {
        let mut visible = vec![true; nsyms];
        match self {
            Filter::None => {}
            Filter::Ignore(ids) => ids.iter().for_each(|&s| visible[s as usize] = false),
            Filter::Consider(ids) => {
                visible.iter_mut().for_each(|v| *v = false);
                ids.iter().for_each(|&s| visible[s as usize] = true);
            }
        }
        visible[LBRACKET as usize] = true;
        visible[RBRACKET as usize] = true;
        visible
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum ModCtx {
    /// Axiom or successor: parameters are expressions.
    String,
    /// Predecessor or context: parameters are names.
    Pattern,
    /// Ignore / consider lists: names only.
    Names,
}

/// Parses a list of modules until the end of the cursor (or a top-level
/// `<`, `>` or `:` in patterns).
fn module_list(cur: &mut Cursor<'_>, ctx: ModCtx) -> Result<Vec<RawModule>> {
    let mut out = Vec::new();
    loop {
        cur.skip_ws();
        let Some(c) = cur.peek() else { break };
        let span = cur.span();
        if ctx == ModCtx::Pattern && matches!(c, '<' | '>' | ':') {
            break;
        }
        if ctx == ModCtx::String && c == ':' {
            break;
        }
        match c {
            '(' | ')' | ',' => {
                return Err(PlantError::syntax(
                    span,
                    format!("unexpected `{c}` in a module string"),
                ));
            }
            'ε' => {
                cur.bump();
                continue;
            }
            _ => {}
        }
        cur.bump();
        let mut name = c.to_string();
        if matches!(c, '?' | '@' | '~')
            && cur
                .peek()
                .is_some_and(|n| !n.is_whitespace() && !matches!(n, '(' | ')' | ',' | ':'))
        {
            name.push(cur.bump().unwrap_or(' '));
        }
        let mut params = Vec::new();
        if cur.peek() == Some('(') {
            cur.bump();
            if ctx == ModCtx::Names {
                return Err(PlantError::syntax(
                    span,
                    "an ignore or consider list takes names only",
                ));
            }
            if !cur.eat(')') {
                loop {
                    params.push(expr::parse_expr(cur)?);
                    if cur.eat(')') {
                        break;
                    }
                    if !cur.eat(',') {
                        let found = cur
                            .peek()
                            .map_or("the end of the statement".to_string(), |c| format!("`{c}`"));
                        return Err(PlantError::syntax(
                            cur.span(),
                            format!(
                                "expected `,` or the `)` closing the `(` of module `{name}` at {span}, found {found}"
                            ),
                        ));
                    }
                }
            }
        }
        if params.len() > u16::MAX as usize {
            return Err(PlantError::syntax(span, "too many parameters"));
        }
        out.push(RawModule { name, span, params });
    }
    Ok(out)
}

/// Checks that the brackets of an axiom or a successor balance: each `]`
/// closes a `[` of the same module string, and every `[` is closed.
fn check_brackets(raw: &[RawModule], what: &str) -> Result<()> {
    let mut open = Vec::new();
    for m in raw {
        match m.name.as_str() {
            "[" => open.push(m.span),
            "]" if open.pop().is_none() => {
                return Err(PlantError::syntax(
                    m.span,
                    format!("`]` without a matching `[` in {what}"),
                ));
            }
            _ => {}
        }
    }
    match open.last() {
        Some(&span) => Err(PlantError::syntax(
            span,
            format!("`[` is never closed in {what}"),
        )),
        None => Ok(()),
    }
}

/// Evaluates the parameters of a module list as constants.
fn constant_string(
    raw: &[RawModule],
    g: &Globals,
    arrays: &[Vec<f64>],
    symbols: &mut SymbolTable,
    user: &UserFns,
) -> Result<ModuleString> {
    let mut s = ModuleString::new();
    let mut vals = Vec::new();
    for m in raw {
        vals.clear();
        for e in &m.params {
            let mut c = Compiler::new(g, Scope::default());
            let code = c.expr(e, m.span)?;
            vals.push(run_const(&code, arrays, user, "the axiom")?);
        }
        let id = symbols.intern(&m.name);
        s.push(id, &vals);
    }
    Ok(s)
}

pub(crate) fn parse_constant_string(l: &LSystem, src: &str) -> Result<ModuleString> {
    let stmts = text::statements(src)?;
    let mut s = ModuleString::new();
    let g = Globals::default();
    for st in &stmts {
        let mut cur = Cursor::new(&st.chars);
        let raw = module_list(&mut cur, ModCtx::String)?;
        if !cur.at_end() {
            return Err(PlantError::syntax(
                cur.span(),
                "unexpected `:` in a module string",
            ));
        }
        let mut vals = Vec::new();
        for m in &raw {
            vals.clear();
            for e in &m.params {
                let mut c = Compiler::new(&g, Scope::default());
                let code = c.expr(e, m.span)?;
                vals.push(run_const(&code, &l.arrays, &l.user, "a module string")?);
            }
            let id = l
                .symbols
                .get(&m.name)
                .ok_or_else(|| PlantError::Undefined {
                    span: m.span,
                    what: "module",
                    name: m.name.clone(),
                })?;
            s.push(id, &vals);
        }
    }
    Ok(s)
}

/// Turns a pattern's raw modules into patterns, binding parameter names to slots.
fn patterns(
    raw: &[RawModule],
    symbols: &mut SymbolTable,
    scope: &mut Scope,
) -> Result<Vec<(Pattern, bool)>> {
    let mut out = Vec::new();
    for m in raw {
        let slot = scope.names.len() as u16;
        for p in &m.params {
            let Expr::Var(n, s) = p else {
                return Err(PlantError::syntax(
                    m.span,
                    "a predecessor or context takes parameter names, not expressions",
                ));
            };
            if scope.names.len() >= u16::MAX as usize {
                return Err(PlantError::syntax(*s, "too many parameters"));
            }
            scope.names.push(n.clone());
        }
        let bracket = m.name == "[" || m.name == "]";
        let sym = symbols.intern(&m.name);
        out.push((
            Pattern {
                sym,
                arity: m.params.len() as u16,
                slot,
            },
            bracket,
        ));
    }
    Ok(out)
}

fn production(
    st: &Stmt,
    g: &Globals,
    symbols: &mut SymbolTable,
    section: Section,
) -> Result<Production> {
    let chars = &st.chars[..];
    let Some((ai, alen)) = text::find_arrow(chars) else {
        return Err(PlantError::syntax(
            st.span(),
            format!(
                "expected a production (`pred -> succ`) or a directive, found `{}`",
                st.text().trim()
            ),
        ));
    };
    let (lhs, rhs) = (&chars[..ai], &chars[ai + alen..]);
    let mut cur = Cursor::new(lhs).end_at(st.span());
    let label = production_label(&mut cur);
    let span = cur.span();
    let name = match &label {
        Some(l) => format!("production {l}"),
        None => format!("production at line {}", span.line),
    };
    let mut scope = Scope::default();
    let (left_raw, pred_raw, right_raw) = context_parts(&mut cur)?;
    if pred_raw.len() != 1 {
        return Err(PlantError::syntax(
            span,
            format!(
                "the strict predecessor must be one module, found {}",
                pred_raw.len()
            ),
        ));
    }
    if section != Section::Productions && (!left_raw.is_empty() || !right_raw.is_empty()) {
        return Err(PlantError::syntax(
            span,
            "decomposition and interpretation rules are context-free",
        ));
    }
    let left = patterns(&left_raw, symbols, &mut scope)?;
    if let Some((_, _)) = left.iter().find(|(_, b)| *b) {
        return Err(PlantError::syntax(
            span,
            "brackets are not supported in a left context",
        ));
    }
    let pred = patterns(&pred_raw, symbols, &mut scope)?;
    if pred[0].1 {
        return Err(PlantError::syntax(
            span,
            "a bracket cannot be a strict predecessor",
        ));
    }
    let right = patterns(&right_raw, symbols, &mut scope)?
        .into_iter()
        .map(|(p, b)| match (b, p.sym) {
            (true, LBRACKET) => RightElem::Open,
            (true, _) => RightElem::Close,
            _ => RightElem::Module(p),
        })
        .collect();
    // Condition part: `{block1} cond {block2}`.
    let nparams = scope.names.len();
    let mut comp = Compiler::new(g, scope);
    let (pre, cond, post) = condition(&mut cur, &mut comp)?;
    if !cur.at_end() {
        let c = cur.peek().unwrap_or(' ');
        return Err(PlantError::syntax(
            cur.span(),
            format!("unexpected `{c}` before the arrow"),
        ));
    }
    let (succ, prob) = successor(rhs, st, &name, symbols, &mut comp)?;
    let uses_random = [&pre, &cond, &post, &prob]
        .iter()
        .any(|c| c.as_ref().is_some_and(Code::uses_random))
        || succ.iter().any(|m| m.params.iter().any(Code::uses_random));
    Ok(Production {
        name,
        span,
        pred: pred[0].0,
        left: left.into_iter().map(|(p, _)| p).collect(),
        right,
        pre,
        cond,
        post,
        succ,
        prob,
        nslots: comp.scope.names.len(),
        nparams,
        uses_random,
    })
}

/// The optional label `p12:` at the start of a production; the cursor is
/// left where it was when there is none.
fn production_label(cur: &mut Cursor<'_>) -> Option<String> {
    let save = cur.pos;
    if let Some(id) = cur.ident() {
        let is_label =
            id.starts_with('p') && id.len() > 1 && id[1..].chars().all(|c| c.is_ascii_digit());
        if is_label && cur.eat(':') {
            return Some(id);
        }
    }
    cur.pos = save;
    None
}

/// The predecessor side `left < pred > right` of a production, as the
/// raw module lists of the left context, the strict predecessor and the
/// right context (the contexts empty when absent).
fn context_parts(cur: &mut Cursor<'_>) -> Result<(Vec<RawModule>, Vec<RawModule>, Vec<RawModule>)> {
    let first = module_list(cur, ModCtx::Pattern)?;
    let (left_raw, pred_raw) = if cur.eat('<') {
        (first, module_list(cur, ModCtx::Pattern)?)
    } else {
        (Vec::new(), first)
    };
    let right_raw = if cur.eat('>') {
        module_list(cur, ModCtx::Pattern)?
    } else {
        Vec::new()
    };
    Ok((left_raw, pred_raw, right_raw))
}

/// The condition part of a production after its `:`, `{block1} cond
/// {block2}`: the blocks and the condition, each optional.
fn condition(
    cur: &mut Cursor<'_>,
    comp: &mut Compiler<'_>,
) -> Result<(Option<Code>, Option<Code>, Option<Code>)> {
    let (mut pre, mut cond, mut post) = (None, None, None);
    if cur.eat(':') {
        if cur.eat('{') {
            let s = cur.span();
            let b = expr::parse_block(cur)?;
            cur.expect('}', "to close the block")?;
            pre = Some(comp.block(&b, s)?);
        }
        cur.skip_ws();
        if cur.peek() == Some('*') && !cur.peek_at(1).is_some_and(|c| c != ' ' && c != '{') {
            cur.bump();
        } else if !cur.at_end() && cur.peek() != Some('{') {
            let s = cur.span();
            let e = expr::parse_expr(cur)?;
            cond = Some(comp.expr(&e, s)?);
        }
        if cur.eat('{') {
            let s = cur.span();
            let b = expr::parse_block(cur)?;
            cur.expect('}', "to close the block")?;
            post = Some(comp.block(&b, s)?);
        }
    }
    Ok((pre, cond, post))
}

/// The successor of a production (right of its arrow) and its probability
/// after a top-level `:`, compiled.
fn successor(
    rhs: &[Ch],
    st: &Stmt,
    name: &str,
    symbols: &mut SymbolTable,
    comp: &mut Compiler<'_>,
) -> Result<(Vec<SuccModule>, Option<Code>)> {
    let mut depth = 0i32;
    let mut colon = None;
    for (k, c) in rhs.iter().enumerate() {
        match c.c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ':' if depth == 0 => colon = Some(k),
            _ => {}
        }
    }
    let (succ_chars, prob_chars) = match colon {
        Some(k) => (&rhs[..k], Some(&rhs[k + 1..])),
        None => (rhs, None),
    };
    let mut scur = Cursor::new(succ_chars).end_at(st.end());
    let empty = {
        let t: String = succ_chars.iter().map(|c| c.c).collect();
        let t = t.trim();
        t == "*" || t == "ε" || t.is_empty()
    };
    let raw_succ = if empty {
        Vec::new()
    } else {
        module_list(&mut scur, ModCtx::String)?
    };
    check_brackets(&raw_succ, &format!("the successor of {name}"))?;
    let mut succ = Vec::with_capacity(raw_succ.len());
    for m in &raw_succ {
        let sym = symbols.intern(&m.name);
        let mut params = Vec::with_capacity(m.params.len());
        for e in &m.params {
            params.push(comp.expr(e, m.span)?);
        }
        succ.push(SuccModule { sym, params });
    }
    let prob = match prob_chars {
        Some(pc) => {
            let mut pcur = Cursor::new(pc).end_at(st.end());
            let s = pcur.span();
            if pcur.at_end() {
                return Err(PlantError::syntax(s, "expected a probability after `:`"));
            }
            let e = expr::parse_expr(&mut pcur)?;
            if !pcur.at_end() {
                return Err(PlantError::syntax(
                    pcur.span(),
                    "unexpected text after the probability",
                ));
            }
            Some(comp.expr(&e, s)?)
        }
        None => None,
    };
    Ok((succ, prob))
}
