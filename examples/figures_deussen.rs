//! Deussen et al.'s ecosystem figures (Deussen et al. 1998) that the plant
//! examples do not show: self-thinning as pictures (Fig. 4) and as a plot
//! (Fig. 5).
//!
//! ```text
//! cargo run --release --example figures_deussen                 # every figure
//! cargo run --release --example figures_deussen -- --quick      # small, for CI
//! ```
//!
//! Writes into `--out` (default `./figures_deussen/`); docs/figures.md
//! sets each beside the source's caption. Pictures and plots carry no text.

mod common;

use std::collections::HashSet;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::plot::{Canvas, Panel, Pen, colour};
use common::{Exit, Run, outln};
use natura::core::glam::Vec3;
use natura::core::{HeightField, Image, Seed};
use natura::plant::eco::{EcoParams, Ecosystem, Plant, Species};

/// Deussen et al.'s ecosystem figures (Deussen et al. 1998) not shown by
/// the plant examples: self-thinning.
#[derive(Parser)]
#[command(name = "figures_deussen", version)]
struct Cli {
    /// Small and fast (CI): a smaller field
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_deussen")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Figs. 4-5: self-thinning, three moments of the field and the log-log plot
    SelfThinning,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[Fig::SelfThinning];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::SelfThinning => &[
                "deussen_fig04_self_thinning.png",
                "deussen_fig05_thinning_plot.png",
            ],
        }
    }
}

type R<T> = Result<T, Exit>;

fn main() -> ExitCode {
    common::run(run)
}

fn run() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let q = cli.quick;
    figures::make(&out, &cli.only, |fig| match fig {
        Fig::SelfThinning => self_thinning(q),
    })
}

/// The steps the pictures show (the source shows steps 99, 134 and 164 of
/// its run; its growth rate is not given, so the steps differ).
const SHOWN: [u32; 3] = [4, 12, 30];

/// The self-thinning experiment (Deussen et al. 1998, §4.3): one species,
/// 62 500 plants per hectare at random places with radii drawn from
/// 2–10 cm, growing 5 cm a step; where two circles overlap the smaller
/// plant dies, and none is re-seeded. The source gives neither the growth
/// rate nor the radius interval.
fn thinning(side_m: f32, steps: u32) -> R<Ecosystem> {
    let species = Species {
        name: "self-thinning".into(),
        seeds_per_ha: 0.0,
        initial_per_ha: 62_500.0,
        r0_min: 0.02,
        r0_max: 0.1,
        max_radius: 3.0,
        growth: 0.05,
        survive_domination: 0.0,
        wet_tolerance: 10.0,
        light_tolerance: 10.0,
        vigor_spread: 0.0,
        ..Species::default()
    };
    let params = EcoParams {
        species: vec![species],
        steps,
        seed: Seed(4),
        ..EcoParams::default()
    };
    let n = (side_m as usize).max(2) + 1;
    let hf = HeightField::flat(n, n, 1.0, 0.0)?;
    Ok(Ecosystem::new(&hf, params)?)
}

/// One moment of the field: the plants alive before the step and the ids
/// of those the step's domination killed.
struct Moment {
    plants: Vec<Plant>,
    dominated: HashSet<u64>,
}

/// The run: (log density per m², log mean circle area in m²) after each
/// step, and the moments of [`SHOWN`].
struct Thinning {
    line: Vec<(f64, f64)>,
    moments: Vec<Moment>,
    side_m: f32,
}

fn run_thinning(side_m: f32) -> R<Thinning> {
    let steps = SHOWN[SHOWN.len() - 1];
    let mut eco = thinning(side_m, steps)?;
    let field = f64::from(side_m).powi(2);
    let (mut line, mut moments) = (Vec::new(), Vec::new());
    for s in 1..=steps {
        let before = eco.plants().to_vec();
        let stats = eco.step()?;
        if stats.old > 0 {
            return Err(Exit::new(
                2,
                "a plant reached its limit size; the figure shows none",
            ));
        }
        if SHOWN.contains(&s) {
            let alive: HashSet<u64> = eco.plants().iter().map(|p| p.id).collect();
            let dominated = before
                .iter()
                .map(|p| p.id)
                .filter(|id| !alive.contains(id))
                .collect();
            moments.push(Moment {
                plants: before,
                dominated,
            });
        }
        let n = eco.plants().len() as f64;
        let area = eco
            .plants()
            .iter()
            .map(|p| std::f64::consts::PI * f64::from(p.radius).powi(2))
            .sum::<f64>()
            / n;
        line.push(((n / field).ln(), area.ln()));
    }
    Ok(Thinning {
        line,
        moments,
        side_m,
    })
}

/// The least-squares slope of `pts` from the `skip`-th point on (the first
/// steps precede the thinning line).
fn slope(pts: &[(f64, f64)], skip: usize) -> f64 {
    let tail = &pts[skip..];
    let m = tail.len() as f64;
    let (mx, my) = tail
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / m, a.1 + p.1 / m));
    let (num, den) = tail.iter().fold((0.0, 0.0), |a, p| {
        (a.0 + (p.0 - mx) * (p.1 - my), a.1 + (p.0 - mx).powi(2))
    });
    num / den
}

/// The points where the thinning line is fitted: from the tenth step on.
const FIT_FROM: usize = 9;

/// Fig. 4: the field at the three [`SHOWN`] steps, each plant's circle
/// green, or red where the step's domination kills it (the source also
/// draws old plants yellow; none reaches its limit size here). Fig. 5: the
/// log of the mean area against the log of the density, slope −1 (blue),
/// and the log of the mean mass (area^{3/2}) against it, slope −3/2
/// (green), with the fitted lines dashed red.
fn self_thinning(quick: bool) -> R<Vec<Image>> {
    let side = if quick { 16.0 } else { 40.0 };
    let t = run_thinning(side)?;
    let size = if quick { 240 } else { 640 };
    let px = size as f32 / t.side_m;
    let mut fields = Vec::new();
    for m in &t.moments {
        let mut c = Canvas::new(size, size);
        let panel = Panel::new(
            [0.0, 0.0, size as f32, size as f32],
            [0.0, f64::from(t.side_m), 0.0, f64::from(t.side_m)],
        );
        for p in &m.plants {
            let col = if m.dominated.contains(&p.id) {
                colour::RED
            } else {
                colour::GREEN
            };
            c.dots(
                &panel,
                &[(f64::from(p.x), f64::from(p.y))],
                col,
                (p.radius * px).max(0.6),
            );
        }
        fields.push(c.into_image()?);
    }
    let area_slope = slope(&t.line, FIT_FROM);
    let mass: Vec<(f64, f64)> = t.line.iter().map(|&(d, a)| (d, 1.5 * a)).collect();
    let mass_slope = slope(&mass, FIT_FROM);
    outln(format_args!(
        "  Figs. 4-5: {} plants at step {}; slopes: area {area_slope:.3} (the source: −1), mass {mass_slope:.3} (−3/2)",
        t.moments[0].plants.len(),
        SHOWN[0]
    ))?;
    let mut c = Canvas::new(640, 520);
    let all = t.line.iter().chain(&mass);
    let (x0, x1, y0, y1) = all.fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |a, p| {
        (a.0.min(p.0), a.1.max(p.0), a.2.min(p.1), a.3.max(p.1))
    });
    let (dx, dy) = (0.05 * (x1 - x0), 0.05 * (y1 - y0));
    let cell = c.grid(1, 1, 24.0, [0.0, 1.0, 0.0, 1.0])[0].rect;
    let panel = Panel::new(cell, [x0 - dx, x1 + dx, y0 - dy, y1 + dy]);
    c.axes(&panel, [0.5, 0.5]);
    for (pts, col) in [(&t.line, colour::BLUE), (&mass, colour::GREEN)] {
        let k = slope(pts, FIT_FROM);
        let tail = &pts[FIT_FROM..];
        let (mx, my) = tail.iter().fold((0.0, 0.0), |a, p| {
            (a.0 + p.0 / tail.len() as f64, a.1 + p.1 / tail.len() as f64)
        });
        let fit = [(x0, my + k * (x0 - mx)), (x1, my + k * (x1 - mx))];
        c.line(&panel, &fit, Pen::dashed(colour::RED, 1.4));
        c.line(&panel, pts, Pen::solid(col, 1.8));
        c.dots(&panel, pts, col, 3.0);
    }
    let sheet = Image::contact_sheet(&fields, 3, 6, Vec3::ONE)?;
    Ok(vec![sheet, c.into_image()?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_follows_slope_minus_one_in_area_and_minus_three_halves_in_mass() {
        // Fig. 5: log mean area against log density has slope −1; since
        // mass ∝ area^{3/2}, log mass against log density has slope −3/2.
        // The source writes "area raised to the power of −3/2": the power
        // is +3/2 (with −3/2 the mass slope would be +3/2).
        let t = run_thinning(40.0).unwrap();
        let a = slope(&t.line, FIT_FROM);
        assert!((a + 1.0).abs() < 0.2, "area slope {a}");
        let mass: Vec<(f64, f64)> = t.line.iter().map(|&(d, a)| (d, 1.5 * a)).collect();
        let m = slope(&mass, FIT_FROM);
        assert!((m + 1.5).abs() < 0.3, "mass slope {m}");
        // The density falls every step once the circles touch.
        assert!(t.line.windows(2).skip(FIT_FROM).all(|w| w[1].0 < w[0].0));
    }

    #[test]
    fn the_pictures_show_dominated_plants_that_the_step_removes() {
        let t = run_thinning(40.0).unwrap();
        assert_eq!(t.moments.len(), SHOWN.len());
        for m in &t.moments {
            assert!(!m.dominated.is_empty());
            assert!(m.dominated.len() < m.plants.len() / 2);
        }
        // Fewer plants at each moment shown.
        assert!(
            t.moments
                .windows(2)
                .all(|w| w[1].plants.len() < w[0].plants.len())
        );
    }
}
