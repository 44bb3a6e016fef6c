//! Musgrave 2001, fig. 17, for `figures_musgrave`: "Building a ridged basis
//! function from a Perlin basis: the Perlin basis, its absolute value, and
//! one minus the absolute value". Three columns, each natura-noise's field
//! as a grey map over the same square of the lattice (`Perlin`,
//! `Abs(Perlin)`, `Ridged(Perlin)`, the library's own combinators) above
//! its profile along the map's middle row, where the creases of `|N|` on
//! the zero set of `N` turn into the ridges of `1 − |N|`.

use natura::core::Image;
use natura::core::glam::{DVec2, Vec3};
use natura::noise::{Abs, Fade, Field, Perlin, Ridged};

use crate::common::Exit;
use crate::common::plot::{Canvas, Panel, Pen, colour};

type R<T> = Result<T, Exit>;

/// Lattice cells across each map and profile.
const CELLS: f64 = 4.0;

/// The figure: the three maps above their middle rows' profiles.
pub(crate) fn picture(seed: u64, quick: bool) -> R<Image> {
    let side = if quick { 120 } else { 360 };
    let gap = side / 12;
    let plot_h = side / 2;
    let (w, h) = (3 * side + 4 * gap, side + plot_h + 3 * gap);
    // The sources' Perlin basis: gradient noise with the cubic fade.
    let basis = Perlin::with_fade(seed, Fade::Cubic);
    let fields: [(&dyn Field, f64, f64); 3] = [
        (&basis, -1.0, 1.0),
        (&Abs(basis), 0.0, 1.0),
        (&Ridged(basis), 0.0, 1.0),
    ];
    // A row a little off the lattice's, so the profile crosses zeros.
    let row = 0.5 * CELLS + 0.37;
    let mut canvas = Canvas::new(w, h);
    for (k, &(field, _, _)) in fields.iter().enumerate() {
        let left = (gap + k * (side + gap)) as f32;
        let top = (2 * gap + side) as f32;
        let panel = Panel::new(
            [left, top, left + side as f32, top + plot_h as f32],
            [0.0, CELLS, -1.05, 1.05],
        );
        canvas.axes(&panel, [1.0, 0.5]);
        let n = 4 * side;
        let pts: Vec<(f64, f64)> = (0..=n)
            .map(|i| {
                let x = CELLS * i as f64 / n as f64;
                (x, field.eval2(DVec2::new(x, row)))
            })
            .collect();
        canvas.line(&panel, &pts, Pen::solid(colour::INK, 1.5));
    }
    // The maps, each field's range to black … white (linear `t²`, which
    // the picture's sRGB encoding shows as about `t`), the profiled row
    // marked in red.
    let mut img = canvas.into_image()?;
    for (k, &(field, lo, hi)) in fields.iter().enumerate() {
        let x0 = gap + k * (side + gap);
        for y in 0..side {
            // y up in the lattice, down in the picture.
            let v = CELLS * (1.0 - (y as f64 + 0.5) / side as f64);
            let on_row = ((v - row) * side as f64 / CELLS).abs() < 0.5;
            for x in 0..side {
                let u = CELLS * (x as f64 + 0.5) / side as f64;
                let t = ((field.eval2(DVec2::new(u, v)) - lo) / (hi - lo)).clamp(0.0, 1.0) as f32;
                let c = if on_row {
                    colour::RED
                } else {
                    Vec3::splat(t * t)
                };
                img.set(x0 + x, gap + y, c);
            }
        }
    }
    Ok(img)
}
