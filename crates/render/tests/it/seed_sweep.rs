//! The landscape's terrain stage over many seeds: synthesis, droplet and
//! stream-power erosion, thermal weathering and the coast must give finite
//! heights within a physical range for every seed, not only the ones the
//! gallery uses.

use natura_core::NoProgress;
use natura_render::{SceneDesc, World};

#[test]
fn two_hundred_seeds_give_finite_heights_in_a_physical_range() {
    let mut scene = SceneDesc::default();
    // The default world (61 km across) at 128², with the default erosion
    // (droplets on, one per four samples, stream power and thermal).
    scene.terrain.resample(128);
    let relief = scene.terrain.relief_m as f32;
    let mut worst = (f32::INFINITY, f32::NEG_INFINITY);
    for seed in 0..200 {
        scene.seed = seed;
        let hf = World::build_terrain(&scene, &NoProgress)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        hf.check_finite()
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        let (lo, hi) = hf.min_max();
        // Synthesis makes at most the relief above sea level; erosion only
        // lowers peaks and fills valleys, and the coast sinks below the sea by
        // less than the relief.
        assert!(
            lo >= -relief && hi <= 1.5 * relief,
            "seed {seed}: heights {lo} … {hi} m outside ±{relief} m"
        );
        worst = (worst.0.min(lo), worst.1.max(hi));
    }
    eprintln!("200 seeds: heights {} … {} m", worst.0, worst.1);
}
