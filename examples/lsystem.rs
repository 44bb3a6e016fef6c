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
//!
//! Stochastic productions use the file's `seed:` directive; `--seed` overrides
//! it (and without either the seed is 1). Files larger than
//! `natura::plant::lang::MAX_SOURCE_BYTES` (16 MiB) are refused before they
//! are read. Every error names the file. The mesh and the picture are all
//! computed before anything is written, and if writing one of the files
//! fails the others written by this run are removed. `--print` may be piped
//! into a program that stops reading (`| head -1`).

mod common;

use natura::core::glam::Vec3;
use natura::plant::mesh::{save_glb, save_obj};
use natura::plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams, preview};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

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
    let seed: Option<u64> = args.optional(
        "--seed",
        "seed of stochastic productions (default: the file's `seed:`, else 1)",
    );
    let radial: u32 = args.ranged("--radial", 8, 3..=64, "vertices around a stem");
    let out = args.out_dir("target/lsystem");
    let file = args.positional();
    args.finish();

    let (name, text) = match &file {
        Some(f) => {
            let stem = Path::new(f)
                .file_stem()
                .map_or("plant".into(), |s| s.to_string_lossy().into_owned());
            (stem, read_source(f))
        }
        None if quick => ("fig1_24d".to_string(), DEFAULT.to_string()),
        None => {
            common::fail("no L-system file given (try --help, or --quick for the built-in one)")
        }
    };
    // Every error from here on starts with the file's name.
    let check = |what: &str, e: natura::plant::PlantError| -> ! {
        common::fail(&format!("{name}: {what}{e}"))
    };
    let lsys = LSystem::parse(&text).unwrap_or_else(|e| check("", e));
    let seed = seed.or(lsys.seed()).unwrap_or(1);
    let mut d = Derivation::new(&lsys, seed).unwrap_or_else(|e| check("derivation: ", e));
    d.derive(steps.unwrap_or(lsys.derivation_length()))
        .unwrap_or_else(|e| check("derivation: ", e));
    let s = d.string();
    if print {
        say(&s.display(lsys.symbols()));
    }
    say(&format!(
        "{name}: {} modules after {} steps",
        s.len(),
        d.steps()
    ));

    let mut tp = TurtleParams::for_lsystem(&lsys);
    let mut geo = Turtle::new(&lsys, tp.clone())
        .and_then(|t| t.interpret(s))
        .unwrap_or_else(|e| check("interpretation: ", e));
    let sets_width = ["!", "#"]
        .iter()
        .any(|w| lsys.symbol(w).is_some_and(|id| s.symbols().contains(&id)));
    if let (false, Some((lo, hi))) = (sets_width, geo.bounds()) {
        tp.width = f64::from((hi - lo).max_element()) / 150.0;
        geo = Turtle::new(&lsys, tp)
            .and_then(|t| t.interpret(s))
            .unwrap_or_else(|e| check("interpretation: ", e));
    }
    let params = MeshParams {
        radial_segments: radial,
        ..MeshParams::default()
    };
    let mesh = PlantMesh::from_geometry(&geo, &params).unwrap_or_else(|e| check("mesh: ", e));
    say(&format!(
        "{} segments, {} polygons, {} surfaces -> {} vertices, {} triangles",
        geo.segment_count(),
        geo.polygons.len(),
        geo.surfaces.len(),
        mesh.vertex_count(),
        mesh.triangle_count()
    ));
    if mesh.triangle_count() == 0 {
        common::fail(&format!("{name}: the L-system draws nothing"));
    }
    // Flat figures (in the turtle's x-z plane) are seen square on; 3-D plants a little from above.
    let (lo, hi) = mesh.bounds().unwrap_or_default();
    let flat = (hi.y - lo.y) < 0.05 * (hi - lo).max_element();
    let view = if flat {
        Vec3::Y
    } else {
        Vec3::new(0.25, 1.0, -0.3)
    };
    let size = if quick { 160 } else { 640 };
    let img =
        preview::snapshot(&mesh, size, size, view, None).unwrap_or_else(|e| check("picture: ", e));

    let glb = out.join(format!("{name}.glb"));
    let obj = out.join(format!("{name}.obj"));
    let png = out.join(format!("{name}.png"));
    // Each file is written atomically; if one fails, the ones before it go too.
    let mut written: Vec<PathBuf> = Vec::new();
    let fail_cleanly = |written: &[PathBuf], msg: String| -> ! {
        for p in written {
            let _ = std::fs::remove_file(p);
        }
        common::fail(&format!("{name}: {msg}"))
    };
    if let Err(e) = save_glb(&mesh, &glb) {
        fail_cleanly(&written, e.to_string());
    }
    written.push(glb.clone());
    if let Err(e) = save_obj(&mesh, &obj) {
        fail_cleanly(&written, e.to_string());
    }
    written.extend([obj.clone(), obj.with_extension("mtl")]);
    if let Err(e) = img.save_png(&png) {
        fail_cleanly(&written, e.to_string());
    }
    for p in [glb, obj, png] {
        say(&format!("wrote {}", p.display()));
    }
}

/// Reads an L-system file, refusing one larger than the language allows
/// before reading it (and reading no more than that from a special file).
fn read_source(f: &str) -> String {
    let max = natura::plant::lang::MAX_SOURCE_BYTES;
    let too_big = |n: u64| -> ! {
        common::fail(&format!(
            "{f}: {n} bytes or more, larger than the {max} bytes (16 MiB) an L-system file may have"
        ))
    };
    let file = std::fs::File::open(f).unwrap_or_else(|e| common::fail(&format!("{f}: {e}")));
    if let Ok(m) = file.metadata()
        && m.len() > max as u64
    {
        too_big(m.len());
    }
    let mut bytes = Vec::new();
    file.take(max as u64 + 1)
        .read_to_end(&mut bytes)
        .unwrap_or_else(|e| common::fail(&format!("{f}: {e}")));
    if bytes.len() > max {
        too_big(bytes.len() as u64);
    }
    String::from_utf8(bytes).unwrap_or_else(|e| common::fail(&format!("{f}: not UTF-8 text: {e}")))
}

/// Prints a line to standard output; a reader that stopped reading (a
/// closed pipe, as with `| head -1`) ends the program normally.
fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = writeln!(out, "{line}").and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            // A normal end, but through the same clean-up as every other
            // exit: nothing staged so far is left behind.
            common::remove_staged();
            std::process::exit(0);
        }
        common::fail(&format!("standard output: {e}"));
    }
}
