//! Empty space along a ray through a [`GridDensity`]: the 3-D DDA of
//! Amanatides & Woo 1987 over the fine majorant blocks, which finds the
//! next run of blocks the density may fill in one walk, where bounding a
//! march's steps box by box reads several blocks per step.

use glam::Vec3;
use natura_core::{Aabb, floor_f32};

use super::{FINE, GridDensity};
use crate::density::ray_box;

/// What a run's ends are widened by, in fine blocks: the walk's crossings
/// accumulate rounding, and a run must cover every point of its blocks.
const MARGIN: f32 = 1e-3;

impl GridDensity {
    /// See [`Density::clear_along`](crate::density::Density::clear_along):
    /// the first run of fine blocks with a positive majorant that the ray
    /// crosses in `[t, t_max]`, each end widened by a thousandth of a block.
    pub(super) fn clear_run(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> (f32, f32) {
        let none = (t_max, t_max);
        let edge = self.cell * FINE as f32;
        let (fx, fy, fz) = self.fine.dims();
        let dims = [fx, fy, fz];
        let bounds = Aabb {
            min: self.origin,
            max: self.origin + Vec3::new(fx as f32, fy as f32, fz as f32) * edge,
        };
        let inv = d.recip();
        let Some((t0, t1)) = ray_box(o, inv, &bounds) else {
            return none;
        };
        let (mut at, end) = (t0.max(t), t1.min(t_max));
        if at >= end {
            return none;
        }
        let p = (o + d * at - self.origin) / edge;
        let mut c = [0i64; 3];
        let mut step = [0i64; 3];
        let mut next = [f32::INFINITY; 3];
        // Where the ray crosses the plane that ends block `k` along axis
        // `a`, from the ray's origin each time (not a running sum of steps,
        // whose rounding grows with the number of blocks crossed).
        let crossing = |a: usize, k: i64, s: i64| -> f32 {
            let plane = self.origin[a] + (k + i64::from(s > 0)) as f32 * edge;
            (plane - o[a]) * inv[a]
        };
        for a in 0..3 {
            let n = dims[a] as i64;
            c[a] = (floor_f32(p[a]) as i64).clamp(0, n - 1);
            if d[a] != 0.0 {
                step[a] = if d[a] > 0.0 { 1 } else { -1 };
                next[a] = crossing(a, c[a], step[a]);
            }
        }
        // The margin covers the crossings' rounding, a few units in the
        // last place of the distance.
        let margin = MARGIN * edge + 1e-5 * end.abs();
        let mut run: Option<f32> = None;
        loop {
            let full = *self
                .fine
                .get(c[0] as usize, c[1] as usize, c[2] as usize)
                .unwrap_or(&self.max)
                > 0.0;
            match (run, full) {
                (None, true) => run = Some((at - margin).max(t)),
                (Some(a), false) => return (a, (at + margin).min(t_max)),
                _ => {}
            }
            let a = if next[0] <= next[1] && next[0] <= next[2] {
                0
            } else if next[1] <= next[2] {
                1
            } else {
                2
            };
            at = next[a].max(at);
            c[a] += step[a];
            if at >= end || c[a] < 0 || c[a] >= dims[a] as i64 {
                break;
            }
            next[a] = crossing(a, c[a], step[a]);
        }
        match run {
            Some(a) => (a, (end + margin).min(t_max)),
            None => none,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::density::Density;
    use natura_core::{Grid3, Seed};

    /// A grid of 40 × 30 × 12 voxels of 25 m, mostly empty: a few voxels
    /// of density here and there.
    fn sparse() -> GridDensity {
        let mut rng = Seed(3).rng();
        let mut v = vec![0.0f32; 40 * 30 * 12];
        for _ in 0..60 {
            let n = v.len();
            let i = (crate::animate::unit(&mut rng) * n as f32) as usize;
            v[i.min(n - 1)] = 1.0;
        }
        let g = Grid3::from_fn(40, 30, 12, |x, y, z| v[(z * 30 + y) * 40 + x]).unwrap();
        GridDensity::new(g, Vec3::new(-300.0, 100.0, 1000.0), 25.0).unwrap()
    }

    /// The runs of the ray from `o` along `d` over `[0, t_max]`, walked as
    /// a march walks them, and the length skipped.
    fn runs(g: &GridDensity, o: Vec3, d: Vec3, t_max: f32) -> (Vec<(f32, f32)>, f32) {
        let (mut runs, mut skipped, mut t) = (Vec::new(), 0.0, 0.0);
        while t < t_max {
            let (a, e) = g.clear_along(o, d, t, t_max).unwrap();
            assert!(t <= a && a <= e && e <= t_max, "{t} {a} {e} {t_max}");
            skipped += a - t;
            if a >= t_max {
                break;
            }
            assert!(e > a);
            runs.push((a, e));
            t = e;
        }
        (runs, skipped)
    }

    #[test]
    fn runs_hold_along_rays_tens_of_kilometres_long() {
        // A row of 720 voxels of 50 m (36 km) with a voxel of density every
        // few kilometres, crossed lengthwise from outside: 360 blocks, and
        // distances where a unit in the last place is 2–4 mm.
        let g = Grid3::from_fn(720, 4, 4, |x, y, z| {
            f32::from(u8::from(x % 97 == 41 && y == 1 && z == 2))
        })
        .unwrap();
        let g = GridDensity::new(g, Vec3::new(-18_000.0, 100.0, 1200.0), 50.0).unwrap();
        let mut rng = Seed(2).rng();
        let mut u = || crate::animate::unit(&mut rng);
        let mut hits = 0;
        for _ in 0..40 {
            let o = Vec3::new(-18_500.0, 150.0 + 40.0 * u(), 1300.0 + 40.0 * u());
            let d = Vec3::new(1.0, (u() - 0.5) * 2e-3, (u() - 0.5) * 2e-3).normalize();
            let (runs, _) = runs(&g, o, d, 40_000.0);
            let mut s = 0.0f32;
            while s < 40_000.0 {
                let p = o + d * s;
                if g.density(p) > 0.0 {
                    hits += 1;
                    assert!(
                        runs.iter().any(|&(a, e)| a <= s && s < e),
                        "density at {s} outside the runs {runs:?}"
                    );
                }
                s += 0.25;
            }
        }
        assert!(hits > 10_000, "{hits}");
    }

    #[test]
    fn every_point_of_density_lies_in_a_run_and_the_runs_skip_space() {
        // Rays from outside and inside the grid, in every direction, axis
        // parallel ones among them; the density sampled every 5 cm.
        let g = sparse();
        let b = g.bounds();
        let mut rng = Seed(9).rng();
        let mut u = || crate::animate::unit(&mut rng);
        let (mut skipped, mut total) = (0.0f64, 0.0f64);
        for k in 0..300 {
            let o =
                b.min + (b.max - b.min) * Vec3::new(u(), u(), u()) * 1.4 - (b.max - b.min) * 0.2;
            let d = match k % 10 {
                0 => Vec3::X,
                1 => -Vec3::Z,
                _ => Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize(),
            };
            let t_max = 900.0 * u();
            let (runs, skip) = runs(&g, o, d, t_max);
            skipped += f64::from(skip);
            total += f64::from(t_max);
            // (The grid's samples are zero outside its bounds.)
            let mut s = 0.0f32;
            while s < t_max {
                let p = o + d * s;
                if g.density(p) > 0.0 {
                    assert!(
                        runs.iter().any(|&(a, e)| a <= s && s < e),
                        "ray {k}: density at {s} outside the runs {runs:?}"
                    );
                }
                s += 0.05;
            }
        }
        // Mostly empty: most of the length is skipped.
        assert!(skipped > 0.5 * total, "{skipped} of {total}");
    }
}
