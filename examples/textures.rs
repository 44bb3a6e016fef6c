//! Every solid texture of natura-texture on a sphere and on a plane, and a
//! contact sheet of them all.
//!
//! ```text
//! cargo run --release --example textures                     # ./textures/
//! cargo run --release --example textures -- --quick --out /tmp/textures
//! cargo run --release --example textures -- --help           # every flag and its default
//! ```
//!
//! Writes `NAME_sphere.png` and `NAME_plane.png` for every texture, the
//! sheet `textures.png`, and `ripples_lake.png` (the ripples on a lake seen
//! from just above it) into `--out` (default: `./textures/`), with a
//! progress bar per swatch.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Run, outln};
use natura::core::glam::{DVec3, Vec3};
use natura::core::io::check_writable;
use natura::core::{Image, ToneMap};
use natura::texture::air::{
    Cyclone, CycloneParams, PlanetClouds, PlanetCloudsParams, PuffyClouds, PuffyCloudsParams,
    Venus, VenusParams,
};
use natura::texture::earth::{
    Luna, LunaParams, Ridge, RidgeParams, Strata, StrataParams, Terran, TerranParams,
};
use natura::texture::fire::{Flame, FlameParams};
use natura::texture::giants::{GasGiant, GasGiantParams, Rings, RingsParams};
use natura::texture::git::{Git, GitParams};
use natura::texture::multicolor::{Multicolor, MulticolorParams};
use natura::texture::preview::{self, Plane};
use natura::texture::water::{Ripples, RipplesParams, WindyWave, WindyWaveParams};
use natura::texture::{SolidTexture, TextureError};

/// Every solid texture of natura-texture on a sphere and on a plane, and a
/// contact sheet of them all. Writes NAME_sphere.png and NAME_plane.png for
/// every texture and the sheet textures.png.
#[derive(Parser)]
#[command(name = "textures", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Swatch side, pixels [default: 384; 96 with --quick]
    #[arg(long)]
    size: Option<u32>,
    /// Random seed
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "textures")]
    out: PathBuf,
}

/// A texture with how to show it on a plane: extent, which plane, emissive.
struct Entry {
    file: &'static str,
    texture: Box<dyn SolidTexture>,
    extent: f64,
    plane: Plane,
    emissive: bool,
    /// Where the sphere is seen from (from its centre towards the viewer).
    eye: DVec3,
}

fn entry(file: &'static str, texture: Box<dyn SolidTexture>, extent: f64) -> Entry {
    Entry {
        file,
        texture,
        extent,
        plane: Plane::Horizontal,
        emissive: false,
        eye: DVec3::NEG_Y,
    }
}

fn catalogue(seed: u64) -> Result<Vec<Entry>, TextureError> {
    Ok(vec![
        entry(
            "puffy",
            Box::new(PuffyClouds::new(PuffyCloudsParams {
                seed,
                ..Default::default()
            })?),
            4.0,
        ),
        entry(
            "planet_clouds",
            Box::new(PlanetClouds::new(PlanetCloudsParams {
                seed,
                ..Default::default()
            })?),
            6.0,
        ),
        // The storm turns about the z axis: its sphere is seen from 25°
        // off the pole, where the spiral is (from the side it is on the limb).
        Entry {
            eye: DVec3::new(0.0, -(25f64.to_radians().sin()), 25f64.to_radians().cos()),
            ..entry(
                "cyclone",
                Box::new(Cyclone::new(CycloneParams {
                    seed,
                    ..Default::default()
                })?),
                2.4,
            )
        },
        entry(
            "venus",
            Box::new(Venus::new(VenusParams {
                seed,
                ..Default::default()
            })?),
            4.0,
        ),
        Entry {
            plane: Plane::Vertical,
            emissive: true,
            ..entry(
                "flame",
                Box::new(Flame::new(FlameParams {
                    seed,
                    ..Default::default()
                })?),
                2.0,
            )
        },
        entry(
            "ripples",
            Box::new(Ripples::new(RipplesParams {
                seed,
                ..Default::default()
            })?),
            8.0,
        ),
        entry(
            "windywave",
            Box::new(WindyWave::new(WindyWaveParams {
                seed,
                ..Default::default()
            })?),
            8.0,
        ),
        entry(
            "strata",
            Box::new(Strata::new(StrataParams {
                seed,
                ..Default::default()
            })?),
            3.0,
        ),
        entry(
            "terran",
            Box::new(Terran::new(TerranParams {
                seed,
                ..Default::default()
            })?),
            4.0,
        ),
        entry(
            "gaea",
            Box::new(Terran::new(TerranParams {
                seed,
                ..TerranParams::gaea()
            })?),
            4.0,
        ),
        entry(
            "luna",
            Box::new(Luna::new(LunaParams {
                seed,
                ..Default::default()
            })?),
            0.2,
        ),
        entry(
            "gas_giant",
            Box::new(GasGiant::new(GasGiantParams {
                seed,
                ..Default::default()
            })?),
            2.0,
        ),
        entry(
            "rings",
            Box::new(Rings::new(RingsParams {
                seed,
                ..Default::default()
            })?),
            5.0,
        ),
        entry(
            "multicolor",
            Box::new(Multicolor::new(MulticolorParams {
                seed,
                ..Default::default()
            })?),
            0.6,
        ),
        entry(
            "git",
            Box::new(Git::new(GitParams {
                seed,
                ..Default::default()
            })?),
            2.0,
        ),
        entry(
            "ridge",
            Box::new(Ridge::new(RidgeParams {
                seed,
                ..Default::default()
            })?),
            3.0,
        ),
    ])
}

fn main() -> ExitCode {
    common::run(textures)
}

/// The program: every error returns through [`common::run`], which removes
/// whatever was staged before reporting it.
fn textures() -> Run {
    let cli: Cli = common::parse();
    let size = cli.size.unwrap_or(if cli.quick { 96 } else { 384 });
    let out = common::out_dir(&cli.out)?;

    let textures = catalogue(cli.seed)?;
    let mut paths = vec![out.join("textures.png"), out.join("ripples_lake.png")];
    for e in &textures {
        paths.push(out.join(format!("{}_sphere.png", e.file)));
        paths.push(out.join(format!("{}_plane.png", e.file)));
    }
    for p in &paths {
        check_writable(p)?;
    }

    let bar = common::Bar::new();
    let mut sheet = Vec::new();
    for e in &textures {
        let t = e.texture.as_ref();
        let sphere = preview::sphere_from(t, size, e.emissive, e.eye, &bar)?;
        let plane = preview::plane(t, size, e.extent, e.plane, e.emissive, &bar)?;
        save(&sphere, &out.join(format!("{}_sphere.png", e.file)))?;
        save(&plane, &out.join(format!("{}_plane.png", e.file)))?;
        sheet.push(sphere);
        sheet.push(plane);
    }
    let sheet = Image::contact_sheet(&sheet, 6, 4, Vec3::splat(0.01))?;
    save(&sheet, &paths[0])?;
    // The ripples as Musgrave shows them ("Spirit Lake", "Lethe"): a
    // mirror-like lake seen from just above it, reflecting the sky.
    if let Some(e) = textures.iter().find(|e| e.file == "ripples") {
        let lake = preview::water(e.texture.as_ref(), size * 4 / 3, size, 1.0, &bar)?;
        let path = out.join("ripples_lake.png");
        lake.tone_mapped(0.0, ToneMap::AcesFilmic).save_png(&path)?;
        outln(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}

fn save(image: &Image, path: &std::path::Path) -> Run {
    image.tone_mapped(0.0, ToneMap::Clip).save_png(path)?;
    outln(format_args!("wrote {}", path.display()))
}
