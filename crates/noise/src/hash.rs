//! Lattice hashing: random numbers indexed by integer lattice position.
//!
//! Every basis draws its per-lattice-point randomness (gradients, values,
//! feature points, impulses) from a stateless hash of the lattice coordinates
//! and the seed, in the spirit of Fournier–Fussell–Carpenter's "random numbers
//! indexed by position". No permutation table: the common table-based
//! implementations repeat every 256 cells, which shows at planet scale;
//! this hash repeats only with the 2³² wrap of the `i32` lattice index.
//!
//! The hash is 32-bit integer arithmetic so the f64 point path and the f32
//! SIMD batch path draw bit-identical lattice values. A lattice point's hash
//! is `fin(x·PX ^ y·PY ^ z·PZ ^ w·PW ^ seed)`: each index is spread by an odd
//! multiplier, the spread indices and the seed are combined by `xor`, and one
//! multiply–xorshift finaliser ([`fin`]) mixes the result. The `row*` hashes
//! are the `xor` of everything but x, so a batch row hoists them out of the
//! per-point loop (`corner(x, row(y, z, …))`), and the point paths spread each
//! index once and reach a neighbouring corner with one add
//! (`(x + 1)·PX = x·PX + PX`).
//!
//! One multiply per lattice point is what the per-point evaluators can
//! afford (a 3-D gradient cell hashes 8 corners, a 3-D Worley search 27
//! cells). Its quality is ample for what the bases draw: the gradient and
//! value consumers read the top bits, which depend on every input bit
//! through the multiply's carries, and the final `h ^ (h >> 16)` gives the
//! low half (Worley's feature coordinates) the same dependence. The
//! statistical tests (uniform gradient choice, zero mean, uncorrelated
//! seeds, stationarity, spectral slopes) hold it to that.

/// Multiplier spreading the x lattice index.
pub(crate) const PX: u32 = 0x8DA6_B343;
/// Multiplier spreading the y lattice index.
pub(crate) const PY: u32 = 0xD816_3841;
/// Multiplier spreading the z lattice index.
pub(crate) const PZ: u32 = 0xCB1A_B31F;
/// Multiplier spreading the w lattice index.
pub(crate) const PW: u32 = 0x1656_67B1;

/// The "lowbias32" integer finaliser (two multiplies; full avalanche), for
/// draws that need more than one multiply's mixing (seeds, impulse streams).
#[inline(always)]
#[must_use]
pub(crate) const fn mix32(mut h: u32) -> u32 {
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846C_A68B);
    h ^ (h >> 16)
}

/// Multiplier of the lattice finaliser [`fin`].
pub(crate) const FIN: u32 = 0x27D4_EB2D;

/// The lattice finaliser: one multiply, then the high half folded into the
/// low half (consumers of the top bits see the plain product, which the
/// compiler then skips the fold for).
#[inline(always)]
#[must_use]
pub(crate) const fn fin(v: u32) -> u32 {
    let h = v.wrapping_mul(FIN);
    h ^ (h >> 16)
}

/// splitmix64's finaliser.
#[inline]
#[must_use]
pub(crate) const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Folds a 64-bit user seed into the 32-bit lattice seed; `salt` separates
/// the bases so the same seed gives unrelated Perlin, value and Worley fields.
#[inline]
#[must_use]
pub(crate) const fn seed32(seed: u64, salt: u64) -> u32 {
    (mix64(seed ^ salt.wrapping_mul(0x9E37_79B9_7F4A_7C15)) >> 32) as u32
}

/// Wraps an `f64` lattice coordinate (already floored) to the `i32` index
/// the hash uses, reproducing the f32 path's wrap-around.
#[inline(always)]
#[must_use]
pub(crate) fn wrap(i: f64) -> u32 {
    // Saturating cast to i64 first (exact for |i| < 2^63), then wrap to 32 bits.
    (i as i64) as u32
}

/// Row hash for 2-D lattices: the spread y index and the seed.
#[inline(always)]
#[must_use]
pub(crate) const fn row2(y: u32, seed: u32) -> u32 {
    y.wrapping_mul(PY) ^ seed
}

/// Row hash for 3-D lattices: the spread (y, z) indices and the seed.
#[inline(always)]
#[must_use]
pub(crate) const fn row3(y: u32, z: u32, seed: u32) -> u32 {
    y.wrapping_mul(PY) ^ z.wrapping_mul(PZ) ^ seed
}

/// Row hash for 4-D lattices: the spread (y, z, w) indices and the seed.
#[inline(always)]
#[must_use]
pub(crate) const fn row4(y: u32, z: u32, w: u32, seed: u32) -> u32 {
    y.wrapping_mul(PY) ^ z.wrapping_mul(PZ) ^ w.wrapping_mul(PW) ^ seed
}

/// Row hash for 1-D lattices (only the seed).
#[inline(always)]
#[must_use]
pub(crate) const fn row1(seed: u32) -> u32 {
    seed ^ 0x2545_F491
}

/// The hash of lattice point `(x, row)`, where `row` is one of the `row*` hashes.
#[inline(always)]
#[must_use]
pub(crate) const fn corner(x: u32, row: u32) -> u32 {
    fin(x.wrapping_mul(PX) ^ row)
}

/// The hash of the lattice point whose x index is already spread
/// (`xp = x·PX`): the point paths step to the next corner by adding `PX`.
#[inline(always)]
#[must_use]
pub(crate) const fn corner_spread(xp: u32, row: u32) -> u32 {
    fin(xp ^ row)
}

/// Hash of the 2-D lattice point `(x, y)` in one step (simplex lattices,
/// whose rows are skewed so nothing can be hoisted); the same value as
/// `corner(x, row2(y, seed))`.
#[inline(always)]
#[must_use]
pub(crate) const fn flat2(x: u32, y: u32, seed: u32) -> u32 {
    corner(x, row2(y, seed))
}

/// Hash of the 3-D lattice point `(x, y, z)` in one step; the same value as
/// `corner(x, row3(y, z, seed))`.
#[inline(always)]
#[must_use]
pub(crate) const fn flat3(x: u32, y: u32, z: u32, seed: u32) -> u32 {
    corner(x, row3(y, z, seed))
}

/// A value uniform in `[-1, 1)` (24 bits) drawn from hash `h`.
#[inline(always)]
#[must_use]
pub(crate) fn signed_unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 8_388_608.0) - 1.0
}

/// A value uniform in `[0, 1)` (16 bits) drawn from the low half of `h`.
#[inline(always)]
#[must_use]
pub(crate) fn unit_lo(h: u32) -> f32 {
    (h & 0xFFFF) as f32 * (1.0 / 65_536.0)
}

/// A value uniform in `[0, 1)` (16 bits) drawn from the high half of `h`.
#[inline(always)]
#[must_use]
pub(crate) fn unit_hi(h: u32) -> f32 {
    (h >> 16) as f32 * (1.0 / 65_536.0)
}

/// A second, independent-looking 32-bit draw from `h` (one multiply-xorshift).
#[inline(always)]
#[must_use]
pub(crate) const fn rehash(h: u32) -> u32 {
    let h = h.wrapping_mul(0x9E37_79B1) ^ 0x68E3_1DA4;
    h ^ (h >> 15)
}

/// The 2-D gradient for hash `h`: one of 8 unit vectors (axes and diagonals),
/// chosen by the top four bits with equal probability.
#[inline(always)]
#[must_use]
pub(crate) const fn grad2(h: u32) -> (f32, f32) {
    const S: f32 = core::f32::consts::FRAC_1_SQRT_2;
    let diag = h & 0x2000_0000 != 0;
    let xaxis = h & 0x1000_0000 != 0;
    let ax = if diag {
        S
    } else if xaxis {
        1.0
    } else {
        0.0
    };
    let ay = if diag {
        S
    } else if xaxis {
        0.0
    } else {
        1.0
    };
    // Bits 31 and 30 are the signs: flip the sign bits directly (the same
    // values as negating, without a compare and select per component).
    let gx = f32::from_bits(ax.to_bits() ^ (h & 0x8000_0000));
    let gy = f32::from_bits(ay.to_bits() ^ ((h << 1) & 0x8000_0000));
    (gx, gy)
}

/// The 3-D gradient for hash `h`: one of the 12 cube-edge directions `(±1, ±1,
/// 0)` and permutations (Perlin 2002), four of them doubled to fill 16 slots.
#[inline(always)]
#[must_use]
pub(crate) const fn grad3(h: u32) -> (f32, f32, f32) {
    let c = h >> 28;
    // u on x for c < 8, else y; v on y for c < 4, x for 12 and 14, else z.
    let ux = if c < 8 { 1.0 } else { 0.0 };
    let uy = 1.0 - ux;
    let vy = if c < 4 { 1.0 } else { 0.0 };
    let vx = if c == 12 || c == 14 { 1.0 } else { 0.0 };
    let vz = 1.0 - vy - vx;
    let su = if c & 1 != 0 { -1.0 } else { 1.0 };
    let sv = if c & 2 != 0 { -1.0 } else { 1.0 };
    (su * ux + sv * vx, su * uy + sv * vy, sv * vz)
}

/// [`grad2`] for each value of the top four hash bits, in f64: the point
/// paths index it with `h >> 28` (the same gradients as the lane kernels'
/// bit selection, exactly).
pub(crate) const GRAD2_64: [[f64; 2]; 16] = {
    let mut t = [[0.0; 2]; 16];
    let mut i = 0;
    while i < 16 {
        let (x, y) = grad2((i as u32) << 28);
        t[i] = [x as f64, y as f64];
        i += 1;
    }
    t
};

/// `g·(dx, dy)` for the gradient of hash `h`, in f64.
#[inline(always)]
#[must_use]
pub(crate) fn dot2(h: u32, dx: f64, dy: f64) -> f64 {
    let g = GRAD2_64[(h >> 28) as usize];
    g[0] * dx + g[1] * dy
}

/// [`grad3`] for each value of the top four hash bits, in f64 (see [`GRAD2_64`]).
pub(crate) const GRAD3_64: [[f64; 3]; 16] = {
    let mut t = [[0.0; 3]; 16];
    let mut i = 0;
    while i < 16 {
        let (x, y, z) = grad3((i as u32) << 28);
        t[i] = [x as f64, y as f64, z as f64];
        i += 1;
    }
    t
};

/// `x` with its sign flipped when bit `bit` of `h` is set (a sign-bit xor:
/// exact, branch-free, vectorisable).
#[inline(always)]
fn flip(x: f64, h: u32, bit: u32) -> f64 {
    f64::from_bits(x.to_bits() ^ (u64::from((h >> bit) & 1) << 63))
}

/// `g·(dx, dy, dz)` for the [`grad3`] gradient of hash `h`, in f64 (a
/// table lookup: cheap for one point).
#[inline(always)]
#[must_use]
pub(crate) fn dot3(h: u32, dx: f64, dy: f64, dz: f64) -> f64 {
    let i = (h >> 28) as usize;
    GRAD3_X[i] * dx + GRAD3_Y[i] * dy + GRAD3_Z[i] * dz
}

/// One component of every [`GRAD3_64`] entry: one table per axis, so a
/// lookup is the top hash bits scaled by the element size (no multiply
/// by the entry size) and two corners' components load side by side.
const fn grad3_axis(a: usize) -> [f64; 16] {
    let mut t = [0.0; 16];
    let mut i = 0;
    while i < 16 {
        t[i] = GRAD3_64[i][a];
        i += 1;
    }
    t
}

/// The x components of [`GRAD3_64`].
static GRAD3_X: [f64; 16] = grad3_axis(0);
/// The y components of [`GRAD3_64`].
static GRAD3_Y: [f64; 16] = grad3_axis(1);
/// The z components of [`GRAD3_64`].
static GRAD3_Z: [f64; 16] = grad3_axis(2);

/// The [`GRAD3_64`] components of two gradients side by side, for every
/// pair of top-four-bit values: entry `16·c0 + c1` holds `[x, y, z]`, each
/// `[g(c0), g(c1)]`, so a pair of corners loads each component pair with
/// one 16-byte load (12 KiB; the per-axis tables need two loads and a merge).
#[repr(align(16))]
struct Grad3Pairs([[[f64; 2]; 3]; 256]);

/// See [`Grad3Pairs`].
static GRAD3_PAIRS: Grad3Pairs = {
    let mut t = [[[0.0; 2]; 3]; 256];
    let mut i = 0;
    while i < 256 {
        let mut a = 0;
        while a < 3 {
            t[i][a] = [GRAD3_64[i >> 4][a], GRAD3_64[i & 15][a]];
            a += 1;
        }
        i += 1;
    }
    Grad3Pairs(t)
};

/// [`dot3`] for two corners that share their x and y offsets (a cell's
/// two z layers): `[g0·(dx, dy, dz[0]), g1·(dx, dy, dz[1])]` for the
/// gradients of hashes `h0` and `h1`, the same values as two [`dot3`] calls,
/// each component pair one table load.
#[inline(always)]
#[must_use]
pub(crate) fn dot3_pair(h0: u32, h1: u32, dx: f64, dy: f64, dz: [f64; 2]) -> [f64; 2] {
    let g = &GRAD3_PAIRS.0[(((h0 >> 24) & 0xF0) | (h1 >> 28)) as usize];
    let mut r = [0.0; 2];
    for k in 0..2 {
        r[k] = g[0][k] * dx + g[1][k] * dy + g[2][k] * dz[k];
    }
    r
}

/// [`dot3`] in the form that vectorises across SIMD lanes: the gradient has
/// two non-zero components `±1`, so `g·d` is the signed sum `±u ± v` of two
/// of the offsets, picked by comparisons and signed by a sign-bit xor. The
/// same value as [`dot3`] exactly, up to the sign of a zero result (`g·d`
/// adds a `±0` term that can turn `−0` into `+0`).
#[inline(always)]
#[must_use]
pub(crate) fn dot3_lanes(h: u32, dx: f64, dy: f64, dz: f64) -> f64 {
    let c = h >> 28;
    let u = if c < 8 { dx } else { dy };
    let v = if c < 4 {
        dy
    } else if c == 12 || c == 14 {
        dx
    } else {
        dz
    };
    flip(u, h, 28) + flip(v, h, 29)
}

/// The 4-D gradient for hash `h`: one of the 32 tesseract-edge directions
/// (three of ±1 and one 0).
#[inline(always)]
#[must_use]
pub(crate) fn grad4(h: u32) -> [f32; 4] {
    let zero = (h >> 27) & 3;
    let s0 = if h & 0x8000_0000 != 0 { -1.0 } else { 1.0 };
    let s1 = if h & 0x4000_0000 != 0 { -1.0 } else { 1.0 };
    let s2 = if h & 0x2000_0000 != 0 { -1.0 } else { 1.0 };
    match zero {
        0 => [0.0, s0, s1, s2],
        1 => [s0, 0.0, s1, s2],
        2 => [s0, s1, 0.0, s2],
        _ => [s0, s1, s2, 0.0],
    }
}

/// The 1-D gradient for hash `h`: uniform in `[-1, 1)`.
#[inline(always)]
#[must_use]
pub(crate) fn grad1(h: u32) -> f32 {
    signed_unit(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both forms of the 3-D gradient dot product equal `g·d` with the
    /// [`grad3`] gradient (the lane form up to the sign of a zero), for
    /// every gradient and offsets of either sign.
    #[test]
    fn dot3_forms_agree_with_the_gradient() {
        let offsets = [0.0, 0.375, -0.625, 0.999_999, -1.0, 1.0e-9, 0.5];
        for c in 0..16u32 {
            let h = (c << 28) | 0x0123_4567;
            let (gx, gy, gz) = grad3(h);
            for &dx in &offsets {
                for &dy in &offsets {
                    for &dz in &offsets {
                        let a = dot3(h, dx, dy, dz);
                        let b = dot3_lanes(h, dx, dy, dz);
                        let g = f64::from(gx) * dx + f64::from(gy) * dy + f64::from(gz) * dz;
                        assert_eq!(a.to_bits(), g.to_bits(), "c {c}");
                        assert_eq!(a, b, "c {c} ({dx}, {dy}, {dz})");
                        if a != 0.0 {
                            assert_eq!(a.to_bits(), b.to_bits(), "c {c}");
                        }
                    }
                }
            }
        }
    }

    /// The pair form equals [`dot3`] on each corner, bit for bit, for every
    /// pair of gradients.
    #[test]
    fn dot3_pair_equals_dot3_per_corner() {
        let offsets = [0.0, -0.0, 0.375, -0.625, 0.999_999, -1.0, 1.0e-9];
        for c0 in 0..16u32 {
            for c1 in 0..16u32 {
                let (h0, h1) = ((c0 << 28) | 0x0765_4321, (c1 << 28) | 0x0ABC_DEF1);
                for &dx in &offsets {
                    for &dy in &offsets {
                        for (&z0, &z1) in offsets.iter().zip(offsets.iter().rev()) {
                            let [a, b] = dot3_pair(h0, h1, dx, dy, [z0, z1]);
                            assert_eq!(a.to_bits(), dot3(h0, dx, dy, z0).to_bits(), "{c0} {c1}");
                            assert_eq!(b.to_bits(), dot3(h1, dx, dy, z1).to_bits(), "{c0} {c1}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn gradients_are_uniform_over_their_sets() {
        let mut c2 = [0u32; 8];
        let mut n3 = 0usize;
        for i in 0..80_000u32 {
            let h = corner(i, row2(7, 99));
            let (x, y) = grad2(h);
            assert!(((x * x + y * y) - 1.0).abs() < 1e-6);
            let k = (libm::atan2f(y, x).rem_euclid(core::f32::consts::TAU)
                / core::f32::consts::FRAC_PI_4
                + 0.5) as usize
                % 8;
            c2[k] += 1;
            let (a, b, c) = grad3(h);
            assert_eq!(a * a + b * b + c * c, 2.0);
            n3 += 1;
            let g4 = grad4(h);
            assert_eq!(g4.iter().map(|v| v * v).sum::<f32>(), 3.0);
        }
        assert_eq!(n3, 80_000);
        for c in c2 {
            // 10 000 expected per direction; 5σ ≈ 470.
            assert!((9_500..10_500).contains(&c), "{c2:?}");
        }
    }

    #[test]
    fn rows_separate_axes_and_seeds() {
        assert_ne!(corner(1, row2(2, 0)), corner(2, row2(1, 0)));
        assert_ne!(row2(5, 1), row2(5, 2));
        assert_ne!(row3(1, 2, 0), row3(2, 1, 0));
        assert_ne!(seed32(1, 0), seed32(1, 1));
        assert_eq!(wrap(-1.0), u32::MAX);
        assert_eq!(wrap(4_294_967_296.0 + 3.0), 3);
    }
}
