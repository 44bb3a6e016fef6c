//! Every solid texture of natura-texture on a sphere and on a plane, and a
//! contact sheet of them all.
//!
//! ```text
//! cargo run --release --example textures                     # docs/gallery/texture/textures/
//! cargo run --release --example textures -- --quick --out /tmp/textures
//! ```

mod common;

use natura::core::glam::Vec3;
use natura::core::io::check_writable;
use natura::core::{Image, NoProgress, ToneMap};
use natura::texture::air::{
    Cyclone, CycloneParams, PlanetClouds, PlanetCloudsParams, PuffyClouds, PuffyCloudsParams,
    Venus, VenusParams,
};
use natura::texture::earth::{
    Luna, LunaParams, Ridge, RidgeParams, Strata, StrataParams, Terran, TerranParams,
};
use natura::texture::fire::{Flame, FlameParams};
use natura::texture::giants::{GasGiant, GasGiantParams, Rings, RingsParams};
use natura::texture::multicolor::{Multicolor, MulticolorParams};
use natura::texture::preview::{self, Plane};
use natura::texture::water::{Ripples, RipplesParams, WindyWave, WindyWaveParams};
use natura::texture::{SolidTexture, TextureError};

/// A texture with how to show it on a plane: extent, which plane, emissive.
struct Entry {
    file: &'static str,
    texture: Box<dyn SolidTexture>,
    extent: f64,
    plane: Plane,
    emissive: bool,
}

fn entry(file: &'static str, texture: Box<dyn SolidTexture>, extent: f64) -> Entry {
    Entry {
        file,
        texture,
        extent,
        plane: Plane::Horizontal,
        emissive: false,
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
        entry(
            "cyclone",
            Box::new(Cyclone::new(CycloneParams {
                seed,
                ..Default::default()
            })?),
            2.4,
        ),
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
            "ridge",
            Box::new(Ridge::new(RidgeParams {
                seed,
                ..Default::default()
            })?),
            3.0,
        ),
    ])
}

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: u32 = args.value(
        "--size",
        if quick { 96 } else { 384 },
        "swatch side, pixels",
    );
    let seed: u64 = args.value("--seed", 1, "random seed");
    let out = args.out_dir("docs/gallery/texture/textures");
    args.finish();

    let textures = common::check(catalogue(seed));
    let mut paths = vec![out.join("textures.png")];
    for e in &textures {
        paths.push(out.join(format!("{}_sphere.png", e.file)));
        paths.push(out.join(format!("{}_plane.png", e.file)));
    }
    for p in &paths {
        common::check(check_writable(p));
    }

    let bar = common::Bar::new();
    let mut sheet = Vec::new();
    for e in &textures {
        let t = e.texture.as_ref();
        let sphere = common::check(preview::sphere(t, size, e.emissive, &bar));
        let plane = common::check(preview::plane(
            t,
            size,
            e.extent,
            e.plane,
            e.emissive,
            &NoProgress,
        ));
        save(&sphere, &out.join(format!("{}_sphere.png", e.file)));
        save(&plane, &out.join(format!("{}_plane.png", e.file)));
        sheet.push(sphere);
        sheet.push(plane);
    }
    let sheet = common::check(Image::contact_sheet(&sheet, 6, 4, Vec3::splat(0.01)));
    save(&sheet, &paths[0]);
}

fn save(image: &Image, path: &std::path::Path) {
    common::check(image.tone_mapped(0.0, ToneMap::Clip).save_png(path));
    println!("wrote {}", path.display());
}
