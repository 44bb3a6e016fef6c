//! The iterations of [`PoissonSystem::solve`]: the preconditioned conjugate
//! gradient with the iterate and residual in `f64`, the multigrid V-cycle
//! preconditioner in the manner of McAdams et al. 2010 (red–black
//! Gauss–Seidel smoothing, restriction, coarse solve, prolongation), and
//! the Gauss–Seidel relaxation baseline of Stam 2003.

use super::{PoissonSystem, PressureSolver, SolveStats, SolverParams};

impl PoissonSystem {
    /// Stam-style relaxation, red–black ordered, with the iterate in `f64`:
    /// every block of sweeps runs in `f32` on the correction equation
    /// `A e = b − A x` (mathematically identical to sweeping on `x`, since
    /// Gauss–Seidel is a stationary iteration) so it can reach tolerances
    /// below f32 round-off of the pressure.
    pub(super) fn gauss_seidel(
        &mut self,
        b: &[f32],
        x: &mut [f64],
        p: &SolverParams,
    ) -> SolveStats {
        let bn = self.levels[0].dot(b, b).sqrt();
        if bn == 0.0 {
            x.fill(0.0);
            return SolveStats {
                iterations: 0,
                relative_residual: 0.0,
                converged: true,
            };
        }
        let b64: Vec<f64> = b.iter().map(|&v| f64::from(v)).collect();
        let mut r = vec![0.0f64; x.len()];
        const BLOCK: u32 = 10;
        let mut it = 0;
        let rel = loop {
            self.levels[0].residual(&b64, x, &mut r);
            let rel = self.levels[0].dot(&r, &r).sqrt() / bn;
            if it >= p.max_iterations || (p.tolerance > 0.0 && rel <= p.tolerance) {
                break rel;
            }
            let l = &mut self.levels[0];
            for (o, &v) in l.b.iter_mut().zip(&r) {
                *o = v as f32;
            }
            l.x.fill(0.0);
            let sweeps = BLOCK.min(p.max_iterations - it);
            for _ in 0..sweeps {
                l.smooth(0);
            }
            it += sweeps;
            for (xv, &e) in x.iter_mut().zip(&l.x) {
                *xv += f64::from(e);
            }
        };
        SolveStats {
            iterations: it,
            relative_residual: rel,
            converged: p.tolerance == 0.0 || rel <= p.tolerance,
        }
    }

    /// Applies the preconditioner: `z = M⁻¹ r`.
    pub(super) fn precondition(&mut self, solver: PressureSolver) {
        match solver {
            PressureSolver::Mic0 => self.mic_apply(),
            _ => {
                let l0 = &mut self.levels[0];
                std::mem::swap(&mut l0.b, &mut self.r);
                self.vcycle(0);
                let l0 = &mut self.levels[0];
                std::mem::swap(&mut l0.b, &mut self.r);
                std::mem::swap(&mut l0.x, &mut self.z);
            }
        }
        let mut z = std::mem::take(&mut self.z);
        self.project_null(&mut z);
        self.z = z;
    }

    pub(super) fn vcycle(&mut self, li: usize) {
        let last = li + 1 == self.levels.len();
        let l = &mut self.levels[li];
        // The iterate starts at zero: the first sweep pair skips reading it
        // (`smooth_from_zero`), which also writes every unknown of `x`.
        if last {
            let sweeps = l.active.iter().map(|&a| l.n[a]).max().unwrap_or(1) * 2 + 8;
            l.smooth_from_zero(0);
            l.smooth(1);
            for _ in 1..sweeps {
                l.smooth(0);
                l.smooth(1);
            }
            return;
        }
        const NU: usize = 2;
        l.smooth_from_zero(0);
        for _ in 1..NU {
            l.smooth(0);
        }
        // Residual into t (t is scratch for smoothing, free now).
        let mut t = std::mem::take(&mut l.t);
        let mut x = std::mem::take(&mut l.x);
        l.residual(&l.b, &mut x, &mut t);
        l.x = x;
        let (fine, coarse) = self.levels.split_at_mut(li + 1);
        self.transfers[li].restrict(&fine[li], &t, &mut coarse[0]);
        fine[li].t = t;
        self.vcycle(li + 1);
        let (fine, coarse) = self.levels.split_at_mut(li + 1);
        self.transfers[li].prolong_add(&coarse[0], &mut fine[li]);
        let l = &mut self.levels[li];
        for _ in 0..NU {
            l.smooth(1);
        }
    }

    /// Preconditioned CG. The iterate and residual are kept in `f64` so that
    /// the true residual can reach tolerances near f32 round-off; the search
    /// direction and preconditioner run in `f32`.
    pub(super) fn pcg(&mut self, b: &[f32], x: &mut [f64], p: &SolverParams) -> SolveStats {
        let l = &self.levels[0];
        let bn = l.dot(b, b).sqrt();
        if bn == 0.0 {
            x.fill(0.0);
            return SolveStats {
                iterations: 0,
                relative_residual: 0.0,
                converged: true,
            };
        }
        if p.solver == PressureSolver::Mic0 && self.mic.is_none() {
            self.build_mic();
        }
        let len = x.len();
        let mut b64 = std::mem::take(&mut self.b64);
        b64.clear();
        b64.extend(b.iter().map(|&v| f64::from(v)));
        let mut r = std::mem::take(&mut self.r64);
        r.clear();
        r.resize(len, 0.0);
        let tol = p.tolerance;
        let mut it = 0u32;
        let mut restarts = 0;
        let mut rn;
        'outer: loop {
            self.levels[0].residual(&b64, x, &mut r);
            rn = self.levels[0].dot(&r, &r).sqrt();
            if rn / bn <= tol || it >= p.max_iterations || restarts > 4 {
                break;
            }
            restarts += 1;
            self.precondition_from(&r, p.solver);
            self.d.copy_from_slice(&self.z);
            let mut rz = self.levels[0].dot(&r, &self.z);
            while it < p.max_iterations {
                it += 1;
                let l = &self.levels[0];
                let mut d = std::mem::take(&mut self.d);
                l.fill_ghosts(&mut d);
                let dq = l.apply_dot(&d, &mut self.q);
                if dq <= 0.0 || !dq.is_finite() {
                    self.d = d;
                    continue 'outer;
                }
                let alpha = rz / dq;
                let rr = step_iterate(x, &mut r, &mut self.r, &d, &self.q, alpha);
                self.d = d;
                if rr.sqrt() / bn <= tol {
                    continue 'outer;
                }
                self.precondition(p.solver);
                let rz_new = self.levels[0].dot(&r, &self.z);
                if !(rz_new > 0.0 && rz_new.is_finite()) {
                    // The preconditioned residual lost positivity (round-off
                    // in a nearly converged direction): restart from the
                    // true residual instead of stepping with a negative β.
                    continue 'outer;
                }
                let beta = (rz_new / rz) as f32;
                rz = rz_new;
                update_direction(&mut self.d, &self.z, beta);
            }
        }
        self.b64 = b64;
        self.r64 = r;
        let rel = rn / bn;
        SolveStats {
            iterations: it,
            relative_residual: rel,
            converged: rel <= tol,
        }
    }

    /// `z = M⁻¹ r` for an `f64` residual.
    pub(super) fn precondition_from(&mut self, r: &[f64], solver: PressureSolver) {
        let r32 = &mut self.r;
        crate::chunks::for_chunks(r32, crate::chunks::BLOCK, |bi, c| {
            let s = bi * crate::chunks::BLOCK;
            for (o, &v) in c.iter_mut().zip(&r[s..]) {
                *o = v as f32;
            }
        });
        self.precondition(solver);
    }
}

/// One pass of a CG iteration: `x += αd`, `r −= αq`, the `f32` copy `r32`
/// of `r` the preconditioner reads, and `r·r`, returned. Every vector is
/// zero off the unknowns, so the flat sum equals the interior one.
fn step_iterate(
    x: &mut [f64],
    r: &mut [f64],
    r32: &mut [f32],
    d: &[f32],
    q: &[f32],
    alpha: f64,
) -> f64 {
    crate::chunks::for_chunks3_sum(x, r, r32, crate::chunks::BLOCK, |bi, xc, rc, r32| {
        let s = bi * crate::chunks::BLOCK;
        let n = xc.len();
        let dd = &d[s..s + n];
        let qq = &q[s..s + n];
        for ((((xv, rv), o), &dv), &qv) in xc
            .iter_mut()
            .zip(rc.iter_mut())
            .zip(r32.iter_mut())
            .zip(dd)
            .zip(qq)
        {
            *xv += alpha * f64::from(dv);
            let nr = *rv - alpha * f64::from(qv);
            *rv = nr;
            *o = nr as f32;
        }
        // r·r of the block while it is in cache: eight lane sums (a single
        // running sum would keep the loop scalar), added in a fixed order.
        let mut lanes = [0.0f64; 8];
        let mut it8 = rc.chunks_exact(8);
        for c in &mut it8 {
            for (a, &v) in lanes.iter_mut().zip(c) {
                *a += v * v;
            }
        }
        let tail: f64 = it8.remainder().iter().map(|&v| v * v).sum();
        lanes.iter().sum::<f64>() + tail
    })
}

/// The next search direction, `d = z + βd`.
fn update_direction(d: &mut [f32], z: &[f32], beta: f32) {
    crate::chunks::for_chunks(d, crate::chunks::BLOCK, |bi, dc| {
        let s = bi * crate::chunks::BLOCK;
        let n = dc.len();
        for (dv, &zv) in dc.iter_mut().zip(&z[s..s + n]) {
            *dv = zv + beta * *dv;
        }
    });
}
