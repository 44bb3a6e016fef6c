//! The modified incomplete Cholesky MIC(0) preconditioner (Bridson 2015,
//! the PCG chapter): its factor (tuning τ = 0.97, safety σ = 0.25) and the
//! forward and backward triangular solves, which are sequential.

use super::PoissonSystem;

impl PoissonSystem {
    pub(super) fn build_mic(&mut self) {
        const TAU: f32 = 0.97;
        const SIGMA: f32 = 0.25;
        let l = &self.levels[0];
        let k = l.active.len();
        let st: Vec<usize> = l.active.iter().map(|&a| l.stride[a]).collect();
        let mut prec = vec![0.0f32; l.len()];
        let pos_count = |m: u16, skip: usize| -> f32 {
            (0..k)
                .filter(|&q| q != skip)
                .map(|q| f32::from((m >> (2 * q + 1)) & 1))
                .sum()
        };
        l.for_each_cell(|_, c| {
            let m = l.mask[c];
            if m == 0 {
                return;
            }
            let diag = f32::from(m >> 8);
            let mut e = diag;
            for (q, &s) in st.iter().enumerate() {
                if (m >> (2 * q)) & 1 == 0 {
                    continue;
                }
                let nb = c - s;
                let pn = prec[nb];
                if pn == 0.0 {
                    continue;
                }
                e -= pn * pn;
                e -= TAU * pos_count(l.mask[nb], q) * pn * pn;
            }
            if e < SIGMA * diag {
                e = diag;
            }
            prec[c] = 1.0 / e.sqrt();
        });
        self.mic = Some(prec);
    }

    pub(super) fn mic_apply(&mut self) {
        let l = &self.levels[0];
        let prec = self.mic.as_ref().expect("built before use");
        let st: Vec<usize> = l.active.iter().map(|&a| l.stride[a]).collect();
        let z = &mut self.z;
        let r = &self.r;
        z.fill(0.0);
        // Forward: L q = r (q stored in z).
        l.for_each_cell(|_, c| {
            let m = l.mask[c];
            if m == 0 {
                return;
            }
            let mut t = r[c];
            for (q, &s) in st.iter().enumerate() {
                if (m >> (2 * q)) & 1 == 1 {
                    let nb = c - s;
                    t += prec[nb] * z[nb];
                }
            }
            z[c] = t * prec[c];
        });
        // Backward: Lᵀ z = q, in reverse order.
        let mut idx = Vec::with_capacity(l.unknowns());
        l.for_each_cell(|_, c| {
            if l.mask[c] != 0 {
                idx.push(c);
            }
        });
        for &c in idx.iter().rev() {
            let m = l.mask[c];
            let mut t = z[c];
            for (q, &s) in st.iter().enumerate() {
                if (m >> (2 * q + 1)) & 1 == 1 {
                    let nb = c + s;
                    if l.mask[nb] != 0 {
                        t += prec[c] * z[nb];
                    }
                }
            }
            z[c] = t * prec[c];
        }
    }
}
