//! A contact sheet of Musgrave's other worlds and elements: Venus under its
//! Coriolis-sheared clouds, a banded Jupiter with Saturn-like rings, Selene
//! with its rayed crater, a fire and a wind-rippled lake.
//!
//! ```text
//! cargo run --release --example planets                      # docs/gallery/texture/planets.png
//! cargo run --release --example planets -- --quick --out /tmp/planets
//! ```

mod common;

use natura::core::glam::Vec3;
use natura::core::io::check_writable;
use natura::core::{Image, NoProgress, ToneMap};
use natura::texture::fire::{Flame, FlameParams};
use natura::texture::planet::{Planet, PlanetParams, TraceSettings, direction};
use natura::texture::preview::{self, Plane};
use natura::texture::water::{WindyWave, WindyWaveParams};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: u32 = args.ranged(
        "--size",
        if quick { 128 } else { 512 },
        8..=16_384,
        "picture side, pixels",
    );
    let seed: u64 = args.value("--seed", 2, "random seed");
    let out = args.out_dir("docs/gallery/texture");
    args.finish();

    let names = ["venus", "jupiter", "selene", "fire", "water"];
    let sheet_path = out.join("planets.png");
    common::check(check_writable(&sheet_path));
    for n in names {
        common::check(check_writable(out.join(format!("planets_{n}.png"))));
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
        let planet = common::check(Planet::new(params));
        let altitude = planet.radius() * (distance - 1.0);
        let vfov = if name == "jupiter" { 0.82 } else { 0.66 };
        let view = common::check(planet.orbit_view(altitude, lat, lon, vfov, size, size));
        let image = common::check(planet.render(&view, &TraceSettings::default(), &bar));
        pictures.push((name, image.tone_mapped(0.5, ToneMap::AcesFilmic)));
    }
    let flame = common::check(Flame::new(FlameParams {
        seed,
        ..FlameParams::default()
    }));
    let fire = common::check(preview::plane(
        &flame,
        size,
        2.0,
        Plane::Vertical,
        true,
        &NoProgress,
    ));
    pictures.push(("fire", fire.tone_mapped(0.0, ToneMap::Clip)));
    let waves = common::check(WindyWave::new(WindyWaveParams {
        seed,
        km: 0.03,
        ..WindyWaveParams::default()
    }));
    let water = common::check(preview::water(&waves, size, size, 1.0, &bar));
    pictures.push(("water", water.tone_mapped(0.0, ToneMap::AcesFilmic)));

    for (name, p) in &pictures {
        save(p, &out.join(format!("planets_{name}.png")));
    }
    let images: Vec<Image> = pictures.into_iter().map(|(_, p)| p).collect();
    let sheet = common::check(Image::contact_sheet(&images, 5, 6, Vec3::splat(0.0)));
    save(&sheet, &sheet_path);
}

fn save(image: &Image, path: &std::path::Path) {
    common::check(image.save_png(path));
    println!("wrote {}", path.display());
}
