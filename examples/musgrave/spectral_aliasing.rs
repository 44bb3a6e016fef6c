//! Plates 4.10–4.11: spectral aliasing in the physical rainbow and its
//! jittered antialiasing (Musgrave 1993, §4.2.4.3.2). natura-atmos's
//! physical rainbow table traced at the centres of its 13 wavelength
//! strata under a point sun shows a set of discrete, overlapping coloured
//! bows; jittering each ray's wavelength within its stratum and convolving
//! with the sun's disk turns them into a continuous band. The same view of
//! the primary bow, once each way.

use natura::atmos::Dir3;
use natura::atmos::rainbow::{Rainbow, RainbowParams};
use natura::core::Image;
use natura::core::glam::{DVec3, Vec3};

use super::R;

/// The angle from the antisolar point at the picture's centre, degrees
/// (the primary bow's middle).
const CENTRE_DEG: f64 = 41.5;

/// Half the picture's height, degrees.
const HALF_FIELD_DEG: f64 = 2.5;

/// Bins of the table over 0–180°: 0.025°, finer than the strata's spacing
/// in the bow (about 0.15°), so the aliasing is not hidden by the bins.
const BINS: usize = 7200;

/// The table of one plate: the sources' 13 wavelength strata, orders 1
/// and 2. Plate 4.10 ("a small number of samples and a point light
/// source"): the strata's centres and a point sun; Plate 4.11 ("jittering
/// and convolution … with a kernel representing the angular illumination
/// distribution across the Sun's disk"): jittered wavelengths and the
/// 0.5° sun. `antialiased` chooses the plate.
pub(crate) fn table(antialiased: bool, quick: bool) -> R<Rainbow> {
    Ok(Rainbow::new(&RainbowParams {
        jitter: antialiased,
        rays_per_wavelength: if quick { 20_000 } else { 200_000 },
        bins: BINS,
        sun_diameter_deg: if antialiased {
            RainbowParams::default().sun_diameter_deg
        } else {
            0.0
        },
        ..RainbowParams::default()
    })?)
}

/// The view direction of pixel `(x, y)` of a `w` × `h` picture: an
/// equidistant map about the antisolar point (−z), its window centred
/// [`CENTRE_DEG`] above it, so the bow is a gently curved band.
fn view(x: usize, y: usize, w: usize, h: usize) -> DVec3 {
    let per_px = 2.0 * HALF_FIELD_DEG / h as f64;
    let u = (x as f64 + 0.5 - w as f64 / 2.0) * per_px;
    let v = CENTRE_DEG + (h as f64 / 2.0 - (y as f64 + 0.5)) * per_px;
    let theta = u.hypot(v).to_radians();
    let phi = u.atan2(v);
    let (s, c) = theta.sin_cos();
    DVec3::new(s * phi.sin(), s * phi.cos(), -c)
}

/// One plate: the bow through uniform rain on black, exposed so the
/// brightest channel is 0.8.
fn picture(rainbow: &Rainbow, w: usize, h: usize) -> R<Image> {
    let sun = Dir3::new(DVec3::Z)?;
    let (depth, extinction) = (1000.0, 1e-3f64);
    let brightest = rainbow
        .table()
        .bins()
        .iter()
        .fold(0.0f64, |m, b| m.max(b.max_element()));
    let exposure = 0.8 / (brightest * -(-extinction * depth).exp_m1());
    let mut err = None;
    let img = Image::from_fn(w, h, |x, y| {
        let Ok(d) = Dir3::new(view(x, y, w, h)) else {
            return Vec3::ZERO;
        };
        match rainbow.radiance(d, sun, DVec3::ONE, extinction, depth) {
            Ok(c) => (c * exposure).as_vec3(),
            Err(e) => {
                err.get_or_insert(e);
                Vec3::ZERO
            }
        }
    })?;
    match err {
        Some(e) => Err(e.into()),
        None => Ok(img),
    }
}

/// Plates 4.10 (aliased: stratum centres) and 4.11 (jittered).
pub(crate) fn pair(quick: bool) -> R<Vec<Image>> {
    let (w, h) = if quick { (240, 160) } else { (900, 600) };
    Ok(vec![
        picture(&table(false, quick)?, w, h)?,
        picture(&table(true, quick)?, w, h)?,
    ])
}

/// The luminance of the table's bins between `lo`° and `hi`°.
#[cfg(test)]
fn profile(rainbow: &Rainbow, lo: f64, hi: f64) -> Vec<f64> {
    let t = rainbow.table();
    let bw = t.bin_width().to_degrees();
    t.bins()[(lo / bw) as usize..(hi / bw) as usize]
        .iter()
        .map(|c| c.dot(DVec3::new(0.2126, 0.7152, 0.0722)))
        .collect()
}

/// The total variation of a profile over its mean: how much it jumps
/// between neighbouring bins.
#[cfg(test)]
fn ripple(v: &[f64]) -> f64 {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    v.windows(2).map(|p| (p[1] - p[0]).abs()).sum::<f64>() / (mean * v.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stratum_centres_alias_and_jitter_smooths_the_bow() {
        // Across the primary bow (39.5°–42.8°) the aliased table jumps from
        // one wavelength's sharp bow to the next; the antialiased one
        // (jittered, the sun's disk) varies far more smoothly.
        let (aliased, jittered) = (table(false, true).unwrap(), table(true, true).unwrap());
        let (a, j) = (
            ripple(&profile(&aliased, 39.5, 42.8)),
            ripple(&profile(&jittered, 39.5, 42.8)),
        );
        assert!(a > 1.5 * j, "ripple aliased {a:.3}, jittered {j:.3}");
        // The same light in all: jitter and the sun's disk move it, they do
        // not add or remove it.
        let total = |r: &Rainbow| profile(r, 30.0, 60.0).iter().sum::<f64>();
        let (ta, tj) = (total(&aliased), total(&jittered));
        assert!((ta - tj).abs() < 0.05 * ta, "{ta} {tj}");
    }

    #[test]
    fn the_window_is_centred_on_the_primary_bow() {
        let d = view(50, 50, 101, 101);
        let deg = d.angle_between(DVec3::NEG_Z).to_degrees();
        assert!((deg - CENTRE_DEG).abs() < 0.05, "{deg}");
        let top = view(50, 0, 101, 101)
            .angle_between(DVec3::NEG_Z)
            .to_degrees();
        assert!((top - CENTRE_DEG - HALF_FIELD_DEG).abs() < 0.05, "{top}");
    }
}
