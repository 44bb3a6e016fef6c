//! Plate 5.9a–f (Musgrave 1993, §5.6; Musgrave 1998, fig. 15.11): the
//! stages in the construction of the terran texture, each natura-texture's
//! `Terran` with the later stages' parameters switched off.

use natura::core::glam::Vec3;
use natura::core::{Image, NoProgress};
use natura::texture::earth::{Terran, TerranParams};
use natura::texture::preview;

use super::R;

/// The climate exponent of stage (d) on: "drive back the glaciers and
/// expand the deserts" (the default texture has none; 2 is chosen).
pub(crate) const MAP_EXP: f64 = 2.0;

/// The six stages' parameters, (a) to (f), for `seed`:
/// (a) fBm quantised at sea level, one land colour and one sea colour;
/// (b) the land coloured by latitude; (c) the latitude perturbed by
/// altitude; (d) the climate index raised to [`MAP_EXP`]; (e) the sea
/// darkened with depth; (f) the land mottled by fBm.
pub(crate) fn stages(seed: u64) -> [TerranParams; 6] {
    let f = TerranParams {
        seed,
        map_exp: MAP_EXP,
        ..TerranParams::default()
    };
    let e = TerranParams {
        mottle_mag: 0.0,
        ..f
    };
    let d = TerranParams {
        depth_scale: 0.0,
        depth_max: 0.0,
        ..e
    };
    let c = TerranParams { map_exp: 0.0, ..d };
    let b = TerranParams {
        pert_scale: 0.0,
        ..c
    };
    let a = TerranParams {
        lat_scale: 0.0,
        ice_caps: 0.0,
        ..b
    };
    [a, b, c, d, e, f]
}

/// Plate 5.9a–f: the six stages on spheres, left to right, top to bottom.
pub(crate) fn picture(seed: u64, quick: bool) -> R<Image> {
    let size = if quick { 64 } else { 340 };
    let mut out = Vec::new();
    for p in stages(seed) {
        out.push(preview::sphere(&Terran::new(p)?, size, false, &NoProgress)?);
    }
    Ok(Image::contact_sheet(&out, 3, 4, Vec3::ZERO)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura::core::glam::DVec3;
    use natura::texture::{Footprint, SolidTexture};

    /// The colours of `p`'s texture at points over the sphere.
    fn colours(p: &TerranParams) -> Vec<DVec3> {
        let t = Terran::new(*p).unwrap();
        (0..2000)
            .map(|i| {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / 2000.0;
                let a = 2.399_963 * f64::from(i);
                let r = (1.0 - z * z).sqrt();
                t.sample(DVec3::new(r * a.cos(), r * a.sin(), z), Footprint::POINT)
                    .colour
            })
            .collect()
    }

    #[test]
    fn each_stage_changes_the_planet_and_the_first_has_two_colours() {
        let s = stages(3);
        let c: Vec<Vec<DVec3>> = s.iter().map(colours).collect();
        // (a): land one colour, sea one colour.
        let mut distinct: Vec<DVec3> = Vec::new();
        for &v in &c[0] {
            if !distinct.iter().any(|d| d.distance(v) < 1e-12) {
                distinct.push(v);
            }
        }
        assert_eq!(distinct.len(), 2, "{distinct:?}");
        // Every later stage changes some of the colours.
        for k in 1..6 {
            let changed = c[k]
                .iter()
                .zip(&c[k - 1])
                .filter(|(a, b)| a.distance(**b) > 1e-9)
                .count();
            assert!(changed > 20, "stage {k} changed {changed} of 2000");
        }
    }
}
