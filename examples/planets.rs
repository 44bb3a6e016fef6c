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
//! `--out` (default: `./planets/`), with a progress bar per picture, and
//! `planets_jupiter_io.png`: the banded giant without its rings, and Io
//! passing before it (Musgrave's Plate 5.6).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::DVec3;
use natura::core::glam::Vec3;
use natura::core::io::check_writable;
use natura::core::{Image, ToneMap};
use natura::texture::earth::luna::LunaParams;
use natura::texture::fire::{Flame, FlameParams};
use natura::texture::planet::{
    LightParams, Planet, PlanetParams, SurfaceParams, TraceSettings, direction,
};
use natura::texture::preview::{self, Plane};
use natura::texture::view::View;
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
    for n in names.iter().chain(&["jupiter_io"]) {
        check_writable(out.join(format!("planets_{n}.png")))?;
    }

    let bar = common::Bar::new();
    let mut pictures = Vec::new();
    let mut io_picture = None;
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
        if name == "jupiter" {
            // Plate 5.6: Jupiter as it is, without the rings, and Io.
            let bare = Planet::new(PlanetParams {
                rings: None,
                ..params
            })?;
            let close = bare.orbit_view(altitude, lat, lon, 0.5, size, size)?;
            let bare = bare.render(&close, &TraceSettings::default(), &bar)?;
            let io = with_io(&close, &bare, params.light.sun, seed, &bar)?;
            io_picture = Some(io.tone_mapped(0.5, ToneMap::AcesFilmic));
        }
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
    if let Some(p) = &io_picture {
        save(p, &out.join("planets_jupiter_io.png"))?;
    }
    let images: Vec<Image> = pictures.into_iter().map(|(_, p)| p).collect();
    let sheet = Image::contact_sheet(&images, 5, 6, Vec3::splat(0.0))?;
    save(&sheet, &sheet_path)
}

fn save(image: &Image, path: &std::path::Path) -> Run {
    image.save_png(path)?;
    outln(format_args!("wrote {}", path.display()))
}

/// Io's radius, metres.
const IO_RADIUS_M: f64 = 1.8216e6;

/// Jupiter's picture `jupiter` (linear, as rendered through `view`) with
/// Io passing before it: a sulphur-yellow moon of Io's radius, mottled by
/// its volcanic plains (natura-texture's Luna surface without its crater,
/// tinted), a tenth of the way from the eye to Jupiter along the ray
/// through the lower left of Jupiter's disc, lit by the same sun `sun`. Io is
/// rendered through the same rays (the view moved to Io's frame) and laid
/// over Jupiter by its coverage of each pixel, from 4 × 4 rays a pixel
/// tested against its sphere.
fn with_io(
    view: &View,
    jupiter: &Image,
    sun: DVec3,
    seed: u64,
    bar: &common::Bar,
) -> Result<Image, common::Exit> {
    let (w, h) = (view.width(), view.height());
    let eye = view.eye();
    let toward = view.direction(0.38 * f64::from(w), 0.6 * f64::from(h));
    let centre = eye + toward * (0.1 * eye.length());
    let io = Planet::new(PlanetParams {
        radius_m: IO_RADIUS_M,
        surface: SurfaceParams::Luna(LunaParams {
            seed: seed ^ 0x10,
            colour: DVec3::new(0.85, 0.72, 0.3),
            highland_color: DVec3::new(0.35, 0.12, 0.02),
            maria_basecolor: 0.85,
            maria_color: 0.25,
            highland_threshold: 0.15,
            peak_ht: 0.0,
            rim_ht: 0.0,
            ..LunaParams::default()
        }),
        atmosphere: None,
        clouds: None,
        rings: None,
        light: LightParams {
            sun,
            ambient: 0.01,
            ..LightParams::default()
        },
    })?;
    let up = if eye.normalize().z.abs() > 0.999 {
        DVec3::X
    } else {
        DVec3::Z
    };
    let io_view = View::look_at(
        eye - centre,
        -centre,
        up,
        view.pixel_angle() * f64::from(h),
        w,
        h,
    )?;
    let moon = io.render(&io_view, &TraceSettings::default(), bar)?;
    let hits = |px: f64, py: f64| {
        let d = view.direction(px, py);
        let c = centre - eye;
        let along = c.dot(d);
        along > 0.0 && (c - d * along).length() < IO_RADIUS_M
    };
    Ok(Image::from_fn(w as usize, h as usize, |x, y| {
        let n = (0..16)
            .filter(|k| {
                let (i, j) = (f64::from(k % 4), f64::from(k / 4));
                hits(x as f64 + (i + 0.5) / 4.0, y as f64 + (j + 0.5) / 4.0)
            })
            .count();
        let cover = n as f32 / 16.0;
        let (m, j) = (
            moon.get(x, y).unwrap_or(Vec3::ZERO),
            jupiter.get(x, y).unwrap_or(Vec3::ZERO),
        );
        // Io's picture is its light over black space, already weighed by
        // its coverage of the pixel: Jupiter shows through the rest.
        m + j * (1.0 - cover)
    })?)
}
