//! Deussen et al.'s ecosystem figures (Deussen et al. 1998) that the plant
//! examples do not show: self-thinning as pictures (Fig. 4) and as a plot
//! (Fig. 5), and eight species that sort themselves by wetness (Fig. 6).
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
use natura::core::NoProgress;
use natura::core::glam::Vec3;
use natura::core::{HeightField, Image, Seed};
use natura::plant::eco::{EcoParams, Ecosystem, Plant, Species};

/// Deussen et al.'s ecosystem figures (Deussen et al. 1998) not shown by
/// the plant examples: self-thinning, and species sorted by wetness.
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
    /// Fig. 6: eight species sorted by the wetness they prefer
    Species,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[Fig::SelfThinning, Fig::Species];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::SelfThinning => &[
                "deussen_fig04_self_thinning.png",
                "deussen_fig05_thinning_plot.png",
            ],
            Fig::Species => &["deussen_fig06_species_by_wetness.png"],
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
        Fig::Species => Ok(vec![species_by_wetness(q)?]),
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

/// Species of Fig. 6.
const KINDS: usize = 8;

/// Fig. 6's ecosystem: [`KINDS`] species alike but for the wetness they
/// prefer (species `k` at `k / 7`, 0 the driest site, 1 the wettest, with a
/// tolerance of 0.1), sown and thinned for 24 steps on an eroded terrain
/// of `n`² samples 2 m apart, its wetness natura-terrain's topographic
/// wetness. The source names the five parameters of a species but gives
/// none of their values.
fn species_run(n: usize) -> R<Ecosystem> {
    let hf = common::tiles::eroded_tile(n, 2.0, 1998, &NoProgress)?;
    let species = (0..KINDS)
        .map(|k| Species {
            name: format!("wetness {k}"),
            seeds_per_ha: 120.0,
            initial_per_ha: 400.0,
            r0_min: 0.2,
            r0_max: 0.5,
            max_radius: 2.5,
            growth: 0.12,
            survive_domination: 0.2,
            wet_optimum: k as f64 / (KINDS - 1) as f64,
            wet_tolerance: 0.1,
            light_tolerance: 10.0,
            altitude_min: 0.0,
            altitude_max: 1.0,
            max_slope: 1.2,
            vigor_spread: 0.3,
            ..Species::default()
        })
        .collect();
    let params = EcoParams {
        species,
        steps: 24,
        seed: Seed(6),
        ..EcoParams::default()
    };
    let mut eco = Ecosystem::new(&hf, params)?;
    eco.run(&NoProgress)?;
    Ok(eco)
}

/// The colour of species `k`: from ochre (dry) through green to blue (wet),
/// as the source draws its wet-loving species blue.
fn wet_colour(k: usize) -> Vec3 {
    let t = k as f32 / (KINDS - 1) as f32;
    let (dry, mid, wet) = (
        Vec3::new(0.85, 0.40, 0.0),
        Vec3::new(0.05, 0.55, 0.05),
        Vec3::new(0.0, 0.12, 0.85),
    );
    if t < 0.5 {
        dry.lerp(mid, 2.0 * t)
    } else {
        mid.lerp(wet, 2.0 * t - 1.0)
    }
}

/// The mean wetness of the sites of each species' plants.
fn mean_wetness(eco: &Ecosystem) -> Vec<f64> {
    let site = eco.site();
    let mut sum = [(0.0f64, 0usize); KINDS];
    for p in eco.plants() {
        let (i, j) = site.nearest(p.x, p.y);
        let e = &mut sum[p.species as usize];
        e.0 += f64::from(site.wetness[(i, j)]);
        e.1 += 1;
    }
    sum.iter().map(|&(w, n)| w / n.max(1) as f64).collect()
}

/// Fig. 6: the terrain's wetness (left, white dry to blue wet) and the
/// plants on a faint copy of it (right), each circle coloured by the
/// wetness its species prefers.
fn species_by_wetness(quick: bool) -> R<Image> {
    let n = if quick { 64 } else { 112 };
    let eco = species_run(n)?;
    let wet = mean_wetness(&eco);
    outln(format_args!(
        "  Fig. 6: {} plants; mean site wetness by species, driest-loving first: {}",
        eco.plants().len(),
        wet.iter()
            .map(|w| format!("{w:.2}"))
            .collect::<Vec<_>>()
            .join(" ")
    ))?;
    let site = eco.site();
    let (ex, ey) = site.extent();
    let size = if quick { 256 } else { 600 };
    let (gw, gh) = site.wetness.dims();
    let map = Image::from_fn(size, size, |x, y| {
        let i = (x * gw / size).min(gw - 1);
        let j = ((size - 1 - y) * gh / size).min(gh - 1);
        Vec3::ONE.lerp(
            Vec3::new(0.1, 0.3, 0.85),
            site.wetness[(i, j)].clamp(0.0, 1.0),
        )
    })?;
    let mut c = Canvas::new(size, size);
    let panel = Panel::new(
        [0.0, 0.0, size as f32, size as f32],
        [0.0, f64::from(ex), 0.0, f64::from(ey)],
    );
    let px = size as f32 / ex;
    for p in eco.plants() {
        c.dots(
            &panel,
            &[(f64::from(p.x), f64::from(p.y))],
            wet_colour(p.species as usize),
            (p.radius * px).max(0.8),
        );
    }
    // The plants over a faint copy of the map (where the canvas is blank).
    let plants = c.into_image()?;
    let over = Image::from_fn(size, size, |x, y| {
        let p = plants.get(x, y).unwrap_or(Vec3::ONE);
        if p.min_element() > 0.999 {
            Vec3::ONE.lerp(map.get(x, y).unwrap_or(Vec3::ONE), 0.45)
        } else {
            p
        }
    })?;
    Ok(Image::contact_sheet(&[map, over], 2, 6, Vec3::ONE)?)
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

    #[test]
    fn species_settle_where_the_wetness_suits_them() {
        // Fig. 6: the wet-loving species gather in the wet places. The
        // mean wetness under each species rises with the wetness it
        // prefers, and the wettest-loving sits far wetter than the driest.
        let eco = species_run(64).unwrap();
        let wet = mean_wetness(&eco);
        let rising = wet.windows(2).filter(|w| w[1] > w[0]).count();
        assert!(rising >= KINDS - 2, "{wet:?}");
        assert!(wet[KINDS - 1] > wet[0] + 0.3, "{wet:?}");
    }
}
