//! Packet (frustum) skip for rays that share an origin: one conservative
//! walk over the max-mipmap for a whole packet of primary rays, which hands
//! every ray a start parameter below which it provably hits nothing.
//!
//! Primary rays of a screen tile leave one eye point in nearly the same
//! direction. From a camera near the ground toward the horizon, each ray
//! first climbs away from the terrain through empty space, one node at a time
//! and ascending one level per node (Tevs, Ihrke & Seidel 2008), before it
//! meets a node whose range holds its altitude; the rays of a tile all do
//! this over nearly the same nodes. The packet walk does it once for them
//! (the "beam" or "frustum" traversal of height fields: bound the packet, not
//! each ray).
//!
//! **The bound.** Let the packet's rays share the grid-space origin `o`
//! and have directions `dₗ`, horizontal length `hₗ = |(dₗ.x, dₗ.y)| > 0`.
//! At horizontal distance `s` from `o`, ray `l` is at
//! `o.xy + s·uₗ` (`uₗ = dₗ.xy / hₗ`), altitude `o.z + s·σₗ` (`σₗ = dₗ.z / hₗ`),
//! at parameter `t = s / hₗ`. Over a stretch `s ∈ [a, b]` every ray of the
//! packet lies in the axis-aligned box spanned by the `uₗ`'s extremes at `a`
//! and `b` (each ray's stretch is a segment between its two end points, and a
//! box holding all end points holds the segments), and no ray is lower than
//! `o.z + min(a·σ_min, b·σ_min)`. If that altitude, less a margin, is above
//! the maximum of every pyramid node meeting the box, no ray of the packet
//! touches the surface over the stretch: every triangle there lies below the
//! ray by more than the margin. The walk advances `s` node by node like the
//! single-ray walk (coarser after a skip, finer after a failure) and stops
//! at the first stretch it cannot prove empty at its finest level.
//!
//! **Why hits stay bit-identical.** Ray `l` then starts its walk at
//! `t_start = s / hₗ` (rounded down by far more than the arithmetic's
//! error), as if traced over `[max(t₀, t_start), t_max]`: nothing else of its
//! set-up changes (the rounding bounds, the shear and the hit acceptance
//! over the caller's `[t_min, t_max]` do not depend on where the walk starts;
//! see [`crate::grid_ray::GridRay`]). The walk from there visits, front to
//! back, every cell along the rest of the ray that its culls cannot rule
//! out, and runs the same exact, watertight triangle tests on them (their
//! results depend on the ray and the triangle alone). The cells before
//! `t_start` hold no hit: a triangle hit there would put the ray on the
//! surface where it is proven higher than every height by more than the
//! margin, which exceeds every rounding bound of the test (`GridRay::zm`
//! plus a quantum of the pyramid). So the nearest hit, and everything the
//! walk reports with it, is the same as from `t₀`, bit for bit; a ray whose
//! whole clipped range lies before `t_start` misses. The tests compare the
//! batch path with one [`crate::Tracer::trace`] per ray on grazing, top-down,
//! axis-parallel, random and strongly diverging packets, and with brute force.

use crate::grid_ray::{SETUP_LANES, SetupLanes, walk_start};
use crate::max_mipmap::MipmapTracer;

/// The finest level the packet walk steps at; below it the per-ray walks
/// take over.
const MIN_LEVEL: u32 = 1;
/// The level the packet walk starts at.
const START_LEVEL: u32 = 4;
/// Most pyramid nodes one packet step reads before it steps a level coarser.
const MAX_NODES: u32 = 12;
/// Most packet steps per packet.
const MAX_STEPS: u32 = 64;
/// Packets whose first ray crosses the field's height range within this
/// many cells of horizontal distance skip the packet walk.
const GATE: f32 = 256.0;
/// Packets whose horizontal directions spread more than this (the sum of
/// the ranges of their x and y components; a 32 × 32 tile of a 1080p view
/// spreads about 0.03) skip the packet walk.
const SPREAD: f64 = 0.15;
/// `t_start` is rounded down by this factor: far more than the `f64`
/// arithmetic's error and the rounding of `f32` conversion.
const SHRINK: f64 = 1.0 - 1e-5;

impl MipmapTracer<'_> {
    /// The horizontal distance from the packet's common origin up to which
    /// every `ok` ray among the first `lens[i]` lanes of `groups[i]` is
    /// proven above the surface, the proof starting at `from` (itself
    /// proven by an enclosing packet, or 0); `None` if the rays do not share
    /// one origin, one has no horizontal extent, or nothing is gained.
    ///
    /// The per-ray extents are computed in `f32` lanes (branch-free, so the
    /// loop vectorises) and widened by far more than their rounding error.
    #[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
    pub(crate) fn packet_bound(
        &self,
        groups: &[SetupLanes],
        lens: &[usize],
        from: f64,
    ) -> Option<f64> {
        let g0 = groups.first()?;
        let first = (0..lens[0]).find(|&l| g0.ok[l])?;
        let o = [g0.o[0][first], g0.o[1][first], g0.o[2][first]];
        // A steep packet crosses the field's height range within a short
        // horizontal distance: its rays' own walks are short, and the packet
        // walk would cost more than it saves. (A heuristic on the first ray:
        // whether the packet walk runs never changes a hit.)
        let (dx, dy, dz) = (g0.d[0][first], g0.d[1][first], g0.d[2][first]);
        let depth = self.f.zmax - self.f.zmin;
        if dz < 0.0 && depth * (dx * dx + dy * dy).sqrt() < -dz * GATE {
            return None;
        }
        // The same for the spread of directions, from the first and the
        // last ray: scattered pixels (a strided subset) are caught here.
        if let (Some(g), Some(&n)) = (groups.last(), lens.last()) {
            let l = n.max(1) - 1;
            let (ex, ey) = (g.d[0][l], g.d[1][l]);
            let he = (ex * ex + ey * ey).sqrt();
            let h0 = (dx * dx + dy * dy).sqrt();
            let dev = (ex / he - dx / h0).abs() + (ey / he - dy / h0).abs();
            if g.ok[l] && dev > SPREAD as f32 {
                return None;
            }
        }
        // Rays from different points (shadow rays, say) rarely share the
        // first and last lanes' origins: a cheap early exit before the
        // full check below.
        for (g, &n) in groups.iter().zip(lens) {
            for l in [0, n.max(1) - 1] {
                if g.ok[l] && [g.o[0][l], g.o[1][l], g.o[2][l]] != o {
                    return None;
                }
            }
        }
        let big = f32::MAX;
        // Per lane, over the groups: [min ux, −max ux, min uy, −max uy,
        // min slope, −max s_end, min s_start]; reduced over lanes once.
        let mut acc = [[big; SETUP_LANES]; 7];
        let mut zacc = [0.0f32; SETUP_LANES];
        let mut bacc = [0u32; SETUP_LANES];
        for (g, &n) in groups.iter().zip(lens) {
            for l in 0..SETUP_LANES {
                let on = g.ok[l] & (l < n);
                let (dx, dy, dz) = (g.d[0][l], g.d[1][l], g.d[2][l]);
                let h = (dx * dx + dy * dy).sqrt();
                let same = (g.o[0][l] == o[0]) & (g.o[1][l] == o[1]) & (g.o[2][l] == o[2]);
                // Not one origin, or a (nearly) vertical ray: no useful bound.
                bacc[l] |= u32::from(on & !(same & (h > 1e-20)));
                let r = 1.0 / h;
                let v = [
                    dx * r,
                    -(dx * r),
                    dy * r,
                    -(dy * r),
                    dz * r,
                    -(g.t1[l] * h),
                    g.t0[l] * h,
                ];
                for k in 0..7 {
                    acc[k][l] = crate::float::fmin(acc[k][l], if on { v[k] } else { big });
                }
                zacc[l] = crate::float::fmax(zacc[l], if on { g.zm[l] } else { 0.0 });
            }
        }
        let mut ext = [big; 7];
        let mut zm = 0.0f32;
        let mut bad = 0;
        for l in 0..SETUP_LANES {
            for k in 0..7 {
                ext[k] = crate::float::fmin(ext[k], acc[k][l]);
            }
            zm = crate::float::fmax(zm, zacc[l]);
            bad |= bacc[l];
        }
        // A ray whose range starts behind the origin (`t_min < 0`) is not
        // covered by distances `s ≥ 0`.
        if bad != 0 || ext[6] < 0.0 {
            return None;
        }
        // Widen by far more than the lanes' rounding (a few ulps each).
        const W: f64 = 1e-5;
        let x = |k: usize| f64::from(ext[k]);
        let u = [x(0) - W, -x(1) + W, x(2) - W, -x(3) + W];
        let slope = x(4) - W * (1.0 + x(4).abs());
        let s_end = -x(5) * (1.0 + W);
        let from = from.max(x(6) * (1.0 - W));
        // Strongly diverging rays (scattered pixels, very wide views) sweep
        // a box too wide to prove empty: the walk would cost more than it
        // saves.
        if (u[1] - u[0]) + (u[3] - u[2]) > SPREAD {
            return None;
        }
        let s = self.packet_walk(o, u, slope, f64::from(zm), from, s_end);
        (s > from).then_some(s)
    }

    /// Starts the walks of the `ok` rays among the first `lens[i]` lanes of
    /// `groups[i]` at horizontal distance `s` from their common origin
    /// (proven empty up to there by [`MipmapTracer::packet_bound`]): `t0`,
    /// the entry cell and the start level become what the set-up computes
    /// for the shorter range; rays whose whole range lies before `s` become
    /// misses (`ok` cleared). Branch-free over the lanes.
    #[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
    pub(crate) fn packet_skip(&self, groups: &mut [SetupLanes], lens: &[usize], s: f64) {
        let f = &self.f;
        let (cx, cy) = ((f.ncx - 1) as f32, (f.ncy - 1) as f32);
        let top = self.mip.top;
        // `t_start = s / h`, rounded down by far more than its rounding.
        let s = (s * SHRINK) as f32;
        for (g, &n) in groups.iter_mut().zip(lens) {
            for l in 0..SETUP_LANES {
                let (dx, dy) = (g.d[0][l], g.d[1][l]);
                let h = (dx * dx + dy * dy).sqrt();
                let ts = s / h;
                let (t0, t1) = (g.t0[l], g.t1[l]);
                let later = g.ok[l] & (l < n) & (ts > t0);
                // The entry cell and start level, as `setup_lanes` computes them.
                let tn = if later { ts } else { t0 };
                let (ci, cj, level) =
                    walk_start([g.o[0][l], g.o[1][l]], [dx, dy], tn, t1, [cx, cy], top);
                // A ray whose whole clipped range lies before `t_start` misses.
                g.ok[l] &= !(later & (ts > t1));
                g.t0[l] = tn;
                g.ci[l] = if later { ci } else { g.ci[l] };
                g.cj[l] = if later { cj } else { g.cj[l] };
                g.level[l] = if later { level } else { g.level[l] };
            }
        }
    }

    /// The packet walk: the largest horizontal distance `s` (from the
    /// packet's origin `o`, grid space) up to which the packet with
    /// horizontal directions within `u = [ux_min, ux_max, uy_min, uy_max]`,
    /// lowest climb `slope` (altitude per unit of horizontal distance) and
    /// altitude rounding bound `zm` is proven above the surface; 0 if none.
    /// `s_end` is where every ray has left the box.
    fn packet_walk(
        &self,
        o: [f32; 3],
        u: [f64; 4],
        slope: f64,
        zm: f64,
        from: f64,
        s_end: f64,
    ) -> f64 {
        let f = &self.f;
        let m = &self.mip;
        let (ox, oy, oz) = (f64::from(o[0]), f64::from(o[1]), f64::from(o[2]));
        let (lo, scale) = (f64::from(m.lo), f64::from(m.scale));
        // A quantum of the pyramid, the rays' altitude rounding bound and a
        // relative allowance for this walk's own arithmetic.
        let margin = zm + scale + 1e-9 * (oz.abs() + f64::from(f.zabs));
        // Lateral allowance: the rounding of the rays' positions and of the
        // box corners here, far above either.
        let pad = 1e-3 + 1e-9 * (ox.abs() + oy.abs());
        let (ncx, ncy) = (f.ncx, f.ncy);
        let top = m.top;
        let mut level = START_LEVEL.min(top).max(MIN_LEVEL.min(top));
        let mut s = from;
        for _ in 0..MAX_STEPS {
            if s >= s_end {
                break;
            }
            let b = s + f64::from(1u32 << level);
            let lowest = oz + (s * slope).min(b * slope) - margin;
            let xlo = ox + (s * u[0]).min(b * u[0]) - pad;
            let xhi = ox + (s * u[1]).max(b * u[1]) + pad;
            let ylo = oy + (s * u[2]).min(b * u[2]) - pad;
            let yhi = oy + (s * u[3]).max(b * u[3]) + pad;
            // Cells meeting the box (the point x = ncx is on cell ncx − 1).
            let empty = if xhi < 0.0 || yhi < 0.0 || xlo > f64::from(ncx) || ylo > f64::from(ncy) {
                // Outside the grid: no surface at all.
                true
            } else {
                let cell = |v: f64, n: u32| (v.max(0.0) as u32).min(n - 1);
                let (a0, a1) = (cell(xlo, ncx) >> level, cell(xhi, ncx) >> level);
                let (b0, b1) = (cell(ylo, ncy) >> level, cell(yhi, ncy) >> level);
                if u64::from(a1 - a0 + 1) * u64::from(b1 - b0 + 1) > u64::from(MAX_NODES)
                    && level < top
                {
                    level += 1;
                    continue;
                }
                let k = level as usize;
                let w = m.width[k] as usize;
                let base = m.offset[k];
                let mut qmax = 0u32;
                for bb in b0..=b1 {
                    let row = base + bb as usize * w;
                    for &q in &m.nodes[row + a0 as usize..=row + a1 as usize] {
                        qmax = qmax.max(q >> 16);
                    }
                }
                lo + f64::from(qmax) * scale < lowest
            };
            if empty {
                s = b;
                level = (level + 1).min(top);
            } else if level > MIN_LEVEL {
                level -= 1;
            } else {
                break;
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use natura_core::HeightField;

    use crate::grid_ray::{SETUP_LANES, SetupLanes};
    use crate::lockstep::kernels::setup_with;
    use crate::{MipmapTracer, Ray, brute_force};
    use natura_core::simd::Simd;

    /// Rolling terrain with a ridge across it.
    fn field(n: usize) -> HeightField {
        HeightField::from_fn(n, n, 10.0, |i, j| {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            40.0 * (9.0 * x).sin() * (7.0 * y).cos()
                + 15.0 * (31.0 * x + 17.0 * y).sin()
                + if (x - 0.7).abs() < 0.02 { 300.0 } else { 0.0 }
        })
        .unwrap()
    }

    /// The packet walk engages on grazing packets, and the start it hands
    /// each ray lies below the ray's brute-force first hit (rays it turns
    /// into misses have none): the skip is conservative and not vacuous.
    #[test]
    fn packet_starts_lie_before_every_hit() {
        let hf = field(257);
        let tr = MipmapTracer::new(&hf).unwrap();
        let e = hf.extent();
        let mut engaged = 0;
        let mut advanced = 0;
        for (k, (x, y, dz, fan)) in [
            (0.05, 0.1, -0.02, 0.06),
            (0.1, 0.5, -0.005, 0.05),
            (0.5, 0.05, 0.01, 0.02),
            (0.3, 0.3, -0.1, 0.08),
            (0.2, 0.2, -0.01, 0.01),
            // Too wide a fan: the packet walk declines.
            (0.9, 0.9, -0.01, 1.5),
        ]
        .into_iter()
        .enumerate()
        {
            let o = Vec3::new(
                x * e.x,
                y * e.y,
                hf.height_at(x * e.x, y * e.y).unwrap() + 30.0,
            );
            let base = Vec3::new(0.9 * e.x, 0.75 * e.y, 0.0) - Vec3::new(o.x, o.y, 0.0);
            let base = base.normalize();
            let mut groups = [SetupLanes::new(); 8];
            let mut rays = Vec::new();
            for (g, lanes) in groups.iter_mut().enumerate() {
                let mut batch = [Ray::new(o, Vec3::X); SETUP_LANES];
                for (l, r) in batch.iter_mut().enumerate() {
                    let a = fan * ((l as f32 / 15.0) - 0.5) + 0.001 * k as f32;
                    let d = Vec3::new(
                        base.x * a.cos() - base.y * a.sin(),
                        base.x * a.sin() + base.y * a.cos(),
                        dz - 0.003 * g as f32,
                    );
                    *r = Ray::new(o, d);
                }
                setup_with(
                    Simd::baseline(),
                    &tr.f,
                    &batch,
                    0.0,
                    f32::INFINITY,
                    tr.mip.top,
                    lanes,
                );
                rays.extend_from_slice(&batch);
            }
            let before = groups;
            let lens = [SETUP_LANES; 8];
            let Some(s) = tr.packet_bound(&groups, &lens, 0.0) else {
                continue;
            };
            engaged += 1;
            tr.packet_skip(&mut groups, &lens, s);
            for (i, r) in rays.iter().enumerate() {
                let (g, l) = (i / SETUP_LANES, i % SETUP_LANES);
                assert!(before[g].ok[l], "the test's rays meet the box");
                let want = brute_force(&hf, r, 0.0, f32::INFINITY).unwrap();
                if groups[g].ok[l] {
                    let t0 = groups[g].t0[l];
                    assert!(t0 >= before[g].t0[l]);
                    advanced += usize::from(t0 > before[g].t0[l]);
                    if let Some(h) = want {
                        assert!(
                            h.t >= t0,
                            "packet {k} ray {i}: hit {} before start {t0}",
                            h.t
                        );
                    }
                } else {
                    assert!(want.is_none(), "packet {k} ray {i}: skipped a hit");
                    advanced += 1;
                }
            }
        }
        assert!(engaged >= 3, "{engaged} packets engaged");
        assert!(advanced > 200, "{advanced} rays advanced");
    }
}
