//! Steam rising from a teacup (Ebert 2001, slides "Steam rising from a
//! teacup"): the basic gas shaped radially and vertically, drifting up with
//! time over a cup of tea. Four moments, lit from behind and the side, with
//! Ebert's shadow-table march.
//!
//! ```text
//! cargo run --release --example steam                 # 320 × 400 frames
//! cargo run --release --example steam -- --quick      # small, for CI
//! cargo run --release --example steam -- --seed 5 --out renders
//! cargo run --release --example steam -- --help       # every flag and its default
//! ```
//!
//! Writes `steam.png` (the four moments side by side) into `--out`
//! (default: `./steam/`), with a progress bar over the frames.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::{Image, NoProgress, Progress, ToneMap};
use natura::volume::scene::SteamCup;
use natura::volume::transport::{CacheParams, FastRenderer, Scattering, Shadows};

/// Steam rising from a teacup (Ebert's basic gas, shaped and drifting up):
/// four moments rendered with the shadow-table march. Writes steam.png, the
/// four side by side.
#[derive(Parser)]
#[command(name = "steam", version)]
struct Cli {
    /// Small and fast (CI): 64 × 80 frames, a coarser shadow table
    #[arg(long)]
    quick: bool,
    /// Noise seed
    #[arg(long, default_value_t = 3)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "steam")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(steam)
}

fn steam() -> Run {
    let cli: Cli = common::parse();
    let out = common::out_dir(&cli.out)?;
    let (quick, seed) = (cli.quick, cli.seed);
    let (w, h) = if quick { (64, 80) } else { (320, 400) };
    let times = [0.0f32, 0.5, 1.0, 1.5];
    let bar = common::Bar::new();
    // Two units per frame: its shadow tables and its render.
    bar.start("frames", 2 * times.len() as u64);
    let mut shots = Vec::new();
    for time in times {
        let cup = SteamCup::new(time, seed, w as u32, h as u32)?;
        let mut settings = cup.fast_settings();
        if quick {
            settings.shadows = Shadows::Table(32);
            settings.scattering = quick_cache();
        }
        let scene = cup.scene();
        let fast = FastRenderer::new(&scene, settings)?;
        bar.advance(1);
        // Two by two rays a pixel, resolved by the camera's pixel filter:
        // one ray a pixel leaves the cup's rim a staircase of lit pixels.
        shots.push(
            fast.render_supersampled(&cup.camera(), 2, &NoProgress)?
                .tone_mapped(0.5, ToneMap::AcesFilmic),
        );
        bar.advance(1);
    }
    bar.finish();
    let strip = Image::from_fn(w * 4 + 12, h, |x, y| {
        let (k, r) = (x / (w + 4), x % (w + 4));
        if r >= w {
            Vec3::ONE
        } else {
            shots[k].get(r, y).unwrap_or(Vec3::ONE)
        }
    })?;
    let path = out.join("steam.png");
    strip.save_png(&path)?;
    outln(format_args!("wrote {}", path.display()))
}

/// The multiple-scattering cache for `--quick`: a fortieth of the default
/// events (the set-up cost; the picture is noisier).
fn quick_cache() -> Scattering {
    Scattering::Cache(CacheParams {
        events: 100_000,
        local: 100_000,
        ..CacheParams::default()
    })
}
