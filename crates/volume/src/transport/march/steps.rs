//! The eye ray's steps: the march over a volume's extent (empty space
//! skipped, densities fetched in batches) and each step's exact integral of
//! the sources of [`FastRenderer`]'s light model (the step integrals
//! `step_inscatter` and `step_transmittance` of the transport's model).
//!
//! With [`FastSettings::substeps`](super::FastSettings::substeps) `n > 1`, each step's density is sampled
//! at the midpoints of its `n` equal parts, the source per unit density is
//! looked up once at the step's midpoint (every source is proportional to
//! the density there: `σ_s`, `σ_a` and the peak's `σ_t` all are), and the
//! parts are integrated one after another, each exactly for its own
//! extinction. This is the split of Hillaire 2016 (clouds chapter, the
//! march in the cloud: light sampled more coarsely than the density) and
//! of Schneider 2015 (§"Rendering": the detail's density is fetched at
//! every step, the light at fewer): the light is smooth on the scale of the
//! shadow tables' nodes and the cache's cells, the detail is not.
//!

use glam::Vec3;
use natura_core::Aabb;

use super::super::model::{emitted, step_inscatter, step_transmittance};
use super::{Along, EyeRay, FastRenderer};
use crate::density::fill_densities;

impl FastRenderer<'_> {
    /// Marches the eye ray over `[t0, t1]`: steps (uniform, or growing with
    /// the distance), empty space skipped over blocks of steps, densities
    /// fetched in batches, each sample added by [`Self::add_sample`] until
    /// the transmittance falls below the threshold.
    pub(super) fn march(&self, ray: &EyeRay, t0: f32, t1: f32, a: &mut Along) {
        let sc = self.scene;
        let (o, d) = (ray.o, ray.d);
        let h = self.settings.step;
        let growth = self.settings.step_growth;
        // With no growth, the steps divide [t0, t1] evenly (so a box is
        // crossed exactly); otherwise each grows with the distance from the eye.
        let uniform = {
            let n = ((t1 - t0) / h).ceil().max(1.0);
            (t1 - t0) / n
        };
        let step_at = |t: f32| {
            if growth > 0.0 {
                (h + growth * t).min(t1 - t)
            } else {
                uniform
            }
        };
        let skip = 8.0f32;
        const BATCH: usize = 16;
        let (mut xs, mut ys, mut zs) = ([0.0f32; BATCH], [0.0f32; BATCH], [0.0f32; BATCH]);
        let (mut steps, mut mids, mut rhos) = ([0.0f32; BATCH], [0.0f32; BATCH], [0.0f32; BATCH]);
        let mut t = t0;
        while t1 - t > 1e-6 * t1.abs().max(1.0) {
            // Empty space skipped: along the density's own runs where it
            // knows them (its steps then need no bound of their own), else
            // over blocks of steps.
            let mut bound_steps = sc.emission.is_none();
            let end = match sc
                .emission
                .is_none()
                .then(|| sc.density.clear_along(o, d, t, t1))
            {
                Some(Some((a, b))) => {
                    if a >= t1 {
                        return;
                    }
                    t = t.max(a);
                    bound_steps = false;
                    b
                }
                _ => {
                    let span = (step_at(t) * skip).min(t1 - t);
                    let (pa, pb) = (o + d * t, o + d * (t + span));
                    let block = Aabb {
                        min: pa.min(pb),
                        max: pa.max(pb),
                    };
                    if bound_steps && sc.density.bound_in(&block) <= 0.0 {
                        t += span;
                        continue;
                    }
                    t + span
                }
            };
            let open = |t: f32| end - t > 1e-6 * end.abs().max(1.0);
            let parts = self.settings.substeps as usize;
            if parts > 1 {
                // Whole steps, `BATCH / parts` at a time, each as its parts'
                // densities in one batch.
                let per = BATCH / parts;
                let mut centre = [0.0f32; BATCH];
                while open(t) {
                    let (mut c, mut n) = (0, 0);
                    while c < per && open(t) {
                        let dt = step_at(t).min(end - t);
                        // A step the density's bound finds empty costs no samples.
                        if bound_steps
                            && sc.density.bound_near(o + d * (t + 0.5 * dt), 0.5 * dt) <= 0.0
                        {
                            t += dt;
                            continue;
                        }
                        centre[c] = t + 0.5 * dt;
                        let h = dt / parts as f32;
                        for j in 0..parts {
                            let tm = t + (j as f32 + 0.5) * h;
                            let p = o + d * tm;
                            (steps[n], mids[n]) = (h, tm);
                            (xs[n], ys[n], zs[n]) = (p.x, p.y, p.z);
                            n += 1;
                        }
                        t += dt;
                        c += 1;
                    }
                    fill_densities(sc.density, &xs[..n], &ys[..n], &zs[..n], &mut rhos[..n]);
                    for k in 0..c {
                        let r = k * parts..(k + 1) * parts;
                        if self.add_parts(
                            ray,
                            centre[k],
                            &mids[r.clone()],
                            steps[k * parts],
                            &rhos[r],
                            a,
                        ) {
                            return;
                        }
                    }
                }
                t = t.max(end);
                continue;
            }
            while open(t) {
                // The block's next steps, their densities in one batch.
                let mut n = 0;
                while n < BATCH && open(t) {
                    let dt = step_at(t).min(end - t);
                    let tm = t + 0.5 * dt;
                    t += dt;
                    let p = o + d * tm;
                    (steps[n], mids[n]) = (dt, tm);
                    (xs[n], ys[n], zs[n]) = (p.x, p.y, p.z);
                    n += 1;
                }
                fill_densities(sc.density, &xs[..n], &ys[..n], &zs[..n], &mut rhos[..n]);
                for i in 0..n {
                    if self.add_sample(ray, mids[i], steps[i], rhos[i], a) {
                        return;
                    }
                }
            }
            t = t.max(end);
        }
    }

    /// Adds a step centred at `tc` along the eye ray in parts of length `h`
    /// centred at `tms`, of densities `rhos`, to the sums `a`: the source
    /// per unit density looked up once at `tc`, each part integrated exactly
    /// (see the module docs); true once the march is to stop.
    fn add_parts(
        &self,
        ray: &EyeRay,
        tc: f32,
        tms: &[f32],
        h: f32,
        rhos: &[f32],
        a: &mut Along,
    ) -> bool {
        let sc = self.scene;
        let (m0, m) = (&sc.medium, &self.medium);
        let p = ray.o + ray.d * tc;
        let le = sc.emission.map_or(Vec3::ZERO, |e| {
            emitted(e.colour, e.field.density(p), e.offset)
        });
        if le == Vec3::ZERO && rhos.iter().all(|&r| r <= 0.0) {
            return false;
        }
        // Every source is proportional to the density: those of density 1.
        let (src, src0) = self.sources(ray, p, m.extinction, m0.extinction, le, a.tau_eye0);
        for (&rho, &tm) in rhos.iter().zip(tms) {
            if rho > 0.0 && self.add_step(tm, h, rho, src * rho, src0 * rho, a) {
                return true;
            }
        }
        false
    }

    /// Adds the step of length `dt` centred at `tm` along the eye ray, of
    /// density `rho`, to the sums `a`; true once the march is to stop (the
    /// transmittance below the threshold, then set to 0).
    #[inline]
    fn add_sample(&self, ray: &EyeRay, tm: f32, dt: f32, rho: f32, a: &mut Along) -> bool {
        let sc = self.scene;
        let (m0, m) = (&sc.medium, &self.medium);
        let p = ray.o + ray.d * tm;
        let le = sc.emission.map_or(Vec3::ZERO, |e| {
            emitted(e.colour, e.field.density(p), e.offset)
        });
        if rho <= 0.0 && le == Vec3::ZERO {
            return false;
        }
        let (src, src0) = self.sources(
            ray,
            p,
            m.extinction * rho,
            m0.extinction * rho,
            le,
            a.tau_eye0,
        );
        self.add_step(tm, dt, rho, src, src0, a)
    }

    /// Adds the step of length `dt` centred at `tm`, of density `rho` and
    /// sources `src` (transport medium) and `src0` (the peak's, exact
    /// medium), to the sums `a`; true once the march is to stop (the
    /// transmittance below the threshold, then set to 0).
    #[inline]
    fn add_step(&self, tm: f32, dt: f32, rho: f32, src: Vec3, src0: Vec3, a: &mut Along) -> bool {
        let (m0, m) = (&self.scene.medium, &self.medium);
        let truncated = self.peak.is_some();
        let sigma_t = m.extinction * rho;
        let sigma_t0 = m0.extinction * rho;
        let add = if truncated {
            step_inscatter(src, sigma_t, dt) * a.tr + step_inscatter(src0, sigma_t0, dt) * a.tr0
        } else {
            step_inscatter(src + src0, sigma_t, dt) * a.tr
        };
        a.l += add;
        let w = add.element_sum();
        a.depth_w += w;
        a.depth_sum += w * tm;
        a.tr *= step_transmittance(sigma_t, dt);
        a.tau_eye0 += sigma_t0 * dt;
        a.tr0 = if truncated {
            a.tr0 * step_transmittance(sigma_t0, dt)
        } else {
            a.tr
        };
        if a.tr < self.settings.min_transmittance {
            a.tr = 0.0;
            return true;
        }
        false
    }
}
