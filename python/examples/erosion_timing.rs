//! The Rust side of `python/bench/bench.py`'s erosion comparison: times an
//! erosion model on a spectral-synthesis height field through natura's Rust
//! API, exactly as `natura.terrain.erode_<model>` runs it from Python.
//!
//! ```text
//! cargo run --release -p natura-python --example erosion_timing -- MODEL SIZE STEPS REPEATS
//! ```
//! prints the best wall time of `REPEATS` runs, in seconds, and an FNV-1a
//! hash of the result (the Python benchmark checks it equals its own).

use std::time::Instant;

use natura_core::{HeightField, NoProgress, Seed};
use natura_terrain::erosion::{MusgraveHydraulic, Thermal};
use natura_terrain::synth::{SpectralParams, spectral_synthesis};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [model, size, steps, repeats] = args.as_slice() else {
        return Err("usage: erosion_timing MODEL SIZE STEPS REPEATS".into());
    };
    let (size, steps, repeats): (usize, u32, u32) =
        (size.parse()?, steps.parse()?, repeats.parse()?);
    let start = spectral_synthesis(size, size, 10.0, &SpectralParams::default(), Seed(1))?;
    let mut best = f64::INFINITY;
    let mut hash = 0;
    for _ in 0..repeats {
        let mut hf: HeightField = start.clone();
        let t = Instant::now();
        match model.as_str() {
            "hydraulic" => {
                MusgraveHydraulic::new(Default::default(), &hf)?.run(&mut hf, steps, &NoProgress)?
            }
            "thermal" => Thermal::new(Default::default(), &hf)?.run(&mut hf, steps, &NoProgress)?,
            other => return Err(format!("unknown model {other}").into()),
        }
        best = best.min(t.elapsed().as_secs_f64());
        hash = hf
            .heights()
            .as_slice()
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
                (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
            });
    }
    println!("{best:.6} {hash}");
    Ok(())
}
