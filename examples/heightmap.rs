//! Renders a height map as a shaded relief picture: terrain false colour times
//! a hill shade, north up.
//!
//! ```text
//! cargo run --release --example heightmap                        # a synthetic field
//! cargo run --release --example heightmap -- --quick --out /tmp/heightmap
//! cargo run --release --example heightmap -- --input dem.png --cell-size 30 --range 0,4000
//! cargo run --release --example heightmap -- --help              # every flag and its default
//! ```
//!
//! Writes `heightmap.png` into `--out` (default: `./heightmap/`). Without
//! `--input`, the field is a sum of bilinearly interpolated position-indexed
//! Gaussian values (natura-core's `Seed::gaussian2`), the simplest stochastic
//! surface core can make on its own.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::scene::{LatticeTerrain, lattice_terrain};
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{HeightField, Image, Ramp, Seed};

/// Renders a height map (a file, or a synthetic field made by natura-core
/// alone) as a shaded relief picture, terrain false colour times a hill
/// shade, north up. Writes heightmap.png.
#[derive(Parser)]
#[command(name = "heightmap", version)]
struct Cli {
    /// Small synthetic field (CI)
    #[arg(long)]
    quick: bool,
    /// Samples per side of the synthetic field [default: 1024; 128 with
    /// --quick]
    #[arg(long)]
    size: Option<usize>,
    /// Random seed of the synthetic field
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Height map to load (.png or .exr) instead of the synthetic field
    /// [default: none, the synthetic field]
    #[arg(long, value_name = "FILE")]
    input: Option<PathBuf>,
    /// Metres between samples, overriding the file's [default: the file's;
    /// 10 for the synthetic field]
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    cell_size: Option<f32>,
    /// Heights in metres of grey 0 and white in a PNG [default: the range
    /// stored in the file]
    #[arg(long, value_name = "LO,HI", value_parser = common::parse_range, allow_hyphen_values = true)]
    range: Option<(f32, f32)>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "heightmap")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(heightmap)
}

/// The program: every error returns through [`common::run`].
fn heightmap() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 128 } else { 1024 });
    let out = common::out_dir(&cli.out)?;

    let hf = match &cli.input {
        Some(path) => HeightField::load(path, cli.cell_size, cli.range)?,
        None => lattice_terrain(
            size,
            cli.cell_size.unwrap_or(10.0),
            Seed(cli.seed),
            &LatticeTerrain::FBM,
        )?,
    };

    let (lo, hi) = hf.min_max();
    let shade = hf.hillshade(Vec3::new(-1.0, 1.0, 1.2).normalize())?;
    let (nx, ny) = (hf.nx(), hf.ny());
    // Map orientation: image row 0 is the grid row of largest y (north).
    let img = Image::from_fn(nx, ny, |x, r| {
        let j = ny - 1 - r;
        let h = hf.heights()[(x, j)];
        Ramp::Terrain.map(h, lo, hi) * (0.25 + 0.75 * shade[(x, j)])
    })?;
    let png = out.join("heightmap.png");
    img.save_png(&png)?;
    outln(format_args!(
        "{nx} × {ny} samples, heights {lo:.1} … {hi:.1} m"
    ))?;
    outln(format_args!("wrote {}", png.display()))
}
