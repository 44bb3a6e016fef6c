//! Musgrave 2001, fig. 32 for `figures_musgrave`: "A multifractal texture
//! as a model of the Milky Way": a glowing band of stars crossed by dark
//! dust lanes whose optical depth is natura-noise's multiplicative
//! multifractal cascade.

use natura::core::glam::{DVec2, DVec3};
use natura::core::{Image, Seed};
use natura::noise::{Fbm, Field, Multifractal, MultifractalParams, Perlin, Spectral};

use crate::common::Exit;
use crate::landscape::supersampled;

type R<T> = Result<T, Exit>;

/// The dust: the cascade with offset 0.55 (spiky: its values span orders
/// of magnitude), H = 0.25, 7 octaves, λ = 2 (the figure's are not given).
pub(crate) fn dust(seed: u64) -> R<Multifractal<Perlin>> {
    Ok(Multifractal::new(
        Perlin::new(seed),
        MultifractalParams {
            spectral: Spectral {
                h: 0.25,
                lacunarity: 2.0,
                octaves: 7.0,
                frequency: 3.0,
                ..Spectral::default()
            },
            offset: 0.55,
            ..MultifractalParams::default()
        },
    )?)
}

/// A star of the picture: where it is, in pixels, and its image's peak.
#[derive(Debug, Clone, Copy)]
struct Star {
    at: DVec2,
    peak: f64,
}

/// The faintest star the picture records (its image's peak, linear).
const FAINTEST: f64 = 0.015;
/// The brightest (it saturates and spreads as a bright star does).
const BRIGHTEST: f64 = 3.0;
/// The seeing disc's standard deviation, pixels.
const SEEING_PX: f64 = 0.75;
/// Candidate stars per pixel, before the band's concentration thins them.
const STARS_PER_PIXEL: f64 = 0.012;

/// Stars over a `w × h` picture: uniform positions, their number per area
/// following the band's concentration `density(p)` (a share in `[0, 1]`
/// of the candidates kept, `p` in picture-height units), and their
/// brightness drawn from the counts of a uniform population in Euclidean
/// space, N(> S) ∝ S^(−3/2) (the classic log N–log S law), from
/// [`FAINTEST`] up, capped at [`BRIGHTEST`].
fn star_catalogue(seed: u64, w: u32, h: u32, density: impl Fn(DVec2) -> f64) -> Vec<Star> {
    let s = Seed(seed).derive("milky way stars");
    let n = (f64::from(w) * f64::from(h) * STARS_PER_PIXEL).round() as i64;
    (0..n)
        .filter_map(|k| {
            let at = DVec2::new(
                s.uniform2(k, 0) * f64::from(w),
                s.uniform2(k, 1) * f64::from(h),
            );
            if s.uniform2(k, 2) >= density(at / f64::from(h)) {
                return None;
            }
            // u in (0, 1]: S = S_min · u^(−2/3) inverts N(> S) ∝ S^(−3/2).
            let u = 1.0 - s.uniform2(k, 3);
            let peak = (FAINTEST * u.powf(-2.0 / 3.0)).min(BRIGHTEST);
            Some(Star { at, peak })
        })
        .collect()
}

/// The stars in square buckets `cell` pixels wide (`cols × rows`), for
/// [`StarGrid::light`].
struct StarGrid {
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<Star>>,
}

impl StarGrid {
    fn new(stars: &[Star], w: u32, h: u32) -> Self {
        // Buckets as wide as the disc's reach (3 σ), so a sample sees the
        // 3 × 3 buckets about its own.
        let cell = 3.0 * SEEING_PX;
        let cols = (f64::from(w) / cell).ceil() as usize;
        let rows = (f64::from(h) / cell).ceil() as usize;
        let mut buckets = vec![Vec::new(); cols * rows];
        for st in stars {
            let (i, j) = ((st.at.x / cell) as usize, (st.at.y / cell) as usize);
            buckets[j.min(rows - 1) * cols + i.min(cols - 1)].push(*st);
        }
        StarGrid {
            cell,
            cols,
            rows,
            buckets,
        }
    }

    /// The stars' light at pixel position `q`: each star's seeing disc, a
    /// Gaussian of σ = [`SEEING_PX`], summed over the 3 × 3 buckets about
    /// `q`'s own.
    fn light(&self, q: DVec2) -> f64 {
        let (ci, cj) = ((q.x / self.cell) as isize, (q.y / self.cell) as isize);
        let mut sum = 0.0;
        for j in cj - 1..=cj + 1 {
            for i in ci - 1..=ci + 1 {
                if i < 0 || j < 0 || i as usize >= self.cols || j as usize >= self.rows {
                    continue;
                }
                for st in &self.buckets[j as usize * self.cols + i as usize] {
                    let r2 = (q - st.at).length_squared();
                    sum += st.peak * (-0.5 * r2 / (SEEING_PX * SEEING_PX)).exp();
                }
            }
        }
        sum
    }
}

/// Fig. 32: stars and the band's diffuse glow (a Gaussian across the band
/// times fBm), seen through the dust where the band is. The stars gather
/// toward the band's plane (5.6 times as many a pixel at its middle as
/// far from it), their counts by brightness follow the log N–log S
/// law, and each is drawn as the seeing disc the air and the lens spread a
/// point into: 1.8 pixels across at half its peak, as in a wide-field
/// photograph of the sky.
pub(crate) fn milky_way_picture(seed: u64, quick: bool) -> R<Image> {
    let (w, h) = if quick { (240u32, 120u32) } else { (1200, 600) };
    let dust = dust(seed)?;
    let glow = Fbm::new(
        Perlin::new(seed ^ 0x32),
        Spectral {
            octaves: 6.0,
            frequency: 2.0,
            ..Spectral::default()
        },
    )?;
    // The cascade's values span orders of magnitude: scaled by its 90th
    // percentile over the picture, an optical depth of 1.2 there.
    let (s, c) = 12f64.to_radians().sin_cos();
    // Across and along the band (x along, tilted by 12°; unit height).
    let frame = |p: DVec2| {
        let q = p - DVec2::new(1.0, 0.5);
        (q.y * c - q.x * s, q.x * c + q.y * s)
    };
    let band_at = |p: DVec2| (-(frame(p).0 / 0.16).powi(2)).exp();
    // Dust lanes drawn out along the band: its domain stretched 3:1.
    let dust_at = |p: DVec2| {
        let (across, along) = frame(p);
        dust.eval2(DVec2::new(along * 0.5, across * 1.5))
    };
    let mut sample: Vec<f64> = (0..64 * 32)
        .map(|k| dust_at(DVec2::new((k % 64) as f64 / 32.0, (k / 64) as f64 / 32.0)))
        .collect();
    sample.sort_by(f64::total_cmp);
    let dust_ref = sample[sample.len() * 9 / 10].max(f64::MIN_POSITIVE);
    let stars = StarGrid::new(
        &star_catalogue(seed, w, h, |p| (0.35 + 1.6 * band_at(p)) / 1.95),
        w,
        h,
    );
    // 3 × 3 samples a pixel, resolved by the camera's pixel filter.
    supersampled(w, h, if quick { 2 } else { 3 }, |x, y| {
        let q = DVec2::new(f64::from(x), f64::from(y));
        let p = q / f64::from(h);
        let band = band_at(p);
        let star = stars.light(q);
        let haze = band * (0.55 + 0.45 * glow.eval2(p)).max(0.0);
        let tau = 1.2 * band.sqrt() * dust_at(p).max(0.0) / dust_ref;
        let light = DVec3::new(1.0, 0.9, 0.75) * (0.55 * haze) + DVec3::splat(star);
        (light * (-tau).exp()).as_vec3()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Excess kurtosis of the samples.
    fn kurtosis(v: &[f64]) -> f64 {
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        let m2 = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n;
        let m4 = v.iter().map(|x| (x - m).powi(4)).sum::<f64>() / n;
        m4 / (m2 * m2) - 3.0
    }

    #[test]
    fn star_counts_follow_log_n_log_s_and_gather_to_the_band() {
        // Uniform density: N(> 2S) / N(> S) = 2^(−3/2) ≈ 0.354 below the cap.
        let all = star_catalogue(3, 2000, 1000, |_| 1.0);
        let above = |s: f64| all.iter().filter(|st| st.peak > s).count() as f64;
        for s in [FAINTEST * 2.0, FAINTEST * 8.0] {
            let r = above(2.0 * s) / above(s);
            assert!((r - 0.354).abs() < 0.03, "N(>2S)/N(>S) at {s}: {r}");
        }
        assert!(
            all.iter()
                .all(|st| (FAINTEST..=BRIGHTEST).contains(&st.peak))
        );
        // Half the candidates kept on the left half, all on the right.
        let half = star_catalogue(3, 2000, 1000, |p| if p.x < 1.0 { 0.5 } else { 1.0 });
        let left = half.iter().filter(|st| st.at.x < 1000.0).count() as f64;
        let right = half.len() as f64 - left;
        assert!((left / right - 0.5).abs() < 0.03, "{left} against {right}");
    }

    #[test]
    fn a_star_is_a_seeing_disc() {
        let star = Star {
            at: DVec2::new(10.3, 7.6),
            peak: 0.8,
        };
        let grid = StarGrid::new(&[star], 20, 15);
        assert!((grid.light(star.at) - 0.8).abs() < 1e-12);
        let one_sigma = grid.light(star.at + DVec2::new(0.0, SEEING_PX));
        assert!((one_sigma - 0.8 * (-0.5f64).exp()).abs() < 1e-12);
        // Its light reaches three σ, from buckets beside the sample's.
        let edge = grid.light(star.at + DVec2::new(-2.9 * SEEING_PX, 0.0));
        assert!(edge > 0.0 && edge < 0.8 * 0.015);
    }

    #[test]
    fn the_dust_is_intermittent_where_fbm_is_gaussian() {
        // A multifractal's values span orders of magnitude: heavy tails
        // (large excess kurtosis) where fBm's are near Gaussian (≈ 0).
        let d = dust(5).unwrap();
        let f = Fbm::new(
            Perlin::new(5),
            Spectral {
                h: 0.25,
                octaves: 7.0,
                frequency: 3.0,
                ..Spectral::default()
            },
        )
        .unwrap();
        let pts: Vec<DVec2> = (0..40_000)
            .map(|k| DVec2::new((k % 200) as f64 * 0.037, (k / 200) as f64 * 0.037))
            .collect();
        let dv: Vec<f64> = pts.iter().map(|&p| d.eval2(p)).collect();
        let fv: Vec<f64> = pts.iter().map(|&p| f.eval2(p)).collect();
        let (kd, kf) = (kurtosis(&dv), kurtosis(&fv));
        assert!(kd > 2.0 && kf.abs() < 1.0, "dust {kd}, fBm {kf}");
    }
}
