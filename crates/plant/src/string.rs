//! The module string: symbols and parameters as struct-of-arrays.
//!
//! A string of `n` modules with `m` parameters in all takes `8 n + 8 m`
//! bytes: one `u32` symbol id and one `u32` parameter offset per module, and
//! one `f64` pool for all parameters. Derivation writes a new string beside
//! the old one and swaps them (double buffering), so no module allocates.

use crate::symbols::{LBRACKET, RBRACKET, SymbolTable};
use std::fmt::Write as _;

/// A bracketed string of parametric modules.
#[derive(Clone, Debug, PartialEq)]
pub struct ModuleString {
    sym: Vec<u32>,
    /// `off[i]..off[i + 1]` are module `i`'s parameters; `off.len() == len() + 1`.
    off: Vec<u32>,
    params: Vec<f64>,
}

impl Default for ModuleString {
    fn default() -> Self {
        Self::new()
    }
}

impl ModuleString {
    /// Returns the empty string.
    #[must_use]
    pub fn new() -> Self {
        Self {
            sym: Vec::new(),
            off: vec![0],
            params: Vec::new(),
        }
    }

    /// Returns an empty string with room for `modules` modules and `params` parameters.
    #[must_use]
    pub fn with_capacity(modules: usize, params: usize) -> Self {
        let mut off = Vec::with_capacity(modules + 1);
        off.push(0);
        Self {
            sym: Vec::with_capacity(modules),
            off,
            params: Vec::with_capacity(params),
        }
    }

    /// Number of modules.
    #[must_use]
    #[inline]
    pub fn len(&self) -> usize {
        self.sym.len()
    }

    /// True if there are no modules.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.sym.is_empty()
    }

    /// Total number of parameters.
    #[must_use]
    pub fn param_count(&self) -> usize {
        self.params.len()
    }

    /// Removes every module, keeping the memory.
    pub fn clear(&mut self) {
        self.sym.clear();
        self.off.clear();
        self.off.push(0);
        self.params.clear();
    }

    /// Appends a module.
    ///
    /// # Panics
    ///
    /// If the string would hold more than `u32::MAX` parameters (the
    /// derivation engine stops far earlier, at its growth limit).
    #[inline]
    pub fn push(&mut self, sym: u32, params: &[f64]) {
        self.sym.push(sym);
        self.params.extend_from_slice(params);
        self.off
            .push(u32::try_from(self.params.len()).expect("parameter pool over u32::MAX"));
    }

    /// Starts a module whose parameters follow with [`Self::push_param`] and
    /// which is closed by [`Self::end_module`].
    #[inline]
    pub(crate) fn begin_module(&mut self, sym: u32) {
        self.sym.push(sym);
    }

    #[inline]
    pub(crate) fn push_param(&mut self, v: f64) {
        self.params.push(v);
    }

    #[inline]
    pub(crate) fn end_module(&mut self) {
        self.off.push(self.params.len() as u32);
    }

    /// Appends module `i` of `other`.
    #[inline]
    pub(crate) fn push_from(&mut self, other: &ModuleString, i: usize) {
        self.sym.push(other.sym[i]);
        let (a, b) = (other.off[i] as usize, other.off[i + 1] as usize);
        self.params.extend_from_slice(&other.params[a..b]);
        self.off.push(self.params.len() as u32);
    }

    /// Appends modules `a..b` of `other`.
    pub(crate) fn extend_from_range(&mut self, other: &ModuleString, a: usize, b: usize) {
        let base = self.params.len() as i64 - i64::from(other.off[a]);
        self.sym.extend_from_slice(&other.sym[a..b]);
        self.params
            .extend_from_slice(&other.params[other.off[a] as usize..other.off[b] as usize]);
        self.off.extend(
            other.off[a + 1..=b]
                .iter()
                .map(|&o| (i64::from(o) + base) as u32),
        );
    }

    /// Makes room for `modules` more modules and `params` more parameters,
    /// growing each array by doubling but never past `max_modules` modules
    /// and `max_params` parameters (unless the room asked for needs more).
    pub(crate) fn reserve_within(
        &mut self,
        modules: usize,
        params: usize,
        max_modules: usize,
        max_params: usize,
    ) {
        fn grow<T>(v: &mut Vec<T>, extra: usize, limit: usize) {
            let need = v.len() + extra;
            if need > v.capacity() {
                let target = (2 * v.capacity()).max(need).min(limit.max(need));
                v.reserve_exact(target - v.len());
            }
        }
        grow(&mut self.sym, modules, max_modules);
        grow(&mut self.off, modules, max_modules.saturating_add(1));
        grow(&mut self.params, params, max_params);
    }

    /// Returns module `i`'s symbol id.
    ///
    /// # Panics
    ///
    /// If `i >= len()`.
    #[must_use]
    #[inline]
    pub fn symbol(&self, i: usize) -> u32 {
        self.sym[i]
    }

    /// Returns module `i`'s parameters.
    ///
    /// # Panics
    ///
    /// If `i >= len()`.
    #[must_use]
    #[inline]
    pub fn params(&self, i: usize) -> &[f64] {
        &self.params[self.off[i] as usize..self.off[i + 1] as usize]
    }

    /// Returns module `i`'s parameters, mutably.
    ///
    /// # Panics
    ///
    /// If `i >= len()`.
    #[inline]
    pub fn params_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self.params[self.off[i] as usize..self.off[i + 1] as usize]
    }

    /// Returns the number of parameters of module `i`.
    #[must_use]
    #[inline]
    pub(crate) fn arity(&self, i: usize) -> usize {
        (self.off[i + 1] - self.off[i]) as usize
    }

    /// Returns all symbol ids.
    #[must_use]
    pub fn symbols(&self) -> &[u32] {
        &self.sym
    }

    /// Bytes of memory the string holds (capacity, not length).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.sym.capacity() * 4 + self.off.capacity() * 4 + self.params.capacity() * 8
    }

    /// Returns, for each bracket, the index of its partner: `u32::MAX` for an
    /// unmatched `]`, `len()` for an unmatched `[`; other entries are unused.
    pub(crate) fn bracket_partners(&self, out: &mut Vec<u32>, stack: &mut Vec<u32>) {
        out.clear();
        out.resize(self.len(), 0);
        stack.clear();
        for (i, &s) in self.sym.iter().enumerate() {
            if s == LBRACKET {
                stack.push(i as u32);
            } else if s == RBRACKET {
                if let Some(o) = stack.pop() {
                    out[o as usize] = i as u32;
                    out[i] = o;
                } else {
                    out[i] = u32::MAX;
                }
            }
        }
        for &o in stack.iter() {
            out[o as usize] = self.len() as u32;
        }
    }

    /// Writes the string in L-system notation: `A(1)B(3,2.5)[+F]`.
    #[must_use]
    pub fn display(&self, symbols: &SymbolTable) -> String {
        let mut s = String::new();
        for i in 0..self.len() {
            s.push_str(symbols.name(self.sym[i]));
            let p = self.params(i);
            if !p.is_empty() {
                s.push('(');
                for (k, v) in p.iter().enumerate() {
                    if k > 0 {
                        s.push(',');
                    }
                    let _ = write!(s, "{v}");
                }
                s.push(')');
            }
        }
        s
    }
}
