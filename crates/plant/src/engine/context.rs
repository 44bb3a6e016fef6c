//! Context matching in bracketed strings (Prusinkiewicz & Lindenmayer 1990,
//! §1.8, "context-sensitive L-systems"; Prusinkiewicz, Hanan & Měch 2000,
//! for the handling of branches and of the ignore / consider lists).
//!
//! A left context is matched leftwards from the predecessor: a complete
//! branch `[…]` to the left is skipped, a `[` is crossed into the parent
//! axis, and symbols not seen by matching (ignored) are skipped. A right
//! context is matched rightwards: a complete branch is skipped unless the
//! pattern itself asks for a `[`, the end of the current branch (`]`) ends
//! the match, and a `]` in the pattern skips the rest of the current branch.

use crate::lang::{Pattern, RightElem};
use crate::string::ModuleString;
use crate::symbols::{LBRACKET, RBRACKET};

/// Binds a pattern's parameters from module `j` into `slots`.
#[inline]
fn bind(p: &Pattern, s: &ModuleString, j: usize, slots: &mut [f64]) -> bool {
    if s.symbol(j) != p.sym || s.arity(j) != p.arity as usize {
        return false;
    }
    let a = p.slot as usize;
    slots[a..a + p.arity as usize].copy_from_slice(s.params(j));
    true
}

/// Matches the predecessor at `i` (symbol already known equal).
#[inline]
pub(crate) fn bind_pred(p: &Pattern, s: &ModuleString, i: usize, slots: &mut [f64]) -> bool {
    bind(p, s, i, slots)
}

/// Matches a left context ending just before module `i`.
pub(crate) fn match_left(
    left: &[Pattern],
    s: &ModuleString,
    i: usize,
    partners: &[u32],
    visible: &[bool],
    slots: &mut [f64],
) -> bool {
    let syms = s.symbols();
    let mut j = i as isize - 1;
    let mut p = left.len();
    while p > 0 {
        if j < 0 {
            return false;
        }
        let ju = j as usize;
        let sym = syms[ju];
        if sym == RBRACKET {
            let o = partners[ju];
            if o == u32::MAX {
                return false;
            }
            j = o as isize - 1;
            continue;
        }
        if sym == LBRACKET || !visible[sym as usize] {
            j -= 1;
            continue;
        }
        if !bind(&left[p - 1], s, ju, slots) {
            return false;
        }
        p -= 1;
        j -= 1;
    }
    true
}

/// Matches a right context starting just after module `i`.
pub(crate) fn match_right(
    right: &[RightElem],
    s: &ModuleString,
    i: usize,
    partners: &[u32],
    visible: &[bool],
    slots: &mut [f64],
) -> bool {
    let syms = s.symbols();
    let n = syms.len();
    let mut j = i + 1;
    let mut p = 0;
    while p < right.len() {
        match right[p] {
            RightElem::Open => {
                // Skip ignored symbols up to the `[`.
                loop {
                    if j >= n {
                        return false;
                    }
                    let sym = syms[j];
                    if sym == LBRACKET {
                        break;
                    }
                    if sym == RBRACKET || visible[sym as usize] {
                        return false;
                    }
                    j += 1;
                }
                j += 1;
                p += 1;
            }
            RightElem::Close => {
                // Skip the rest of the current branch, including nested branches.
                loop {
                    if j >= n {
                        return false;
                    }
                    let sym = syms[j];
                    if sym == RBRACKET {
                        break;
                    }
                    if sym == LBRACKET {
                        j = partners[j] as usize + 1;
                    } else {
                        j += 1;
                    }
                }
                j += 1;
                p += 1;
            }
            RightElem::Module(ref pat) => {
                loop {
                    if j >= n {
                        return false;
                    }
                    let sym = syms[j];
                    if sym == LBRACKET {
                        j = partners[j] as usize + 1;
                        continue;
                    }
                    if sym == RBRACKET {
                        return false;
                    }
                    if !visible[sym as usize] {
                        j += 1;
                        continue;
                    }
                    break;
                }
                if !bind(pat, s, j, slots) {
                    return false;
                }
                j += 1;
                p += 1;
            }
        }
    }
    true
}
