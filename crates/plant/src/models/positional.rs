//! Positional information (Prusinkiewicz, Mündermann, Karwowski & Lane 2001).
//!
//! * [`organ_positions`]: organ spacing by a density, §4, eq. 11 and
//!   Algorithm 3 — nodes sit where `N(0, s) = ∫₀ˢ ds/λ(s)` passes an integer.
//! * [`ridley`]: compact phyllotaxis on a surface of revolution, §5, eq. 14 and
//!   Algorithm 5 — organs of radius ρ(s) at unit steps of
//!   `N(0, s) = ∫₀ˢ 2 f_x(s)/ρ²(s) ds`, rolled by 137.5° about the axis
//!   (Vogel's eq. 13 on a flat disc).
//! * [`branch_mapping_text`]: Algorithm 6 as L-system text — a child axis of
//!   length ℓ starts at `s = max_len − ℓ` so it repeats the distal part of
//!   the longest axis of its order (§6); [`BranchMapping`]: the same with the
//!   children's lengths drawn from a silhouette, and decussate or spiral.
//!
//! Errata: Algorithm 5 as printed places one last organ when the curve ends
//! with `a < 1`; here an organ is placed only when `a ≥ 1`. The appendix's
//! statement of the interleaving property reads `s_{i+1} = N(s₀, s_i) + 1`
//! where `N(s₀, s_{i+1}) = N(s₀, s_i) + 1` is meant. Algorithm 3 places at
//! most one node per step, so it needs `Δs < min λ` (checked here).

use crate::error::Result;
use crate::lang::Function;
use crate::mesh::invalid;

/// Algorithm 3: positions of nodes along an axis of length `len`, slices `ds`,
/// with internode density `1/λ(s)`. Returns the arc lengths of the nodes.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if `len` or `ds` is not positive and finite,
/// or `λ(s)` is not finite or not larger than `ds` somewhere on the axis.
pub fn organ_positions(len: f64, ds: f64, lambda: impl Fn(f64) -> f64) -> Result<Vec<f64>> {
    if !(len.is_finite() && len > 0.0) {
        return Err(invalid("len", len, "a positive length"));
    }
    if !(ds.is_finite() && ds > 0.0 && ds <= len && len / ds < 1e9) {
        return Err(invalid(
            "ds",
            ds,
            "a positive step at most len, len/ds < 1e9",
        ));
    }
    let mut out = Vec::new();
    let (mut s, mut a) = (0.0f64, 0.0f64);
    let n = (len / ds).floor() as u64;
    for k in 0..n {
        let l = lambda(s);
        if !(l.is_finite() && l > ds) {
            return Err(invalid("lambda", l, "finite and larger than ds everywhere"));
        }
        a += ds / l;
        s = (k + 1) as f64 * ds;
        if a >= 1.0 {
            a -= 1.0;
            out.push(s);
        }
    }
    Ok(out)
}

/// One organ placed by [`ridley`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Organ {
    /// Arc length on the generating curve.
    pub s: f64,
    /// Distance from the axis, `f_x(s)`.
    pub x: f64,
    /// Height on the axis, `f_y(s)`.
    pub y: f64,
    /// Angle about the axis, degrees (`n·137.5`).
    pub angle_deg: f64,
    /// Organ radius ρ(s).
    pub radius: f64,
}

/// Algorithm 5: organs on the surface of revolution of the arc-length curve
/// `curve(s) = (f_x, f_y)`, `s ∈ [0, len]`, with organ radius `rho(s)`, integrated in steps `ds`.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) for a non-positive `len` or `ds`, or a
/// radius that is not positive and finite, or a curve point that is not finite.
pub fn ridley(
    len: f64,
    ds: f64,
    curve: impl Fn(f64) -> (f64, f64),
    rho: impl Fn(f64) -> f64,
) -> Result<Vec<Organ>> {
    if !(len.is_finite() && len > 0.0) {
        return Err(invalid("len", len, "a positive length"));
    }
    if !(ds.is_finite() && ds > 0.0 && len / ds < 1e9) {
        return Err(invalid("ds", ds, "a positive step, len/ds < 1e9"));
    }
    let mut out = Vec::new();
    let (mut s, mut a) = (0.0f64, 0.0f64);
    while s < len {
        while a < 1.0 && s < len {
            let (x, _) = curve(s);
            let r = rho(s);
            if !(r.is_finite() && r > 0.0) {
                return Err(invalid("rho", r, "a positive finite radius"));
            }
            if !x.is_finite() {
                return Err(invalid("curve", x, "finite points"));
            }
            a += 2.0 * x / (r * r) * ds;
            s += ds;
        }
        if a < 1.0 {
            break;
        }
        a -= 1.0;
        let (x, y) = curve(s);
        out.push(Organ {
            s,
            x,
            y,
            angle_deg: out.len() as f64 * 137.5,
            radius: rho(s),
        });
    }
    Ok(out)
}

/// Algorithm 6 (branch mapping) as L-system text, with `max_len[o]` the
/// longest axis of each order (the last entry is the order past the deepest,
/// which the listing indexes), internode length `int_len`, branch angle
/// `angle_deg`, and child length `branch_len(o, rel) = child_ratio · max_len[o+1] · (1 − rel)`
/// (a cone-shaped silhouette). Decussate: pairs of opposite branches rolled 90°.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if a length is not positive and finite or fewer than 2 orders are given.
pub fn branch_mapping_text(
    max_len: &[f64],
    int_len: f64,
    angle_deg: f64,
    child_ratio: f64,
) -> Result<String> {
    if max_len.len() < 2 || max_len.len() > 8 {
        return Err(invalid("max_len", max_len.len() as f64, "2 to 8 orders"));
    }
    for &m in max_len {
        if !(m.is_finite() && m > 0.0) {
            return Err(invalid("max_len", m, "positive finite lengths"));
        }
    }
    if !(int_len.is_finite() && int_len > 0.0) {
        return Err(invalid("int_len", int_len, "a positive internode"));
    }
    if !(angle_deg.is_finite() && child_ratio.is_finite() && child_ratio > 0.0) {
        return Err(invalid(
            "child_ratio",
            child_ratio,
            "positive and finite, with a finite angle",
        ));
    }
    let child = format!("max_len[o+1] - {child_ratio}*max_len[o+1]*(1-rel)");
    Ok(algorithm_6(max_len, int_len, &child, &decussate(angle_deg)))
}

/// Algorithm 6's branches at a node: a decussate pair, rolled 90° from the
/// last (lilac).
fn decussate(angle_deg: f64) -> String {
    format!("[+({angle_deg})A(o+1,c)][-({angle_deg})A(o+1,c)]/(90)")
}

/// Algorithm 6's text: the child's start `c` given by the expression
/// `child` of `o`, `rel` and `max_len`, and `branches` the branching at a
/// node (which starts `A(o+1, c)`). One template for every variant.
fn algorithm_6(max_len: &[f64], int_len: f64, child: &str, branches: &str) -> String {
    let arr: Vec<String> = max_len.iter().map(f64::to_string).collect();
    let max = max_len.len() - 1;
    format!(
        "#define MAX {max}\n\
         Define: {{ array max_len[{}] = {{{}}}; }}\n\
         ω: A(0,0)\n\
         A(o,s) : (o < MAX) && (s < max_len[o]) {{ rel = s/max_len[o]; c = {child}; }} -> F({int_len}){branches}A(o,s+{int_len})\n\
         A(o,s) : s >= max_len[o] -> ~K\n\
         A(o,s) : o >= MAX -> ~K\n",
        max_len.len(),
        arr.join(", ")
    )
}

/// Algorithm 6 (branch mapping) with the child length drawn from a
/// silhouette: `branch_len(o, rel) = max_len[o+1]·silhouette(rel)`. With
/// straight first-order axes and short higher orders the silhouette is the
/// crown's outline (§6, Fig. 20); branches are decussate pairs (lilac,
/// Fig. 18) or, the source's "small modification", one branch a node
/// rolled 137.5° from the last (spiral, *Astilbe*, Fig. 19).
#[derive(Clone, Debug, PartialEq)]
pub struct BranchMapping {
    /// The longest axis of each order (the last entry is the order past the
    /// deepest, which the listing indexes).
    pub max_len: Vec<f64>,
    /// Internode length.
    pub internode: f64,
    /// Branching angle, degrees.
    pub angle_deg: f64,
    /// A child's length as a fraction of the longest of its order, by the
    /// position `rel ∈ [0, 1]` of its node along its mother (values in
    /// `[0, 1]`).
    pub silhouette: Function,
    /// One branch a node rolled 137.5° (spiral) instead of decussate pairs.
    pub spiral: bool,
}

impl BranchMapping {
    /// The L-system, with the silhouette as `func(1, rel)`.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) as [`branch_mapping_text`], or if
    /// the silhouette leaves `[−0.25, 1.25]` on `[0, 1]` (checked at 65
    /// evenly spaced positions). The smooth curve through a silhouette's
    /// points may overshoot them a little; the fraction is clamped to
    /// `[0, 1]`.
    pub fn lsystem(&self) -> Result<crate::LSystem> {
        // The cone's checks, on the same lengths.
        branch_mapping_text(&self.max_len, self.internode, self.angle_deg, 1.0)?;
        for x in (0..=64).map(|k| f64::from(k) / 64.0) {
            let v = self.silhouette.eval(x);
            if !(-0.25..=1.25).contains(&v) {
                return Err(invalid("silhouette", v, "a fraction in [0, 1] over [0, 1]"));
            }
        }
        let branches = if self.spiral {
            format!("[+({})A(o+1,c)]/(137.5)", self.angle_deg)
        } else {
            decussate(self.angle_deg)
        };
        let text = algorithm_6(
            &self.max_len,
            self.internode,
            "max_len[o+1] - max_len[o+1]*clamp(func(1,rel),0,1)",
            &branches,
        );
        let mut l = crate::LSystem::parse(&text)?;
        l.set_function(1, self.silhouette.clone());
        Ok(l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_density_gives_equal_spacing() {
        let v = organ_positions(10.0, 1e-3, |_| 0.7).unwrap();
        for w in v.windows(2) {
            assert!((w[1] - w[0] - 0.7).abs() < 2e-3);
        }
        assert_eq!(v.len(), (10.0f64 / 0.7).floor() as usize);
    }

    #[test]
    fn linear_density_gives_geometric_internodes() {
        // λ(s) = a s + b ⇒ l_{i+1} = e^a l_i (appendix A.3); a = 0.3, b = 0.2.
        let v = organ_positions(12.0, 1e-5, |s| 0.3 * s + 0.2).unwrap();
        let l: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
        for w in l.windows(2).skip(2) {
            assert!((w[1] / w[0] - 0.3f64.exp()).abs() < 2e-3, "{}", w[1] / w[0]);
        }
        assert!(organ_positions(1.0, 0.5, |_| 0.3).is_err());
    }

    #[test]
    fn ridley_on_a_disc_matches_vogel() {
        // f_x = s on a flat disc, constant ρ: organs up to radius R ≈ R²/ρ².
        let rho = 0.05;
        let v = ridley(1.0, 1e-5, |s| (s, 0.0), |_| rho).unwrap();
        let expect = 1.0 / (rho * rho);
        assert!(
            (v.len() as f64 - expect).abs() <= 1.0,
            "{} vs {expect}",
            v.len()
        );
        // Vogel: the n-th organ's distance grows as √n.
        let n = v.len();
        let ratio = v[n - 1].x / v[n / 4 - 1].x;
        assert!((ratio - 2.0).abs() < 0.02, "{ratio}");
    }

    #[test]
    fn a_straight_silhouette_is_the_cone() {
        // The silhouette 1 − rel is the cone of `branch_mapping_text` (child
        // ratio 1): the same segments and flowers; a spiral has one branch
        // a node; a silhouette far outside [0, 1] is refused.
        use crate::{Derivation, LSystem};
        let count = |l: &LSystem| {
            let mut d = Derivation::new(l, 0).unwrap();
            d.derive(64).unwrap();
            let n = |name: &str| {
                let id = l.symbol(name).unwrap();
                d.string().symbols().iter().filter(|&&x| x == id).count()
            };
            (n("F"), n("~K"))
        };
        let max_len = vec![10.0, 6.0, 3.0];
        let cone = LSystem::parse(&branch_mapping_text(&max_len, 1.0, 45.0, 1.0).unwrap()).unwrap();
        let mut m = BranchMapping {
            max_len,
            internode: 1.0,
            angle_deg: 45.0,
            silhouette: Function::new(&[(0.0, 1.0), (1.0, 0.0)]).unwrap(),
            spiral: false,
        };
        let (f, k) = count(&cone);
        assert_eq!(count(&m.lsystem().unwrap()), (f, k));
        m.spiral = true;
        let (fs, ks) = count(&m.lsystem().unwrap());
        assert!(fs < f && ks < k, "{fs} {ks} against {f} {k}");
        m.silhouette = Function::new(&[(0.0, 2.0), (1.0, 0.0)]).unwrap();
        let e = m.lsystem().unwrap_err().to_string();
        assert!(e.contains("silhouette"), "{e}");
    }

    #[test]
    fn branch_mapping_children_repeat_the_distal_part() {
        use crate::{Derivation, LSystem};
        let text = branch_mapping_text(&[10.0, 6.0, 3.0], 1.0, 45.0, 1.0).unwrap();
        let l = LSystem::parse(&text).unwrap();
        let mut d = Derivation::new(&l, 0).unwrap();
        d.derive(40).unwrap();
        let s = d.string().display(l.symbols());
        assert!(!s.contains('A'), "all apices terminated");
        // Main axis: 10 internodes, each with two children; a child started at
        // s = max_len[1] − ℓ grows exactly ℓ (rounded up to whole internodes).
        let k = l.symbol("~K").unwrap();
        let flowers = d.string().symbols().iter().filter(|&&x| x == k).count();
        assert!(flowers > 20, "{flowers}");
        assert!(branch_mapping_text(&[1.0], 1.0, 45.0, 1.0).is_err());
    }
}
