//! The cell model of Musgrave–Kolb–Mace hydraulic erosion (Musgrave et al.
//! 1989, §4.1; Musgrave 1993, §2.4.1), with the corrections stated in the
//! parent module: what one cell keeps and sends in one step. The grid passes
//! in `super` gather each cell's inputs and call `Rates::transport`.

/// The rates of the cell model, in the `f32` of the grids.
pub(super) struct Rates {
    pub(super) capacity: f32,
    pub(super) deposition: f32,
    pub(super) softness: f32,
    pub(super) transfer: f32,
    pub(super) guard: bool,
}

/// What one cell keeps and sends in one step.
pub(super) struct CellOutcome {
    pub(super) bed: f32,
    pub(super) water_kept: f32,
    pub(super) sediment_kept: f32,
    pub(super) water_sent: f32,
    pub(super) sediment_sent: f32,
}

impl Rates {
    /// The cell model (Musgrave et al. 1989, §4.1, with the corrections in
    /// the module's docs): a cell of bed `a`, water `w` and sediment `s`
    /// whose lower neighbours' surface drops sum to `total` (largest
    /// `biggest`, lowest receiving bed `lowest_bed`) sends
    /// `ΔW = min(w, transfer·biggest)` carrying up to `C_s = K_c·ΔW`; over
    /// capacity the excess settles at the cell (`K_d`), under it the bed is
    /// eroded by `soft·(C_s − s)` (never below `lowest_bed` with the guard).
    /// Standing water only settles its sediment. Conserves `a + s` exactly.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn transport(
        &self,
        a: f32,
        w: f32,
        s: f32,
        total: f32,
        biggest: f32,
        lowest_bed: f32,
        soft: f32,
    ) -> CellOutcome {
        let kd = self.deposition;
        let (mut bed, water_kept, sediment_kept, water_sent, sediment_sent);
        if w <= 0.0 || total <= 0.0 {
            bed = a + kd * s;
            sediment_kept = s - kd * s;
            water_kept = w;
            water_sent = 0.0;
            sediment_sent = 0.0;
        } else {
            water_sent = w.min(self.transfer * biggest);
            water_kept = w - water_sent;
            let cs = self.capacity * water_sent;
            if s >= cs {
                sediment_sent = cs;
                let rest = s - cs;
                bed = a + kd * rest;
                sediment_kept = rest - kd * rest;
            } else {
                let mut e = soft * (cs - s);
                if self.guard {
                    e = e.min((a - lowest_bed).max(0.0));
                }
                sediment_sent = s + e;
                bed = a - e;
                sediment_kept = 0.0;
            }
        }
        if !bed.is_finite() {
            bed = a;
        }
        CellOutcome {
            bed,
            water_kept,
            sediment_kept,
            water_sent,
            sediment_sent,
        }
    }
}
