//! Měch & Prusinkiewicz's figures (Měch & Prusinkiewicz 1996) that the
//! plant examples do not show: the number of terminal segments of the
//! light-competing tree against time, with and without competition
//! (Fig. 11).
//!
//! ```text
//! cargo run --release --example figures_mech                 # every figure
//! cargo run --release --example figures_mech -- --quick      # small, for CI
//! ```
//!
//! Writes into `--out` (default `./figures_mech/`); docs/figures.md sets
//! each beside the source's caption. Plots carry no text.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::figures::{self, Figure};
use common::plot::{Canvas, Panel, Pen, colour};
use common::{Exit, Run, outln};
use natura::core::Image;
use natura::plant::models::crowns::{CrownParams, crowns};

/// Měch & Prusinkiewicz's figures (Měch & Prusinkiewicz 1996) not shown by
/// the plant examples: terminal segments against time.
#[derive(Parser)]
#[command(name = "figures_mech", version)]
struct Cli {
    /// Small and fast (CI): fewer years
    #[arg(long)]
    quick: bool,
    /// Only this figure; repeat for several [default: all]
    #[arg(long, value_enum, value_name = "NAME")]
    only: Vec<Fig>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "figures_mech")]
    out: PathBuf,
}

/// The figures, in the source's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Fig {
    /// Fig. 11: terminal segments by year, unlimited bifurcation against light competition
    TerminalCounts,
}

impl Figure for Fig {
    const ALL: &'static [Fig] = &[Fig::TerminalCounts];

    fn files(self) -> &'static [&'static str] {
        match self {
            Fig::TerminalCounts => &["mech_fig11_terminal_counts.png"],
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
        Fig::TerminalCounts => Ok(vec![terminal_counts(q)?]),
    })
}

/// The apices `A` of the tree grown for `years` years: its terminal
/// segments. With `compete`, leaf clusters shade each other (the source's
/// model: transmittance τ = 0.25); without, the leaves are transparent
/// (τ = 1), so every cluster sees the whole sky and every apex branches
/// every year — the source's "unlimited bifurcation".
fn apices(years: u32, compete: bool) -> R<usize> {
    let p = CrownParams {
        years,
        transmittance: if compete { 0.25 } else { 1.0 },
        ..CrownParams::default()
    };
    Ok(crowns(&p)?.count("A"))
}

/// Terminal segments for years `0..=years`, with and without competition.
fn counts(years: u32) -> R<[Vec<usize>; 2]> {
    let mut out = [Vec::new(), Vec::new()];
    for y in 0..=years {
        out[0].push(apices(y, false)?);
        out[1].push(apices(y, true)?);
    }
    Ok(out)
}

/// Fig. 11: log₂ of the number of terminal segments against years;
/// unlimited bifurcation (dashed, doubling every year) and the tree
/// competing for light (solid).
fn terminal_counts(quick: bool) -> R<Image> {
    let years = if quick { 8 } else { 14 };
    let [free, lit] = counts(years)?;
    for (y, (a, b)) in free.iter().zip(&lit).enumerate() {
        outln(format_args!(
            "  Fig. 11: year {y}: {a} terminal segments unlimited, {b} competing for light"
        ))?;
    }
    let mut c = Canvas::new(700, 500);
    let top = f64::from(years) + 0.5;
    let panel = Panel::new(
        c.grid(1, 1, 30.0, [0.0, 1.0, 0.0, 1.0])[0].rect,
        [-0.3, f64::from(years) + 0.3, -0.3, top],
    );
    c.axes(&panel, [1.0, 1.0]);
    let line = |v: &[usize]| -> Vec<(f64, f64)> {
        v.iter()
            .enumerate()
            .map(|(y, &n)| (y as f64, (n.max(1) as f64).log2()))
            .collect()
    };
    let (free, lit) = (line(&free), line(&lit));
    c.line(&panel, &free, Pen::dashed(colour::RED, 2.0));
    c.dots(&panel, &free, colour::RED, 4.0);
    c.line(&panel, &lit, Pen::solid(colour::BLUE, 2.2));
    c.dots(&panel, &lit, colour::BLUE, 4.0);
    Ok(c.into_image()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unlimited_bifurcation_doubles_the_terminal_segments_every_year() {
        // Fig. 11: "with unlimited bifurcation, the number of terminal
        // segments doubles every year".
        let [free, _] = counts(5).unwrap();
        assert_eq!(free, vec![1, 2, 4, 8, 16, 32]);
    }

    #[test]
    fn competing_for_light_slows_the_growth() {
        // Fig. 11: with competition the count grows more slowly. The young
        // tree's clusters do not yet shade each other enough to stop an
        // apex (6 years: 64, as unlimited); from the seventh year the count
        // falls below the doubling, and keeps growing.
        let [free, lit] = counts(8).unwrap();
        assert_eq!(lit[..=6], free[..=6]);
        for y in 7..=8 {
            assert!(lit[y] < free[y], "year {y}: {} vs {}", lit[y], free[y]);
            assert!(lit[y] > lit[y - 1], "{lit:?}");
        }
    }
}
