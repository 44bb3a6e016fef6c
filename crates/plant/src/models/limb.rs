//! Curved limbs by differential turtle geometry: Prusinkiewicz, Mündermann,
//! Karwowski & Lane 2001, §3, eq. 4 and Algorithm 1 (the stems and leaves of
//! their Fig. 4).
//!
//! A limb of length `ℓ` is cut into slices of length `Δs`. Over each slice
//! the turtle turns by the rates of its three axes times `Δs`
//! (`ΔΩ_U = ω_U(s)Δs` about `U`, `ΔΩ_L = ω_L(s)Δs` about `L`,
//! `ΔΩ_H = ω_H(s)Δs` about `H`, eq. 4), then draws a slice of width
//! `width(s)`. A twist `φ` accumulating at the rate `φ′(s)` rolls only the
//! slice's cross-section (`/(φ) F \(φ)`), not the axis: a leaf blade turns
//! over along its length while its midrib stays where the rates put it.
//! The cross-section's orientation is the turtle's `U` recorded for each
//! segment ([`crate::Geometry::up`]); a caller sweeps a blade across `L`.
//!
//! Rates are in degrees per unit length (the L-system's angles are in
//! degrees). Since infinitesimal rotations commute, the order of the three
//! turns within a slice does not matter as `Δs → 0`.
//!
//! Erratum: the listing writes `+(ΔΩ_L) &(ΔΩ_U)`, pairing the turn about
//! `U` (`+`) with the rate about `L`. Its own Algorithm 2 and eq. 4 pair
//! each turn with its axis's rate; this module does (`+(ΔΩ_U) &(ΔΩ_L)`).
//! The slices are counted by an integer `k` with `s = k·Δs` (the listing
//! adds `Δs` to `s`, whose rounding can drop the last slice).

use glam::DVec3;

use super::Run;
use crate::Derivation;
use crate::error::Result;
use crate::lang::{Function, LSystem};
use crate::mesh::invalid;
use crate::turtle::{TurtleFrame, TurtleParams};

/// Parameters of Algorithm 1: the limb's length and slice, and the
/// functions of the arc length `s` that shape it.
#[derive(Clone, Debug)]
pub struct LimbParams {
    /// Total length `ℓ`.
    pub length: f64,
    /// Slice length `Δs`.
    pub ds: f64,
    /// Rate of turning about `U` (to the left), degrees per unit length.
    pub omega_u: Function,
    /// Rate of pitching about `L` (down), degrees per unit length.
    pub omega_l: Function,
    /// Rate of rolling the axis about `H`, degrees per unit length.
    pub omega_h: Function,
    /// Rate of twisting the cross-section alone, degrees per unit length.
    pub twist: Function,
    /// Width of the cross-section.
    pub width: Function,
    /// Where the limb starts and how it is turned.
    pub start: TurtleFrame,
}

impl Default for LimbParams {
    /// A straight limb 10 long and 0.1 wide in slices of 0.05, heading `+z`
    /// with `L` along `+y` (so `U = H × L` along `−x`).
    fn default() -> Self {
        let c = |v: f64| Function::new(&[(0.0, v)]).expect("a constant is a valid function");
        Self {
            length: 10.0,
            ds: 0.05,
            omega_u: c(0.0),
            omega_l: c(0.0),
            omega_h: c(0.0),
            twist: c(0.0),
            width: c(0.1),
            start: TurtleFrame::new(DVec3::ZERO, DVec3::Z, DVec3::Y),
        }
    }
}

/// The Algorithm 1 L-system for `slices` slices of `ds`, the functions by
/// id: `func(1, s)` `ω_U`, 2 `ω_L`, 3 `ω_H`, 4 the twist rate, 5 the width
/// (each slice tapers from the width at its start to that at its end).
fn text(slices: u64, ds: f64) -> String {
    format!(
        "#define N {slices}\n\
         #define DS {ds:?}\n\
         ω: A(0,0)\n\
         A(k,p) : k < N {{ s = k*DS; du = func(1,s)*DS; dl = func(2,s)*DS; \
         dh = func(3,s)*DS; p = p + func(4,s)*DS; }} \
         -> +(du)&(dl)/(dh)/(p)#(func(5,s+DS))F(DS)\\(p)A(k+1,p)\n\
         A(k,p) : k >= N -> ε\n"
    )
}

/// Grows the limb of `p` (Algorithm 1), one slice a derivation step. The
/// result's geometry has one segment a slice, each with the turtle's `U`
/// rolled by the twist so far.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`](crate::PlantError::InvalidParameter) if `length` or `ds` is not positive
/// and finite, `ds` exceeds `length` or there are more than 10⁶ slices;
/// errors of the derivation (a function giving a value that is not finite).
pub fn limb(p: &LimbParams) -> Result<Run> {
    natura_core::check::positive("LimbParams::length", p.length)?;
    natura_core::check::positive("LimbParams::ds", p.ds)?;
    let n = p.length / p.ds;
    if n > 1e6 {
        return Err(invalid("LimbParams::ds", p.ds, "at most 10^6 slices"));
    }
    if n < 1.0 - 1e-9 {
        return Err(invalid("LimbParams::ds", p.ds, "at most the length"));
    }
    let slices = (n + 1e-9).floor() as u64;
    let mut lsystem = LSystem::parse(&text(slices, p.ds))?;
    for (id, f) in [&p.omega_u, &p.omega_l, &p.omega_h, &p.twist, &p.width]
        .into_iter()
        .enumerate()
    {
        lsystem.set_function(id as u32 + 1, f.clone());
    }
    let turtle = TurtleParams {
        width: p.width.eval(0.0),
        start: p.start,
        ..TurtleParams::default()
    };
    let mut d = Derivation::new(&lsystem, 0)?;
    // One step a slice and one to erase the apex.
    d.derive(slices as u32 + 1)?;
    let string = d.into_string();
    Ok(Run {
        lsystem,
        string,
        turtle,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn c(v: f64) -> Function {
        Function::new(&[(0.0, v)]).unwrap()
    }

    #[test]
    fn a_constant_rate_bends_the_limb_into_a_circle() {
        // ω_U = 360°/ℓ turns the heading once round over the limb: a closed
        // circle of circumference ℓ (radius ℓ/2π) in the plane of H and L.
        let p = LimbParams {
            length: 2.0 * std::f64::consts::PI,
            ds: 2.0 * std::f64::consts::PI / 720.0,
            omega_u: c(360.0 / (2.0 * std::f64::consts::PI)),
            ..LimbParams::default()
        };
        let g = limb(&p).unwrap().geometry().unwrap();
        assert_eq!(g.segment_count(), 720);
        let end = g.end.last().unwrap().as_dvec3();
        assert!(end.length() < 1e-3, "the circle closes: {end}");
        // `+` turns H towards L: halfway round, the limb is a diameter (2)
        // from its start along L (+y); every point lies at 1 from the centre.
        // (Each slice turns before it moves, which sets the chords half a
        // slice's turn, 0.25°, off the circle's: 0.0044 at radius 1.)
        let centre = 0.5 * g.end[359].as_dvec3();
        assert!((centre - DVec3::Y).length() < 5e-3, "{centre}");
        for e in &g.end {
            assert_relative_eq!(e.as_dvec3().distance(centre), 1.0, epsilon = 2e-3);
        }
    }

    #[test]
    fn the_twist_turns_the_cross_section_and_not_the_axis() {
        // Twisting 180° along a straight limb: the axis stays on +z, the
        // recorded U turns from the start's U (−x) to +x, across it halfway.
        let p = LimbParams {
            length: 4.0,
            ds: 0.01,
            twist: c(45.0),
            ..LimbParams::default()
        };
        let g = limb(&p).unwrap().geometry().unwrap();
        let end = g.end.last().unwrap().as_dvec3();
        assert!((end - DVec3::new(0.0, 0.0, 4.0)).length() < 1e-6, "{end}");
        let up = |k: usize| g.up[k].as_dvec3();
        assert!(up(0).dot(DVec3::NEG_X) > 0.999, "{}", up(0));
        assert!(up(199).dot(DVec3::X).abs() < 0.01, "{}", up(199));
        assert!(up(399).dot(DVec3::X) > 0.999, "{}", up(399));
        // Without the twist the cross-section keeps its U.
        let g = limb(&LimbParams {
            length: 4.0,
            ..LimbParams::default()
        })
        .unwrap()
        .geometry()
        .unwrap();
        assert!(
            g.up.iter()
                .all(|u| u.as_dvec3().dot(DVec3::NEG_X) > 0.999999)
        );
    }

    #[test]
    fn the_width_follows_its_function() {
        let p = LimbParams {
            length: 1.0,
            ds: 0.1,
            width: Function::new(&[(0.0, 0.5), (1.0, 0.1)]).unwrap(),
            ..LimbParams::default()
        };
        let g = limb(&p).unwrap().geometry().unwrap();
        assert_eq!(g.segment_count(), 10);
        for k in 0..10 {
            let s = (k + 1) as f64 * 0.1;
            assert_relative_eq!(f64::from(g.width1[k]), p.width.eval(s), epsilon = 1e-6);
        }
    }

    #[test]
    fn bad_lengths_are_refused_by_name() {
        for (length, ds, name) in [
            (0.0, 0.1, "LimbParams::length"),
            (f64::NAN, 0.1, "LimbParams::length"),
            (1.0, -0.1, "LimbParams::ds"),
            (1.0, 2.0, "LimbParams::ds"),
            (1e7, 1.0, "LimbParams::ds"),
        ] {
            let p = LimbParams {
                length,
                ds,
                ..LimbParams::default()
            };
            let e = limb(&p).unwrap_err();
            assert!(e.to_string().contains(name), "{e}");
        }
    }
}
