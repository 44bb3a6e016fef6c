//! A contact sheet of Musgrave's other worlds and elements: Venus under its
//! Coriolis-sheared clouds, a banded Jupiter with Saturn-like rings, Selene
//! with its rayed crater, a fire and a wind-rippled lake.
//!
//! ```text
//! cargo run --release --example planets                      # ./planets/planets.png
//! cargo run --release --example planets -- --quick --out /tmp/planets
//! cargo run --release --example planets -- --help            # every flag and its default
//! ```
//!
//! Writes `planets_venus.png`, `planets_jupiter.png`, `planets_selene.png`,
//! `planets_fire.png`, `planets_water.png` and the sheet `planets.png` into
//! `--out` (default: `./planets/`), with a progress bar per picture.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::Vec3;
use natura::core::io::check_writable;
use natura::core::{Image, ToneMap};
use natura::texture::fire::{Flame, FlameParams};
use natura::texture::planet::{Planet, PlanetParams, TraceSettings, direction};
use natura::texture::preview::{self, Plane};
use natura::texture::water::{WindyWave, WindyWaveParams};

/// A contact sheet of Musgrave's other worlds and elements: Venus under its
/// Coriolis-sheared clouds, a banded Jupiter with Saturn-like rings, Selene
/// with its rayed crater, a fire and a wind-rippled lake. Writes
/// planets_venus.png, planets_jupiter.png, planets_selene.png,
/// planets_fire.png, planets_water.png and the sheet planets.png.
#[derive(Parser)]
#[command(name = "planets", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Picture side, pixels [default: 512; 128 with --quick]
    #[arg(long, value_parser = common::in_range(8u32, 16_384))]
    size: Option<u32>,
    /// Random seed
    #[arg(long, default_value_t = 2)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "planets")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(planets)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn planets() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 128 } else { 512 });
    let seed = cli.seed;
    let out = common::out_dir(&cli.out)?;

    let names = ["venus", "jupiter", "selene", "fire", "water"];
    let sheet_path = out.join("planets.png");
    check_writable(&sheet_path)?;
    for n in names {
        check_writable(out.join(format!("planets_{n}.png")))?;
    }

    let bar = common::Bar::new();
    let mut pictures = Vec::new();
    // The worlds, each seen from four radii away with the sun to the upper left.
    let worlds: [(&str, PlanetParams, f64); 3] = [
        ("venus", PlanetParams::venus(), 3.4),
        ("jupiter", PlanetParams::jupiter(), 6.2),
        ("selene", PlanetParams::selene(), 3.4),
    ];
    for (name, mut params, distance) in worlds {
        match &mut params.surface {
            natura::texture::planet::SurfaceParams::Venus(v) => v.seed = seed,
            natura::texture::planet::SurfaceParams::GasGiant(g) => g.seed = seed,
            natura::texture::planet::SurfaceParams::Luna(l) => l.seed = seed,
            natura::texture::planet::SurfaceParams::Terrain(_) => {}
        }
        if let Some(r) = &mut params.rings {
            r.seed = seed;
        }
        // Selene is seen from above its north pole, where its crater is.
        let (lat, lon) = if name == "selene" {
            (0.9, 0.4)
        } else {
            (0.35, 0.4)
        };
        params.light.sun = direction(lat + 0.3, lon + 0.9);
        let planet = Planet::new(params)?;
        let altitude = planet.radius() * (distance - 1.0);
        let vfov = if name == "jupiter" { 0.82 } else { 0.66 };
        let view = planet.orbit_view(altitude, lat, lon, vfov, size, size)?;
        let image = planet.render(&view, &TraceSettings::default(), &bar)?;
        pictures.push((name, image.tone_mapped(0.5, ToneMap::AcesFilmic)));
    }
    let flame = Flame::new(FlameParams {
        seed,
        ..FlameParams::default()
    })?;
    let fire = preview::plane(&flame, size, 2.0, Plane::Vertical, true, &bar)?;
    pictures.push(("fire", fire.tone_mapped(0.0, ToneMap::Clip)));
    let waves = WindyWave::new(WindyWaveParams {
        seed,
        km: 0.03,
        ..WindyWaveParams::default()
    })?;
    let water = preview::water(&waves, size, size, 1.0, &bar)?;
    pictures.push(("water", water.tone_mapped(0.0, ToneMap::AcesFilmic)));

    for (name, p) in &pictures {
        save(p, &out.join(format!("planets_{name}.png")))?;
    }
    let images: Vec<Image> = pictures.into_iter().map(|(_, p)| p).collect();
    let sheet = Image::contact_sheet(&images, 5, 6, Vec3::splat(0.0))?;
    save(&sheet, &sheet_path)
}

fn save(image: &Image, path: &std::path::Path) -> Run {
    image.save_png(path)?;
    outln(format_args!("wrote {}", path.display()))
}
