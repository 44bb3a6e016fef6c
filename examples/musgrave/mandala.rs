//! Plate 4.8 of `figures_musgrave`, "Fractal Mandala": balls of glowing
//! gas, each a natura-atmos radial (Gaussian) atmosphere whose extinction
//! vector imitates black-body colours, white-hot where the column is deep
//! and cherry red towards the edges, set out as a fractal mandala on black.

use natura::atmos::Medium;
use natura::atmos::medium::{Attenuation, RadialAtmosphere};
use natura::core::Image;
use natura::core::glam::DVec3;

use crate::common::Exit;

type R<T> = Result<T, Exit>;

/// The extinction per unit of a ball's size, per channel: red saturates
/// first, blue last (the source's vector is not given).
pub(crate) const GLOW_EXTINCTION: [f64; 3] = [9.0, 2.4, 0.9];
/// The glow's colour where every channel saturates: white-hot.
pub(crate) const WHITE_HOT: [f64; 3] = [1.0, 0.97, 0.92];

/// A glowing ball of size `s` at `c`: density e^−(r²/s²) (a radial
/// atmosphere with a core of s/100 and scale height 50 s), extinction
/// `GLOW_EXTINCTION / s`, so every ball has the same colours.
pub(crate) fn glow(c: DVec3, s: f64) -> R<RadialAtmosphere> {
    let [r, g, b] = GLOW_EXTINCTION;
    let [wr, wg, wb] = WHITE_HOT;
    Ok(RadialAtmosphere::new(
        DVec3::new(r, g, b) / s,
        DVec3::new(wr, wg, wb),
        c,
        s / 100.0,
        50.0 * s,
    )?)
}

/// The mandala: a ball of size 1 at the origin, six of 0.42 around it at
/// 1.9, and so on for `levels` levels, each ring turned by 30°, all in the
/// x–z plane (the choice of the arrangement is natura's).
fn mandala(levels: u32) -> R<Vec<(DVec3, f64, RadialAtmosphere)>> {
    let mut balls = vec![(DVec3::ZERO, 1.0, 0.0)];
    let mut last = balls.clone();
    for _ in 1..levels {
        let mut next = Vec::new();
        for &(c, s, turn) in &last {
            for k in 0..6 {
                let a = turn + std::f64::consts::FRAC_PI_3 * k as f64;
                next.push((
                    c + DVec3::new(a.cos(), 0.0, a.sin()) * 1.9 * s,
                    0.42 * s,
                    turn + std::f64::consts::FRAC_PI_6,
                ));
            }
        }
        balls.extend(&next);
        last = next;
    }
    balls
        .into_iter()
        .map(|(c, s, _)| Ok((c, s, glow(c, s)?)))
        .collect()
}

/// Looking along +y at the x–z plane from 10 units away, orthographically:
/// the light along the line through (x, z), against black.
fn column(balls: &[(DVec3, f64, RadialAtmosphere)], x: f64, z: f64) -> DVec3 {
    let (a, b) = (DVec3::new(x, -10.0, z), DVec3::new(x, 10.0, z));
    let mut tau = DVec3::ZERO;
    for (c, s, ball) in balls {
        // Beyond 4 sizes the density is below e^−16.
        if (c.x - x).hypot(c.z - z) < 4.0 * s {
            tau += ball.optical_depth(a, b);
        }
    }
    let [wr, wg, wb] = WHITE_HOT;
    Attenuation::beer(tau, DVec3::new(wr, wg, wb)).apply(DVec3::ZERO)
}

/// Pl. 4.8: the mandala, 3 levels (4 when not quick), 3.6 units across the
/// centre ball's ring and beyond.
pub(crate) fn mandala_picture(quick: bool) -> R<Image> {
    let balls = mandala(if quick { 3 } else { 4 })?;
    let n = if quick { 160 } else { 800 };
    let half = 3.4;
    Ok(Image::from_fn(n, n, |i, j| {
        let x = (i as f64 + 0.5) / n as f64 * 2.0 * half - half;
        let z = half - (j as f64 + 0.5) / n as f64 * 2.0 * half;
        column(&balls, x, z).as_vec3()
    })?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_hot_at_the_centre_cherry_red_at_the_edge() {
        // Musgrave 1993, §4.1.6: "white-hot at the center … cherry red
        // towards the edges", and semi-luminous: (1 − σ)·I_a against black.
        let balls = mandala(1).unwrap();
        let centre = column(&balls, 0.0, 0.0);
        let [wr, wg, wb] = WHITE_HOT;
        let white = DVec3::new(wr, wg, wb);
        assert!((centre / white).min_element() > 0.6, "{centre}");
        let edge = column(&balls, 1.6, 0.0);
        assert!(
            edge.x > 2.0 * edge.y && edge.y > edge.z && edge.x > 0.05,
            "{edge}"
        );
        let a = DVec3::new(1.6, -10.0, 0.0);
        let tau = balls[0].2.optical_depth(a, a + DVec3::Y * 20.0);
        let want =
            (DVec3::ONE - DVec3::new((-tau.x).exp(), (-tau.y).exp(), (-tau.z).exp())) * white;
        assert!((edge - want).abs().max_element() < 1e-12);
    }
}
