//! A gallery of classic L-systems from *The Algorithmic Beauty of Plants*
//! (Prusinkiewicz & Lindenmayer 1990): the Koch curve and quadratic Koch
//! island (§1.2–1.3), the bracketed plants of fig. 1.24a–f, the 3-D bush of
//! fig. 1.25, the monopodial tree of fig. 2.6, the ternary tree of fig. 2.8
//! (bent down by its `tropism:` directive) and a sunflower head by Vogel's
//! formula (§4.1).
//!
//! ```text
//! cargo run --release --example plants                 # ./plants/plants.png
//! cargo run --release --example plants -- --quick      # small, for CI
//! cargo run --release --example plants -- --out DIR    # into DIR
//! cargo run --release --example plants -- --help       # every flag and its default
//! ```
//!
//! Writes a contact sheet (`plants.png`), the monopodial tree as `tree.glb`,
//! and a grove of that tree instanced nine times (`grove.glb`,
//! `EXT_mesh_gpu_instancing`) into `--out` (default: `./plants/`).

mod common;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use common::{Exit, Run, outln};
use natura::core::glam::Vec3;
use natura::plant::mesh::{Instance, save_glb, save_glb_instanced};
use natura::plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams, preview};

const GALLERY: [&str; 12] = [
    include_str!("lsystems/koch_curve.l"),
    include_str!("lsystems/koch_island.l"),
    include_str!("lsystems/fig1_24a.l"),
    include_str!("lsystems/fig1_24b.l"),
    include_str!("lsystems/fig1_24c.l"),
    include_str!("lsystems/fig1_24d.l"),
    include_str!("lsystems/fig1_24e.l"),
    include_str!("lsystems/fig1_24f.l"),
    include_str!("lsystems/fig1_25.l"),
    include_str!("lsystems/fig2_6.l"),
    include_str!("lsystems/fig2_8.l"),
    include_str!("lsystems/sunflower.l"),
];

/// A gallery of classic L-systems from The Algorithmic Beauty of Plants:
/// writes a contact sheet (plants.png), the monopodial tree of fig. 2.6 as
/// tree.glb and a grove of it instanced nine times (grove.glb).
#[derive(Parser)]
#[command(name = "plants", version)]
struct Cli {
    /// Small pictures (CI)
    #[arg(long)]
    quick: bool,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "plants")]
    out: PathBuf,
}

/// Derives `text` for its derivation length and meshes it; stems get 1/150
/// of the plant's size as width where the L-system sets none.
fn grow(text: &str) -> Result<PlantMesh, Exit> {
    let lsys = LSystem::parse(text)?;
    let mut d = Derivation::new(&lsys, 1)?;
    d.derive(lsys.derivation_length())?;
    let s = d.string();
    let mut tp = TurtleParams::for_lsystem(&lsys);
    let mut geo = Turtle::new(&lsys, tp.clone()).and_then(|t| t.interpret(s))?;
    let sets_width = lsys.symbol("!").is_some_and(|id| s.symbols().contains(&id));
    if let (false, Some((lo, hi))) = (sets_width, geo.bounds()) {
        tp.width = f64::from((hi - lo).max_element()) / 150.0;
        geo = Turtle::new(&lsys, tp).and_then(|t| t.interpret(s))?;
    }
    Ok(PlantMesh::from_geometry(&geo, &MeshParams::default())?)
}

fn main() -> ExitCode {
    common::run(plants)
}

/// The program: every error returns through [`common::run`].
fn plants() -> Run {
    let Cli { quick, out } = common::parse();
    let out = common::out_dir(&out)?;
    let cell = if quick { 96 } else { 200 };
    let meshes = GALLERY
        .iter()
        .map(|t| grow(t))
        .collect::<Result<Vec<PlantMesh>, Exit>>()?;
    let pictures = meshes
        .iter()
        .map(|m| {
            let (lo, hi) = m.bounds().unwrap_or_default();
            let flat = (hi.y - lo.y) < 0.05 * (hi - lo).max_element();
            let view = if flat {
                Vec3::Y
            } else {
                Vec3::new(0.25, 1.0, -0.3)
            };
            preview::snapshot(m, cell, cell, view, None)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let sheet = natura::core::Image::contact_sheet(&pictures, 4, 4, Vec3::ONE)?;
    let png = out.join("plants.png");
    sheet.save_png(&png)?;

    let tree = &meshes[9];
    let glb = out.join("tree.glb");
    save_glb(tree, &glb)?;
    let grove: Vec<Instance> = (0..9)
        .map(|k| {
            let (x, y) = ((k % 3) as f32 * 4.0, (k / 3) as f32 * 4.0);
            Instance::new(Vec3::new(x, y, 0.0), 0.7 * k as f32, 0.8 + 0.05 * k as f32)
        })
        .collect();
    let grove_glb = out.join("grove.glb");
    save_glb_instanced(&[(tree, &grove)], &grove_glb)?;
    for p in [png, glb, grove_glb] {
        outln(format_args!("wrote {}", p.display()))?;
    }
    Ok(())
}
