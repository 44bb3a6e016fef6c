//! Erosion gallery: a ridged-multifractal terrain eroded by each natura-terrain
//! method, written as hill-shaded relief pictures, a flow map and 16-bit height
//! maps.
//!
//! ```text
//! cargo run --release --example erosion                 # 1024² into ./erosion/
//! cargo run --release --example erosion -- --quick --out /tmp/erosion
//! cargo run --release --example erosion -- --only pipe --size 512
//! cargo run --release --example erosion -- --help       # every flag and its default
//! ```
//!
//! Writes `erosion_*.png` into `--out` (default: `./erosion/`), with a
//! progress bar per erosion run.

mod common;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use clap::builder::PossibleValuesParser;
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Grid2, HeightField, Image, Seed};
use natura::noise::{Perlin, RidgedMultifractal, RidgedParams, Spectral};
use natura::terrain::analysis::{self, Depressions};
use natura::terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, Edges, Erodibility,
    MusgraveHydraulic, MusgraveParams, PipeModel, PipeParams, StreamPower, StreamPowerParams,
    Thermal, ThermalParams,
};
use natura::terrain::export;
use natura::terrain::synth::{FieldMapping, fill_noise};

/// The erosion methods, in the order they run (`--only`).
const METHODS: [&str; 7] = [
    "stream_power",
    "musgrave",
    "pipe",
    "droplets",
    "thermal",
    "diffusion",
    "combined",
];

/// A ridged-multifractal terrain (a 10 km tile, 1500 m of relief) eroded by
/// each natura-terrain method. Writes hill-shaded relief pictures
/// (erosion_*.png), a flow map, a deposition map and 16-bit height maps.
#[derive(Parser)]
#[command(name = "erosion", version)]
struct Cli {
    /// Small terrain, few steps (CI)
    #[arg(long)]
    quick: bool,
    /// Samples per side (the tile stays 10 km across; steps scale with it)
    /// [default: 1024; 128 with --quick]
    #[arg(long, value_parser = common::in_range(16usize, 16384))]
    size: Option<usize>,
    /// Random seed
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Run one method only [default: every method]
    #[arg(long, value_name = "METHOD", value_parser = PossibleValuesParser::new(METHODS))]
    only: Option<String>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "erosion")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(erosion)
}

/// The program: every error returns through [`common::run`].
fn erosion() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 128 } else { 1024 });
    let seed = cli.seed;
    let only = cli.only;
    let out = common::out_dir(&cli.out)?;
    let want = |name: &str| only.as_deref().is_none_or(|o| o == name);
    let bar = common::Bar::new();
    // Work scales with the grid so --quick stays quick; steps are per 1024².
    let scale = size as f64 / 1024.0;
    let steps = |n: f64| ((n * scale).round() as u32).max(10);
    let cell = 10.0 * 1024.0 / size as f32; // a 10 km tile at any resolution

    // ---- the ridged multifractal (natura-noise), 1500 m of relief.
    let spectral = Spectral::default()
        .with_h(1.0)
        .with_lacunarity(natura::noise::DEFAULT_LACUNARITY)
        .with_octaves(8.0)
        .with_frequency(1.0 / 3500.0);
    let ridged = RidgedMultifractal::new(
        Perlin::new(seed),
        RidgedParams {
            spectral,
            ..Default::default()
        },
    )?;
    let mut base = fill_noise(
        size,
        size,
        cell,
        &FieldMapping {
            frequency: 1.0,
            height_m: 1.0,
            ..Default::default()
        },
        &ridged,
    )?;
    let (lo, hi) = base.min_max();
    base.heights_mut()
        .as_mut_slice()
        .iter_mut()
        .for_each(|v| *v = (*v - lo) / (hi - lo) * 1500.0);
    save_relief(&base, &out.join("erosion_before.png"))?;
    export::save_height_png16(
        &downsample_hf(&base)?,
        out.join("erosion_before_height.png"),
    )?;

    // ---- stream power with uplift: the drainage network. The map edge is the
    // base level (sea level, 0 m) that every river reaches.
    let mut sp_hf = base.clone();
    let (nx, ny) = (sp_hf.nx(), sp_hf.ny());
    for j in 0..ny {
        for i in 0..nx {
            if i == 0 || j == 0 || i == nx - 1 || j == ny - 1 {
                sp_hf.heights_mut()[(i, j)] = 0.0;
            }
        }
    }
    let strata = Erodibility::strata(&base, 120.0, 1.4, 0.6, None)?;
    let sp_params = StreamPowerParams {
        k: 4e-5,
        dt_yr: 10_000.0,
        ..Default::default()
    };
    let mut sp = StreamPower::new(sp_params, &sp_hf).and_then(|m| m.with_erodibility(strata))?;
    if want("stream_power") || want("combined") {
        sp.run(&mut sp_hf, steps(120.0), &bar)?;
    }
    if want("stream_power") {
        save_relief(&sp_hf, &out.join("erosion_stream_power.png"))?;
        export::save_height_png16(
            &downsample_hf(&sp_hf)?,
            out.join("erosion_stream_power_height.png"),
        )?;
        let area = analysis::flow_accumulation_d8(&sp_hf, Depressions::Route)?;
        save(&export::flow_image(&area)?, &out.join("erosion_flow.png"))?;
    }

    if want("musgrave") {
        // ---- Musgrave–Kolb–Mace hydraulic (corrected) + thermal, as in MKM Plate 9.
        let mut mkm_hf = base.clone();
        let mkm = MusgraveParams {
            rain_period: 20,
            k_c: 5.0,
            ..Default::default()
        };
        let mut m = MusgraveHydraulic::new(mkm, &mkm_hf)?;
        m.run(&mut mkm_hf, steps(200.0), &bar)?;
        let th = ThermalParams {
            talus_rate: 0.05,
            ..Default::default()
        };
        Thermal::new(th, &mkm_hf)?.run(&mut mkm_hf, steps(100.0), &bar)?;
        save_relief(&mkm_hf, &out.join("erosion_musgrave.png"))?;
    }

    if want("pipe") {
        // ---- virtual-pipe shallow water.
        let mut pipe_hf = base.clone();
        let pp = PipeParams {
            edges: Edges::Open,
            rain_m_per_s: 0.02,
            k_c: 0.1,
            ..Default::default()
        };
        let mut pipe = PipeModel::new(pp, &pipe_hf)?;
        pipe.run(&mut pipe_hf, steps(600.0), &bar)?;
        save_relief(&pipe_hf, &out.join("erosion_pipe.png"))?;
    }

    if want("droplets") {
        // ---- droplets.
        let mut drop_hf = base.clone();
        let mut drops = DropletErosion::new(DropletParams::default(), &drop_hf, Seed(seed))?;
        drops.run(
            &mut drop_hf,
            (400_000.0 * scale * scale).max(5000.0) as u64,
            &bar,
        )?;
        save_relief(&drop_hf, &out.join("erosion_droplets.png"))?;
    }

    // ---- thermal weathering and diffusion alone.
    if want("thermal") {
        let mut th_hf = base.clone();
        let th = ThermalParams {
            talus_rate: 0.1,
            ..Default::default()
        };
        Thermal::new(th, &th_hf)?.run(&mut th_hf, steps(300.0), &bar)?;
        save_relief(&th_hf, &out.join("erosion_thermal.png"))?;
    }

    if want("diffusion") {
        let mut df_hf = base.clone();
        Diffusion::new(DiffusionParams::default(), &df_hf)?.run(&mut df_hf, steps(100.0), &bar)?;
        save_relief(&df_hf, &out.join("erosion_diffusion.png"))?;
    }

    if want("combined") {
        // ---- the landscape pipeline: stream power, then pipe-model and thermal detail.
        let mut combo = sp_hf.clone();
        let mut pipe = PipeModel::new(
            PipeParams {
                edges: Edges::Open,
                ..Default::default()
            },
            &combo,
        )?;
        pipe.run(&mut combo, steps(300.0), &bar)?;
        let th = ThermalParams {
            talus_rate: 0.05,
            ..Default::default()
        };
        Thermal::new(th, &combo)?.run(&mut combo, steps(50.0), &bar)?;
        save_relief(&combo, &out.join("erosion_combined.png"))?;
        let hi = analysis::hypsometric_integral(&combo).unwrap_or(0.0);
        outln(format_args!(
            "hypsometric integral after stream power + pipe + thermal {hi:.3}"
        ))?;
        export::save_height_png16(
            &downsample_hf(&combo)?,
            out.join("erosion_combined_height.png"),
        )?;
        // Net deposition swings by metres either way from one cell to the
        // next (the per-cell balance of pick-up and drop-off): its mean over
        // 50 m, on the scale of that mean, tints the hill shading, north up
        // like the relief pictures, so it reads against the valleys.
        let r = (2.0 * scale).round().max(1.0) as usize;
        let deposit = box_blur(&pipe.deposition()?, r)?;
        let lim = quantile_abs(&deposit, 0.99).max(1e-6);
        let shade = export::hillshade_image(&combo, Vec3::new(-1.0, 1.0, 0.9).normalize())?;
        let (nx, ny) = deposit.dims();
        let img = Image::from_fn(nx, ny, |x, row| {
            let c = natura::core::Ramp::Coolwarm.map(deposit[(x, ny - 1 - row)], -lim, lim);
            c * (0.35 + 0.65 * shade.pixels()[(x, row)].x)
        })?;
        save(&img, &out.join("erosion_deposition.png"))?;
        outln(format_args!(
            "deposition (mean over {} m) shown from −{lim:.2} m to +{lim:.2} m",
            f64::from(cell) * (2 * r + 1) as f64
        ))?;
    }

    let hi_before = analysis::hypsometric_integral(&base).unwrap_or(0.0);
    outln(format_args!(
        "{size} × {size} cells of {cell} m; hypsometric integral before {hi_before:.3}"
    ))?;
    outln(format_args!("wrote pictures to {}", out.display()))
}

/// The mean of `g` over the `(2r + 1)²` cells round each cell (clamped at
/// the edges): two passes of a running sum.
fn box_blur(g: &Grid2<f32>, r: usize) -> Result<Grid2<f32>, common::Exit> {
    let (nx, ny) = g.dims();
    let pass = |src: &[f32], n: usize, m: usize, at: &dyn Fn(usize, usize) -> usize| {
        let mut out = vec![0.0f32; src.len()];
        for j in 0..m {
            let mut sum = 0.0f64;
            let mut count = 0usize;
            for i in 0..n.min(r + 1) {
                sum += f64::from(src[at(i, j)]);
                count += 1;
            }
            for i in 0..n {
                out[at(i, j)] = (sum / count as f64) as f32;
                if i + r + 1 < n {
                    sum += f64::from(src[at(i + r + 1, j)]);
                    count += 1;
                }
                if i >= r {
                    sum -= f64::from(src[at(i - r, j)]);
                    count -= 1;
                }
            }
        }
        out
    };
    let rows = pass(g.as_slice(), nx, ny, &|i, j| j * nx + i);
    let both = pass(&rows, ny, nx, &|j, i| j * nx + i);
    Ok(Grid2::from_vec(nx, ny, both)?)
}

/// The `q`-quantile of `|v|` over `g`.
fn quantile_abs(g: &Grid2<f32>, q: f64) -> f32 {
    let mut a: Vec<f32> = g.as_slice().iter().map(|v| v.abs()).collect();
    a.sort_by(f32::total_cmp);
    a[((a.len() - 1) as f64 * q).round() as usize]
}

/// Gallery pictures are at most 512 px across (PNG size); heights stay f32.
fn downsample_hf(hf: &HeightField) -> Result<HeightField, common::Exit> {
    let factor = hf.nx().max(hf.ny()).div_ceil(512).max(1);
    Ok(hf.box_downsample(factor)?)
}

/// Writes `hf` as a hill-shaded relief picture.
fn save_relief(hf: &HeightField, path: &Path) -> Run {
    let img = export::relief_image(hf, Vec3::new(-1.0, 1.0, 0.9).normalize())?;
    save(&img, path)
}

/// Writes `img`, box-filtered to at most 512 px across.
fn save(img: &Image, path: &Path) -> Run {
    img.fit_within(512)?.save_png(path)?;
    Ok(())
}
