//! Writes one false-colour picture per natura-noise basis and fractal, all
//! with the same seed, plus a contact sheet of them all.
//!
//! ```text
//! cargo run --release --example noise_gallery                 # 256² tiles into ./noise_gallery/
//! cargo run --release --example noise_gallery -- --quick --out /tmp/noise
//! cargo run --release --example noise_gallery -- --size 512 --seed 3
//! cargo run --release --example noise_gallery -- --help       # every flag and its default
//! ```
//!
//! Each file is named after what it shows (`basis_perlin.png`,
//! `fractal_ridged_multifractal.png`, …); `contact_sheet.png` tiles them in
//! the order of `index.md`. Values are mapped through the viridis ramp from
//! each picture's own minimum to maximum (terrain-like fractals use the
//! terrain ramp; the multiplicative cascade, whose values span decades, is
//! shown on a logarithmic scale). Everything goes into `--out` (default: `./noise_gallery/`).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::DVec2;
use natura::core::{Grid2, Image, Progress, Ramp, io};
use natura::noise::*;

struct Tile {
    name: &'static str,
    what: &'static str,
    field: Box<dyn Field>,
    /// Lattice cells across the picture.
    span: f64,
    ramp: Ramp,
    /// Whether the picture shows the logarithm of the field.
    log: bool,
}

fn tiles(seed: u64) -> natura::noise::Result<Vec<Tile>> {
    let p = Perlin::new(seed);
    let s = Spectral::default();
    let t = |name, what, field: Box<dyn Field>, span, ramp| Tile {
        name,
        what,
        field,
        span,
        ramp,
        log: false,
    };
    let worley = |feature, metric| {
        Worley::new(
            seed,
            WorleyParams {
                feature,
                metric,
                jitter: 1.0,
                ..WorleyParams::default()
            },
        )
    };
    let v = Ramp::Viridis;
    let terrain = Ramp::Terrain;
    Ok(vec![
        t(
            "basis_perlin",
            "Perlin gradient noise, quintic fade (Musgrave 1993, §2.3.1)",
            Box::new(p),
            8.0,
            v,
        ),
        t(
            "basis_perlin_cubic",
            "Perlin noise with the sources' cubic fade",
            Box::new(Perlin::with_fade(seed, Fade::Cubic)),
            8.0,
            v,
        ),
        t(
            "basis_value_linear",
            "value noise, linear interpolation (Musgrave 2001, \"Linear\")",
            Box::new(Value::new(seed)),
            8.0,
            v,
        ),
        t(
            "basis_value_quintic",
            "value noise, quintic fade",
            Box::new(Value::with_interp(seed, ValueInterp::Quintic)),
            8.0,
            v,
        ),
        t(
            "basis_simplex",
            "simplex noise",
            Box::new(Simplex::new(seed)),
            8.0,
            v,
        ),
        t(
            "basis_worley_f1",
            "Worley F1, Euclidean (Musgrave 2001, \"Voronoi\")",
            Box::new(worley(WorleyFeature::F1, Metric::Euclidean)?),
            8.0,
            v,
        ),
        t(
            "basis_worley_f1_squared",
            "Worley F1, distance squared",
            Box::new(worley(WorleyFeature::F1, Metric::EuclideanSquared)?),
            8.0,
            v,
        ),
        t(
            "basis_worley_f2",
            "Worley F2",
            Box::new(worley(WorleyFeature::F2, Metric::Euclidean)?),
            8.0,
            v,
        ),
        t(
            "basis_worley_f2_minus_f1",
            "Worley F2 − F1 (cell edges)",
            Box::new(worley(WorleyFeature::F2MinusF1, Metric::Euclidean)?),
            8.0,
            v,
        ),
        t(
            "basis_worley_f1_manhattan",
            "Worley F1, Manhattan",
            Box::new(worley(WorleyFeature::F1, Metric::Manhattan)?),
            8.0,
            v,
        ),
        t(
            "basis_worley_f1_chebyshev",
            "Worley F1, Chebyshev",
            Box::new(worley(WorleyFeature::F1, Metric::Chebyshev)?),
            8.0,
            v,
        ),
        t(
            "basis_sparse_convolution",
            "sparse convolution, cone kernel (Musgrave 2001, \"Sparse Convolution\")",
            Box::new(SparseConvolution::new(seed, SparseParams::default())?),
            8.0,
            v,
        ),
        t(
            "basis_sine",
            "sine product (Musgrave 2001, \"Sine\")",
            Box::new(Sine),
            25.0,
            v,
        ),
        t(
            "basis_steps",
            "steps (Musgrave 2001, \"Steps\")",
            Box::new(Steps::new(seed)),
            8.0,
            v,
        ),
        t(
            "basis_checkerboard",
            "checkerboard (Musgrave 2001, \"Checkerboard\")",
            Box::new(Checkerboard),
            8.0,
            v,
        ),
        t(
            "basis_ridged",
            "ridged basis 1 − |N| (Musgrave 1993, §2.3.2.5.3)",
            Box::new(Ridged(p)),
            8.0,
            v,
        ),
        t(
            "fractal_fbm",
            "fBm, H = 0.5, λ = e − ½, 8 octaves (Musgrave 1993, §2.3.2.1)",
            Box::new(Fbm::new(p, s)?),
            4.0,
            terrain,
        ),
        t(
            "fractal_fbm_h08",
            "fBm, H = 0.8 (terrain-like)",
            Box::new(Fbm::new(p, s.with_h(0.8))?),
            4.0,
            terrain,
        ),
        t(
            "fractal_turbulence",
            "turbulence Σ w|N|",
            Box::new(Turbulence::new(p, s)?),
            4.0,
            v,
        ),
        // A product of octaves spans decades, a few peaks towering over a
        // dark floor: its logarithm (a sum of octaves) is what the eye can read.
        Tile {
            log: true,
            ..t(
                "fractal_multifractal",
                "multiplicative cascade, logarithmic scale",
                Box::new(Multifractal::new(p, MultifractalParams::default())?),
                4.0,
                Ramp::Magma,
            )
        },
        t(
            "fractal_hetero_terrain",
            "heterogeneous terrain (Musgrave 1993, §2.3.2.5)",
            Box::new(HeteroTerrain::new(p, HeteroTerrainParams::default())?),
            4.0,
            terrain,
        ),
        t(
            "fractal_hell",
            "heterogeneous terrain of the ridged basis (\"Hell\", Musgrave 1993, Plate 2.9)",
            Box::new(HeteroTerrain::new(
                Ridged(p),
                HeteroTerrainParams::default(),
            )?),
            4.0,
            terrain,
        ),
        t(
            "fractal_hybrid_multifractal",
            "hybrid multifractal",
            Box::new(HybridMultifractal::new(p, HybridParams::default())?),
            4.0,
            terrain,
        ),
        t(
            "fractal_ridged_multifractal",
            "ridged multifractal (\"Emil\")",
            Box::new(RidgedMultifractal::new(p, RidgedParams::default())?),
            4.0,
            terrain,
        ),
        t(
            "fractal_stats_by_altitude",
            "statistics by altitude (hfBm equation) (Musgrave 1993, §2.3.2.3.1)",
            Box::new(StatsByAltitude::new(p, StatsByAltitudeParams::default())?),
            4.0,
            terrain,
        ),
        t(
            "fractal_fbm_of_worley",
            "fBm of Worley F1",
            Box::new(Fbm::new(worley(WorleyFeature::F1, Metric::Euclidean)?, s)?),
            4.0,
            v,
        ),
        t(
            "fractal_fbm_simplex",
            "fBm of simplex noise",
            Box::new(Fbm::new(Simplex::new(seed), s)?),
            4.0,
            terrain,
        ),
        t(
            "fractal_crossover",
            "crossover: Perlin at large scales, Worley at small",
            Box::new(CrossoverFbm::new(
                p,
                worley(WorleyFeature::F1, Metric::Euclidean)?,
                s,
                0.5,
                0.1,
            )?),
            4.0,
            v,
        ),
        t(
            "fractal_filtered_fbm",
            "filtered fBm (octaves finer than 1/64 dropped)",
            Box::new(FilteredFbm::new(p, s, 1.0 / 64.0)?),
            4.0,
            terrain,
        ),
        t(
            "fractal_driven_h",
            "fBm with H varying 0 → 1 across the picture (Musgrave 1993, §2.3.2.2)",
            Box::new(Driven::new(p, s, DrivenKind::Fbm)?.with_h(Param::Field(
                std::sync::Arc::new(Transform::new(XRamp).with_range(0.5, 0.5)),
            ))),
            4.0,
            terrain,
        ),
        t(
            "distortion_distnoise",
            "DistNoise, d = 1 (Musgrave 1998, \"A Variety of fBm\")",
            Box::new(DistNoise::dist_noise(p, 1.0)?),
            8.0,
            v,
        ),
        t(
            "distortion_vlnoise",
            "VLNoise (C form) (Musgrave 1993, §5.2)",
            Box::new(VlNoise::vl_noise(p, 1.0)?),
            8.0,
            v,
        ),
        t(
            "distortion_fbm_distnoise",
            "fBm of DistNoise (Plate 2.7d)",
            Box::new(Fbm::new(
                DistNoise::dist_noise(p, 1.0)?,
                s.with_octaves(6.0),
            )?),
            4.0,
            v,
        ),
        t(
            "distortion_cyclone",
            "cyclone twist of fBm (Musgrave 1993, §5.3)",
            Box::new(Warped {
                field: Fbm::new(p, s)?,
                warp: Twist::new(TwistLaw::Cyclone {
                    max_radius: 1.6,
                    twist: 0.5,
                    power: 2.0,
                })?,
            }),
            4.0,
            v,
        ),
        t(
            "distortion_vector_fbm",
            "fBm displaced by vector fBm (\"cotton\", Fig 15.3)",
            Box::new(Warped {
                field: Fbm::new(p, s)?,
                warp: Displace::new(VectorFbm::new(VecNoise::new(p), s.with_octaves(4.0))?, 0.5)?,
            }),
            4.0,
            v,
        ),
        t(
            "distortion_curl",
            "fBm displaced by curl noise, divergence-free (Bridson et al. 2007, §2)",
            Box::new(Warped {
                field: Fbm::new(p, s)?,
                warp: Displace::new(CurlNoise::new(p), 0.25)?,
            }),
            4.0,
            v,
        ),
    ])
}

/// Replaces a non-negative field by its natural logarithm, from the
/// smallest positive value the picture holds (zeros, where one octave's
/// factor vanished, take that floor); refuses negative values.
fn to_log(g: &mut Grid2<f32>, name: &str) -> Run {
    let floor = g
        .as_slice()
        .iter()
        .copied()
        .filter(|&v| v > 0.0)
        .fold(f32::INFINITY, f32::min);
    if !floor.is_finite() || g.as_slice().iter().any(|&v| v < 0.0) {
        return Err(common::Exit::new(
            2,
            format!("{name}: a logarithmic picture needs values ≥ 0, some > 0"),
        ));
    }
    g.as_mut_slice()
        .iter_mut()
        .for_each(|v| *v = v.max(floor).ln());
    Ok(())
}

/// x across the picture, from −1 to 1 (drives H in `fractal_driven_h`).
#[derive(Debug)]
struct XRamp;

impl Field for XRamp {
    fn eval2(&self, p: DVec2) -> f64 {
        (p.x / 2.0).clamp(-1.0, 1.0)
    }
    fn eval3(&self, p: natura::core::glam::DVec3) -> f64 {
        (p.x / 2.0).clamp(-1.0, 1.0)
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        0.5
    }
    fn lipschitz3(&self) -> f64 {
        0.5
    }
}

/// One false-colour picture per natura-noise basis, fractal and distortion,
/// all with the same seed, plus contact_sheet.png (all of them, in the order
/// of index.md) and index.md (what each picture shows).
#[derive(Parser)]
#[command(name = "noise_gallery", version)]
struct Cli {
    /// Small pictures (CI)
    #[arg(long)]
    quick: bool,
    /// Pixels per side of each picture [default: 256; 96 with --quick]
    #[arg(long, value_parser = common::in_range(8usize, 16384))]
    size: Option<usize>,
    /// Random seed
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "noise_gallery")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(gallery)
}

/// The program: every error returns through [`common::run`].
fn gallery() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 96 } else { 256 });
    let seed = cli.seed;
    let out = common::out_dir(&cli.out)?;

    let tiles = tiles(seed)?;
    let bar = common::Bar::new();
    bar.start("pictures", tiles.len() as u64);
    let mut thumbs = Vec::new();
    let mut index = String::from(
        "# natura-noise gallery\n\nSame seed for every picture; contact_sheet.png tiles them in this order (left to right, top to bottom).\n\n| file | what |\n|---|---|\n",
    );
    for t in &tiles {
        let mut g = Grid2::new(size, size, 0.0f32)?;
        let step = t.span / size as f64;
        // Centre the picture on the origin; rows in parallel, each a batch fill.
        let origin = -t.span / 2.0;
        let field = &t.field;
        g.par_rows_mut(|j, row| {
            let y = origin + (size - 1 - j) as f64 * step;
            field.fill_row2(DVec2::new(origin, y), step, row);
        });
        if let Some((x, y, v)) = g.find(|v| !v.is_finite()) {
            return Err(common::Exit::new(
                2,
                format!("{}: non-finite value {v} at ({x}, {y})", t.name),
            ));
        }
        if t.log {
            to_log(&mut g, t.name)?;
        }
        let img = Image::false_colour_auto(&g, t.ramp);
        let path = out.join(format!("{}.png", t.name));
        img.save_png(&path)?;
        index.push_str(&format!("| `{}.png` | {} |\n", t.name, t.what));
        // Only the thumbnail is kept for the contact sheet (at most 128 px).
        thumbs.push(img.fit_within(128)?);
        bar.advance(1);
    }
    bar.finish();

    // Contact sheet: 6 columns of thumbnails, 2-pixel dark gutters.
    let sheet = Image::contact_sheet(&thumbs, 6, 2, natura::core::glam::Vec3::splat(0.02))?;
    sheet.save_png(out.join("contact_sheet.png"))?;
    io::write_bytes_atomic(out.join("index.md"), index.as_bytes())?;
    outln(format_args!(
        "wrote {} pictures, contact_sheet.png and index.md to {}",
        tiles.len(),
        out.display()
    ))
}
