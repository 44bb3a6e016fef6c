//! The SIMD plumbing of the pressure solver: one natura-simd [`Kernel`]
//! struct per row operation, each holding a row's arguments and calling the
//! row equation of [`super::operator`] or [`super::transfer`] inside
//! `#[inline(always)]` `call`, so [`natura_core::simd::run`] compiles that
//! equation for the chosen instruction set. No arithmetic of the model
//! lives here: every level runs the same source and gives the same bits
//! (checked by the tests below).

use super::level::Level;
use super::operator::{self, Real};
use super::transfer::Transfer;
use natura_core::simd::Kernel;

/// One row of [`Level::apply`]: [`operator::apply_row`].
pub(crate) struct ApplyRow<'a, const K: usize, T> {
    pub diag: &'a [f32],
    pub x: &'a [T],
    pub s: usize,
    pub st: [usize; K],
    pub out: &'a mut [T],
}

impl<const K: usize, T: Real> Kernel for ApplyRow<'_, K, T> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        operator::apply_row::<K, T>(self.diag, self.x, self.s, self.st, self.out);
    }
}

/// One row of a red–black half sweep ([`Level::gs_half`]):
/// [`operator::gs_row`].
pub(crate) struct GsRow<'a, const K: usize> {
    pub x: &'a [f32],
    pub b: &'a [f32],
    pub wc: &'a [f32],
    pub s: usize,
    pub st: [usize; K],
    pub out: &'a mut [f32],
}

impl<const K: usize> Kernel for GsRow<'_, K> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        operator::gs_row::<K>(self.x, self.b, self.wc, self.s, self.st, self.out);
    }
}

/// One row of [`Level::residual`]: [`operator::residual_row`].
pub(crate) struct ResidualRow<'a, const K: usize, T> {
    pub x: &'a [T],
    pub b: &'a [T],
    pub diag: &'a [f32],
    pub s: usize,
    pub st: [usize; K],
    pub out: &'a mut [T],
}

impl<const K: usize, T: Real> Kernel for ResidualRow<'_, K, T> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        operator::residual_row::<K, T>(self.x, self.b, self.diag, self.s, self.st, self.out);
    }
}

/// One coarse row of [`Transfer::restrict`]: [`Transfer::restrict_row`].
pub(crate) struct RestrictRow<'a> {
    pub tr: &'a Transfer,
    pub fine: &'a Level,
    pub r: &'a [f32],
    pub cl: &'a Level,
    /// Coarse x cells with the fixed interior weights.
    pub interior: (usize, usize),
    pub row_i: usize,
    pub row: &'a mut [f32],
}

impl Kernel for RestrictRow<'_> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        self.tr.restrict_row(
            self.fine,
            self.r,
            self.cl,
            self.interior,
            self.row_i,
            self.row,
        );
    }
}

/// One fine row of [`Transfer::prolong_add`]: [`Transfer::prolong_row`].
pub(crate) struct ProlongRow<'a> {
    pub tr: &'a Transfer,
    pub coarse: &'a Level,
    pub fl: &'a Level,
    pub row_i: usize,
    pub row: &'a mut [f32],
}

impl Kernel for ProlongRow<'_> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        self.tr
            .prolong_row(self.coarse, self.fl, self.row_i, self.row);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::CellKind;
    use crate::pressure::level::GUARD;
    use crate::pressure::operator::{neighbour_sum, neighbour_sum_wide};
    use crate::pressure::transfer::{coarsen, interior_range};
    use natura_core::simd::{self, Simd};

    fn level(n: [usize; 3], periodic: [bool; 3]) -> Level {
        let kinds: Vec<CellKind> = (0..n[0] * n[1] * n[2])
            .map(|c| match natura_core::mix64(c as u64 ^ 0x51d) % 11 {
                0 => CellKind::Solid,
                1 => CellKind::Air,
                _ => CellKind::Fluid,
            })
            .collect();
        Level::new(n, kinds, [[false; 2]; 3], periodic)
    }

    fn random(l: &Level, seed: u64) -> Vec<f32> {
        let mut v: Vec<f32> = (0..l.len())
            .map(|p| {
                if l.mask[p] != 0 {
                    (natura_core::mix64(seed ^ p as u64) % 2001) as f32 / 997.0 - 1.0
                } else {
                    0.0
                }
            })
            .collect();
        l.fill_ghosts(&mut v);
        v
    }

    /// Runs `row(simd, s, out)` over every interior row at every supported
    /// SIMD level and checks each level's output equals the baseline's bit
    /// for bit.
    fn same_at_every_level<T: Real + PartialEq + std::fmt::Debug>(
        l: &Level,
        row: impl Fn(Simd, usize, &mut [T]),
    ) {
        let (p0, n0) = (l.pad[0], l.n[0]);
        for r in 0..l.rows() {
            let Some(base) = l.row_base(r) else { continue };
            let s = base + p0;
            let mut want = vec![T::default(); n0];
            row(Simd::baseline(), s, &mut want);
            for simd in Simd::supported() {
                let mut got = vec![T::default(); n0];
                row(simd, s, &mut got);
                for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                    let (g, w): (f64, f64) = ((*g).into(), (*w).into());
                    assert_eq!(g.to_bits(), w.to_bits(), "{:?} row {r} [{i}]", simd.level());
                }
            }
        }
    }

    fn check<const K: usize>(l: &Level) {
        let st = l.strides::<K>();
        let x = random(l, 1);
        let b = random(l, 2);
        let x64: Vec<f64> = x.iter().map(|&v| f64::from(v) * 3.0 + 1e3).collect();
        let b64: Vec<f64> = b.iter().map(|&v| f64::from(v)).collect();
        for colour in 0..2 {
            same_at_every_level::<f32>(l, |simd, s, out| {
                simd::run(
                    simd,
                    GsRow::<K> {
                        x: &x,
                        b: &b,
                        wc: &l.invc[colour],
                        s,
                        st,
                        out,
                    },
                )
            });
        }
        same_at_every_level::<f32>(l, |simd, s, out| {
            simd::run(
                simd,
                ResidualRow::<K, f32> {
                    x: &x,
                    b: &b,
                    diag: &l.diag,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f64>(l, |simd, s, out| {
            simd::run(
                simd,
                ResidualRow::<K, f64> {
                    x: &x64,
                    b: &b64,
                    diag: &l.diag,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f32>(l, |simd, s, out| {
            simd::run(
                simd,
                ApplyRow::<K, f32> {
                    diag: &l.diag,
                    x: &x,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f64>(l, |simd, s, out| {
            simd::run(
                simd,
                ApplyRow::<K, f64> {
                    diag: &l.diag,
                    x: &x64,
                    s,
                    st,
                    out,
                },
            )
        });
    }

    /// Restriction and prolongation rows at every SIMD level against the
    /// baseline, bit for bit.
    fn check_transfers(fine: &Level) {
        let (nc, ck) = coarsen(fine);
        let mut coarse = Level::new(nc, ck, fine.open, fine.periodic);
        coarse.x = random(&coarse, 5);
        let tr = Transfer::new(fine, &coarse);
        let r = random(fine, 6);
        let (lo_c, hi_c) = interior_range(coarse.n[0], fine.n[0], fine.n[0] > 1);
        let restrict = |simd: Simd| -> Vec<f32> {
            let mut out = vec![0.0f32; coarse.len()];
            let m0 = coarse.m[0];
            for (row_i, row) in out[GUARD..GUARD + coarse.rows() * m0]
                .chunks_mut(m0)
                .enumerate()
            {
                simd::run(
                    simd,
                    RestrictRow {
                        tr: &tr,
                        fine,
                        r: &r,
                        cl: &coarse,
                        interior: (lo_c, hi_c),
                        row_i,
                        row,
                    },
                );
            }
            out
        };
        let prolong = |simd: Simd| -> Vec<f32> {
            let mut out = random(fine, 7);
            let m0 = fine.m[0];
            for (row_i, row) in out[GUARD..GUARD + fine.rows() * m0]
                .chunks_mut(m0)
                .enumerate()
            {
                simd::run(
                    simd,
                    ProlongRow {
                        tr: &tr,
                        coarse: &coarse,
                        fl: fine,
                        row_i,
                        row,
                    },
                );
            }
            out
        };
        let (rw, pw) = (restrict(Simd::baseline()), prolong(Simd::baseline()));
        for simd in Simd::supported() {
            let (rg, pg) = (restrict(simd), prolong(simd));
            assert!(rg.iter().zip(&rw).all(|(a, b)| a.to_bits() == b.to_bits()));
            assert!(pg.iter().zip(&pw).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }

    /// The neighbour sums (which start from `+0` in registers) equal the
    /// earlier form that cleared the accumulator first and added every axis
    /// into it, bit for bit: `f32` and `f64` sums and the `f64` sum of `f32`
    /// data, signed zeros included, full and partial blocks.
    #[test]
    fn neighbour_sums_equal_the_cleared_accumulator_form() {
        fn cleared<T: Real>(x: &[T], c: usize, st: &[usize], acc: &mut [T]) {
            acc.fill(T::default());
            for &s in st {
                for (k, a) in acc.iter_mut().enumerate() {
                    *a = *a + (x[c + k - s] + x[c + k + s]);
                }
            }
        }
        fn check_k<const K: usize>(l: &Level) {
            let st = l.strides::<K>();
            let mut x = random(l, 9);
            // Negative zeros, so `+0 + (−0 + −0)` is exercised.
            for (p, v) in x.iter_mut().enumerate() {
                if p % 7 == 0 {
                    *v = -0.0;
                }
            }
            let x64: Vec<f64> = x.iter().map(|&v| f64::from(v)).collect();
            let (p0, n0) = (l.pad[0], l.n[0]);
            for r in 0..l.rows() {
                let Some(base) = l.row_base(r) else { continue };
                let s = base + p0;
                for w in [n0, n0 / 2 + 1, 1] {
                    let (mut got, mut want) = (vec![1.0f32; w], vec![2.0f32; w]);
                    neighbour_sum::<K, f32>(&x, s, st, &mut got);
                    cleared(&x, s, &st, &mut want);
                    assert!(
                        got.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                    let (mut got, mut want) = (vec![1.0f64; w], vec![2.0f64; w]);
                    neighbour_sum::<K, f64>(&x64, s, st, &mut got);
                    cleared(&x64, s, &st, &mut want);
                    assert!(
                        got.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                    let mut wide = vec![3.0f64; w];
                    neighbour_sum_wide::<K, f32>(&x, s, st, &mut wide);
                    assert!(
                        wide.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                }
            }
        }
        check_k::<2>(&level([300, 1, 37], [false; 3]));
        check_k::<2>(&level([64, 1, 40], [true, false, false]));
        check_k::<3>(&level([21, 13, 9], [false; 3]));
        check_k::<3>(&level([16, 8, 12], [true, true, false]));
    }

    /// The dispatched row kernels (smoother half sweep, residual, operator,
    /// restriction, prolongation) give the same bits at every SIMD level as
    /// the baseline build.
    #[test]
    fn row_kernels_are_bit_identical_at_every_simd_level() {
        for (l, three) in [
            (level([300, 1, 37], [false; 3]), false),
            (level([64, 1, 40], [true, false, false]), false),
            (level([21, 13, 9], [false; 3]), true),
            (level([16, 8, 12], [true, true, false]), true),
        ] {
            if three {
                check::<3>(&l);
            } else {
                check::<2>(&l);
            }
            check_transfers(&l);
        }
    }
}
