//! A forest over eroded terrain: the ecosystem simulation of Deussen et al.
//! 1998 (natura-plant) on a stream-power-eroded spectral terrain
//! (natura-terrain); writes the instance list (CSV), a top-down picture of
//! the plants over the shaded terrain and a GLB of the prototypes placed with
//! EXT_mesh_gpu_instancing.
//!
//! ```text
//! cargo run --release --example forest                  # 1024² × 2 m (4.2 km²), ~1 M plants
//! cargo run --release --example forest -- --size 256    # the gallery picture (0.26 km²)
//! cargo run --release --example forest -- --quick --out /tmp/forest
//! cargo run --release --example forest -- --help        # every flag and its default
//! ```
//!
//! Writes `forest_instances.csv`, `forest_top.png` and `forest.glb` into
//! `--out` (default: `./forest/`), with a progress bar per stage.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use common::{Exit, Run, outln};
use natura::core::{Progress, Seed};
use natura::plant::eco::{
    EcoParams, Ecosystem, Instancing, MAX_PER_HA, MAX_SEEDS_PER_SPECIES, top_view,
};
use natura::plant::mesh::{Instance, MeshParams, PlantMesh, save_glb_instanced};

/// A forest over eroded terrain: the ecosystem simulation of Deussen et al.
/// 1998 on a stream-power-eroded spectral terrain 2 m a sample. Writes the
/// instance list (forest_instances.csv), a top-down picture of the plants
/// over the shaded terrain (forest_top.png) and the prototypes placed with
/// EXT_mesh_gpu_instancing (forest.glb).
#[derive(Parser)]
#[command(name = "forest", version)]
struct Cli {
    /// Small and fast (CI)
    #[arg(long)]
    quick: bool,
    /// Terrain samples per side [default: 1024; 128 with --quick]
    #[arg(long, value_parser = common::in_range(16usize, 65_536))]
    size: Option<usize>,
    /// Random seed
    #[arg(long, default_value_t = 1998)]
    seed: u64,
    /// Grass seeds per hectare per step (5× as many sown at the start)
    #[arg(long, default_value_t = 400.0, value_parser = common::in_range(0.0, MAX_PER_HA / 5.0))]
    grass_per_ha: f64,
    /// Most instances in the GLB
    #[arg(long, default_value_t = 20_000)]
    glb_max: usize,
    /// Output directory (created if needed)
    #[arg(long, value_name = "DIR", default_value = "forest")]
    out: PathBuf,
}

fn main() -> ExitCode {
    common::run(forest)
}

/// The program: every error returns through [`common::run`].
fn forest() -> Run {
    let Cli {
        quick,
        size,
        seed,
        grass_per_ha: grass,
        glb_max,
        out,
    } = common::parse();
    let n = size.unwrap_or(if quick { 128 } else { 1024 });
    // The initial grass (5× the seeds per step) over the terrain's area must
    // stay within what one species may sow: checked here, so the refusal
    // names the flag rather than the species' field it sets.
    let ha = ((n - 1) as f64 * 2.0).powi(2) / 1e4;
    let cap = (EcoParams::default().max_plants as f64).min(MAX_SEEDS_PER_SPECIES as f64);
    if 5.0 * grass * ha > cap {
        return Err(Exit::new(
            2,
            format!(
                "--grass-per-ha {}: must be in 0..={:.0} on this {ha:.1} ha terrain \
                 (5 × it per hectare is sown at the start, at most {cap:.0} grass plants)",
                common::short(grass),
                (cap / (5.0 * ha)).floor()
            ),
        ));
    }
    let out = common::out_dir(&out)?;
    let bar = common::Bar::new();
    let t0 = Instant::now();
    // The synthesis is quick; the erosion reports its steps.
    let hf = common::tiles::eroded_tile(n, 2.0, seed, &bar)?;
    let t_terrain = t0.elapsed();
    let mut params = EcoParams {
        seed: Seed(seed),
        ..EcoParams::default()
    };
    // Grass seeding sets the density: the default gives ~1 M plants on the full 4 km² run.
    if let Some(g) = params.species.iter_mut().find(|s| s.name == "grass") {
        g.seeds_per_ha = grass;
        g.initial_per_ha = 5.0 * grass;
    }
    let t1 = Instant::now();
    let mut eco = Ecosystem::new(&hf, params)?;
    let stats = eco.run(&bar)?;
    let t_eco = t1.elapsed();
    let inst = Instancing::new(&eco, 7)?;
    let sl = eco.site().slope.as_slice();
    let steep = sl.iter().filter(|&&v| v > 0.7).count() as f64 / sl.len() as f64;
    outln(format_args!(
        "{:.0}% of the terrain is steeper than 40°",
        100.0 * steep
    ))?;
    let last = stats.last().copied().unwrap_or_default();
    let (ex, ey) = eco.site().extent();
    outln(format_args!(
        "terrain {n}² ({:.2} km²) in {:.1} s; {} plants after {} steps in {:.1} s \
         (last step: {} seeded, {} thinned, {} old); {} prototypes, {:.0} instances each",
        ex * ey / 1e6,
        t_terrain.as_secs_f64(),
        last.alive,
        eco.steps(),
        t_eco.as_secs_f64(),
        last.seeded,
        last.thinned,
        last.old,
        inst.prototypes.len(),
        inst.reduction()
    ))?;
    // The three files, about a second each at the default size.
    bar.start("outputs", 3);
    inst.write_csv(out.join("forest_instances.csv"))?;
    bar.advance(1);
    let img = top_view(&eco, if quick { 256 } else { 320 })?;
    img.save_png(out.join("forest_top.png"))?;
    bar.advance(1);
    // The GLB holds every prototype mesh with (at most glb_max) instances of it.
    let mp = MeshParams::default();
    let meshes = inst
        .prototypes
        .iter()
        .map(|p| PlantMesh::from_geometry(&p.geometry, &mp))
        .collect::<Result<Vec<PlantMesh>, _>>()?;
    let step = inst.instances.len().div_ceil(glb_max.max(1)).max(1);
    let mut per: Vec<Vec<Instance>> = vec![Vec::new(); meshes.len()];
    for i in inst.instances.iter().step_by(step) {
        per[i.prototype as usize].push(Instance::new(i.position, i.rotation, i.scale));
    }
    let items: Vec<(&PlantMesh, &[Instance])> = meshes
        .iter()
        .zip(&per)
        .filter(|(_, v)| !v.is_empty())
        .map(|(m, v)| (m, v.as_slice()))
        .collect();
    save_glb_instanced(&items, out.join("forest.glb"))?;
    bar.advance(1);
    bar.finish();
    outln(format_args!("wrote {}", out.display()))
}
