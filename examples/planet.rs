//! Gaea: an Earth-sized procedural planet seen from orbit — displaced
//! terrain, oceans, the radial atmosphere with its umbra at the terminator,
//! and a cloud shell casting its shadow — or, with `--view ground`, the same
//! planet from a mountain top.
//!
//! ```text
//! cargo run --release --example planet                       # ./planet/planet_orbit.png
//! cargo run --release --example planet -- --view ground      # ./planet/planet_ground.png
//! cargo run --release --example planet -- --quick --out /tmp/planet --exr --cube 64
//! cargo run --release --example planet -- --help             # every flag and its default
//! ```
//!
//! Writes `planet_orbit.png` or `planet_ground.png` into `--out` (default:
//! `./planet/`), with a progress bar per stage. `--exr` also writes the
//! linear render; `--cube N` exports the surface as six N² cube faces and a
//! 2N × N equirectangular map (EXR height and colour).

mod common;

use std::f64::consts::{FRAC_PI_2, TAU};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use common::{Run, outln};
use natura::core::io::check_writable;
use natura::core::{Image, ToneMap};
use natura::texture::earth::Continents;
use natura::texture::planet::{
    GroundViewParams, Planet, PlanetParams, SurfaceParams, TraceSettings, direction,
};

/// Where the camera is: in orbit, or on a mountain top. (No doc comment on
/// the variants: clap would switch --help to its long layout.)
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum View {
    Orbit,
    Ground,
}

/// Gaea: an Earth-sized procedural planet seen from orbit (displaced
/// terrain, oceans, the radial atmosphere with its umbra at the terminator,
/// a cloud shell casting its shadow) or from a mountain top. Writes
/// planet_orbit.png or planet_ground.png; with --exr the linear render, with
/// --cube the surface as cube faces and an equirectangular map (EXR).
#[derive(Parser)]
#[command(name = "planet", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// The view: from orbit (the whole planet) or from the ground (a
    /// mountain top)
    #[arg(long, value_enum, default_value_t = View::Orbit)]
    view: View,
    /// Image width, pixels [default: 1920 orbit, 960 ground; 240 with
    /// --quick]
    #[arg(long)]
    width: Option<u32>,
    /// Image height, pixels [default: 1080 orbit, 540 ground; 135 with
    /// --quick]
    #[arg(long)]
    height: Option<u32>,
    /// Random seed
    #[arg(long, default_value_t = 3)]
    seed: u64,
    /// Also write the linear render as EXR
    #[arg(long)]
    exr: bool,
    /// Also export cube faces of N² samples and a 2N × N equirectangular map
    /// (0: none; a size the cube map refuses is refused before anything is
    /// rendered)
    #[arg(long, value_name = "N", default_value_t = 0)]
    cube: usize,
    /// Gaea's multifractal continents (slower)
    #[arg(long)]
    multifractal: bool,
    /// Orbit view: altitude, m (from just above the highest peaks to a
    /// million kilometres out, where the planet is a few pixels wide)
    #[arg(
        long,
        default_value_t = 1.55e7,
        allow_negative_numbers = true,
        value_parser = common::in_range(1e5, 1e9)
    )]
    altitude: f64,
    /// Orbit view: vertical field of view, radians
    #[arg(
        long,
        default_value_t = 0.62,
        allow_negative_numbers = true,
        value_parser = common::in_range(1e-3, 3.0)
    )]
    vfov: f64,
    /// Latitude below the camera, radians [default: 0.35 orbit, 0.5 ground]
    #[arg(
        long,
        allow_negative_numbers = true,
        value_parser = common::in_range(-FRAC_PI_2, FRAC_PI_2)
    )]
    lat: Option<f64>,
    /// Longitude below the camera, radians [default: 0.25 orbit, 1.0 ground]
    #[arg(long, allow_negative_numbers = true, value_parser = common::in_range(-TAU, TAU))]
    lon: Option<f64>,
    /// Ground view: peak search radius, m (at most half of Gaea's
    /// circumference) [default: 100000]
    #[arg(long, allow_negative_numbers = true, value_parser = common::in_range(0.0, 2e7))]
    search: Option<f64>,
    /// Ground view: compass heading, radians
    #[arg(
        long,
        default_value_t = 0.2,
        allow_negative_numbers = true,
        value_parser = common::in_range(-TAU, TAU)
    )]
    heading: f64,
    /// Exposure, stops (beyond ±20 the picture is white or black whatever it
    /// shows) [default: 0 orbit, +1 ground]
    #[arg(
        long,
        allow_negative_numbers = true,
        value_parser = common::in_range(-20.0f32, 20.0)
    )]
    ev: Option<f32>,
    /// Rays a pixel takes along each axis, resolved by the camera's pixel
    /// filter (1 to 16) [default: 2 orbit, 1 ground, whose rays cost
    /// ten times as much]
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16))]
    supersample: Option<u32>,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "planet")]
    out: PathBuf,
}

/// Grey aerosol extinction added to the ground view's air, per metre
/// (with the air's Rayleigh green, a visual range near 240 km).
const AEROSOL_PER_M: f64 = 3e-6;

/// Light from the sky on the ground view, a fraction of the sun's.
const SKYLIGHT: f64 = 0.2;

fn main() -> ExitCode {
    common::run(planet)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn planet() -> Run {
    let cli: Cli = common::parse();
    let Cli {
        quick,
        view,
        width,
        height,
        seed,
        exr,
        cube,
        multifractal,
        altitude,
        vfov,
        lat,
        lon,
        search,
        heading,
        ev,
        supersample,
        out,
    } = cli;
    let orbit = view == View::Orbit;
    let name = if orbit {
        "planet_orbit"
    } else {
        "planet_ground"
    };
    let (w0, h0) = match (quick, orbit) {
        (true, _) => (240, 135),
        (false, true) => (1920, 1080),
        (false, false) => (960, 540),
    };
    let (width, height) = (width.unwrap_or(w0), height.unwrap_or(h0));
    let lat = lat.unwrap_or(if orbit { 0.35 } else { 0.5 });
    let lon = lon.unwrap_or(if orbit { 0.25 } else { 1.0 });
    if cube > 0 {
        // The cube map's own check, before the render writes its picture.
        natura::texture::planet::CubeMap::check_size(cube)
            .map_err(|e| common::Exit::new(2, format!("--cube {cube}: {e}")))?;
    }
    let out = common::out_dir(&out)?;
    let png = out.join(format!("{name}.png"));
    check_writable(&png)?;
    if exr {
        check_writable(out.join(format!("{name}.exr")))?;
    }

    let mut params = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut params.surface {
        t.terran.seed = seed;
        if multifractal {
            t.terran.continents = Continents::VectorMultifractal;
        }
    }
    if let Some(c) = &mut params.clouds {
        c.clouds.seed = seed;
    }
    // From the ground the air holds a little aerosol besides its
    // molecules, a grey extinction that fades far ridges towards the sky's
    // colour, and the sky lights what the sun does not (ambient 0.2 of the
    // sun). From orbit nothing but the night air's faint glow lights the
    // night side: a uniform 2 % of the sun there left its texture a level
    // or two above black in the picture, specks of single pixels.
    if orbit {
        params.light.ambient = 0.0;
    } else {
        if let Some(a) = &mut params.atmosphere {
            a.extinction += glam::DVec3::splat(AEROSOL_PER_M);
        }
        params.light.ambient = SKYLIGHT;
    }
    // The sun 75° round from the view (orbit), or in the morning east,
    // 40° round (ground).
    params.light.sun = if orbit {
        direction(0.2, lon + 1.3)
    } else {
        direction(lat + 0.1, lon + 0.7)
    };
    let planet = Planet::new(params)?;
    let camera = if orbit {
        planet.orbit_view(altitude, lat, lon, vfov, width, height)?
    } else {
        let g = GroundViewParams {
            latitude: lat,
            longitude: lon,
            search_radius_m: search.unwrap_or(100_000.0),
            heading,
            // A person on a rise, looking a little down the valleys.
            eye_height_m: 30.0,
            pitch: -0.1,
            ..GroundViewParams::default()
        };
        planet.ground_view(&g, width, height)?
    };
    let bar = common::Bar::new();
    let started = std::time::Instant::now();
    let settings = TraceSettings {
        supersample: supersample.unwrap_or(if orbit { 2 } else { 1 }),
        ..TraceSettings::default()
    };
    let image = planet.render(&camera, &settings, &bar)?;
    outln(format_args!(
        "rendered {width}×{height} in {:.2} s",
        started.elapsed().as_secs_f64()
    ))?;
    let ev = ev.unwrap_or(if orbit { 0.0 } else { 1.0 });
    save(&image, &png, exr, ev)?;

    if cube > 0 {
        let started = std::time::Instant::now();
        let map = planet.cube_map(cube, &bar)?;
        let written = map.write_exr(&out, "gaea_cube")?;
        let eq = planet.equirect(2 * cube, cube, &bar)?;
        let flat = eq.write_exr(&out, "gaea_equirect")?;
        outln(format_args!(
            "exported {} cube-face files and {} equirectangular files ({cube}² per face) in {:.2} s",
            written.len(),
            flat.len(),
            started.elapsed().as_secs_f64()
        ))?;
    }
    Ok(())
}

fn save(image: &Image, png: &std::path::Path, exr: bool, ev: f32) -> Run {
    image.tone_mapped(ev, ToneMap::AcesFilmic).save_png(png)?;
    outln(format_args!("wrote {}", png.display()))?;
    if exr {
        let p = png.with_extension("exr");
        image.save_exr(&p)?;
        outln(format_args!("wrote {}", p.display()))?;
    }
    Ok(())
}
