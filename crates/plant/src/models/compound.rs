//! Single-compound structures: a stem carrying organs at positions set by a
//! density, Prusinkiewicz, Mündermann, Karwowski & Lane 2001, §5,
//! Algorithm 4 (a pinnate leaf such as the sickle fern of their Fig. 7).
//!
//! The stem is cut into slices of length `Δs`. Each slice turns the turtle
//! towards the tangent of a given stem curve (the curve framing of §3,
//! eq. 10), draws a segment of width `stem_width(s)` and adds `Δs/λ(s)` to
//! the organ count `a` (eq. 11). Where `a` passes 1 a node is placed: a pair
//! of leaflets `~L(length(s), width(s))` at `±brangle(s)`, the pair rolled
//! about the stem by the accumulated phyllotactic angle `φ += Φ`. `Φ = 0`
//! gives a distichous (planar) leaf, `Φ = 90°` a decussate one, and
//! `Φ = 137.5°` with one organ per node a spiral (§5).
//!
//! The functions are the caller's [`Function`]s of the arc length `s`, as
//! the source edits them graphically.
//!
//! Errata and choices: the listing assigns `ΔΩ_L = K·(T′·L)` and
//! `ΔΩ_U = −K·(T′·U)`, swapping the two rates of eq. 10; the eq. 10 form
//! (turn by `T′·L`, pitch up by `T′·U`) is used, with the arc sine rather
//! than the dot product for the angle (the language's `asin` returns
//! degrees, so the listing's factor `K` is not needed). The slices are counted by an integer
//! `k` with `s = k·Δs` (the listing adds `Δs` to `s`, whose rounding can drop
//! the last slice). Housekeeping rules the listing omits erase the apex
//! once the stem is complete.

use super::Run;
use crate::error::Result;
use crate::lang::{Curve, Function, LSystem};
use crate::mesh::invalid;
use crate::turtle::{Turtle, TurtleFrame, TurtleParams};
use crate::{Derivation, ModuleString};
use glam::DVec3;

/// Parameters of Algorithm 4.
#[derive(Clone, Debug)]
pub struct CompoundParams {
    /// Stem length `ℓ`.
    pub length: f64,
    /// Slice length `Δs` (must be smaller than `λ` everywhere).
    pub ds: f64,
    /// Phyllotactic angle `Φ` in degrees, added at each node.
    pub phyllotaxis_deg: f64,
    /// Two opposite organs per node (`true`, the listing) or one (spiral).
    pub pairs: bool,
    /// Internode length `λ(s)` (organ density `1/λ`).
    pub internode: Function,
    /// Leaflet length at a node.
    pub leaflet_length: Function,
    /// Leaflet width at a node.
    pub leaflet_width: Function,
    /// Branching angle of the leaflets, degrees.
    pub branch_angle: Function,
    /// Stem width (diameter).
    pub stem_width: Function,
    /// The stem's curve, arc-length parametrised; `None` for a straight stem.
    /// The turtle starts at the origin heading `+z` and turns towards the
    /// curve's tangent; the curve's own start point is not used.
    pub stem: Option<Curve>,
}

impl Default for CompoundParams {
    /// A straight distichous leaf of length 10 with leaflets every 0.5, 2
    /// long, 0.6 wide, at 60°, and `Δs = 0.05`.
    fn default() -> Self {
        let c = |v: f64| Function::new(&[(0.0, v)]).expect("a constant is a valid function");
        Self {
            length: 10.0,
            ds: 0.05,
            phyllotaxis_deg: 0.0,
            pairs: true,
            internode: c(0.5),
            leaflet_length: c(2.0),
            leaflet_width: c(0.6),
            branch_angle: c(60.0),
            stem_width: c(0.1),
            stem: None,
        }
    }
}

impl CompoundParams {
    /// A pinnate leaf after the source's sickle fern (Fig. 7 f): leaflets
    /// longest below the middle, internodes and branching angles shrinking
    /// towards the tip, on a stem arching by about 52° in the leaf's plane
    /// (`y`–`z`). The values are ours, read off the figure's shape.
    #[must_use]
    pub fn fern() -> Self {
        let f = |pts: &[(f64, f64)]| Function::new(pts).expect("valid control points");
        let stem: Vec<DVec3> = (0..=32)
            .map(|k| {
                let a = 0.9 * f64::from(k) / 32.0;
                DVec3::new(0.0, 12.0 * (1.0 - a.cos()), 12.0 * a.sin())
            })
            .collect();
        let stem = Curve::new(&stem).expect("a valid arc");
        let len = stem.length();
        Self {
            length: len,
            ds: 0.02,
            internode: f(&[(0.0, 0.9), (4.0, 0.6), (len, 0.25)]),
            leaflet_length: f(&[(0.0, 1.5), (3.0, 3.2), (8.0, 1.6), (len, 0.4)]),
            leaflet_width: f(&[(0.0, 0.35), (len, 0.2)]),
            branch_angle: f(&[(0.0, 80.0), (len, 35.0)]),
            stem_width: f(&[(0.0, 0.12), (len, 0.03)]),
            stem: Some(stem),
            ..Self::default()
        }
    }
}

/// The Algorithm 4 L-system text for `p` (functions and curve by id: `func(1..5, s)`
/// for λ, leaflet length, width, angle and stem width, curve 1 for the stem).
fn text(p: &CompoundParams, slices: u64) -> String {
    let steer = if p.stem.is_some() {
        "tx = tanX(1,t); ty = tanY(1,t); tz = tanZ(1,t); \
         du = asin(clamp(tx*lx+ty*ly+tz*lz,-1,1)); \
         dl = -asin(clamp(tx*ux+ty*uy+tz*uz,-1,1));"
    } else {
        "du = 0; dl = 0;"
    };
    let organs = if p.pairs {
        "[/(p)[+(b)~L(l,w)][-(b)~L(l,w)]]"
    } else {
        "[/(p)[+(b)~L(l,w)]]"
    };
    format!(
        "#define N {slices}\n\
         #define DS {ds:?}\n\
         #define PHI {phi:?}\n\
         ω: A(0,0,0)?U(0,0,0)?L(0,0,0)\n\
         A(k,a,p) > ?U(ux,uy,uz) ?L(lx,ly,lz) : k < N \
         {{ s = k*DS; t = (k+1)*DS; {steer} a = a + DS/func(1,s); f = 0; \
         if (a >= 1) {{ a = a - 1; f = 1; p = p + PHI; }} }} \
         -> +(du)&(dl)#(func(5,s))F(DS)B(s,p,f)A(k+1,a,p)\n\
         A(k,a,p) : k >= N -> ε\n\
         B(s,p,f) : f == 0 -> ε\n\
         B(s,p,f) : f == 1 {{ l = func(2,s); w = func(3,s); b = func(4,s); }} -> {organs}\n",
        ds = p.ds,
        phi = p.phyllotaxis_deg,
    )
}

/// Grows the compound structure of `p` (Algorithm 4), one slice per
/// derivation step, with the query modules `?U ?L` refreshed from the turtle
/// before each step. The result holds the final string; its leaflets are the
/// `~L` modules.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if `length` or `ds` is not positive and
/// finite, there are more than 10⁶ slices, `λ(s)` is not larger than `ds`
/// somewhere on the stem, or `phyllotaxis_deg` is not finite; errors of the
/// derivation (an expression failing on the caller's functions).
pub fn compound(p: &CompoundParams) -> Result<Run> {
    natura_core::check::positive("CompoundParams::length", p.length)?;
    natura_core::check::positive("CompoundParams::ds", p.ds)?;
    natura_core::check::finite("CompoundParams::phyllotaxis_deg", p.phyllotaxis_deg)?;
    let n = p.length / p.ds;
    if n > 1e6 {
        return Err(invalid("CompoundParams::ds", p.ds, "at most 10^6 slices"));
    }
    let slices = (n + 1e-9).floor() as u64;
    for k in 0..slices {
        let l = p.internode.eval(k as f64 * p.ds);
        if !(l.is_finite() && l > p.ds) {
            return Err(invalid(
                "CompoundParams::internode",
                l,
                "finite and larger than ds on the whole stem (one node per slice)",
            ));
        }
    }
    let mut lsystem = LSystem::parse(&text(p, slices))?;
    for (id, f) in [
        &p.internode,
        &p.leaflet_length,
        &p.leaflet_width,
        &p.branch_angle,
        &p.stem_width,
    ]
    .into_iter()
    .enumerate()
    {
        lsystem.set_function(id as u32 + 1, f.clone());
    }
    if let Some(c) = &p.stem {
        lsystem.set_curve(1, c.clone());
    }
    let turtle = TurtleParams {
        width: p.stem_width.eval(0.0),
        start: TurtleFrame::new(DVec3::ZERO, DVec3::Z, DVec3::Y),
        ..TurtleParams::default()
    };
    let string: ModuleString = {
        let t = Turtle::new(&lsystem, turtle.clone())?;
        let mut d = Derivation::new(&lsystem, 0)?;
        // One step per slice, one to turn the last node into organs and one
        // to erase the apex.
        for _ in 0..slices + 2 {
            d.fill_queries(&t)?;
            d.step()?;
        }
        d.into_string()
    };
    Ok(Run {
        lsystem,
        string,
        turtle,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::positional::organ_positions;

    fn leaflets(p: &CompoundParams) -> Vec<crate::turtle::SurfaceInstance> {
        let run = compound(p).unwrap();
        let g = run.geometry().unwrap();
        g.surfaces.into_iter().filter(|s| s.name == 'L').collect()
    }

    fn func(pts: &[(f64, f64)]) -> Function {
        Function::new(pts).unwrap()
    }

    #[test]
    fn node_count_matches_algorithm_3_and_the_organ_sizes_follow_s() {
        // Linear λ: internodes grow geometrically (appendix A.3); the nodes
        // are those of Algorithm 3 on the same density.
        let p = CompoundParams {
            internode: func(&[(0.0, 0.2), (10.0, 1.2)]),
            leaflet_length: func(&[(0.0, 1.0), (10.0, 3.0)]),
            ..CompoundParams::default()
        };
        let nodes = organ_positions(p.length, p.ds, |s| p.internode.eval(s)).unwrap();
        let run = compound(&p).unwrap();
        assert_eq!(run.count("~L"), 2 * nodes.len());
        assert_eq!(run.count("A"), 0, "the apex is erased");
        assert_eq!(run.count("B"), 0);
        // Slices: one F per Δs.
        assert_eq!(run.count("F"), 200);
        let leaf = leaflets(&p);
        // Each pair sits at its node s (B(s) receives the slice's start, one Δs
        // before Algorithm 3's s'), with the length given by the function there.
        for (k, &s3) in nodes.iter().enumerate() {
            let s = s3 - p.ds;
            for l in &leaf[2 * k..2 * k + 2] {
                assert!(
                    (l.frame.p.z - s - p.ds).abs() < 1e-9,
                    "{} vs {s}",
                    l.frame.p.z
                );
                assert!((l.length - p.leaflet_length.eval(s)).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn phyllotaxis_by_one_constant() {
        // Φ = 0: distichous, every leaflet in the plane of H and L (x = 0).
        let d = CompoundParams::default();
        let nodes = organ_positions(d.length, d.ds, |_| 0.5).unwrap().len();
        assert!((19..=20).contains(&nodes), "{nodes}");
        let flat = leaflets(&d);
        assert_eq!(flat.len(), 2 * nodes);
        for l in &flat {
            assert!(l.frame.h.x.abs() < 1e-9, "{:?}", l.frame.h);
        }
        // Φ = 90°: decussate, consecutive pairs in perpendicular planes.
        let dec = leaflets(&CompoundParams {
            phyllotaxis_deg: 90.0,
            ..CompoundParams::default()
        });
        for w in dec.chunks(2).collect::<Vec<_>>().windows(2) {
            let n0 = w[0][0].frame.h.cross(w[0][1].frame.h).normalize();
            let n1 = w[1][0].frame.h.cross(w[1][1].frame.h).normalize();
            assert!(n0.dot(n1).abs() < 1e-9);
        }
        // Φ = 137.5° and one organ per node: a spiral; organ k's azimuth is k·137.5°.
        let sp = leaflets(&CompoundParams {
            phyllotaxis_deg: 137.5,
            pairs: false,
            ..CompoundParams::default()
        });
        assert_eq!(sp.len(), nodes);
        let az = |l: &crate::turtle::SurfaceInstance| l.frame.h.y.atan2(l.frame.h.x);
        for w in sp.windows(2) {
            let d = (az(&w[1]) - az(&w[0])).to_degrees().rem_euclid(360.0);
            assert!((d - 137.5).abs() < 1e-6, "{d}");
        }
    }

    #[test]
    fn stem_follows_its_curve() {
        // A quarter circle of radius 4 in the x-z plane, starting up +z.
        let r = 4.0;
        let pts: Vec<DVec3> = (0..=64)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * f64::from(k) / 64.0;
                DVec3::new(r * (1.0 - a.cos()), 0.0, r * a.sin())
            })
            .collect();
        let curve = Curve::new(&pts).unwrap();
        let p = CompoundParams {
            length: curve.length(),
            ds: 0.01,
            stem: Some(curve.clone()),
            ..CompoundParams::default()
        };
        let run = compound(&p).unwrap();
        let g = run.geometry().unwrap();
        let tip = g.end.last().unwrap().as_dvec3();
        assert!(
            (tip - DVec3::new(r, 0.0, r)).length() < 0.05,
            "tip {tip} vs ({r}, 0, {r})"
        );
        // The stem stays in the curve's plane.
        assert!(g.end.iter().all(|e| e.y.abs() < 1e-6));
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        let d = CompoundParams::default;
        for p in [
            CompoundParams {
                length: f64::NAN,
                ..d()
            },
            CompoundParams { ds: 0.0, ..d() },
            CompoundParams { ds: 1e-9, ..d() },
            CompoundParams {
                phyllotaxis_deg: f64::INFINITY,
                ..d()
            },
            CompoundParams {
                internode: func(&[(0.0, 0.01)]),
                ..d()
            },
        ] {
            assert!(
                matches!(
                    compound(&p),
                    Err(crate::PlantError::InvalidParameter { .. })
                ),
                "{p:?}"
            );
        }
    }
}
