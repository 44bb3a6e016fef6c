//! Where a pixel's samples go, and when a pixel takes more of them.
//!
//! Every pixel takes its `spp` base samples, stratified over the pixel
//! ([`sample_position`]). Where they disagree — a silhouette against a far
//! brighter sky, sunlit needles among shade — four samples count a quarter
//! of the bright part or none of it, and a pixel on a ridge whose sky
//! covers a few per cent shows as a speck four times brighter than its
//! neighbours. Such a pixel takes more samples, up to the scene's
//! `render.adaptive_samples` in all, and averages them with its base ones
//! (adaptive supersampling, Mitchell 1987: refine where the contrast
//! of the first samples exceeds a threshold). A pixel whose samples agree
//! keeps its base samples only, so it equals the render without the
//! refinement bit for bit.

use glam::Vec2;
use natura_core::colour::luminance;

/// When a pixel's base samples disagree, and how many samples it then takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Adaptive {
    /// Samples a pixel whose base samples disagree takes in all; the base
    /// count when refinement is off.
    total: u32,
    /// The contrast above which the base samples disagree.
    contrast: f32,
    /// Luminance added to the contrast's denominator: differences among
    /// samples this dark or darker show as black and do not count.
    floor: f32,
    /// Luminance at which a sample shows as white: brighter samples are
    /// clamped to it, so a sun glint among bright sky is no contrast.
    ceiling: f32,
}

/// The black level of the contrast test, in units of the white surface's
/// luminance under the sun and the sky: about what an automatic exposure
/// shows as the darkest step of an 8-bit picture.
const FLOOR_OF_WHITE: f32 = 1.0 / 256.0;

/// The white level of the contrast test, in units of the white surface's
/// luminance: an automatic exposure maps a landscape's log-average to mid
/// grey, and the filmic tone map shows about twice a lit white surface as
/// white.
const CEILING_OF_WHITE: f32 = 2.0;

impl Adaptive {
    /// Pixels of `spp` base samples whose contrast exceeds `contrast` take
    /// `total` samples in all; `white` is the luminance of a white
    /// Lambertian surface in the scene's sun and sky, which sets the test's
    /// black and white levels. Off (`total` becomes `spp`) when `total ≤
    /// spp` or `spp < 2`: one sample has nothing to disagree with.
    pub(crate) fn new(spp: u32, total: u32, contrast: f32, white: f32) -> Self {
        let white = if white.is_finite() && white > 0.0 {
            white
        } else {
            1.0
        };
        Self {
            total: if spp >= 2 && total > spp { total } else { spp },
            contrast,
            floor: FLOOR_OF_WHITE * white,
            ceiling: CEILING_OF_WHITE * white,
        }
    }

    /// The samples a pixel whose base samples disagree takes in all.
    pub(crate) fn total(&self) -> u32 {
        self.total
    }

    /// Whether the base samples' radiances `base` disagree: the contrast
    /// `(max − min) / (max + min + floor)` of their luminances, each
    /// clamped to `[0, ceiling]`, exceeds the threshold (Mitchell 1987's
    /// contrast, with a black level). Never when refinement is off.
    pub(crate) fn disagree(&self, base: &[glam::Vec3]) -> bool {
        self.total as usize > base.len() && self.contrast_exceeds(base.iter().copied())
    }

    fn contrast_exceeds(&self, samples: impl Iterator<Item = glam::Vec3>) -> bool {
        let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
        for c in samples {
            // `min` before `max` sends a NaN to the ceiling.
            let l = luminance(c).min(self.ceiling).max(0.0);
            lo = lo.min(l);
            hi = hi.max(l);
        }
        hi - lo > self.contrast * (hi + lo + self.floor)
    }
}

/// Sample `s` of a pixel that takes `total` samples, the first `n` of them
/// its base samples: for `s < n`, [`sample_position`] of `n` (so a pixel
/// that takes no more samples has today's pattern); beyond, the refinement's
/// samples. When `n = k²` and `total = n·m²` they fill the finer `km × km`
/// grid: each base sample's cell of the `k × k` grid is split `m × m`, the
/// base sample keeps the sub-cell it falls in and the others take one each,
/// so all `total` samples are one jittered grid. Otherwise the `total − n`
/// further samples are a stratified set of their own
/// ([`sample_position`] of `total − n`). `jitter(s)` is sample `s`'s
/// jitter in `[0, 1)²`; `shuffle(k)` a hash of the pixel and `k`.
pub(crate) fn refined_position(
    s: u32,
    n: u32,
    total: u32,
    jitter: impl Fn(u32) -> (f32, f32),
    shuffle: impl Fn(i64) -> u64,
) -> Vec2 {
    if s < n {
        return sample_position(s, n, jitter(s), || shuffle(-1));
    }
    let e = s - n;
    let k = n.isqrt();
    let m = (total / n.max(1)).isqrt();
    if n >= 2 && k * k == n && m >= 2 && n * m * m == total {
        // Base sample b's cell, and the sub-cell its jitter put it in.
        let per = m * m - 1;
        let b = e / per;
        let sub = |j: f32| ((j * m as f32) as u32).min(m - 1);
        let (bj, j) = (jitter(b), e % per);
        let taken = sub(bj.0) + sub(bj.1) * m;
        let q = if j < taken { j } else { j + 1 };
        let (cx, cy) = ((b % k) * m + q % m, (b / k) * m + q / m);
        let (jx, jy) = jitter(s);
        let side = (k * m) as f32;
        return Vec2::new(
            below_one((cx as f32 + jx) / side),
            below_one((cy as f32 + jy) / side),
        );
    }
    sample_position(e, total - n, jitter(s), || shuffle(-2))
}

/// `v`, or the largest `f32` below 1 if `v` rounded up to 1 or beyond.
fn below_one(v: f32) -> f32 {
    v.min(1.0 - f32::EPSILON)
}

/// Sample `s` of `n` in the unit pixel, jittered by `jitter ∈ [0, 1)²`:
/// the centre for one sample; for a square count `n = k²`, stratum
/// `(s mod k, s div k)` of a `k × k` grid; for any other count, a Latin
/// hypercube ("n-rooks", Shirley 1991; Pharr et al. 2023, §8.5): the x
/// stratum `s` and the y stratum `(a·s + b) mod n` of `n` each, with `a`
/// coprime to `n` and `b` drawn per pixel from the hash `shuffle` (asked
/// for only then), so every row and
/// every column of strata holds one sample. (A `⌈√n⌉²` grid filled in
/// order would leave its last rows empty: with 2 samples both fell in the
/// pixel's top half.)
pub(crate) fn sample_position(
    s: u32,
    n: u32,
    jitter: (f32, f32),
    shuffle: impl FnOnce() -> u64,
) -> Vec2 {
    let (jx, jy) = jitter;
    if n <= 1 {
        return Vec2::splat(0.5);
    }
    let side = (n as f32).sqrt().round() as u32;
    if side * side == n {
        let (sx, sy) = ((s % side) as f32, (s / side) as f32);
        return Vec2::new((sx + jx) / side as f32, below_one((sy + jy) / side as f32));
    }
    let gcd = |mut a: u64, mut b: u64| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    let (n64, shuffle) = (u64::from(n), shuffle());
    let mut a = 1 + (shuffle >> 32) % (n64 - 1);
    while gcd(a, n64) != 1 {
        a = a % (n64 - 1) + 1;
    }
    let b = (shuffle & 0xFFFF_FFFF) % n64;
    let row = (a * u64::from(s % n) + b) % n64;
    Vec2::new(
        below_one((s as f32 + jx) / n as f32),
        below_one((row as f32 + jy) / n as f32),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Every count's samples are stratified: for a square count one in
    /// each cell of the grid, for any other one in each row and each
    /// column of `n` strata; all inside the pixel.
    #[test]
    fn samples_fill_the_pixel_for_every_count() {
        for n in 1..=40u32 {
            for pixel in 0..20u64 {
                let shuffle = pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x1234_5678;
                let pts: Vec<_> = (0..n)
                    .map(|s| {
                        // Jitters away from the strata's edges, where
                        // rounding could move a point across one.
                        let j = (
                            (((s * 7 + 3) % 11) as f32 + 0.5) / 12.0,
                            (((s * 5 + 1) % 13) as f32 + 0.5) / 14.0,
                        );
                        sample_position(s, n, j, || shuffle.wrapping_add(u64::from(pixel as u32)))
                    })
                    .collect();
                assert!(
                    pts.iter()
                        .all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y))
                );
                let side = (n as f32).sqrt().round() as u32;
                let (cols, rows) = if side * side == n {
                    (side, side)
                } else {
                    (n, n)
                };
                let mut seen_x = vec![0; cols as usize];
                let mut seen_y = vec![0; rows as usize];
                for p in &pts {
                    seen_x[(p.x * cols as f32) as usize] += 1;
                    seen_y[(p.y * rows as f32) as usize] += 1;
                }
                let per = n / cols;
                assert!(
                    seen_x.iter().all(|&c| c == per),
                    "n {n}: columns {seen_x:?}"
                );
                assert!(seen_y.iter().all(|&c| c == per), "n {n}: rows {seen_y:?}");
            }
        }
        // Two samples: one in each half of the pixel, top and bottom.
        let two: Vec<_> = (0..2)
            .map(|s| sample_position(s, 2, (0.5, 0.5), || 99))
            .collect();
        assert!(two.iter().any(|p| p.y < 0.5) && two.iter().any(|p| p.y >= 0.5));
    }

    /// A pseudo-random jitter per sample, as the renderer's hash gives.
    fn jitter(pixel: u64) -> impl Fn(u32) -> (f32, f32) {
        move |s| {
            let h = natura_core::mix64(pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ u64::from(s));
            let g = natura_core::mix64(h ^ 0x5555);
            (
                natura_core::unit_f64(h) as f32,
                natura_core::unit_f64(g) as f32,
            )
        }
    }

    /// The base samples are [`sample_position`]'s; with `n·m²` samples in
    /// all they fill the finer grid, one in each cell; with other counts the
    /// further samples fill the pixel by rows and columns of their own.
    #[test]
    fn refined_samples_keep_the_base_pattern_and_fill_the_pixel() {
        for (n, total) in [(4, 16), (4, 64), (9, 36), (1, 16), (4, 13), (2, 8), (3, 12)] {
            for pixel in 0..50u64 {
                let j = jitter(pixel);
                let shuffle = |k: i64| pixel ^ (k as u64).wrapping_mul(0xABCD_EF01);
                let pts: Vec<Vec2> = (0..total)
                    .map(|s| refined_position(s, n, total, &j, shuffle))
                    .collect();
                for s in 0..n {
                    assert_eq!(pts[s as usize], sample_position(s, n, j(s), || shuffle(-1)));
                }
                assert!(
                    pts.iter()
                        .all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y))
                );
                let (k, m) = (n.isqrt(), (total / n).isqrt());
                if n >= 2 && k * k == n && n * m * m == total {
                    let side = (k * m) as f32;
                    let mut seen = vec![0; total as usize];
                    for p in &pts {
                        seen[(p.x * side) as usize + (p.y * side) as usize * (k * m) as usize] += 1;
                    }
                    assert!(seen.iter().all(|&c| c == 1), "{n} of {total}: {seen:?}");
                } else {
                    let rest = total - n;
                    let mut rows = vec![0; rest as usize];
                    for p in &pts[n as usize..] {
                        rows[(p.y * rest as f32) as usize] += 1;
                    }
                    let side = rest.isqrt();
                    if side * side != rest {
                        assert!(rows.iter().all(|&c| c == 1), "{n} of {total}: {rows:?}");
                    }
                }
            }
        }
    }

    /// A pixel straddling a sharp edge (a sky 20 times brighter than a
    /// ridge over a fraction `a ≤ ¼` of it, along its top as a crest seen
    /// side on) converges to the coverage with the refinement: four samples
    /// count a quarter of the sky or none, 64 in a jittered 8 × 8 grid
    /// count it within a row of the grid; a flat pixel takes only its base
    /// samples.
    #[test]
    fn an_edge_pixel_converges_to_its_coverage_and_a_flat_one_is_not_refined() {
        let (ridge, sky) = (Vec3::splat(0.05), Vec3::splat(1.0));
        let adaptive = Adaptive::new(4, 64, 0.25, 1.0);
        // The pixel with refinement, the samples it took, and its base
        // samples' mean.
        let render = |pixel: u64, edge: f32| {
            let j = jitter(pixel);
            let shade = |p: Vec2| if p.y < edge { sky } else { ridge };
            let base: Vec<Vec3> = (0..4)
                .map(|s| shade(refined_position(s, 4, 64, &j, |_| 0)))
                .collect();
            let mut sum = base.iter().copied().sum::<Vec3>();
            let plain = sum / 4.0;
            if !adaptive.disagree(&base) {
                return (plain, 4, plain);
            }
            for s in 4..64 {
                sum += shade(refined_position(s, 4, 64, &j, |_| 0));
            }
            (sum / 64.0, 64, plain)
        };
        let contrast = sky.x - ridge.x;
        let (mut over, mut over_plain, mut sq, mut refined) = (0.0f32, 0.0f32, 0.0f32, 0);
        let pixels = 400;
        for pixel in 0..pixels {
            let a = 0.01 + 0.24 * (pixel as f32 / pixels as f32);
            let truth = a * sky.x + (1.0 - a) * ridge.x;
            let (got, taken, plain) = render(pixel, a);
            // How much brighter than its coverage the pixel shows.
            over = over.max((got.x - truth) / contrast);
            over_plain = over_plain.max((plain.x - truth) / contrast);
            if taken == 64 {
                refined += 1;
                sq += ((got.x - truth) / contrast).powi(2);
            } else {
                // Not refined: every base sample saw the ridge.
                assert!((got.x - ridge.x).abs() < 1e-6, "{got}");
            }
        }
        let rms = (sq / refined as f32).sqrt();
        assert!(refined > pixels / 4, "{refined} of {pixels} refined");
        // Four samples alone: a pixel with a sliver of sky counts a quarter.
        assert!(over_plain > 0.2, "{over_plain}");
        // Refined: within one row of the 8 × 8 grid, and close on average.
        assert!(over <= 1.0 / 8.0 + 1e-6, "worst excess {over}");
        assert!(rms < 0.035, "rms error {rms} of the contrast");
        // Flat pixels, at every brightness, take only their base samples.
        for pixel in 0..100u64 {
            let level = 10f32.powf(-3.0 + 4.0 * pixel as f32 / 100.0);
            let (got, taken, _) = render(pixel, -1.0);
            assert_eq!((got.x, taken), (ridge.x, 4));
            let flat = vec![Vec3::splat(level); 4];
            assert!(!adaptive.disagree(&flat));
        }
        // Off: never refined, however strong the contrast.
        let off = Adaptive::new(4, 4, 0.25, 1.0);
        assert!(!off.disagree(&[ridge, ridge, ridge, sky]));
        assert!(adaptive.disagree(&[ridge, ridge, ridge, sky]));
        // Black differences and glints among bright sky are no contrast.
        assert!(!adaptive.disagree(&[Vec3::ZERO, Vec3::splat(1e-4), Vec3::ZERO, Vec3::ZERO]));
        assert!(!adaptive.disagree(&[Vec3::splat(50.0), Vec3::splat(2.5), sky * 2.5, sky * 3.0]));
    }
}
