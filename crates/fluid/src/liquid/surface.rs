//! Velocity conditions at objects and at the free surface of the liquid:
//! object velocities on occupied faces (Foster & Fedkiw 2001, §9),
//! divergence-free surface cells and empty–empty faces (§7.1.1–7.1.2), and
//! the extrapolation of velocity into the air.

use super::{Liquid, LiquidCell, ObjectMode};
use crate::grid::{CellKind, Side};
use crate::mac;

impl Liquid {
    /// Object constraints (Foster & Fedkiw 2001, §9) on faces touching object cells.
    pub(super) fn apply_objects(&mut self) {
        if self.obstacles.is_empty() {
            return;
        }
        let d = self.dims;
        let n = d.n();
        let sv = crate::shape::solid_face_velocity(d, self.h, &self.owner, &self.obstacles);
        let is_obj = |c: [usize; 3]| self.owner[d.idx(c[0], c[1], c[2])] != u16::MAX;
        for a in 0..3 {
            if !d.active(a) {
                continue;
            }
            let fd = d.face_dims(a);
            for k in 0..fd[2] {
                for j in 0..fd[1] {
                    for i in 0..fd[0] {
                        let f = [i, j, k];
                        let mut lo = f;
                        let lo_obj = f[a] > 0 && {
                            lo[a] -= 1;
                            is_obj(lo)
                        };
                        let hi_obj = f[a] < n[a] && is_obj(f);
                        if !lo_obj && !hi_obj {
                            continue;
                        }
                        let vo = sv(a, f);
                        let g = self.vel.comp_mut(a);
                        let v = &mut g[(i, j, k)];
                        if (lo_obj && hi_obj) || self.params.object_mode == ObjectMode::StickyNormal
                        {
                            *v = vo;
                        } else if hi_obj {
                            // Object on the + side: inflow means v − vo > 0.
                            if *v > vo {
                                *v = vo;
                            }
                        } else if *v < vo {
                            *v = vo;
                        }
                    }
                }
            }
        }
    }

    /// Sets faces between surface cells and empty cells so each surface cell
    /// is divergence-free (Foster & Fedkiw 2001, §7.1.2), and zeroes faces between empty cells (Foster & Fedkiw 2001, §7.1.1).
    pub(super) fn fix_surface_cells(&mut self) {
        let d = self.dims;
        let n = d.n();
        let cells = self.cells.as_slice().to_vec();
        let bounds = self.params.bounds;
        let kind = |c: [usize; 3]| cells[d.idx(c[0], c[1], c[2])];
        let is_air = |c: [usize; 3]| kind(c) == LiquidCell::Empty;
        // Empty–empty faces to zero.
        for a in 0..3 {
            if !d.active(a) {
                continue;
            }
            let fd = d.face_dims(a);
            for k in 0..fd[2] {
                for j in 0..fd[1] {
                    for i in 1..fd[0].max(1) {
                        let _ = i;
                    }
                    for i in 0..fd[0] {
                        let f = [i, j, k];
                        if f[a] == 0 || f[a] == n[a] {
                            continue;
                        }
                        let mut lo = f;
                        lo[a] -= 1;
                        if is_air(lo) && is_air(f) {
                            self.vel.comp_mut(a)[(i, j, k)] = 0.0;
                        }
                    }
                }
            }
        }
        for c in 0..d.cells() {
            if cells[c] != LiquidCell::Surface {
                continue;
            }
            let ijk = d.ijk(c);
            // Net outflow through non-air faces, and the list of air faces.
            let mut net = 0.0f32;
            let mut air: Vec<(usize, [usize; 3], f32)> = Vec::new();
            for a in 0..3 {
                if n[a] == 1 {
                    continue;
                }
                for e in 0..2 {
                    let mut f = ijk;
                    if e == 1 {
                        f[a] += 1;
                    }
                    let sign = if e == 1 { 1.0 } else { -1.0 };
                    let edge = if e == 0 {
                        ijk[a] == 0
                    } else {
                        ijk[a] + 1 == n[a]
                    };
                    let nb_air = if edge {
                        bounds.side(a, e) == Side::Open
                    } else {
                        let mut nb = ijk;
                        nb[a] = if e == 0 { ijk[a] - 1 } else { ijk[a] + 1 };
                        is_air(nb)
                    };
                    if nb_air {
                        air.push((a, f, sign));
                    } else {
                        net += sign * self.vel.comp(a)[(f[0], f[1], f[2])];
                    }
                }
            }
            if air.is_empty() {
                continue;
            }
            // Σ_air sign·u = −net: the smallest change to the air faces
            // (the divergence shared equally), which keeps their current
            // velocities — a free-falling droplet keeps falling.
            let div = net
                + air
                    .iter()
                    .map(|&(a, f, sign)| sign * self.vel.comp(a)[(f[0], f[1], f[2])])
                    .sum::<f32>();
            let share = div / air.len() as f32;
            for (a, f, sign) in air {
                self.vel.comp_mut(a)[(f[0], f[1], f[2])] -= sign * share;
            }
        }
    }

    /// Extrapolates face velocities into the air by breadth-first layers:
    /// each unknown face takes the mean of its known same-component neighbours.
    pub(super) fn extrapolate(&mut self) {
        let d = self.dims;
        let n = d.n();
        let cells = self.cells.as_slice();
        let liquid = |c: [usize; 3]| {
            matches!(
                cells[d.idx(c[0], c[1], c[2])],
                LiquidCell::Surface | LiquidCell::Full
            )
        };
        for a in 0..3 {
            if !d.active(a) {
                continue;
            }
            let fd = d.face_dims(a);
            let len = fd[0] * fd[1] * fd[2];
            let fidx = |f: [usize; 3]| (f[2] * fd[1] + f[1]) * fd[0] + f[0];
            let mut known = vec![false; len];
            for (s, kn) in known.iter_mut().enumerate() {
                let f = [s % fd[0], (s / fd[0]) % fd[1], s / (fd[0] * fd[1])];
                let mut lo = f;
                let lo_l = f[a] > 0 && {
                    lo[a] -= 1;
                    liquid(lo)
                };
                let hi_l = f[a] < n[a] && liquid(f);
                *kn = lo_l || hi_l;
            }
            let g = self.vel.comp_mut(a);
            for _ in 0..self.params.extrapolation_layers {
                let mut updates = Vec::new();
                for s in 0..len {
                    if known[s] {
                        continue;
                    }
                    let f = [s % fd[0], (s / fd[0]) % fd[1], s / (fd[0] * fd[1])];
                    let mut sum = 0.0;
                    let mut cnt = 0;
                    for b in 0..3 {
                        if fd[b] == 1 {
                            continue;
                        }
                        for e in [-1i64, 1] {
                            let q = f[b] as i64 + e;
                            if q < 0 || q >= fd[b] as i64 {
                                continue;
                            }
                            let mut nb = f;
                            nb[b] = q as usize;
                            if known[fidx(nb)] {
                                sum += g.as_slice()[fidx(nb)];
                                cnt += 1;
                            }
                        }
                    }
                    if cnt > 0 {
                        updates.push((s, sum / cnt as f32));
                    }
                }
                if updates.is_empty() {
                    break;
                }
                for (s, v) in updates {
                    g.as_mut_slice()[s] = v;
                    known[s] = true;
                }
            }
            // Faces beyond the band carry no information: zero them.
            for (s, &k) in known.iter().enumerate() {
                if !k {
                    g.as_mut_slice()[s] = 0.0;
                }
            }
        }
        // Walls stay closed.
        let sv = |_: usize, _: [usize; 3]| 0.0f32;
        let kinds: Vec<CellKind> = self
            .cells
            .as_slice()
            .iter()
            .map(|&c| {
                if c == LiquidCell::Object {
                    CellKind::Solid
                } else {
                    CellKind::Fluid
                }
            })
            .collect();
        let mut bounds = self.params.bounds;
        // Only walls are enforced here; object faces were set before.
        let _ = &mut bounds;
        let vel = &mut self.vel;
        let has_obj = !self.obstacles.is_empty();
        mac::enforce_solids(vel, &kinds, &bounds, &sv);
        if has_obj {
            self.apply_objects();
        }
    }
}
