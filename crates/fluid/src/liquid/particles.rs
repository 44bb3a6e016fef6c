//! The marker particles of the liquid (Foster & Fedkiw 2001, §5.1–5.4):
//! seeding, advection (RK2 in the grid velocity, ballistic beyond the
//! velocity band), the level-set correction `φ ← min(φ, φ_p)`, radii, and
//! deletion and reseeding near the surface.

use glam::Vec3;
use natura_core::Seed;

use super::{Liquid, ParticleCorrection};
use crate::advect::VelSampler;
use crate::grid::{self, Dims};

impl Liquid {
    /// Rebuilds φ from the particles alone (Foster & Fedkiw 2001, §5.2): `φ = min_p |x − x_p| − r`,
    /// then reinitialised to a signed distance.
    pub fn rebuild_phi_from_particles(&mut self) {
        let d = self.dims;
        let h = self.h;
        let r = self.params.particle_radius * h;
        let far = 3.0 * h;
        self.phi.phi_mut().as_mut_slice().fill(far);
        let radii = vec![r; self.particles.len()];
        self.splat_particles(&self.particles.clone(), &radii, None);
        self.phi
            .reinitialize(2 * (d.nx.max(d.ny).max(d.nz) as u32).min(64));
    }

    /// `φ ← min(φ, |x − x_p| − r)` at cells within two cells of each particle
    /// (all particles, or those flagged).
    pub(super) fn splat_particles(&mut self, ps: &[Vec3], radii: &[f32], only: Option<&[bool]>) {
        let d = self.dims;
        let h = self.h;
        let n = d.n();
        let phi = self.phi.phi_mut();
        for (pi, p) in ps.iter().enumerate() {
            if only.is_some_and(|o| !o[pi]) {
                continue;
            }
            let c = (*p / h).to_array();
            let range = |a: usize| {
                let lo = ((c[a] - 2.5).floor().max(0.0) as usize).min(n[a] - 1);
                let hi = ((c[a] + 1.5).ceil().max(0.0) as usize).min(n[a] - 1);
                lo..=hi
            };
            for k in range(2) {
                for j in range(1) {
                    for i in range(0) {
                        let x = grid::cell_centre([i, j, k], h);
                        let v = (x - *p).length() - radii[pi];
                        let s = &mut phi[(i, j, k)];
                        *s = s.min(v);
                    }
                }
            }
        }
    }

    /// Moves particles with the grid velocity (trilinear, RK2, Foster & Fedkiw 2001, §5.1);
    /// particles further into the air than the extrapolated velocity band
    /// (escaped spray, Foster & Fedkiw 2001, §5.4) fly ballistically under gravity until they
    /// come back into the band.
    pub(super) fn move_particles(&mut self, dt: f32) {
        let d = self.dims;
        let h = self.h;
        let g = self.params.gravity;
        let vs = VelSampler::mac(&self.vel);
        let ext: [f32; 3] = std::array::from_fn(|a| d.n()[a] as f32 * h);
        let band = (self.params.extrapolation_layers.max(2) - 1) as f32 * h;
        let phi = &self.phi;
        let moved: Vec<(Vec3, Vec3)> = crate::chunks::map_collect(self.particles.len(), |i| {
            let p = self.particles[i];
            let (q, v) = if phi.value_at(p) > band {
                let v = self.pvel[i] + dt * g;
                (p + dt * v, v)
            } else {
                let v1 = Vec3::from_array(vs.at((p / h).to_array()));
                let mid = p + 0.5 * dt * v1;
                let v2 = Vec3::from_array(vs.at((mid / h).to_array()));
                (p + dt * v2, v2)
            };
            let mut v = v;
            let q = Vec3::from_array(std::array::from_fn(|a| {
                if d.active(a) {
                    let c = q[a].clamp(1e-3 * h, ext[a] - 1e-3 * h);
                    if c != q[a] {
                        v[a] = 0.0;
                    }
                    c
                } else {
                    p[a]
                }
            }));
            (q, v)
        });
        self.particles = moved.iter().map(|m| m.0).collect();
        self.pvel = moved.iter().map(|m| m.1).collect();
        self.push_particles_out();
    }

    /// Moves particles found inside an object to just outside its surface (Foster & Fedkiw 2001, §9).
    pub(super) fn push_particles_out(&mut self) {
        if self.obstacles.is_empty() {
            return;
        }
        let h = self.h;
        for p in &mut self.particles {
            for o in &self.obstacles {
                let s = o.shape.sdf(*p);
                if s < 0.0 {
                    let e = 1e-3 * h;
                    let grad = Vec3::new(
                        o.shape.sdf(*p + Vec3::X * e) - o.shape.sdf(*p - Vec3::X * e),
                        o.shape.sdf(*p + Vec3::Y * e) - o.shape.sdf(*p - Vec3::Y * e),
                        o.shape.sdf(*p + Vec3::Z * e) - o.shape.sdf(*p - Vec3::Z * e),
                    )
                    .normalize_or_zero();
                    *p -= grad * (s - 0.05 * h);
                }
            }
        }
    }

    /// Particle correction (Foster & Fedkiw 2001, §5.4): only ever adds liquid
    /// (`φ ← min(φ, |x − x_p| − r_p)` near flagged particles).
    pub(super) fn correct_with_particles(&mut self) {
        let h = self.h;
        let flags: Vec<bool> = match self.params.correction {
            ParticleCorrection::Curvature => {
                let kappa = self.phi.curvature();
                let ks = crate::interp::Sampler::new(
                    kappa.as_slice(),
                    [kappa.nx(), kappa.ny(), kappa.nz()],
                    [0.5; 3],
                    false,
                );
                let thr = self.params.curvature_threshold / h;
                self.particles
                    .iter()
                    .map(|p| {
                        // A particle carries liquid: where the level set has it
                        // in the air (it "pokes out") near the surface, it
                        // restores the liquid.
                        let phi = self.phi.value_at(*p);
                        phi > 0.0 && phi < 2.0 * h && ks.linear((*p / h).to_array()).abs() > thr
                    })
                    .collect()
            }
            ParticleCorrection::Escaped => self
                .particles
                .iter()
                .zip(&self.radii)
                .map(|(p, &r)| self.phi.value_at(*p) > r)
                .collect(),
        };
        let radii = match self.params.correction {
            ParticleCorrection::Curvature => {
                vec![self.params.particle_radius * h; self.particles.len()]
            }
            ParticleCorrection::Escaped => self.radii.clone(),
        };
        let ps = self.particles.clone();
        self.splat_particles(&ps, &radii, Some(&flags));
    }

    /// Sets each non-escaped particle's radius to its depth below the
    /// surface, clamped to `[0.1 h, r_max]` (Enright et al. 2002).
    pub(super) fn update_radii(&mut self) {
        let h = self.h;
        let rmax = self.params.particle_radius * h;
        let rmin = (0.1 * h).min(rmax);
        let phi = &self.phi;
        for (p, r) in self.particles.iter().zip(self.radii.iter_mut()) {
            let v = phi.value_at(*p);
            if v <= *r {
                *r = (-v).clamp(rmin, rmax);
            }
        }
    }

    /// Deletes particles deep inside and reseeds sparse near-surface cells (Foster & Fedkiw 2001, §5.4).
    pub(super) fn maintain_particles(&mut self) {
        let d = self.dims;
        let h = self.h;
        let band = self.params.delete_band * h;
        let phi = &self.phi;
        let keep: Vec<bool> = self
            .particles
            .iter()
            .map(|p| phi.value_at(*p) >= -band)
            .collect();
        let mut it = keep.iter();
        self.particles.retain(|_| *it.next().expect("same length"));
        let mut it = keep.iter();
        self.radii.retain(|_| *it.next().expect("same length"));
        let mut it = keep.iter();
        self.pvel.retain(|_| *it.next().expect("same length"));
        let mut count = vec![0u32; d.cells()];
        for p in &self.particles {
            let c: [usize; 3] = std::array::from_fn(|a| ((p[a] / h) as usize).min(d.n()[a] - 1));
            count[d.idx(c[0], c[1], c[2])] += 1;
        }
        let ppc = self.params.particles_per_cell;
        let rmax = self.params.particle_radius * h;
        let seed = Seed(self.params.seed)
            .derive("reseed")
            .derive_index(self.steps);
        for c in 0..d.cells() {
            let pc = self.phi.phi().as_slice()[c];
            if self.owner[c] != u16::MAX
                || !(pc < 0.0 && pc > -band)
                || (count[c] as usize) * 2 >= ppc
            {
                continue;
            }
            let ijk = d.ijk(c);
            for q in 0..ppc - count[c] as usize {
                let p = jitter(seed, c, q, ijk, d, h);
                if self.phi.value_at(p) < 0.0 {
                    self.particles.push(p);
                    self.radii.push(rmax);
                    self.pvel.push(Vec3::ZERO);
                }
            }
        }
        self.update_radii();
    }
}

/// A deterministic jittered position inside cell `ijk`.
pub(super) fn jitter(seed: Seed, c: usize, q: usize, ijk: [usize; 3], d: Dims, h: f32) -> Vec3 {
    let u = |axis: i64| seed.uniform3(c as i64, q as i64, axis) as f32;
    Vec3::from_array(std::array::from_fn(|a| {
        let t = if d.active(a) { u(a as i64) } else { 0.5 };
        (ijk[a] as f32 + t) * h
    }))
}
