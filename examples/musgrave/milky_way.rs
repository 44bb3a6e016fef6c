//! Musgrave 2001, fig. 32 for `figures_musgrave`: "A multifractal texture
//! as a model of the Milky Way": a glowing band of stars crossed by dark
//! dust lanes whose optical depth is natura-noise's multiplicative
//! multifractal cascade.

use natura::core::Image;
use natura::core::glam::{DVec2, DVec3};
use natura::noise::{
    Fbm, Field, Multifractal, MultifractalParams, Perlin, Spectral, Value, Worley, WorleyParams,
};

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

/// Fig. 32: stars (Worley points, brightness from value noise) and the
/// band's diffuse glow (a Gaussian across the band times fBm), seen
/// through the dust where the band is.
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
    let stars = Worley::new(seed ^ 0x5a, WorleyParams::default())?;
    let bright = Value::new(seed ^ 0x77);
    let star_cells = 90.0;
    // The cascade's values span orders of magnitude: scaled by its 90th
    // percentile over the picture, an optical depth of 1.2 there.
    let (s, c) = 12f64.to_radians().sin_cos();
    // Across and along the band (x along, tilted by 12°; unit height).
    let frame = |p: DVec2| {
        let q = p - DVec2::new(1.0, 0.5);
        (q.y * c - q.x * s, q.x * c + q.y * s)
    };
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
    // Stars are points smaller than a pixel: 3 × 3 samples a pixel,
    // resolved by the camera's pixel filter, share each with its
    // neighbours as a photograph's lens does.
    supersampled(w, h, if quick { 2 } else { 3 }, |x, y| {
        let p = DVec2::new(f64::from(x) / f64::from(h), f64::from(y) / f64::from(h));
        let across = frame(p).0;
        let band = (-(across / 0.16).powi(2)).exp();
        let q = p * star_cells;
        let f1 = stars.eval2(q);
        let b = 0.2 + 0.8 * (0.5 + 0.5 * bright.eval2(q * 0.37)).powi(3);
        let star = (1.0 - f1 / 0.09).max(0.0).powi(2) * b * (0.35 + 1.6 * band);
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
