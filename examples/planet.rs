//! Gaea: an Earth-sized procedural planet seen from orbit — displaced
//! terrain, oceans, the radial atmosphere with its umbra at the terminator,
//! and a cloud shell casting its shadow — or, with `--view ground`, the same
//! planet from a mountain top.
//!
//! ```text
//! cargo run --release --example planet                       # docs/gallery/texture/planet_orbit.png
//! cargo run --release --example planet -- --view ground      # planet_ground.png
//! cargo run --release --example planet -- --quick --out /tmp/planet --exr --cube 64
//! ```
//!
//! `--exr` also writes the linear render; `--cube N` exports the surface as
//! six N² cube faces and a 2N × N equirectangular map (EXR height and colour).

mod common;

use std::f64::consts::{FRAC_PI_2, TAU};

use natura::core::io::check_writable;
use natura::core::{Image, ToneMap};
use natura::texture::earth::Continents;
use natura::texture::planet::{
    GroundViewParams, Planet, PlanetParams, SurfaceParams, TraceSettings, direction,
};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let view: String = args.value("--view", "orbit".to_string(), "orbit or ground");
    let width: Option<u32> = args.optional("--width", "image width (1920 orbit, 1280 ground)");
    let height: Option<u32> = args.optional("--height", "image height (1080 orbit, 720 ground)");
    let seed: u64 = args.value("--seed", 3, "random seed");
    let exr = args.switch("--exr", "also write the linear render as EXR");
    let cube: usize = args.value(
        "--cube",
        0,
        "also export cube faces of N² samples (0: none)",
    );
    let multifractal = args.switch("--multifractal", "Gaea's multifractal continents (slower)");
    // Gaea's camera from just above its highest peaks to a million
    // kilometres out (where it is a few pixels wide).
    let altitude: f64 = args.ranged("--altitude", 1.55e7, 1e5..=1e9, "orbit view: altitude, m");
    let vfov: f64 = args.ranged(
        "--vfov",
        0.62,
        1e-3..=3.0,
        "orbit view: vertical field of view, radians",
    );
    let lat: Option<f64> = args.optional("--lat", "latitude below the camera, radians");
    let lon: Option<f64> = args.optional("--lon", "longitude below the camera, radians");
    let search: Option<f64> = args.optional(
        "--search",
        "ground view: peak search radius, m (150 km; 100 km with --quick)",
    );
    let heading: f64 = args.ranged(
        "--heading",
        0.2,
        -TAU..=TAU,
        "ground view: compass heading, radians",
    );
    let ev: Option<f32> = args.optional("--ev", "exposure in stops (default 0 orbit, +1.5 ground)");
    let out = args.out_dir("docs/gallery/texture");
    args.finish();
    let in_range = |flag: &str, v: f64, lo: f64, hi: f64, unit: &str| {
        if !(lo..=hi).contains(&v) {
            common::fail(&format!(
                "{flag} {}: must be in {lo}..={hi} {unit}",
                common::short(v)
            ));
        }
    };
    if let Some(v) = lat {
        in_range("--lat", v, -FRAC_PI_2, FRAC_PI_2, "radians");
    }
    if let Some(v) = lon {
        in_range("--lon", v, -TAU, TAU, "radians");
    }
    // Half of Gaea's circumference: the farthest a peak can be.
    if let Some(v) = search {
        in_range("--search", v, 0.0, 2e7, "m");
    }
    // Beyond ±20 stops the picture is white or black whatever it shows.
    if let Some(v) = ev
        && !(-20.0..=20.0).contains(&v)
    {
        common::fail(&format!(
            "--ev {}: must be in -20..=20 stops",
            common::short(v)
        ));
    }

    let name = match view.as_str() {
        "orbit" => "planet_orbit",
        "ground" => "planet_ground",
        other => common::fail(&format!("--view {other}: expected orbit or ground")),
    };
    let orbit = name == "planet_orbit";
    let (w0, h0) = match (quick, orbit) {
        (true, _) => (240, 135),
        (false, true) => (1920, 1080),
        (false, false) => (1280, 720),
    };
    let (width, height) = (width.unwrap_or(w0), height.unwrap_or(h0));
    let lat = lat.unwrap_or(if orbit { 0.35 } else { 0.3 });
    let lon = lon.unwrap_or(if orbit { 0.25 } else { 2.1 });
    let png = out.join(format!("{name}.png"));
    common::check(check_writable(&png));
    if exr {
        common::check(check_writable(out.join(format!("{name}.exr"))));
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
    // The sun 75° round from the view (orbit), or low in the east (ground).
    params.light.sun = if orbit {
        direction(0.2, lon + 1.3)
    } else {
        direction(lat - 0.1, lon + 1.25)
    };
    let planet = common::check(Planet::new(params));
    let camera = if orbit {
        common::check(planet.orbit_view(altitude, lat, lon, vfov, width, height))
    } else {
        let g = GroundViewParams {
            latitude: lat,
            longitude: lon,
            search_radius_m: search.unwrap_or(if quick { 100_000.0 } else { 150_000.0 }),
            heading,
            ..GroundViewParams::default()
        };
        common::check(planet.ground_view(&g, width, height))
    };
    let bar = common::Bar::new();
    let started = std::time::Instant::now();
    let image = common::check(planet.render(&camera, &TraceSettings::default(), &bar));
    println!(
        "rendered {width}×{height} in {:.2} s",
        started.elapsed().as_secs_f64()
    );
    let ev = ev.unwrap_or(if orbit { 0.0 } else { 1.5 });
    save(&image, &png, exr, ev);

    if cube > 0 {
        let started = std::time::Instant::now();
        let map = common::check(planet.cube_map(cube, &bar));
        let written = common::check(map.write_exr(&out, "gaea_cube"));
        let eq = common::check(planet.equirect(2 * cube, cube, &bar));
        let flat = common::check(eq.write_exr(&out, "gaea_equirect"));
        println!(
            "exported {} cube-face files and {} equirectangular files ({cube}² per face) in {:.2} s",
            written.len(),
            flat.len(),
            started.elapsed().as_secs_f64()
        );
    }
}

fn save(image: &Image, png: &std::path::Path, exr: bool, ev: f32) {
    common::check(image.tone_mapped(ev, ToneMap::AcesFilmic).save_png(png));
    println!("wrote {}", png.display());
    if exr {
        let p = png.with_extension("exr");
        common::check(image.save_exr(&p));
        println!("wrote {}", p.display());
    }
}
