//! Plate 4.12: a full-circle rainbow on black, its intensity modulated by
//! 2-D fBm (Musgrave 1993, §4.2.4.3.2), from natura-atmos's physical
//! rainbow table.

use natura::atmos::Dir3;
use natura::atmos::rainbow::{Rainbow, RainbowParams};
use natura::core::Image;
use natura::core::glam::{DVec2, DVec3, Vec3};
use natura::noise::{Fbm, Field, Perlin, Spectral};

use super::R;
use crate::common::outln;

/// The rainbow table of Pl. 4.12: the dissertation's (13 jittered
/// wavelengths, orders 1 and 2, 0.1° bins, a 0.5° sun), with fewer rays
/// when quick.
fn bow_table(quick: bool) -> R<Rainbow> {
    let params = RainbowParams {
        rays_per_wavelength: if quick { 5_000 } else { 50_000 },
        ..RainbowParams::default()
    };
    Ok(Rainbow::new(&params)?)
}

/// The largest angle from the antisolar point the picture shows, degrees.
const BOW_FIELD_DEG: f64 = 60.0;

/// The view direction of pixel (x, y) of an n × n picture centred on the
/// antisolar point (−z, the sun behind the viewer at +z), in an equidistant
/// projection (angle from the centre proportional to the radius), so the
/// bows are circles; `None` outside the field.
fn bow_view(x: usize, y: usize, n: usize) -> Option<DVec3> {
    let half = n as f64 / 2.0;
    let u = (x as f64 + 0.5 - half) / half;
    let v = (half - (y as f64 + 0.5)) / half;
    let r = u.hypot(v);
    let theta = r * BOW_FIELD_DEG.to_radians();
    if r > 1.0 {
        return None;
    }
    let (s, c) = theta.sin_cos();
    let (cu, cv) = if r > 0.0 { (u / r, v / r) } else { (0.0, 0.0) };
    Some(DVec3::new(s * cu, s * cv, -c))
}

/// Pl. 4.12: the primary and secondary bows as full circles on black, the
/// rain's optical depth scaled by 2-D fBm of the view direction (cloud
/// shadows and patchy rain, Musgrave 1993, §4.2.4.3.2).
pub(crate) fn picture(seed: u64, quick: bool) -> R<Image> {
    let rainbow = bow_table(quick)?;
    let n = if quick { 192 } else { 900 };
    let sun = Dir3::new(DVec3::Z)?;
    let patchy = Fbm::new(
        Perlin::new(seed ^ 0x412),
        Spectral {
            h: 0.5,
            lacunarity: 2.0,
            octaves: 6.0,
            frequency: 2.5,
            ..Spectral::default()
        },
    )?;
    let irradiance = DVec3::splat(1.0);
    // Exposed so the primary's brightest channel, through the mean rain,
    // is 0.7.
    let [primary, secondary] = bow_peaks(&rainbow);
    let brightest = rainbow
        .table()
        .lookup(primary[0].to_radians())
        .max_element();
    // Rain 1 km deep; 1e-3 /m is a heavy shower's geometric extinction.
    let (depth, extinction) = (1000.0, 1e-3f64);
    let exposure = 0.7 / (brightest * -(-extinction * depth).exp_m1());
    let mut err = None;
    let img = Image::from_fn(n, n, |x, y| {
        let Some(d) = bow_view(x, y, n) else {
            return Vec3::ZERO;
        };
        let Ok(view) = Dir3::new(d) else {
            return Vec3::ZERO;
        };
        // The rain's density, e^(2.5·fBm): smooth, positive, patchy.
        let m = (2.5 * patchy.eval2(DVec2::new(d.x, d.y) / (1.0 - d.z).max(1e-9))).exp();
        match rainbow.radiance(view, sun, irradiance, extinction * m, depth) {
            Ok(c) => (c * exposure).as_vec3(),
            Err(e) => {
                err.get_or_insert(e);
                Vec3::ZERO
            }
        }
    })?;
    if let Some(e) = err {
        return Err(e.into());
    }
    outln(format_args!(
        "  Pl. 4.12: primary red {:.1}°, blue {:.1}°; secondary red {:.1}°, blue {:.1}°; \
         Alexander's band {:.2} of the light inside the primary",
        primary[0],
        primary[1],
        secondary[0],
        secondary[1],
        mean_luminance(&rainbow, 44.0, 49.0) / mean_luminance(&rainbow, 30.0, 40.0)
    ))?;
    Ok(img)
}

/// The angle (degrees) of the brightest bin of `channel` (0 red, 2 blue)
/// of the rainbow table between `lo`° and `hi`°.
fn peak(rainbow: &Rainbow, channel: usize, lo: f64, hi: f64) -> f64 {
    let t = rainbow.table();
    let w = t.bin_width().to_degrees();
    let bins = t.bins();
    ((lo / w) as usize..(hi / w) as usize)
        .max_by(|&i, &j| bins[i][channel].total_cmp(&bins[j][channel]))
        .map_or(f64::NAN, |i| (i as f64 + 0.5) * w)
}

/// The red and blue peaks (degrees) of the primary (30°–46°) and the
/// secondary (46°–60°): `[[red, blue]; 2]`.
fn bow_peaks(rainbow: &Rainbow) -> [[f64; 2]; 2] {
    [(30.0, 46.0), (46.0, 60.0)]
        .map(|(lo, hi)| [peak(rainbow, 0, lo, hi), peak(rainbow, 2, lo, hi)])
}

/// The table's mean luminance (Rec. 709 weights) over `lo`°–`hi`°.
fn mean_luminance(rainbow: &Rainbow, lo: f64, hi: f64) -> f64 {
    let t = rainbow.table();
    let w = t.bin_width().to_degrees();
    let bins = &t.bins()[(lo / w) as usize..(hi / w) as usize];
    bins.iter()
        .map(|c| c.dot(DVec3::new(0.2126, 0.7152, 0.0722)))
        .sum::<f64>()
        / bins.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bows_are_at_42_and_52_degrees_with_a_dark_band_between() {
        // Musgrave 1993, §4.2.4.3: the primary ≈ 42°, red outside, the
        // secondary ≈ 52°, red inside, Alexander's dark band between them.
        // Tolerance 0.5°: the 0.5° sun's smear plus a 0.1° bin.
        let bow = bow_table(true).unwrap();
        let [[p_red, p_blue], [s_red, s_blue]] = bow_peaks(&bow);
        assert!((p_red - 42.0).abs() < 0.5, "primary red at {p_red}°");
        assert!(p_blue < p_red && s_red < s_blue);
        let s_mid = 0.5 * (s_red + s_blue);
        assert!((s_mid - 52.0).abs() < 0.5, "secondary at {s_mid}°");
        let band = mean_luminance(&bow, 44.0, 49.0);
        assert!(band < 0.05 * mean_luminance(&bow, 30.0, 40.0), "{band}");
        assert!(band < 0.05 * mean_luminance(&bow, 54.0, 60.0), "{band}");
    }
}
