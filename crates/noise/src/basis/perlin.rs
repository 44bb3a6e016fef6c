//! Perlin gradient noise, 1-D to 4-D.
//!
//! Musgrave's `Noise()` (Musgrave 1993, §2.3.1; Musgrave et al. 1989, §3.2;
//! Musgrave 2001, "Perlin"): random gradients at the integer lattice points,
//! blended across each cell by a fade, so the noise is **zero at every lattice
//! point** with slope equal to the lattice gradient there, and has its power
//! concentrated near half the integer frequency ("primary frequency", Musgrave
//! 1993, §2.3.1).
//!
//! * Gradients: 1-D uniform in `[-1, 1)`; 2-D one of 8 unit vectors (axes and
//!   diagonals); 3-D one of the 12 cube edges `(±1, ±1, 0)…` (Perlin 2002); 4-D
//!   one of the 32 tesseract edges. Drawn from a hash of the lattice position
//!   and seed (no 256-periodic table).
//! * Fade: quintic by default (C²); [`Fade::Cubic`] reproduces the sources
//!   (C¹ only: the sources call the cubic-faded noise C², but its second
//!   derivative jumps across cell faces).
//! * Range: values are scaled by `1/sup|raw|` so that [`Field::bound`] is
//!   exactly 1 and attained (the sources' implementations differ in range;
//!   MojoWorld's basis contract asks for `[-1, 1]`, Musgrave 2001, "The Basis
//!   Function"). The sups were found by maximising `Σ_c W_c(p)·max_g g·(p−c)`
//!   over the cell (each corner picks its worst gradient independently): 1-D ½,
//!   2-D √2/2, 3-D 1.0363 (quintic) / 1.0449 (cubic), 4-D see
//!   [`PERLIN4_SUP_QUINTIC`].
//! * Lipschitz constants are the maximised `|∇N|` of the normalised noise,
//!   rounded up by 1%.
//! * Batch rows: for steps up to 1/16 of a cell a row is evaluated span by
//!   span (four coefficients per cell, each lattice column hashed once per
//!   row, whole 16-lane groups); larger steps run a per-lane kernel whose
//!   32-point blocks are rebased to a local origin (one f64 split per block,
//!   then f32/u32 lanes from precomputed lane offsets), so lattice indices stay
//!   exact at planet-scale coordinates while every lane runs at the full f32
//!   width. Both equal the f64 point path within 1e-5.

use glam::{DVec2, DVec3, DVec4};

use crate::basis::Fade;
use crate::basis::lattice::lattice_sum;
use crate::field::{Field, Lattice3};
use crate::hash::{
    PX, PY, PZ, corner_spread, dot2, dot3_lanes, dot3_pair, grad1, grad2, grad3, grad4, seed32,
};
use crate::lattice_math::{Kernel, Simd, run, split, split_fast, split_n};

mod batch_rows;
mod points;

/// sup |raw 1-D gradient noise| (either fade): at the cell centre, `2·½·½`.
pub const PERLIN1_SUP: f64 = 0.5;
/// sup |raw 2-D gradient noise| (either fade): √2/2, at the cell centre with
/// every corner's diagonal gradient pointing away.
pub const PERLIN2_SUP: f64 = core::f64::consts::FRAC_1_SQRT_2;
/// sup |raw 3-D gradient noise| with the quintic fade (numerically maximised).
pub const PERLIN3_SUP_QUINTIC: f64 = 1.036_330;
/// sup |raw 3-D gradient noise| with the cubic fade (numerically maximised).
pub const PERLIN3_SUP_CUBIC: f64 = 1.044_887;
/// sup |raw 4-D gradient noise| with the quintic fade (numerically maximised).
pub const PERLIN4_SUP_QUINTIC: f64 = 1.5;
/// sup |raw 4-D gradient noise| with the cubic fade (numerically maximised).
pub const PERLIN4_SUP_CUBIC: f64 = 1.5;

/// The 2-D normalisation `1 / PERLIN2_SUP`.
const K2: f64 = 1.0 / PERLIN2_SUP;

/// Lipschitz constants of the *normalised* noise, `[cubic, quintic]`, per dimension 1-4.
const LIPSCHITZ: [[f64; 2]; 4] = [[2.86, 2.73], [2.54, 2.87], [2.90, 3.64], [4.0, 4.8]];

/// Salt separating Perlin's lattice from the other bases' under the same seed.
const SALT: u64 = 0x5045_524C; // "PERL"

/// Perlin gradient noise with a seed and a fade; unit lattice spacing, values in `[-1, 1]`.
///
/// ```
/// use natura_noise::{Field, Perlin};
/// use glam::DVec2;
/// let n = Perlin::new(7);
/// assert_eq!(n.eval2(DVec2::new(3.0, -2.0)), 0.0); // zero on the lattice
/// assert!(n.eval2(DVec2::new(3.3, -2.6)).abs() <= 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(from = "PerlinSpec", into = "PerlinSpec"))]
pub struct Perlin {
    seed: u64,
    fade: Fade,
    s: u32,
}

/// Serialised form of [`Perlin`] (seed and fade).
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct PerlinSpec {
    seed: u64,
    fade: Fade,
}

#[cfg(feature = "serde")]
impl From<PerlinSpec> for Perlin {
    fn from(s: PerlinSpec) -> Self {
        Perlin::with_fade(s.seed, s.fade)
    }
}

#[cfg(feature = "serde")]
impl From<Perlin> for PerlinSpec {
    fn from(p: Perlin) -> Self {
        PerlinSpec {
            seed: p.seed,
            fade: p.fade,
        }
    }
}

impl Default for Perlin {
    fn default() -> Self {
        Perlin::new(0)
    }
}

impl Perlin {
    /// Perlin noise with the quintic fade.
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        Self::with_fade(seed, Fade::Quintic)
    }

    /// Perlin noise with the given fade ([`Fade::Cubic`] reproduces the sources).
    #[must_use]
    pub const fn with_fade(seed: u64, fade: Fade) -> Self {
        Self {
            seed,
            fade,
            s: seed32(seed, SALT),
        }
    }

    /// The seed.
    #[must_use]
    pub const fn seed(&self) -> u64 {
        self.seed
    }

    /// The fade.
    #[must_use]
    pub const fn fade(&self) -> Fade {
        self.fade
    }

    /// [`Field::eval2_scaled`] at SIMD level `simd`.
    fn octaves2(&self, simd: Simd, p: DVec2, freq: &[f64], out: &mut [f64]) {
        let out = &mut out[..freq.len()];
        run(
            simd,
            Octaves2 {
                n: self,
                p,
                freq,
                out,
            },
        );
    }

    /// [`Field::eval3_scaled`] at SIMD level `simd`.
    fn octaves3(&self, simd: Simd, p: DVec3, freq: &[f64], out: &mut [f64]) {
        let out = &mut out[..freq.len()];
        run(
            simd,
            Octaves3 {
                n: self,
                p,
                freq,
                out,
            },
        );
    }

    /// The 32-bit lattice seed the hashes use.
    pub(crate) const fn lattice_seed(&self) -> u32 {
        self.s
    }

    fn interp(&self) -> impl Fn(f64) -> (f64, f64) {
        let f = self.fade;
        move |t| (f.eval(t), f.deriv(t))
    }

    /// The 3-D normalisation `1 / sup` for this fade (the value [`Self::scale`] gives).
    #[inline(always)]
    fn k3(&self) -> f64 {
        const Q: f64 = 1.0 / PERLIN3_SUP_QUINTIC;
        const C: f64 = 1.0 / PERLIN3_SUP_CUBIC;
        match self.fade {
            Fade::Quintic => Q,
            Fade::Cubic => C,
        }
    }

    pub(crate) fn scale(&self, dim: usize) -> f64 {
        let q = self.fade == Fade::Quintic;
        1.0 / match dim {
            1 => PERLIN1_SUP,
            2 => PERLIN2_SUP,
            3 if q => PERLIN3_SUP_QUINTIC,
            3 => PERLIN3_SUP_CUBIC,
            _ if q => PERLIN4_SUP_QUINTIC,
            _ => PERLIN4_SUP_CUBIC,
        }
    }

    /// Lipschitz constant in `dim` dimensions (1-4).
    #[must_use]
    pub fn lipschitz_dim(&self, dim: usize) -> f64 {
        LIPSCHITZ[dim.clamp(1, 4) - 1][usize::from(self.fade == Fade::Quintic)]
    }

    /// The value and derivative of 1-D noise at `x`.
    #[must_use]
    pub fn eval_grad1(&self, x: f64) -> (f64, f64) {
        let k = self.scale(1);
        let (v, g) = lattice_sum::<1>(self.s, self.interp(), [x], |h, d| {
            let g = f64::from(grad1(h));
            (g * d[0], [g])
        });
        (v * k, g[0] * k)
    }

    /// The value of 1-D noise at `x`.
    #[must_use]
    pub fn eval1(&self, x: f64) -> f64 {
        self.eval_grad1(x).0
    }

    /// The value and gradient of 4-D noise at `p` (space + time, for animation).
    #[must_use]
    pub fn eval_grad4(&self, p: DVec4) -> (f64, DVec4) {
        let k = self.scale(4);
        let (v, g) = lattice_sum::<4>(self.s, self.interp(), p.to_array(), |h, d| {
            let g = grad4(h).map(f64::from);
            (g[0] * d[0] + g[1] * d[1] + g[2] * d[2] + g[3] * d[3], g)
        });
        (v * k, DVec4::from_array(g) * k)
    }

    /// The value of 4-D noise at `p`.
    #[must_use]
    pub fn eval4(&self, p: DVec4) -> f64 {
        self.eval_grad4(p).0
    }

    /// Reference 2-D evaluation through the generic lattice sum.
    fn grad2_impl(&self, p: DVec2) -> (f64, DVec2) {
        let k = self.scale(2);
        let (v, g) = lattice_sum::<2>(self.s, self.interp(), p.to_array(), |h, d| {
            let (gx, gy) = grad2(h);
            let g = [f64::from(gx), f64::from(gy)];
            (g[0] * d[0] + g[1] * d[1], g)
        });
        (v * k, DVec2::from_array(g) * k)
    }

    fn grad3_impl(&self, p: DVec3) -> (f64, DVec3) {
        let k = self.scale(3);
        let (v, g) = lattice_sum::<3>(self.s, self.interp(), p.to_array(), |h, d| {
            let (gx, gy, gz) = grad3(h);
            let g = [f64::from(gx), f64::from(gy), f64::from(gz)];
            (g[0] * d[0] + g[1] * d[1] + g[2] * d[2], g)
        });
        (v * k, DVec3::from_array(g) * k)
    }
}

impl Field for Perlin {
    #[inline(always)]
    fn eval2(&self, p: DVec2) -> f64 {
        let ([ix, iy], [fx, fy]) = split_n(p.to_array());
        with_fade!(self.fade, |f| cell2(self.s, (ix, fx), (iy, fy), f, dot2)) * K2
    }

    #[inline(always)]
    fn eval3(&self, p: DVec3) -> f64 {
        // x and y as one packed pair, z on its own: split as a third,
        // scalar lane of `split_n`, z's floor correction becomes a branch.
        let ([ix, iy], [fx, fy]) = split_n([p.x, p.y]);
        let (iz, fz) = split(p.z);
        with_fade!(self.fade, |f| cell3(
            self.s,
            (ix, fx),
            (iy, fy),
            (iz, fz),
            f,
            dot3_pair
        )) * self.k3()
    }

    fn eval2_scaled(&self, p: DVec2, freq: &[f64], out: &mut [f64]) {
        self.octaves2(Simd::best(), p, freq, out);
    }

    fn eval3_scaled(&self, p: DVec3, freq: &[f64], out: &mut [f64]) {
        self.octaves3(Simd::best(), p, freq, out);
    }

    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        self.grad2_impl(p)
    }

    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        self.grad3_impl(p)
    }

    fn bound(&self) -> f64 {
        1.0
    }

    fn lipschitz2(&self) -> f64 {
        self.lipschitz_dim(2)
    }

    fn lipschitz3(&self) -> f64 {
        self.lipschitz_dim(3)
    }

    fn fill_grid3(&self, lattice: &Lattice3, out: &mut [f32]) -> crate::Result<()> {
        self.grid3(Simd::best(), lattice, out)
    }

    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        self.rows2(simd, origin, step, out);
    }

    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        self.rows3(simd, origin, step, out);
    }

    fn fill_rows2_with(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
        self.rows2_many(simd, x0, ys, step, out);
    }
}

/// Binds `$f` to the fade as a function of an f64 (monomorphised per fade).
macro_rules! with_fade {
    ($fade:expr, |$f:ident| $body:expr) => {
        match $fade {
            Fade::Quintic => {
                let $f = |t: f64| Fade::Quintic.eval(t);
                $body
            }
            Fade::Cubic => {
                let $f = |t: f64| Fade::Cubic.eval(t);
                $body
            }
        }
    };
}
use with_fade;

/// The model in 2-D (unnormalised): the four corners' gradient dots blended
/// by the fade, for lattice cell and fraction `(ix, fx)`, `(iy, fy)`. `dot`
/// is [`dot2`] (a table lookup, for one point) or [`dot2_bits`] (the same
/// gradients selected by bit logic, for SIMD lanes).
#[inline(always)]
pub(crate) fn cell2(
    seed: u32,
    (ix, fx): (u32, f64),
    (iy, fy): (u32, f64),
    fade: impl Fn(f64) -> f64,
    dot: impl Fn(u32, f64, f64) -> f64,
) -> f64 {
    let x0 = ix.wrapping_mul(PX);
    let x1 = x0.wrapping_add(PX);
    let y0 = iy.wrapping_mul(PY);
    let (r0, r1) = (y0 ^ seed, y0.wrapping_add(PY) ^ seed);
    let (gx, gy) = (fx - 1.0, fy - 1.0);
    let n00 = dot(corner_spread(x0, r0), fx, fy);
    let n10 = dot(corner_spread(x1, r0), gx, fy);
    let n01 = dot(corner_spread(x0, r1), fx, gy);
    let n11 = dot(corner_spread(x1, r1), gx, gy);
    let u = fade(fx);
    let v = fade(fy);
    let a = n00 + u * (n10 - n00);
    let b = n01 + u * (n11 - n01);
    a + v * (b - a)
}

/// The model in 3-D (unnormalised): the eight corners blended along x
/// within each of the cell's four x edges, then along y, then z. The two z
/// layers are computed side by side (`[z0, z1]` pairs), so a scalar caller's
/// corners pair up in two-lane registers: `dot` gives the gradient dots of
/// one (x, y) corner's two z layers, [`dot3_pair`] (one table load per
/// component pair, for one point) or [`dot3_lanes`] per layer (for SIMD
/// lanes).
#[inline(always)]
pub(crate) fn cell3(
    seed: u32,
    (ix, fx): (u32, f64),
    (iy, fy): (u32, f64),
    (iz, fz): (u32, f64),
    fade: impl Fn(f64) -> f64,
    dot: impl Fn(u32, u32, f64, f64, [f64; 2]) -> [f64; 2],
) -> f64 {
    let x0 = ix.wrapping_mul(PX);
    let x1 = x0.wrapping_add(PX);
    let y0 = iy.wrapping_mul(PY);
    let y1 = y0.wrapping_add(PY);
    let zp = iz.wrapping_mul(PZ);
    let z = [zp ^ seed, zp.wrapping_add(PZ) ^ seed];
    let (gx, gy, gz) = (fx - 1.0, fy - 1.0, fz - 1.0);
    let dz = [fz, gz];
    // n[x][y][z]: the corners' gradient dots, z innermost (the pairs a
    // scalar caller holds in one register).
    let (xs, dx) = ([x0, x1], [fx, gx]);
    let (ys, dy) = ([y0, y1], [fy, gy]);
    let mut n = [[[0.0; 2]; 2]; 2];
    for a in 0..2 {
        for b in 0..2 {
            let h = |k: usize| corner_spread(xs[a], ys[b] ^ z[k]);
            n[a][b] = dot(h(0), h(1), dx[a], dy[b], dz);
        }
    }
    let u = fade(fx);
    let v = fade(fy);
    let w = fade(fz);
    // Along x (the four edges, as two z pairs), then y, then z.
    let mut e = [[0.0; 2]; 2];
    for y in 0..2 {
        for k in 0..2 {
            e[y][k] = n[0][y][k] + u * (n[1][y][k] - n[0][y][k]);
        }
    }
    let mut ab = [0.0; 2];
    for k in 0..2 {
        ab[k] = e[0][k] + v * (e[1][k] - e[0][k]);
    }
    ab[0] + w * (ab[1] - ab[0])
}

/// [`dot2`] with the gradient selected by bit logic ([`grad2`]): the same
/// values, in a form that vectorises across lanes.
#[inline(always)]
fn dot2_bits(h: u32, dx: f64, dy: f64) -> f64 {
    let (gx, gy) = grad2(h);
    f64::from(gx) * dx + f64::from(gy) * dy
}

/// [`dot3_lanes`] for a cell's two z layers (the lanes' form of [`dot3_pair`]).
#[inline(always)]
fn dot3_lanes_pair(h0: u32, h1: u32, dx: f64, dy: f64, dz: [f64; 2]) -> [f64; 2] {
    [dot3_lanes(h0, dx, dy, dz[0]), dot3_lanes(h1, dx, dy, dz[1])]
}

/// Octaves evaluated together, as SIMD lanes.
const OCTAVE_LANES: usize = 4;

/// Coordinates below which [`split_fast`] is exact (the lanes' range check).
const LANE_LIMIT: f64 = 2_251_799_813_685_248.0;

/// [`Field::eval2_scaled`] as a [`Kernel`]: the octaves in groups of
/// [`OCTAVE_LANES`] lanes, each lane the point path's [`cell2`] on its own
/// octave's point (bit-identical to it; in 3-D the gradient products are
/// formed as signed sums, [`dot3_lanes`], the same values except that an
/// exactly zero result may carry the other sign); a group with a lane out of
/// the lanes' exact range (or NaN) goes point by point. Every SIMD level
/// gives the same bits.
struct Octaves2<'a> {
    n: &'a Perlin,
    p: DVec2,
    freq: &'a [f64],
    out: &'a mut [f64],
}

impl Kernel for Octaves2<'_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let Self { n, p, freq, out } = self;
        with_fade!(n.fade, |fade| {
            let mut fs = freq.chunks_exact(OCTAVE_LANES);
            let mut os = out.chunks_exact_mut(OCTAVE_LANES);
            for (f, o) in (&mut fs).zip(&mut os) {
                // Whole groups only, as fixed-size arrays and plain loops (no
                // closures, no masked loads or stores: everything inlines
                // into this target-feature context and vectorises).
                let f: &[f64; OCTAVE_LANES] = f.try_into().unwrap();
                let o: &mut [f64; OCTAVE_LANES] = o.try_into().unwrap();
                let mut x = [0.0f64; OCTAVE_LANES];
                let mut y = [0.0f64; OCTAVE_LANES];
                for l in 0..OCTAVE_LANES {
                    x[l] = p.x * f[l];
                    y[l] = p.y * f[l];
                }
                let mut ok = true;
                for l in 0..OCTAVE_LANES {
                    ok &= x[l].abs() < LANE_LIMIT && y[l].abs() < LANE_LIMIT;
                }
                if !ok {
                    for l in 0..OCTAVE_LANES {
                        o[l] = n.eval2(p * f[l]);
                    }
                    continue;
                }
                let mut v = [0.0f64; OCTAVE_LANES];
                for l in 0..OCTAVE_LANES {
                    v[l] = cell2(n.s, split_fast(x[l]), split_fast(y[l]), fade, dot2_bits) * K2;
                }
                *o = v;
            }
            for (o, &f) in os.into_remainder().iter_mut().zip(fs.remainder()) {
                *o = n.eval2(p * f);
            }
        });
    }
}

/// [`Field::eval3_scaled`] as a [`Kernel`] (see [`Octaves2`]).
struct Octaves3<'a> {
    n: &'a Perlin,
    p: DVec3,
    freq: &'a [f64],
    out: &'a mut [f64],
}

impl Kernel for Octaves3<'_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let Self { n, p, freq, out } = self;
        let k = n.k3();
        with_fade!(n.fade, |fade| {
            let mut fs = freq.chunks_exact(OCTAVE_LANES);
            let mut os = out.chunks_exact_mut(OCTAVE_LANES);
            for (f, o) in (&mut fs).zip(&mut os) {
                let f: &[f64; OCTAVE_LANES] = f.try_into().unwrap();
                let o: &mut [f64; OCTAVE_LANES] = o.try_into().unwrap();
                let mut x = [0.0f64; OCTAVE_LANES];
                let mut y = [0.0f64; OCTAVE_LANES];
                let mut z = [0.0f64; OCTAVE_LANES];
                for l in 0..OCTAVE_LANES {
                    x[l] = p.x * f[l];
                    y[l] = p.y * f[l];
                    z[l] = p.z * f[l];
                }
                let mut ok = true;
                for l in 0..OCTAVE_LANES {
                    ok &= x[l].abs() < LANE_LIMIT
                        && y[l].abs() < LANE_LIMIT
                        && z[l].abs() < LANE_LIMIT;
                }
                if !ok {
                    for l in 0..OCTAVE_LANES {
                        o[l] = n.eval3(p * f[l]);
                    }
                    continue;
                }
                let mut v = [0.0f64; OCTAVE_LANES];
                for l in 0..OCTAVE_LANES {
                    let (sx, sy, sz) = (split_fast(x[l]), split_fast(y[l]), split_fast(z[l]));
                    v[l] = cell3(n.s, sx, sy, sz, fade, dot3_lanes_pair) * k;
                }
                *o = v;
            }
            for (o, &f) in os.into_remainder().iter_mut().zip(fs.remainder()) {
                *o = n.eval3(p * f);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The octave lanes equal the point path (bit for bit, but for the sign
    /// of an exact zero in 3-D), give the same bits at every SIMD level, for
    /// both fades, any octave count (whole groups and a partial one), on the
    /// lattice (exact zeros), and in groups that fall back to the point path
    /// (huge or NaN coordinates).
    #[test]
    fn octave_lanes_equal_point_evaluation() {
        let same = |a: f64, b: f64| {
            a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0) || (a.is_nan() && b.is_nan())
        };
        let freq: [f64; 11] = core::array::from_fn(|k| 0.37 * 2.218_f64.powi(k as i32));
        let lattice = [
            1.0, 2.0, 4.0, 8.0, 0.5, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0,
        ];
        let points = [
            DVec3::new(0.3, -7.25, 2.5),
            DVec3::new(-1234.567, 89.01, -0.001),
            DVec3::new(4.0e5 + 0.77, -3.0e6, 1.0e3),
            DVec3::new(3.0e14, 0.5, -0.5),
            DVec3::new(f64::NAN, 1.0, 2.0),
            DVec3::new(3.0, -5.0, 7.0),
        ];
        for fade in [Fade::Quintic, Fade::Cubic] {
            let n = Perlin::with_fade(21, fade);
            for p in points {
                for freq in [&freq, &lattice] {
                    for len in [1, 4, 7, 11] {
                        let mut first: Option<([f64; 11], [f64; 11])> = None;
                        for simd in Simd::supported() {
                            let mut o2 = [0.0; 11];
                            let mut o3 = [0.0; 11];
                            n.octaves2(simd, p.truncate(), &freq[..len], &mut o2);
                            n.octaves3(simd, p, &freq[..len], &mut o3);
                            for k in 0..len {
                                let want = n.eval2(p.truncate() * freq[k]);
                                assert_eq!(
                                    o2[k].to_bits(),
                                    want.to_bits(),
                                    "{fade:?} {p} {simd:?} 2-D {k}"
                                );
                                let want = n.eval3(p * freq[k]);
                                assert!(
                                    same(o3[k], want),
                                    "{fade:?} {p} {simd:?} 3-D {k}: {} vs {want}",
                                    o3[k]
                                );
                            }
                            match first {
                                None => first = Some((o2, o3)),
                                Some((f2, f3)) => {
                                    assert_eq!(
                                        f2.map(f64::to_bits),
                                        o2.map(f64::to_bits),
                                        "{simd:?}"
                                    );
                                    assert_eq!(
                                        f3.map(f64::to_bits),
                                        o3.map(f64::to_bits),
                                        "{simd:?}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}
