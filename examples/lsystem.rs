//! Derives an L-system file and writes its mesh (glTF binary, OBJ + MTL) and
//! a picture. Files in the cpfg / L-Py convention; see `examples/lsystems/`.
//!
//! ```text
//! cargo run --release --example lsystem -- examples/lsystems/fig1_25.l
//! cargo run --release --example lsystem -- examples/lsystems/fig2_8.l --steps 5 --out /tmp/tree
//! cargo run --release --example lsystem -- examples/lsystems/koch_curve.l --steps 2 --print
//! cargo run --release --example lsystem -- --quick      # the built-in bush, small picture (CI)
//! ```
//!
//! Where the L-system sets no widths (`!`, `#`), stems are drawn 1/150 of the
//! plant's size wide, so line drawings such as ABOP's 2-D plants stay visible.

mod common;

use natura::core::glam::Vec3;
use natura::plant::mesh::{save_glb, save_obj};
use natura::plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams, preview};
use std::path::Path;

/// ABOP fig. 1.24d, used when no file is given.
const DEFAULT: &str = include_str!("lsystems/fig1_24d.l");

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch(
        "--quick",
        "small picture; the built-in bush if no FILE (CI)",
    );
    let print = args.switch("--print", "print the derived string");
    let steps: Option<u32> = args.optional(
        "--steps",
        "derivation steps (default: the file's `derivation length:`)",
    );
    let seed: u64 = args.value("--seed", 1, "seed of stochastic productions");
    let radial: u32 = args.ranged("--radial", 8, 3..=64, "vertices around a stem");
    let out = args.out_dir("target/lsystem");
    let file = args.positional();
    args.finish();

    let (name, text) = match &file {
        Some(f) => {
            let stem = Path::new(f)
                .file_stem()
                .map_or("plant".into(), |s| s.to_string_lossy().into_owned());
            (
                stem,
                std::fs::read_to_string(f).unwrap_or_else(|e| common::fail(&format!("{f}: {e}"))),
            )
        }
        None if quick => ("fig1_24d".to_string(), DEFAULT.to_string()),
        None => {
            common::fail("no L-system file given (try --help, or --quick for the built-in one)")
        }
    };
    let lsys = LSystem::parse(&text).unwrap_or_else(|e| common::fail(&format!("{name}: {e}")));
    let mut d = common::check(Derivation::new(&lsys, seed));
    common::check(d.derive(steps.unwrap_or(lsys.derivation_length())));
    let s = d.string();
    if print {
        println!("{}", s.display(lsys.symbols()));
    }
    println!("{name}: {} modules after {} steps", s.len(), d.steps());

    let mut tp = TurtleParams::for_lsystem(&lsys);
    let mut geo = common::check(Turtle::new(&lsys, tp.clone()).and_then(|t| t.interpret(s)));
    let sets_width = ["!", "#"]
        .iter()
        .any(|w| lsys.symbol(w).is_some_and(|id| s.symbols().contains(&id)));
    if let (false, Some((lo, hi))) = (sets_width, geo.bounds()) {
        tp.width = f64::from((hi - lo).max_element()) / 150.0;
        geo = common::check(Turtle::new(&lsys, tp).and_then(|t| t.interpret(s)));
    }
    let params = MeshParams {
        radial_segments: radial,
        ..MeshParams::default()
    };
    let mesh = common::check(PlantMesh::from_geometry(&geo, &params));
    println!(
        "{} segments, {} polygons, {} surfaces -> {} vertices, {} triangles",
        geo.segment_count(),
        geo.polygons.len(),
        geo.surfaces.len(),
        mesh.vertex_count(),
        mesh.triangle_count()
    );
    if mesh.triangle_count() == 0 {
        common::fail("the L-system draws nothing");
    }
    let glb = out.join(format!("{name}.glb"));
    let obj = out.join(format!("{name}.obj"));
    let png = out.join(format!("{name}.png"));
    common::check(save_glb(&mesh, &glb));
    common::check(save_obj(&mesh, &obj));
    // Flat figures (in the turtle's x-z plane) are seen square on; 3-D plants a little from above.
    let (lo, hi) = mesh.bounds().unwrap_or_default();
    let flat = (hi.y - lo.y) < 0.05 * (hi - lo).max_element();
    let view = if flat {
        Vec3::Y
    } else {
        Vec3::new(0.25, 1.0, -0.3)
    };
    let size = if quick { 160 } else { 640 };
    let img = common::check(preview::snapshot(&mesh, size, size, view, None));
    common::check(img.save_png(&png));
    for p in [glb, obj, png] {
        println!("wrote {}", p.display());
    }
}
