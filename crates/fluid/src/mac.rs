//! Operators on the staggered MAC grid (Fedkiw et al. 2001, App. A): divergence, pressure projection, centre-to-face forces,
//! vorticity and vorticity confinement.
//!
//! The MAC divergence and gradient (Fedkiw et al. 2001, App. A) compose to exactly the
//! compact Laplacian the pressure solver inverts, so after [`Projector::project`]
//! the discrete divergence of every fluid cell equals `−r/h²` for the solver
//! residual `r`: the field is divergence-free to the solver tolerance. This is
//! the consistent discretisation that replaces Stable Fluids' mixed
//! wide/compact stencils (Stam 1999, App. B: the divergence there uses
//! the wide stencil while the Poisson solve uses the compact one, so its
//! projected fields are not discretely divergence-free).

use natura_core::Grid3;

use crate::chunks;
use crate::error::Result;
use crate::grid::{Boundaries, CellKind, Dims, MacVelocity, Side};
use crate::pressure::{PoissonSystem, SolveStats, SolverParams};

/// Returns the MAC divergence `(∇·u)_c` (1/s) at every cell centre (Fedkiw et al. 2001, App. A).
///
/// # Errors
///
/// Returns [`FluidError::Core`](crate::FluidError::Core) if the grid cannot be allocated.
pub fn divergence(vel: &MacVelocity, h: f32) -> Result<Grid3<f32>> {
    let mut out = vel.dims().zeros()?;
    chunks::for_chunks(out.as_mut_slice(), vel.dims().n()[0], |r, row| {
        divergence_row(vel, h, r, row);
    });
    Ok(out)
}

/// The MAC divergence of cell row `r` (`r = k·ny + j`) into `row`.
/// Row slices of the face grids (same sums in the same order as the
/// per-face form).
#[inline]
fn divergence_row(vel: &MacVelocity, h: f32, r: usize, row: &mut [f32]) {
    let d = vel.dims();
    let inv = 1.0 / h;
    let n = d.n();
    let c = vel.comps();
    let (u, v, w) = (c[0].as_slice(), c[1].as_slice(), c[2].as_slice());
    let act = [d.active(0), d.active(1), d.active(2)];
    let n0 = n[0];
    let (j, k) = (r % n[1], r / n[1]);
    let ur = &u[(k * n[1] + j) * (n0 + 1)..][..n0 + 1];
    let vr0 = &v[(k * (n[1] + 1) + j) * n0..][..n0];
    let vr1 = &v[(k * (n[1] + 1) + j + 1) * n0..][..n0];
    let wr0 = &w[(k * n[1] + j) * n0..][..n0];
    let wr1 = &w[((k + 1) * n[1] + j) * n0..][..n0];
    for (i, o) in row.iter_mut().enumerate() {
        let mut s = 0.0;
        if act[0] {
            s += ur[i + 1] - ur[i];
        }
        if act[1] {
            s += vr1[i] - vr0[i];
        }
        if act[2] {
            s += wr1[i] - wr0[i];
        }
        *o = s * inv;
    }
}

/// Largest `|∇·u|` over cells of kind [`CellKind::Fluid`].
///
/// One pass over the faces, row by row, with no divergence grid: each row's
/// divergence goes to a row buffer and is folded at once (the same values
/// as [`divergence`]; the maximum does not depend on the order).
///
/// # Errors
///
/// Returns [`FluidError::SizeMismatch`](crate::FluidError::SizeMismatch) if the cell kinds are not the grid's
/// size.
pub fn max_fluid_divergence(vel: &MacVelocity, kinds: &Grid3<CellKind>, h: f32) -> Result<f32> {
    let d = vel.dims();
    let n0 = d.n()[0];
    let rows = d.cells() / n0;
    let ks = kinds.as_slice();
    let fold = |r0: usize, r1: usize| {
        let mut buf = vec![0.0f32; n0];
        let mut m = 0.0f32;
        for r in r0..r1 {
            divergence_row(vel, h, r, &mut buf);
            // Zipped like the grid form: a short `kinds` ends the fold.
            let kr = ks.get(r * n0..).unwrap_or(&[]);
            m = buf
                .iter()
                .zip(kr)
                .filter(|(_, k)| **k == CellKind::Fluid)
                .fold(m, |m, (v, _)| m.max(v.abs()));
        }
        m
    };
    Ok(chunks::max_over_rows(rows, n0, fold))
}

/// Whether face `f` (index into component `a`'s grid) is fixed — a domain
/// wall or touching a solid cell — and so not changed by forces or projection.
#[inline]
pub(crate) fn face_fixed(
    d: Dims,
    kinds: &[CellKind],
    bounds: &Boundaries,
    a: usize,
    f: [usize; 3],
) -> bool {
    let n = d.n();
    let lo = f[a] == 0;
    let hi = f[a] == n[a];
    if lo || hi {
        let side = bounds.side(a, usize::from(hi));
        if side == Side::Wall {
            return true;
        }
        let mut c = f;
        if hi {
            c[a] -= 1;
        }
        return kinds[d.idx(c[0], c[1], c[2])] == CellKind::Solid;
    }
    let mut c0 = f;
    c0[a] -= 1;
    kinds[d.idx(c0[0], c0[1], c0[2])] == CellKind::Solid
        || kinds[d.idx(f[0], f[1], f[2])] == CellKind::Solid
}

/// [`face_fixed`] for the whole face row `(·, j, k)` of component `a`
/// (`j`, `k` in face coordinates), written to `out` (one flag per face).
/// Row-wise so that per-face loops need no index arithmetic per lookup.
pub(crate) fn fixed_row(
    d: Dims,
    kinds: &[CellKind],
    bounds: &Boundaries,
    a: usize,
    j: usize,
    k: usize,
    out: &mut [bool],
) {
    let n = d.n();
    let solid = |r: &[CellKind], i: usize| r[i] == CellKind::Solid;
    if a == 0 {
        let kr = &kinds[d.idx(0, j, k)..d.idx(0, j, k) + n[0]];
        out[0] = bounds.side(0, 0) == Side::Wall || solid(kr, 0);
        out[n[0]] = bounds.side(0, 1) == Side::Wall || solid(kr, n[0] - 1);
        for i in 1..n[0] {
            out[i] = solid(kr, i - 1) || solid(kr, i);
        }
        return;
    }
    let f = if a == 1 { j } else { k };
    let row = |c: usize| {
        let s = if a == 1 {
            d.idx(0, c, k)
        } else {
            d.idx(0, j, c)
        };
        &kinds[s..s + n[0]]
    };
    if (f == 0 && bounds.side(a, 0) == Side::Wall) || (f == n[a] && bounds.side(a, 1) == Side::Wall)
    {
        out.fill(true);
    } else if f == 0 || f == n[a] {
        let kr = row(if f == 0 { 0 } else { f - 1 });
        for (o, &kk) in out.iter_mut().zip(kr) {
            *o = kk == CellKind::Solid;
        }
    } else {
        let (k0, k1) = (row(f - 1), row(f));
        for ((o, &p), &q) in out.iter_mut().zip(k0).zip(k1) {
            *o = p == CellKind::Solid || q == CellKind::Solid;
        }
    }
}

/// For the face row `(·, j, k)` of component `a` (face coordinates), maps
/// a face index `i` to the linear indices of the cells on its low and high
/// side (`None` beyond the domain).
#[inline]
#[cfg(test)]
pub(crate) fn face_cells(
    d: Dims,
    a: usize,
    j: usize,
    k: usize,
) -> (
    impl Fn(usize) -> Option<usize>,
    impl Fn(usize) -> Option<usize>,
) {
    let n = d.n();
    // (row start of the low / high cell row, whether x shifts by one).
    let (lo_row, hi_row, along_x) = if a == 0 {
        let b = d.idx(0, j, k);
        (Some(b), Some(b), true)
    } else {
        let f = if a == 1 { j } else { k };
        let base = |c: usize| {
            if a == 1 {
                d.idx(0, c, k)
            } else {
                d.idx(0, j, c)
            }
        };
        (
            (f > 0).then(|| base(f - 1)),
            (f < n[a]).then(|| base(f)),
            false,
        )
    };
    let n0 = n[0];
    let lo = move |i: usize| {
        if along_x {
            (i > 0).then(|| lo_row.map(|b| b + i - 1)).flatten()
        } else {
            lo_row.map(|b| b + i)
        }
    };
    let hi = move |i: usize| {
        if along_x {
            (i < n0).then(|| hi_row.map(|b| b + i)).flatten()
        } else {
            hi_row.map(|b| b + i)
        }
    };
    (lo, hi)
}

/// Per face of component `a` (x fastest): 1 where the face is fixed (a wall
/// or touching a solid, see [`face_fixed`]), 0 where it is free.
pub(crate) fn fixed_faces(d: Dims, kinds: &[CellKind], bounds: &Boundaries, a: usize) -> Vec<u8> {
    let fd = d.face_dims(a);
    let mut fx = vec![false; fd[0] * fd[1] * fd[2]];
    chunks::for_chunks(&mut fx, fd[0], |r, row| {
        fixed_row(d, kinds, bounds, a, r % fd[1], r / fd[1], row);
    });
    fx.into_iter().map(u8::from).collect()
}

/// Sets wall faces to zero and faces touching solid cells to `solid_vel(a, face_index)`.
pub(crate) fn enforce_solids(
    vel: &mut MacVelocity,
    kinds: &[CellKind],
    bounds: &Boundaries,
    solid_vel: &(dyn Fn(usize, [usize; 3]) -> f32 + Sync),
) {
    let d = vel.dims();
    for a in 0..3 {
        if !d.active(a) {
            continue;
        }
        let fn_ = d.face_dims(a);
        chunks::for_chunks(vel.comp_mut(a).as_mut_slice(), fn_[0], |r, row| {
            let (j, k) = (r % fn_[1], r / fn_[1]);
            let mut fx = vec![false; row.len()];
            fixed_row(d, kinds, bounds, a, j, k, &mut fx);
            for (i, v) in row.iter_mut().enumerate() {
                let f = [i, j, k];
                if !fx[i] {
                    continue;
                }
                let on_wall = (f[a] == 0 || f[a] == d.n()[a])
                    && bounds.side(a, usize::from(f[a] != 0)) == Side::Wall;
                *v = if on_wall { 0.0 } else { solid_vel(a, f) };
            }
        });
    }
}

/// Adds `dt·F` to every free face, with `F` given at cell centres and averaged
/// to faces (Fedkiw et al. 2001, App. A): `u_{i+½} += dt (f_i + f_{i+1})/2`. Open boundary
/// faces take their single inner cell's force.
pub(crate) fn add_centre_forces(
    vel: &mut MacVelocity,
    force: &[Grid3<f32>; 3],
    dt: f32,
    kinds: &[CellKind],
    bounds: &Boundaries,
) {
    let d = vel.dims();
    for a in 0..3 {
        if !d.active(a) {
            continue;
        }
        let fa = force[a].as_slice();
        let fd = d.face_dims(a);
        let n = d.n();
        let n0 = n[0];
        chunks::for_chunks(vel.comp_mut(a).as_mut_slice(), fd[0], |r, row| {
            let (j, k) = (r % fd[1], r / fd[1]);
            let mut fx = vec![false; row.len()];
            fixed_row(d, kinds, bounds, a, j, k, &mut fx);
            // A select rather than a branch so the loops vectorise.
            let add = |v: &mut f32, fixed: bool, val: f32| {
                let t = *v + dt * val;
                *v = if fixed { *v } else { t };
            };
            if a == 0 {
                // Faces 0 and n0 have one cell; face i the cells i − 1 and i.
                let fr = &fa[d.idx(0, j, k)..d.idx(0, j, k) + n0];
                add(&mut row[0], fx[0], fr[0]);
                add(&mut row[n0], fx[n0], fr[n0 - 1]);
                for (((v, &fixed), &f0), &f1) in row[1..n0]
                    .iter_mut()
                    .zip(&fx[1..n0])
                    .zip(&fr[..n0 - 1])
                    .zip(&fr[1..])
                {
                    add(v, fixed, 0.5 * (f0 + f1));
                }
                return;
            }
            let f = if a == 1 { j } else { k };
            let cell_row = |c: usize| {
                let b = if a == 1 {
                    d.idx(0, c, k)
                } else {
                    d.idx(0, j, c)
                };
                &fa[b..b + n0]
            };
            match (
                (f > 0).then(|| cell_row(f - 1)),
                (f < n[a]).then(|| cell_row(f)),
            ) {
                (Some(lo), Some(hi)) => {
                    for (((v, &fixed), &f0), &f1) in row.iter_mut().zip(&fx).zip(lo).zip(hi) {
                        add(v, fixed, 0.5 * (f0 + f1));
                    }
                }
                (Some(c), None) | (None, Some(c)) => {
                    for ((v, &fixed), &fc) in row.iter_mut().zip(&fx).zip(c) {
                        add(v, fixed, fc);
                    }
                }
                (None, None) => {
                    for (v, &fixed) in row.iter_mut().zip(&fx) {
                        add(v, fixed, 0.0);
                    }
                }
            }
        });
    }
}

/// The pressure projection on a MAC grid, caching the Poisson system while
/// the cell kinds stay the same and warm-starting from the last pressure.
#[derive(Clone, Debug, Default)]
pub struct Projector {
    system: Option<PoissonSystem>,
    key: Vec<CellKind>,
    bounds: Boundaries,
    /// Last `p·dt/ρ` per cell (warm start), f64.
    scaled_pressure: Vec<f64>,
    last_dt: f32,
}

impl Projector {
    /// A projector with no cached system.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The pressure (Pa for unit density, i.e. m²/s²) of the last projection, per cell.
    #[must_use]
    pub fn pressure(&self, dims: Dims) -> Option<Grid3<f32>> {
        if self.scaled_pressure.len() != dims.cells() || self.last_dt <= 0.0 {
            return None;
        }
        let inv = 1.0 / f64::from(self.last_dt);
        Grid3::from_vec(
            dims.nx,
            dims.ny,
            dims.nz,
            self.scaled_pressure
                .iter()
                .map(|&p| (p * inv) as f32)
                .collect(),
        )
        .ok()
    }

    /// Makes `vel` discretely divergence-free on fluid cells: solves
    /// `∇²p = ∇·u*/dt` (Fedkiw et al. 2001, §2, eq. 4) with Neumann conditions at solids
    /// and walls and `p = 0` at air cells and open sides, then applies
    /// `u = u* − dt ∇p` (eq. 5) on every free face. Fixed faces (walls,
    /// solids) are not touched: set them before calling.
    ///
    /// # Errors
    ///
    /// Returns [`FluidError::NonFinite`](crate::FluidError::NonFinite) if the velocity or the pressure is not
    /// finite, and [`FluidError::InvalidParameter`](crate::FluidError::InvalidParameter) for a non-positive `dt`.
    pub fn project(
        &mut self,
        vel: &mut MacVelocity,
        kinds: &Grid3<CellKind>,
        bounds: &Boundaries,
        h: f32,
        dt: f32,
        params: &SolverParams,
    ) -> Result<SolveStats> {
        let d = vel.dims();
        crate::error::check_dt(dt)?;
        let ks = kinds.as_slice();
        if self.system.is_none() || self.key.as_slice() != ks || self.bounds != *bounds {
            self.system = Some(PoissonSystem::new(d, ks, bounds, [false; 3])?);
            self.key = ks.to_vec();
            self.bounds = *bounds;
            self.scaled_pressure = vec![0.0; d.cells()];
        }
        // b = −h² div on fluid cells.
        let div = divergence(vel, h)?;
        let h2 = h * h;
        let b: Vec<f32> = div
            .as_slice()
            .iter()
            .zip(ks)
            .map(|(&v, &k)| if k == CellKind::Fluid { -h2 * v } else { 0.0 })
            .collect();
        if self.last_dt > 0.0 && self.last_dt != dt {
            let s = f64::from(dt / self.last_dt);
            self.scaled_pressure.iter_mut().for_each(|p| *p *= s);
        }
        let sys = self.system.as_mut().expect("built above");
        let stats = sys.solve(&b, &mut self.scaled_pressure, params)?;
        self.last_dt = dt;
        apply_pressure(vel, ks, bounds, h, &self.scaled_pressure);
        Ok(stats)
    }
}

/// `u −= (p̃_{c+1} − p̃_c)/h` on free faces, with `p̃ = 0` at air and open sides.
pub(crate) fn apply_pressure(
    vel: &mut MacVelocity,
    kinds: &[CellKind],
    bounds: &Boundaries,
    h: f32,
    p: &[f64],
) {
    let d = vel.dims();
    let inv = 1.0 / f64::from(h);
    for a in 0..3 {
        if !d.active(a) {
            continue;
        }
        let fd = d.face_dims(a);
        let n = d.n();
        let n0 = n[0];
        chunks::for_chunks(vel.comp_mut(a).as_mut_slice(), fd[0], |r, row| {
            let (j, k) = (r % fd[1], r / fd[1]);
            let mut fx = vec![false; row.len()];
            fixed_row(d, kinds, bounds, a, j, k, &mut fx);
            // The low and high cell of face i: cells i − 1 and i of the same
            // row along x, else cell i of the neighbouring cell rows.
            let (lo_row, hi_row) = if a == 0 {
                let b = d.idx(0, j, k);
                (Some(b), Some(b))
            } else {
                let f = if a == 1 { j } else { k };
                let base = |c: usize| {
                    if a == 1 {
                        d.idx(0, c, k)
                    } else {
                        d.idx(0, j, c)
                    }
                };
                ((f > 0).then(|| base(f - 1)), (f < n[a]).then(|| base(f)))
            };
            let cells = |b: Option<usize>| b.map(|b| (&kinds[b..b + n0], &p[b..b + n0]));
            let (lo, hi) = (cells(lo_row), cells(hi_row));
            // Face update from its two cells' (pressure, is-fluid); a select
            // rather than branches so the interior loop vectorises.
            let update =
                |v: &mut f32, fixed: bool, (p0, f0): (f64, bool), (p1, f1): (f64, bool)| {
                    let t = (f64::from(*v) - (p1 - p0) * inv) as f32;
                    *v = if !fixed && (f0 || f1) { t } else { *v };
                };
            let at = |c: Option<(&[CellKind], &[f64])>, i: usize| match c {
                Some((kr, pr)) => {
                    let f = kr[i] == CellKind::Fluid;
                    (if f { pr[i] } else { 0.0 }, f)
                }
                None => (0.0, false),
            };
            if a == 0 {
                update(&mut row[0], fx[0], (0.0, false), at(hi, 0));
                update(&mut row[n0], fx[n0], at(lo, n0 - 1), (0.0, false));
                let (kr, pr) = lo.expect("x faces have both cell rows");
                let inner = &mut row[1..n0];
                for (i, (v, &fixed)) in inner.iter_mut().zip(&fx[1..n0]).enumerate() {
                    update(v, fixed, at(Some((kr, pr)), i), at(Some((kr, pr)), i + 1));
                }
            } else {
                for (i, (v, &fixed)) in row.iter_mut().zip(&fx).enumerate() {
                    update(v, fixed, at(lo, i), at(hi, i));
                }
            }
        });
    }
}

/// Cell-centred central-difference derivative of a centred field along
/// axis `a` (one-sided at the domain edge, zero on flat axes).
#[inline]
fn ddx(g: &[f32], d: Dims, c: [usize; 3], a: usize, h: f32) -> f32 {
    let n = d.n();
    if n[a] == 1 {
        return 0.0;
    }
    let mut lo = c;
    let mut hi = c;
    let mut span = 0.0;
    if c[a] > 0 {
        lo[a] -= 1;
        span += h;
    }
    if c[a] + 1 < n[a] {
        hi[a] += 1;
        span += h;
    }
    (g[d.idx(hi[0], hi[1], hi[2])] - g[d.idx(lo[0], lo[1], lo[2])]) / span
}

/// Cell-centred velocity components (face averages, Fedkiw et al. 2001, App. A).
///
/// # Errors
///
/// Returns [`FluidError::Core`](crate::FluidError::Core) if a result grid cannot be allocated.
pub fn centre_velocity(vel: &MacVelocity) -> Result<[Grid3<f32>; 3]> {
    let d = vel.dims();
    let mut out = [d.zeros()?, d.zeros()?, d.zeros()?];
    let n = d.n();
    for (a, o) in out.iter_mut().enumerate() {
        if !d.active(a) {
            continue;
        }
        let g = vel.comp(a);
        chunks::for_chunks(o.as_mut_slice(), n[0], |r, row| {
            let (j, k) = (r % n[1], r / n[1]);
            for (i, v) in row.iter_mut().enumerate() {
                let mut hi = [i, j, k];
                hi[a] += 1;
                *v = 0.5 * (g[(i, j, k)] + g[(hi[0], hi[1], hi[2])]);
            }
        });
    }
    Ok(out)
}

/// Vorticity `ω = ∇ × u` at cell centres from face-averaged velocities and
/// central differences (Fedkiw et al. 2001, App. A). In 2-D (x–z plane) only the
/// y component is non-zero.
///
/// # Errors
///
/// Returns [`FluidError::Core`](crate::FluidError::Core) if the grids cannot be allocated.
pub fn vorticity(vel: &MacVelocity, h: f32) -> Result<[Grid3<f32>; 3]> {
    let d = vel.dims();
    let u = centre_velocity(vel)?;
    let mut w = [d.zeros()?, d.zeros()?, d.zeros()?];
    let n = d.n();
    let (ux, uy, uz) = (u[0].as_slice(), u[1].as_slice(), u[2].as_slice());
    let [w0, w1, w2] = &mut w;
    for (comp, out) in [(0usize, w0), (1, w1), (2, w2)] {
        chunks::for_chunks(out.as_mut_slice(), n[0], |r, row| {
            let (j, k) = (r % n[1], r / n[1]);
            for (i, v) in row.iter_mut().enumerate() {
                let c = [i, j, k];
                *v = match comp {
                    0 => ddx(uz, d, c, 1, h) - ddx(uy, d, c, 2, h),
                    1 => ddx(ux, d, c, 2, h) - ddx(uz, d, c, 0, h),
                    _ => ddx(uy, d, c, 0, h) - ddx(ux, d, c, 1, h),
                };
            }
        });
    }
    Ok(w)
}

/// The vorticity confinement force `f = ε h (N × ω)` at cell centres
/// (Fedkiw et al. 2001, §3, eqs. 9-11), `N = ∇|ω| / |∇|ω||`.
///
/// Where `|∇|ω||` vanishes (irrotational flow, uniform vorticity) the force
/// is zero rather than NaN (the source divides by it).
///
/// # Errors
///
/// Returns [`FluidError::InvalidParameter`](crate::FluidError::InvalidParameter) for a negative or non-finite `epsilon`,
/// and [`FluidError::Core`](crate::FluidError::Core) if the grids cannot be allocated.
pub fn confinement_force(vel: &MacVelocity, h: f32, epsilon: f32) -> Result<[Grid3<f32>; 3]> {
    let d = vel.dims();
    let w = vorticity(vel, h)?;
    let mag: Vec<f32> = (0..d.cells())
        .map(|c| {
            let v = glam::Vec3::new(w[0].as_slice()[c], w[1].as_slice()[c], w[2].as_slice()[c]);
            v.length()
        })
        .collect();
    let mut f = [d.zeros()?, d.zeros()?, d.zeros()?];
    if epsilon == 0.0 {
        return Ok(f);
    }
    let n = d.n();
    let scale = epsilon * h;
    let ws = [w[0].as_slice(), w[1].as_slice(), w[2].as_slice()];
    let forces: Vec<glam::Vec3> = chunks::map_collect(n[1] * n[2], |r| {
        let (j, k) = (r % n[1], r / n[1]);
        (0..n[0])
            .map(|i| {
                let c = [i, j, k];
                let eta = glam::Vec3::new(
                    ddx(&mag, d, c, 0, h),
                    ddx(&mag, d, c, 1, h),
                    ddx(&mag, d, c, 2, h),
                );
                let len = eta.length();
                // Guard: a gradient below ~1e-6 of |ω|/h carries no direction.
                let ci = d.idx(i, j, k);
                if len.partial_cmp(&(1e-6 * (mag[ci] / h).max(f32::MIN_POSITIVE)))
                    != Some(std::cmp::Ordering::Greater)
                {
                    return glam::Vec3::ZERO;
                }
                let nn = eta / len;
                let om = glam::Vec3::new(ws[0][ci], ws[1][ci], ws[2][ci]);
                scale * nn.cross(om)
            })
            .collect::<Vec<_>>()
    })
    .into_iter()
    .flatten()
    .collect();
    for (a, g) in f.iter_mut().enumerate() {
        for (o, v) in g.as_mut_slice().iter_mut().zip(&forces) {
            *o = v[a];
        }
    }
    Ok(f)
}
