//! Musgrave 1993, Plate 4.2 (Musgrave et al. 1989, Plate 12; Musgrave
//! 2001, fig. 14): "Carolina", receding ridges in exponential mist.

use natura::core::glam::{DVec2, DVec3};
use natura::core::{HeightField, Image};
use natura::noise::{Field, Perlin, Spectral, StatsByAltitude, StatsByAltitudeParams};
use natura::texture::git::{ColourEllipsoid, Git, GitParams};

use crate::R;
use crate::landscape::{misty_sky, picture_size};
use crate::patches::rescaled;
use crate::slickrock::{View, rayleigh_mist_of, render};

/// How many times the terrain function is compressed along the line of
/// sight: the source's "series of ridges" comes from "scaling the terrain
/// generation function to compress the terrain along the line of sight".
pub(crate) const COMPRESSION: f64 = 6.0;

/// "Carolina"'s 100 × 100 height field (the source's size, with its large
/// triangles), 24 km across and 900 m of relief: statistics by altitude
/// over the Perlin basis, whose crossover scale rises with altitude (the
/// source's "subtle multifractal"), its domain compressed along y.
pub(crate) fn carolina_field(seed: u64) -> R<HeightField> {
    let n = 100;
    let f = StatsByAltitude::new(
        Perlin::new(seed),
        StatsByAltitudeParams {
            spectral: Spectral {
                h: 0.9,
                octaves: 7.0,
                ..Spectral::default()
            },
            ..StatsByAltitudeParams::default()
        },
    )?;
    let raw: Vec<f64> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            f.eval2(DVec2::new(x, y * COMPRESSION) * (3.0 / n as f64))
        })
        .collect();
    rescaled(&raw, (n, n), 24_000.0 / (n - 1) as f32, 900.0)
}

/// Plate 4.2: the ridges seen level from the height of the highest tenth
/// of the land, through a 20° lens, along the compressed axis, through
/// exponential mist with the Rayleigh approximation (scale height 300 m,
/// so the mist fills the valleys between the ridges and each ridge stands
/// paler and bluer than the one before, as Lynch describes), under a
/// forest of dark greens.
pub(crate) fn carolina(seed: u64, quick: bool) -> R<Image> {
    let hf = carolina_field(seed)?;
    let (size, ss) = picture_size(quick);
    let forest = Git::new(GitParams {
        seed,
        ellipsoid: ColourEllipsoid::along(
            DVec3::new(0.24, 0.33, 0.17),
            DVec3::new(0.6, 0.3, -0.2),
            [0.04, 0.02, 0.01],
        )?,
        txtscale: 1.0 / 300.0,
        ..GitParams::default()
    })?;
    let mist = rayleigh_mist_of(8.0e-6, 500.0)?;
    let mut heights: Vec<f32> = hf.heights().as_slice().to_vec();
    heights.sort_by(f32::total_cmp);
    let view = View {
        above: 0.0,
        floor: heights[heights.len() - 1] + 150.0,
        pitch: 0.05,
        fov: 20f32.to_radians(),
    };
    render(&hf, &forest, size, ss, &mist, misty_sky, view)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ridges_run_across_the_line_of_sight() {
        // Compressed along y, the terrain changes about COMPRESSION times
        // faster along the line of sight than across it: ridges across.
        let hf = carolina_field(3).unwrap();
        let (n, h) = (hf.nx(), hf.heights());
        let (mut along, mut across) = (0.0, 0.0);
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                along += f64::from((h[(i, j + 1)] - h[(i, j)]).abs());
                across += f64::from((h[(i + 1, j)] - h[(i, j)]).abs());
            }
        }
        let ratio = along / across;
        assert!((3.0..9.0).contains(&ratio), "{ratio}");
        // The source's 100 × 100 samples.
        assert_eq!((hf.nx(), hf.ny()), (100, 100));
    }
}
