//! Renders a height map as a shaded relief picture: terrain false colour times
//! a hill shade, north up.
//!
//! ```text
//! cargo run --release --example heightmap                        # a synthetic field
//! cargo run --release --example heightmap -- --input dem.png --cell-size 30 --range 0,4000
//! ```
//!
//! Without `--input`, the field is a sum of bilinearly interpolated
//! position-indexed Gaussian values (natura-core's `Seed::gaussian2`), the
//! simplest stochastic surface core can make on its own.

mod common;

use common::scene::{LatticeTerrain, lattice_terrain};
use natura::core::glam::Vec3;
use natura::core::{HeightField, Image, Ramp, Seed};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let size: usize = args.value(
        "--size",
        if quick { 128 } else { 1024 },
        "samples per side (synthetic)",
    );
    let seed: u64 = args.value("--seed", 1, "random seed (synthetic)");
    let input: Option<std::path::PathBuf> =
        args.optional("--input", "height map to load (.png or .exr)");
    let cell: Option<f32> =
        args.optional("--cell-size", "metres between samples (overrides the file)");
    let range: Option<String> = args.optional("--range", "LO,HI metres for grey 0 and white (PNG)");
    let out = args.out_dir("docs/gallery");
    args.finish();

    let range = range.map(|r| {
        let v: Vec<f32> = r
            .split(',')
            .map(|s| common::check(s.trim().parse::<f32>()))
            .collect();
        if v.len() != 2 {
            common::fail("--range needs LO,HI");
        }
        (v[0], v[1])
    });
    let hf = match input {
        Some(path) => common::check(HeightField::load(&path, cell, range)),
        None => common::check(lattice_terrain(
            size,
            cell.unwrap_or(10.0),
            Seed(seed),
            &LatticeTerrain::FBM,
        )),
    };

    let (lo, hi) = hf.min_max();
    let shade = common::check(hf.hillshade(Vec3::new(-1.0, 1.0, 1.2).normalize()));
    let (nx, ny) = (hf.nx(), hf.ny());
    // Map orientation: image row 0 is the grid row of largest y (north).
    let img = common::check(Image::from_fn(nx, ny, |x, r| {
        let j = ny - 1 - r;
        let h = hf.heights()[(x, j)];
        Ramp::Terrain.map(h, lo, hi) * (0.25 + 0.75 * shade[(x, j)])
    }));
    let png = out.join("heightmap.png");
    common::check(img.save_png(&png));
    println!("{nx} × {ny} samples, heights {lo:.1} … {hi:.1} m");
    println!("wrote {}", png.display());
}
