//! Derives an L-system file and writes its mesh (glTF binary, OBJ + MTL) and
//! a picture. Files in the cpfg / L-Py convention; see `examples/lsystems/`.
//!
//! ```text
//! cargo run --release --example lsystem -- examples/lsystems/fig1_25.l
//! cargo run --release --example lsystem -- examples/lsystems/fig2_8.l --steps 5 --out /tmp/tree
//! cargo run --release --example lsystem -- examples/lsystems/koch_curve.l --steps 2 --print
//! cargo run --release --example lsystem -- --quick      # the built-in bush, small picture (CI)
//! cargo run --release --example lsystem -- --help       # every flag and its default
//! ```
//!
//! Writes `NAME.glb`, `NAME.obj` (+ `NAME.mtl`) and `NAME.png`, NAME being
//! the file's stem, into `--out` (default: `./lsystem/`).
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

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use common::{Exit, Run, outln};
use natura::core::Progress;
use natura::core::glam::Vec3;
use natura::plant::mesh::{save_glb, save_obj};
use natura::plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams, preview};

/// ABOP fig. 1.24d, used when no file is given.
const DEFAULT: &str = include_str!("lsystems/fig1_24d.l");

/// Derives an L-system file (cpfg / L-Py convention) and writes its mesh as
/// NAME.glb and NAME.obj (+ NAME.mtl) and a picture, NAME.png, NAME being
/// the file's stem.
#[derive(Parser)]
#[command(name = "lsystem", version)]
struct Cli {
    /// The L-system file; without one, --quick uses the built-in bush (ABOP
    /// fig. 1.24d) and a bare call is an error
    #[arg(value_name = "FILE")]
    file: Option<PathBuf>,
    /// Small picture; the built-in bush if no FILE (CI)
    #[arg(long)]
    quick: bool,
    /// Print the derived string
    #[arg(long)]
    print: bool,
    /// Derivation steps [default: the file's `derivation length:`]
    #[arg(long)]
    steps: Option<u32>,
    /// Seed of stochastic productions [default: the file's `seed:`, else 1]
    #[arg(long)]
    seed: Option<u64>,
    /// Vertices around a stem
    #[arg(long, default_value_t = 8, value_parser = common::in_range(3u32, 64))]
    radial: u32,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "lsystem")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(lsystem)
}

/// The program: every error returns through [`common::run`].
fn lsystem() -> Run {
    let Cli {
        file,
        quick,
        print,
        steps,
        seed,
        radial,
        out,
    } = common::parse();

    let (name, text) = match &file {
        Some(f) => {
            let stem = f
                .file_stem()
                .map_or("plant".into(), |s| s.to_string_lossy().into_owned());
            (stem, read_source(f)?)
        }
        None if quick => ("fig1_24d".to_string(), DEFAULT.to_string()),
        None => {
            return Err(Exit::new(
                2,
                "no L-system file given (try --help, or --quick for the built-in one)",
            ));
        }
    };
    // Every error from here on starts with the file's name.
    let check = |what: &str| {
        let name = name.clone();
        let what = what.to_owned();
        move |e: natura::plant::PlantError| Exit::new(2, format!("{name}: {what}{e}"))
    };
    let lsys = LSystem::parse(&text).map_err(check(""))?;
    let out = common::out_dir(&out)?;
    let seed = seed.or(lsys.seed()).unwrap_or(1);
    let mut d = Derivation::new(&lsys, seed).map_err(check("derivation: "))?;
    let bar = common::Bar::new();
    let n = steps.unwrap_or(lsys.derivation_length());
    bar.start("derivation", u64::from(n));
    for _ in 0..n {
        d.step().map_err(check("derivation: "))?;
        bar.advance(1);
    }
    bar.finish();
    let s = d.string();
    if print {
        outln(s.display(lsys.symbols()))?;
    }
    outln(format_args!(
        "{name}: {} modules after {} steps",
        s.len(),
        d.steps()
    ))?;

    let mut tp = TurtleParams::for_lsystem(&lsys);
    let mut geo = Turtle::new(&lsys, tp.clone())
        .and_then(|t| t.interpret(s))
        .map_err(check("interpretation: "))?;
    let sets_width = ["!", "#"]
        .iter()
        .any(|w| lsys.symbol(w).is_some_and(|id| s.symbols().contains(&id)));
    if let (false, Some((lo, hi))) = (sets_width, geo.bounds()) {
        tp.width = f64::from((hi - lo).max_element()) / 150.0;
        geo = Turtle::new(&lsys, tp)
            .and_then(|t| t.interpret(s))
            .map_err(check("interpretation: "))?;
    }
    let params = MeshParams {
        radial_segments: radial,
        ..MeshParams::default()
    };
    let mesh = PlantMesh::from_geometry(&geo, &params).map_err(check("mesh: "))?;
    outln(format_args!(
        "{} segments, {} polygons, {} surfaces -> {} vertices, {} triangles",
        geo.segment_count(),
        geo.polygons.len(),
        geo.surfaces.len(),
        mesh.vertex_count(),
        mesh.triangle_count()
    ))?;
    if mesh.triangle_count() == 0 {
        return Err(Exit::new(2, format!("{name}: the L-system draws nothing")));
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
    let img = preview::snapshot(&mesh, size, size, view, None).map_err(check("picture: "))?;

    let glb = out.join(format!("{name}.glb"));
    let obj = out.join(format!("{name}.obj"));
    let png = out.join(format!("{name}.png"));
    // Each file is written atomically; if one fails, the ones before it go too.
    let mut written: Vec<PathBuf> = Vec::new();
    let fail_cleanly = |written: &[PathBuf], e: &dyn std::fmt::Display| {
        for p in written {
            let _ = std::fs::remove_file(p);
        }
        Exit::new(2, format!("{name}: {e}"))
    };
    save_glb(&mesh, &glb).map_err(|e| fail_cleanly(&written, &e))?;
    written.push(glb.clone());
    save_obj(&mesh, &obj).map_err(|e| fail_cleanly(&written, &e))?;
    written.extend([obj.clone(), obj.with_extension("mtl")]);
    img.save_png(&png).map_err(|e| fail_cleanly(&written, &e))?;
    for p in [glb, obj, png] {
        outln(format_args!("wrote {}", p.display()))?;
    }
    Ok(())
}

/// Reads an L-system file, refusing one larger than the language allows
/// before reading it (and reading no more than that from a special file).
fn read_source(f: &Path) -> Result<String, Exit> {
    let max = natura::plant::lang::MAX_SOURCE_BYTES;
    let shown = f.display();
    let too_big = |n: u64| {
        Exit::new(
            2,
            format!(
                "{shown}: {n} bytes or more, larger than the {max} bytes (16 MiB) an L-system file may have"
            ),
        )
    };
    let io = |e: std::io::Error| Exit::new(2, format!("{shown}: {e}"));
    let file = std::fs::File::open(f).map_err(io)?;
    if let Ok(m) = file.metadata()
        && m.len() > max as u64
    {
        return Err(too_big(m.len()));
    }
    let mut bytes = Vec::new();
    file.take(max as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() > max {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| Exit::new(2, format!("{shown}: not UTF-8 text: {e}")))
}
