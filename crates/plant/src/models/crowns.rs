//! Tree crowns competing for light (after Takenaka 1994).
//!
//! Měch & Prusinkiewicz 1996, §8, Fig. 11–16: leaf clusters `L` report
//! their radius through `?E(r)` once a year (every `Del + 1` = 31 steps); the
//! environment answers with the light flux from the sky reaching the
//! cluster, which decides whether the leaf survives and whether the apex
//! behind it branches, grows straight or rests. Photosynthates flow towards
//! the base one `!` per step (a pipe model of widths, `w² = w1² + w2²`), and
//! a branch whose flow stays negative is shed with `%`.
//!
//! The environment ([`SkyLight`]) bins the clusters into a tight grid of
//! 32×32×32 voxels, casts one ray from each cluster towards each of nine sky
//! sources, takes the clusters whose projections overlap the cluster's as
//! occluders, and computes, per source `S` of radiance `B`,
//! `Φ = (A_i − A_ij)·B + A_ij·τ·B` with leaf transmittance τ = 0.25, several
//! occluders multiplying their influences; the flux is summed over sources.
//!
//! Errata and readings (the listing was damaged in conversion): the right
//! context of p4/p5 is `?E(r)` (printed `E(r)`); p5's condition is
//! `((age == LS) || (r·LP < LM)) && (del == Del)`; p6's lateral branch holds
//! the new shoot (`[+(α2)!(W,−PB,1)F(vig)L…A(vig,0)[!(0,0,0)]!(W,0,1)]`),
//! as the text describes, not an empty `[+(α2)]`; `!` belongs to the
//! `Consider:` list, since p10/p11 match it. The nine sources' radiances are
//! not printed: here a zenith source and eight at 45° elevation weighted by
//! the standard overcast sky, `(1 + 2 cos θ)/3` (our choice). The
//! multiplication of influences is read as
//! `Φ_S = B·A_i·Π_j (1 − (1 − τ)·A_ij/A_i)`, and the flux is normalised so an
//! unshaded cluster receives 1, which the thresholds `LP·r` against `LM`,
//! `PB`, `PG` need (the source does not state it).
//!
//! The extension of Fig. 12 ("a gradual reduction of the branching angle
//! of a young branch whose sister branch has been shed"; rules ours): a
//! fork writes a module `C(s1, s2)` before its lateral branch. `C` sees
//! both daughters' first `!` in its right context; a daughter shed by p11
//! is left as `!(w, 0, 0)` with `w > 0` (a virtual branch has `w = 0`), and
//! `C` records it (`s1`: the lateral shed, `s2`: the main axis shed). The
//! daughters' turns `+(α2)` and `-(α1)` have `C` as their left context and
//! shrink by a factor `SR` a step while their sister is gone, with
//! `SR^(Del+1) = 1 − straightening` a year; p10 and p11 are written once
//! more with `C` between the mother's leaf and the fork.
//!
//! Table 1 of the source counts the trees of Fig. 12 (22 462 branch
//! segments, 19 195 leaf clusters, 744 steps = 24 years) and Fig. 15
//! (13 502 segments, 3 448 clusters, 194 steps, 15 years). Neither is the
//! listing's model: Fig. 12 is its extension (a branch whose sister was
//! shed straightens to become the leader; here
//! [`CrownParams::straightening`], with rules of our own) and Fig. 15 a
//! conifer variant (here [`conifers`](super::conifers), also with rules of
//! our own), and the source prints neither's rules; with the sky's
//! radiances and the flux's normalisation also missing, the table cannot
//! be reproduced. The listing's model here, one tree, gives 127 segments
//! (`F`) and 127 leaf modules `L` (126 alive) after 6 years, and 463
//! segments and 465 `L` (409 alive) after 8 years; the extension, losing
//! half the angle a year, 11 839 segments and 9 356 living clusters after
//! 24 years.

use glam::DVec3;
use natura_core::check;

use super::{Run, run_open};
use crate::error::{PlantError, Result};
use crate::lang::LSystem;
use crate::open::{Environment, Message, Reply};
use crate::turtle::TurtleParams;

/// Parameters of the tree model (defaults: the source's listing).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CrownParams {
    /// Divergence angle φ, degrees.
    pub divergence_deg: f64,
    /// Direction change without branching α0, degrees.
    pub alpha0_deg: f64,
    /// Branching angle of the main axis α1, degrees.
    pub alpha1_deg: f64,
    /// Branching angle of the lateral axis α2, degrees.
    pub alpha2_deg: f64,
    /// Initial branch width W.
    pub width: f64,
    /// Apex vigor decrement VD.
    pub vigor_decrement: f64,
    /// Delay Del (steps per year − 1).
    pub delay: u32,
    /// Years a leaf stays, LS.
    pub leaf_years: u32,
    /// Full photosynthate production LP.
    pub production: f64,
    /// Leaf maintenance LM.
    pub leaf_maintenance: f64,
    /// Photosynthates needed for branching PB.
    pub branching: f64,
    /// Photosynthates needed for growth PG.
    pub growth: f64,
    /// Branch maintenance coefficient BM.
    pub branch_maintenance: f64,
    /// Branch maintenance exponent BE.
    pub branch_exponent: f64,
    /// Threshold of terminal segments above which a branch is never shed, Nmin.
    pub shed_min: u32,
    /// Transmittance τ of a leaf cluster.
    pub transmittance: f64,
    /// Years to grow.
    pub years: u32,
    /// Positions of the trees' bases along x (one tree per entry).
    pub trees_x: Vec<f64>,
    /// The source's extension of the model (Fig. 12): the fraction of its
    /// branching angle a branch loses each year once its sister has been
    /// shed, so it turns into its mother segment's direction and becomes
    /// the leader. 0 (the default) is the listing.
    pub straightening: f64,
}

impl Default for CrownParams {
    fn default() -> Self {
        Self {
            divergence_deg: 137.5,
            alpha0_deg: 5.0,
            alpha1_deg: 20.0,
            alpha2_deg: 32.0,
            width: 0.02,
            vigor_decrement: 0.95,
            delay: 30,
            leaf_years: 5,
            production: 8.0,
            leaf_maintenance: 2.0,
            branching: 0.8,
            growth: 0.4,
            branch_maintenance: 0.32,
            branch_exponent: 1.5,
            shed_min: 25,
            transmittance: 0.25,
            years: 6,
            trees_x: vec![0.0],
            straightening: 0.0,
        }
    }
}

impl CrownParams {
    /// Checks every value is finite and in range.
    ///
    /// # Errors
    ///
    /// [`PlantError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        for (n, v) in [
            ("CrownParams::divergence_deg", self.divergence_deg),
            ("CrownParams::alpha0_deg", self.alpha0_deg),
            ("CrownParams::alpha1_deg", self.alpha1_deg),
            ("CrownParams::alpha2_deg", self.alpha2_deg),
            ("CrownParams::branch_exponent", self.branch_exponent),
        ] {
            check::finite(n, v)?;
        }
        for (n, v) in [
            ("CrownParams::width", self.width),
            ("CrownParams::production", self.production),
        ] {
            check::positive(n, v)?;
        }
        for (n, v) in [
            ("CrownParams::leaf_maintenance", self.leaf_maintenance),
            ("CrownParams::branching", self.branching),
            ("CrownParams::growth", self.growth),
            ("CrownParams::branch_maintenance", self.branch_maintenance),
        ] {
            check::non_negative(n, v)?;
        }
        check::in_range(
            "CrownParams::vigor_decrement",
            self.vigor_decrement,
            1e-6,
            1.0,
            "a ratio in (0, 1]",
        )?;
        check::in_range(
            "CrownParams::straightening",
            self.straightening,
            0.0,
            1.0,
            "a fraction in [0, 1]",
        )?;
        check::in_range(
            "CrownParams::transmittance",
            self.transmittance,
            0.0,
            1.0,
            "a number in [0, 1]",
        )?;
        check_stand(
            [
                "CrownParams::delay",
                "CrownParams::leaf_years",
                "CrownParams::years",
                "CrownParams::trees_x",
            ],
            self.delay,
            self.leaf_years,
            self.years,
            &self.trees_x,
        )?;
        Ok(())
    }

    /// Derivation steps per year, `Del + 1`.
    #[must_use]
    pub fn steps_per_year(&self) -> u32 {
        self.delay + 1
    }

    /// The model's L-system text (the source's listing with the errata
    /// above applied, and with [`Self::straightening`] above 0 its
    /// extension, described in the module docs).
    #[must_use]
    pub fn lsystem_text(&self) -> String {
        let axiom = stand_axiom(
            &self.trees_x,
            "!(W,1,1)F(2)L(1,LP,0,0)A(1,0)[!(0,0,0)]!(W,0,1)",
        );
        // The extension (see the module docs) marks each fork with `C`.
        let extended = self.straightening > 0.0;
        let (mark, consider) = if extended {
            ("C(0,0)", "?E [ ] L ! C")
        } else {
            ("", "?E [ ] L !")
        };
        let fork = format!(
            "/(φ){mark}[+(α2)!(W,-PB,1)F(vig)L(vig,LP,0,0)A(vig,0)[!(0,0,0)]!(W,0,1)]-(α1)!(W,0,1)F(vig)L(vig,LP,0,0)/A(vig,0)"
        );
        let grow = "/(φ)-(α0)[!(0,0,0)]!(W,-PG,1)F(vig)L(vig,LP,0,0)A(vig,0)";
        // p10 and p11: the pipe model's flow to the base and the shedding,
        // for a mother whose fork carries `ctx` between its leaf and the
        // fork.
        let flow = |ctx: &str| {
            format!(
                "!(w0,q0,n0) > L(vig,pL,age,del) {ctx}[!(w1,q1,n1)] !(w2,q2,n2) : {{ w = (w1^2+w2^2)^0.5; q = q1+q2+pL-BM*(w/W)^BE; }} (q > 0) || (n1+n2 >= Nmin) -> !(w,q,n1+n2)\n\
                 !(w0,q0,n0) > L(vig,pL,age,del) {ctx}[!(w1,q1,n1)] !(w2,q2,n2) -> !(w0,0,0)L%\n"
            )
        };
        let extension = if extended {
            let sr = (1.0 - self.straightening).powf(1.0 / f64::from(self.steps_per_year()));
            format!(
                "#define SR {sr}\n\
                 C(s1,s2) > [!(w1,q1,n1)] !(w2,q2,n2) : (s1 == 0) && (w1 > 0) && (n1 == 0) -> C(1,s2)\n\
                 C(s1,s2) > [!(w1,q1,n1)] !(w2,q2,n2) : (s2 == 0) && (w2 > 0) && (n2 == 0) -> C(s1,1)\n\
                 C(s1,s2) < +(a) : s2 == 1 -> +(a*SR)\n\
                 C(s1,s2) < -(a) : s1 == 1 -> -(a*SR)\n{}",
                flow("C(s1,s2) ")
            )
        } else {
            String::new()
        };
        format!(
            "#define φ {}\n#define α0 {}\n#define α1 {}\n#define α2 {}\n#define W {}\n#define VD {}\n\
             #define BM {}\n#define BE {}\n#define Nmin {}\n{}\
             Consider: {consider}\n\
             ω: {axiom}\n\
             {}{extension}{}",
            self.divergence_deg,
            self.alpha0_deg,
            self.alpha1_deg,
            self.alpha2_deg,
            self.width,
            self.vigor_decrement,
            self.branch_maintenance,
            self.branch_exponent,
            self.shed_min,
            light_defines(
                self.delay,
                self.leaf_years,
                [
                    self.production,
                    self.leaf_maintenance,
                    self.branching,
                    self.growth
                ]
            ),
            light_rules(&fork, grow),
            flow(""),
        )
    }
}

/// The axiom of a stand: `tree` at each base along x, each in a branch of
/// its own (moved there with `f`), so each tree is one top-level branch.
pub(super) fn stand_axiom(trees_x: &[f64], tree: &str) -> String {
    trees_x
        .iter()
        .map(|x| format!("[-(90)f({x})+(90){tree}]"))
        .collect()
}

/// Checks the growing season and the stand shared by the crowns and the
/// conifers: `Del` 1 to 1000 steps, `LS` 1 to 100 years, at most 40 years,
/// 1 to 64 trees at finite places; `names` name the four fields in errors.
pub(super) fn check_stand(
    names: [&'static str; 4],
    delay: u32,
    leaf_years: u32,
    years: u32,
    trees_x: &[f64],
) -> Result<()> {
    let [n_delay, n_leaf, n_years, n_trees] = names;
    check::count(n_delay, delay as usize, 1, 1000, "1 to 1000 steps")?;
    check::count(n_leaf, leaf_years as usize, 1, 100, "1 to 100 years")?;
    check::count(n_years, years as usize, 0, 40, "at most 40 years")?;
    check::count(n_trees, trees_x.len(), 1, 64, "1 to 64 trees")?;
    for &x in trees_x {
        check::finite(n_trees, x)?;
    }
    Ok(())
}

/// The `#define`s of the light economy shared by the crowns and the
/// conifers: `Del`, `LS` and `[LP, LM, PB, PG]`.
pub(super) fn light_defines(delay: u32, leaf_years: u32, [lp, lm, pb, pg]: [f64; 4]) -> String {
    format!(
        "#define Del {delay}\n#define LS {leaf_years}\n#define LP {lp}\n#define LM {lm}\n#define PB {pb}\n#define PG {pg}\n"
    )
}

/// The listing's rules of the leaf clusters and the apices, shared by the
/// crowns and the conifers (p1–p9): each year a leaf reports its cluster
/// through `?E`, lives or dies by the light it is answered, and the apex
/// behind it forks (`fork`), grows (`grow`) or rests.
pub(super) fn light_rules(fork: &str, grow: &str) -> String {
    format!(
        "A(vig,del) : del < Del -> A(vig,del+1)\n\
         L(vig,p,age,del) : (age < LS) && (del < Del-1) -> L(vig,p,age,del+1)\n\
         L(vig,p,age,del) : (age < LS) && (del == Del-1) -> L(vig,p,age,del+1)?E(vig*0.5)\n\
         L(vig,p,age,del) > ?E(r) : (age < LS) && (r*LP >= LM) && (del == Del) -> L(vig,LP*r-LM,age+1,0)\n\
         L(vig,p,age,del) > ?E(r) : ((age == LS) || (r*LP < LM)) && (del == Del) -> L(0,0,LS,0)\n\
         ?E(r) < A(vig,del) : r*LP-LM > PB {{ vig = vig*VD; }} -> {fork}\n\
         ?E(r) < A(vig,del) : r*LP-LM > PG {{ vig = vig*VD; }} -> {grow}\n\
         ?E(r) < A(vig,del) : r*LP-LM <= PG -> A(vig,0)\n\
         ?E(r) -> ε\n"
    )
}

/// The light environment: nine sky sources over a 32³ voxel grid of leaf clusters.
#[derive(Clone, Debug)]
pub struct SkyLight {
    /// Unit directions towards the sources and their radiances.
    pub sources: Vec<(DVec3, f64)>,
    /// Transmittance τ of a leaf cluster.
    pub transmittance: f64,
    /// Use the voxel grid (true) or test every pair (false; the reference).
    pub use_grid: bool,
    /// Messages answered so far (for tests and statistics).
    pub answered: usize,
}

impl SkyLight {
    /// Nine sources: the zenith and eight azimuths at 45° elevation, weighted by the overcast sky.
    #[must_use]
    pub fn overcast(transmittance: f64) -> Self {
        let mut sources = vec![(DVec3::Z, 1.0)];
        let e = std::f64::consts::FRAC_PI_4;
        for k in 0..8 {
            let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let d = DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
            sources.push((d, (1.0 + 2.0 * d.z) / 3.0));
        }
        Self {
            sources,
            transmittance,
            use_grid: true,
            answered: 0,
        }
    }

    /// Light reaching each cluster `(centre, radius)`, normalised so an unshaded one receives 1.
    #[must_use]
    pub fn flux(&self, clusters: &[(DVec3, f64)]) -> Vec<f64> {
        let grid = Voxels::new(clusters);
        let total: f64 = self.sources.iter().map(|s| s.1).sum();
        let mut stamp = vec![u32::MAX; clusters.len()];
        let mut cand = Vec::new();
        let mut out = Vec::with_capacity(clusters.len());
        for (i, &(c, r)) in clusters.iter().enumerate() {
            let ai = std::f64::consts::PI * r * r;
            let mut phi = 0.0;
            for (si, &(s, b)) in self.sources.iter().enumerate() {
                cand.clear();
                if self.use_grid {
                    grid.along_ray(c, s, r, (i * 16 + si) as u32, &mut stamp, &mut cand);
                } else {
                    cand.extend(0..clusters.len() as u32);
                }
                let mut f = 1.0;
                for &j in &cand {
                    let j = j as usize;
                    if j == i {
                        continue;
                    }
                    let (cj, rj) = clusters[j];
                    let v = cj - c;
                    let along = v.dot(s);
                    if along <= 0.0 {
                        continue;
                    }
                    let d = (v - s * along).length();
                    let aij = lens_area(r, rj, d);
                    if aij > 0.0 {
                        f *= 1.0 - (1.0 - self.transmittance) * (aij / ai).min(1.0);
                    }
                }
                phi += b * f;
            }
            out.push(if ai > 0.0 { phi / total } else { 0.0 });
        }
        out
    }
}

/// Area of the intersection of two discs of radii `a`, `b` whose centres are `d` apart.
#[must_use]
pub fn lens_area(a: f64, b: f64, d: f64) -> f64 {
    use std::f64::consts::PI;
    if d >= a + b {
        return 0.0;
    }
    if d <= (a - b).abs() {
        let m = a.min(b);
        return PI * m * m;
    }
    let x = ((d * d + a * a - b * b) / (2.0 * d * a)).clamp(-1.0, 1.0);
    let y = ((d * d + b * b - a * a) / (2.0 * d * b)).clamp(-1.0, 1.0);
    let k = (-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b);
    a * a * x.acos() + b * b * y.acos() - 0.5 * k.max(0.0).sqrt()
}

/// Clusters binned by centre into a tight grid of at most 32³ voxels.
struct Voxels {
    lo: DVec3,
    size: DVec3,
    r_max: f64,
    start: Vec<u32>,
    items: Vec<u32>,
}

const N: usize = 32;

impl Voxels {
    fn new(clusters: &[(DVec3, f64)]) -> Self {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let mut r_max: f64 = 0.0;
        for &(c, r) in clusters {
            lo = lo.min(c);
            hi = hi.max(c);
            r_max = r_max.max(r);
        }
        if clusters.is_empty() {
            lo = DVec3::ZERO;
            hi = DVec3::ONE;
        }
        // Voxels no smaller than a cluster's diameter, so the inflated neighbourhood of a ray
        // sample is the 3×3×3 block around it.
        let size = ((hi - lo) / N as f64).max(DVec3::splat((2.0 * r_max).max(1e-6)));
        let mut g = Self {
            lo,
            size,
            r_max,
            start: vec![0; N * N * N + 1],
            items: vec![0; clusters.len()],
        };
        let keys: Vec<usize> = clusters.iter().map(|&(c, _)| g.key(g.cell(c))).collect();
        for &k in &keys {
            g.start[k + 1] += 1;
        }
        for k in 0..N * N * N {
            g.start[k + 1] += g.start[k];
        }
        let mut fill = g.start.clone();
        for (i, &k) in keys.iter().enumerate() {
            g.items[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        g
    }

    fn cell(&self, p: DVec3) -> [i64; 3] {
        let q = (p - self.lo) / self.size;
        [q.x, q.y, q.z].map(|v| (v.floor() as i64).clamp(-1, N as i64))
    }

    fn key(&self, c: [i64; 3]) -> usize {
        let [x, y, z] = c.map(|v| v.clamp(0, N as i64 - 1) as usize);
        (z * N + y) * N + x
    }

    /// Clusters whose centres lie within `r + r_max` of the ray from `c` along `s`.
    fn along_ray(
        &self,
        c: DVec3,
        s: DVec3,
        r: f64,
        tag: u32,
        stamp: &mut [u32],
        out: &mut Vec<u32>,
    ) {
        let reach = r + self.r_max;
        let h = self.size.min_element();
        let k = (reach / self.size).ceil();
        let (kx, ky, kz) = (k.x as i64 + 1, k.y as i64 + 1, k.z as i64 + 1);
        let ext = (self.size * N as f64).length() + 2.0 * reach;
        let steps = (ext / h).ceil() as usize + 1;
        let mut last = [i64::MIN; 3];
        for t in 0..steps {
            let p = c + s * (t as f64 * h);
            let cc = self.cell(p);
            if cc == last {
                continue;
            }
            last = cc;
            // Once the sample point has left the grid by more than the reach, nothing lies ahead.
            let q = (p - self.lo) / self.size;
            let outside = [q.x, q.y, q.z]
                .iter()
                .zip([kx, ky, kz])
                .any(|(&v, k)| v < -(k as f64) - 1.0 || v > (N as i64 + k) as f64 + 1.0);
            if outside {
                break;
            }
            let c0 = [(p - self.lo) / self.size]
                .map(|q| [q.x.floor() as i64, q.y.floor() as i64, q.z.floor() as i64])[0];
            for z in (c0[2] - kz).max(0)..=(c0[2] + kz).min(N as i64 - 1) {
                for y in (c0[1] - ky).max(0)..=(c0[1] + ky).min(N as i64 - 1) {
                    for x in (c0[0] - kx).max(0)..=(c0[0] + kx).min(N as i64 - 1) {
                        let key = (z as usize * N + y as usize) * N + x as usize;
                        for &j in
                            &self.items[self.start[key] as usize..self.start[key + 1] as usize]
                        {
                            if stamp[j as usize] != tag {
                                stamp[j as usize] = tag;
                                out.push(j);
                            }
                        }
                    }
                }
            }
        }
    }
}

impl Environment for SkyLight {
    fn respond(&mut self, _step: u32, m: &[Message], r: &mut Vec<Reply>) -> Result<()> {
        if m.is_empty() {
            return Ok(());
        }
        let clusters: Vec<(DVec3, f64)> = m
            .iter()
            .map(|msg| {
                (
                    msg.state.frame.p,
                    msg.values.first().copied().unwrap_or(0.0),
                )
            })
            .collect();
        if let Some(bad) = clusters.iter().find(|c| !(c.1.is_finite() && c.1 >= 0.0)) {
            return Err(PlantError::Environment {
                message: format!("leaf cluster radius {}", bad.1),
            });
        }
        for (msg, f) in m.iter().zip(self.flux(&clusters)) {
            r.push(Reply {
                address: msg.address,
                values: vec![f],
            });
        }
        self.answered += m.len();
        Ok(())
    }
}

/// Grows the trees for [`CrownParams::years`] years in one shared light environment.
///
/// # Errors
///
/// [`CrownParams::validate`]'s errors; derivation, turtle and environment errors.
pub fn crowns(p: &CrownParams) -> Result<Run> {
    p.validate()?;
    let l = LSystem::parse(&p.lsystem_text())?;
    let t = TurtleParams::for_lsystem(&l);
    let mut env = SkyLight::overcast(p.transmittance);
    run_open(l, t, &mut env, p.years * p.steps_per_year(), 0)
}

/// A living leaf cluster of a run's final string ([`living_clusters`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeafCluster {
    /// Index of its module `L` in the string.
    pub module: usize,
    /// Its centre (the turtle's position at `L`).
    pub centre: DVec3,
    /// Its radius as the light model sees it, `vig/2`.
    pub radius: f64,
}

/// The living leaf clusters of a run of [`crowns`] (or of the conifers,
/// whose leaves are the same module): every `L(vig, p, age, del)` with
/// `vig > 0` and `age < leaf_years`.
///
/// # Errors
///
/// The turtle's errors.
pub fn living_clusters(run: &Run, leaf_years: u32) -> Result<Vec<LeafCluster>> {
    let leaf = run.lsystem.symbol("L");
    let s = &run.string;
    let mut out = Vec::new();
    crate::Turtle::new(&run.lsystem, run.turtle.clone())?.visit(s, |i, st| {
        if Some(s.symbol(i)) == leaf {
            let q = s.params(i);
            if q.len() == 4 && q[0] > 0.0 && q[2] < f64::from(leaf_years) {
                out.push(LeafCluster {
                    module: i,
                    centre: st.frame.p,
                    radius: 0.5 * q[0],
                });
            }
        }
    })?;
    Ok(out)
}

#[cfg(test)]
mod tests;
