//! The turtle's frame and its rotations, and differential turtle geometry.
//!
//! The frame is a position `P` and orthonormal heading `H`, left `L` and up
//! `U` with `H × L = U` (Prusinkiewicz & Lindenmayer 1990, §1.5; Prusinkiewicz
//! et al. 2001, §3, eqs. 5–7). Rotations are right-handed about the named
//! axis: `+` is `R_U(+δ)` and turns `H` towards `L` (left); `&` is `R_L(+δ)`
//! and turns `H` towards `−U` (pitch down); `/` is `R_H(+δ)` and turns `L`
//! towards `U` (roll right). ABOP's printed matrices leave the signs
//! ambiguous; this convention is the one that makes Prusinkiewicz et al.
//! 2001's eq. 10 read `dΩ_U = T′·L`, `dΩ_L = −T′·U`.

use crate::error::{PlantError, Result};
use glam::DVec3;
use natura_core::check;

/// Position and orientation of the turtle.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TurtleFrame {
    /// Position.
    pub p: DVec3,
    /// Heading (the direction of `F`).
    pub h: DVec3,
    /// Left.
    pub l: DVec3,
    /// Up (`H × L`).
    pub u: DVec3,
}

impl Default for TurtleFrame {
    /// At the origin heading up (+z), left −x, up −y: a plant grows along +z
    /// and its 2-D figures lie in the x-z plane, seen from −y.
    fn default() -> Self {
        Self {
            p: DVec3::ZERO,
            h: DVec3::Z,
            l: DVec3::NEG_X,
            u: DVec3::NEG_Y,
        }
    }
}

/// Rotates `v` about the unit `axis` by `angle` radians (right-handed).
#[inline]
#[must_use]
pub fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

impl TurtleFrame {
    /// Returns a frame at `p` heading along `h` with left `l` (made orthonormal).
    #[must_use]
    pub fn new(p: DVec3, h: DVec3, l: DVec3) -> Self {
        let mut f = Self {
            p,
            h,
            l,
            u: h.cross(l),
        };
        f.orthonormalize();
        f
    }

    /// Restores `H`, `L`, `U` to an orthonormal right-handed frame (Gram–Schmidt on `H`, `L`).
    #[inline]
    pub fn orthonormalize(&mut self) {
        self.h = self.h.normalize();
        self.l = (self.l - self.h * self.l.dot(self.h)).normalize();
        self.u = self.h.cross(self.l);
    }

    /// Turns about `U` by `a` radians (`+` for positive `a`, `-` for negative).
    #[inline]
    pub fn turn(&mut self, a: f64) {
        let (s, c) = a.sin_cos();
        let h = self.h * c + self.l * s;
        let l = self.l * c - self.h * s;
        self.h = h;
        self.l = l;
        self.orthonormalize();
    }

    /// Pitches about `L` by `a` radians (`&` for positive `a`, `^` for negative).
    #[inline]
    pub fn pitch(&mut self, a: f64) {
        let (s, c) = a.sin_cos();
        let h = self.h * c - self.u * s;
        let u = self.u * c + self.h * s;
        self.h = h;
        self.u = u;
        self.l = self.u.cross(self.h);
        self.orthonormalize();
    }

    /// Rolls about `H` by `a` radians (`/` for positive `a`, `\` for negative).
    #[inline]
    pub fn roll(&mut self, a: f64) {
        let (s, c) = a.sin_cos();
        let l = self.l * c + self.u * s;
        self.l = l;
        self.orthonormalize();
    }

    /// Rolls about `H` so that `L` is horizontal (`$`; ABOP §2.3, p. 57):
    /// `L = V × H / |V × H|` with `V` the world's up (+z). Unchanged when `H` is vertical.
    pub fn roll_horizontal(&mut self) {
        let l = DVec3::Z.cross(self.h);
        if l.length_squared() > 1e-24 {
            self.l = l.normalize();
            self.u = self.h.cross(self.l);
        }
    }

    /// Bends the heading towards `t` by `e · |H × T|` radians about `H × T`
    /// (tropism, ABOP §2.3, p. 58). `t` need not be unit; its length scales the effect.
    pub fn tropism(&mut self, t: DVec3, e: f64) {
        let axis = self.h.cross(t);
        let n = axis.length();
        if n < 1e-15 {
            return;
        }
        let a = e * n;
        let axis = axis / n;
        self.h = rotate(self.h, axis, a);
        self.l = rotate(self.l, axis, a);
        self.orthonormalize();
    }

    /// Rotates the frame by the rotation vector `ω ds` given in the frame's own
    /// axes (`omega = (ω_H, ω_L, ω_U)`), the solution of Prusinkiewicz et al.
    /// 2001, Theorem A.1, eq. 15 for rates constant over the step.
    pub fn rotate_local(&mut self, omega: DVec3, ds: f64) {
        let w = self.h * omega.x + self.l * omega.y + self.u * omega.z;
        let a = w.length() * ds;
        if a == 0.0 {
            return;
        }
        let axis = w.normalize();
        self.h = rotate(self.h, axis, a);
        self.l = rotate(self.l, axis, a);
        self.orthonormalize();
    }
}

/// Differential turtle geometry: walks a curve given by its unit tangent
/// `tangent(s)` in steps of `ds`, turning the frame with the rates of
/// Prusinkiewicz et al. 2001, eq. 10, `dΩ_U = T′·L`, `dΩ_L = −T′·U` and
/// `ω_H = 0` (the parallel-transport frame, free of the Frenet frame's flips
/// at inflections), then moving `ds` along `H` (eq. 16).
///
/// The listings of that paper's Algorithms 2 and 4 swap the two rates
/// (`ΔΩ_L = T′·L`, `ΔΩ_U = −T′·U`); eq. 10 is the correct form and is used here.
/// The dot products are the sines of the small angles, as in the source.
///
/// Returns the frames at `s = 0, ds, 2ds, …, ≤ length`.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`] naming `length` or `ds` if `length` is
/// not finite and non-negative, `ds` not finite and positive, or the curve
/// would take more than [`MAX_CURVE_SAMPLES`] steps; naming `tangent` if it
/// returns a non-finite vector.
pub fn track_curve(
    start: TurtleFrame,
    length: f64,
    ds: f64,
    tangent: impl Fn(f64) -> DVec3,
) -> Result<Vec<TurtleFrame>> {
    check::non_negative("track_curve length", length)?;
    check::positive("track_curve ds", ds)?;
    let steps = (length / ds).floor();
    if steps.is_nan() || steps > MAX_CURVE_SAMPLES as f64 {
        return Err(PlantError::InvalidParameter {
            name: "track_curve ds",
            value: format!("{ds:e} for length {length:e}"),
            reason: format!(
                "length / ds = {steps:e} steps, more than the {MAX_CURVE_SAMPLES} a curve may take"
            ),
        });
    }
    let n = steps as usize;
    let mut out = Vec::with_capacity(n + 1);
    let mut f = start;
    out.push(f);
    for k in 0..n {
        let s = (k + 1) as f64 * ds;
        let t = tangent(s);
        if !t.is_finite() {
            return Err(PlantError::InvalidParameter {
                name: "track_curve tangent",
                value: format!("{t} at s = {s}"),
                reason: "the tangent must be finite".into(),
            });
        }
        let d_u = t.dot(f.l).clamp(-1.0, 1.0).asin();
        let d_l = (-t.dot(f.u)).clamp(-1.0, 1.0).asin();
        f.turn(d_u);
        f.pitch(d_l);
        f.p += f.h * ds;
        out.push(f);
    }
    Ok(out)
}

/// The most steps [`track_curve`] takes.
pub const MAX_CURVE_SAMPLES: usize = 1 << 22;
