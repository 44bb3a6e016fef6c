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
//! ```

mod common;

use std::time::Instant;

use natura::core::Seed;
use natura::plant::eco::{
    EcoParams, Ecosystem, Instancing, MAX_PER_HA, MAX_SEEDS_PER_SPECIES, top_view,
};
use natura::plant::mesh::{Instance, MeshParams, PlantMesh, save_glb_instanced};

fn main() {
    let mut args = common::Args::from_env();
    let quick = args.switch("--quick", "small and fast (CI)");
    let n: usize = args.value(
        "--size",
        if quick { 128 } else { 1024 },
        "terrain samples per side",
    );
    let seed: u64 = args.value("--seed", 1998, "random seed");
    let grass: f64 = args.ranged(
        "--grass-per-ha",
        400.0,
        0.0..=MAX_PER_HA / 5.0,
        "grass seeds per hectare per step (5× as many sown at the start)",
    );
    let glb_max: usize = args.value("--glb-max", 20_000, "most instances in the GLB");
    let out = args.out_dir("docs/gallery/plant");
    args.finish();
    if !(16..=65_536).contains(&n) {
        common::fail(&format!("--size {n}: must be in 16..=65536"));
    }
    // The initial grass (5× the seeds per step) over the terrain's area must
    // stay within what one species may sow: checked here, so the refusal
    // names the flag rather than the species' field it sets.
    let ha = ((n - 1) as f64 * 2.0).powi(2) / 1e4;
    let cap = (EcoParams::default().max_plants as f64).min(MAX_SEEDS_PER_SPECIES as f64);
    if 5.0 * grass * ha > cap {
        common::fail(&format!(
            "--grass-per-ha {}: must be in 0..={:.0} on this {ha:.1} ha terrain \
             (5 × it per hectare is sown at the start, at most {cap:.0} grass plants)",
            common::short(grass),
            (cap / (5.0 * ha)).floor()
        ));
    }
    let t0 = Instant::now();
    let hf = common::check(common::tiles::eroded_tile(n, 2.0, seed));
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
    let mut eco = common::check(Ecosystem::new(&hf, params));
    let bar = common::Bar::new();
    let stats = common::check(eco.run(&bar));
    let t_eco = t1.elapsed();
    let inst = common::check(Instancing::new(&eco, 7));
    let sl = eco.site().slope.as_slice();
    let steep = sl.iter().filter(|&&v| v > 0.7).count() as f64 / sl.len() as f64;
    println!("{:.0}% of the terrain is steeper than 40°", 100.0 * steep);
    let last = stats.last().copied().unwrap_or_default();
    let (ex, ey) = eco.site().extent();
    println!(
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
    );
    common::check(inst.write_csv(out.join("forest_instances.csv")));
    let img = common::check(top_view(&eco, if quick { 256 } else { 320 }));
    common::check(img.save_png(out.join("forest_top.png")));
    // The GLB holds every prototype mesh with (at most glb_max) instances of it.
    let mp = MeshParams::default();
    let meshes: Vec<PlantMesh> = inst
        .prototypes
        .iter()
        .map(|p| common::check(PlantMesh::from_geometry(&p.geometry, &mp)))
        .collect();
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
    common::check(save_glb_instanced(&items, out.join("forest.glb")));
    println!("wrote {}", out.display());
}
