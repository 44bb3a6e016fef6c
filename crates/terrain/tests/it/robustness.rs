//! Hostile heights, parameters and slices: a typed error, never NaN in an
//! `Ok` field and never a panic.

use natura_core::{HeightField, NoProgress, Seed};
use natura_terrain::TerrainError;
use natura_terrain::analysis::flow::{Depressions, FlowGraph, priority_flood_levels};
use natura_terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, MAX_HEIGHT, MusgraveHydraulic,
    MusgraveParams, PipeModel, PipeParams, StreamPower, StreamPowerParams, Thermal, ThermalParams,
};

fn field(z: f32) -> HeightField {
    HeightField::from_fn(16, 16, 10.0, |i, j| if (i + j) % 2 == 0 { z } else { -z }).unwrap()
}

/// Every model on `hf`: each either refuses it or leaves it finite.
fn each_model(hf: &HeightField) -> Vec<(&'static str, Result<HeightField, TerrainError>)> {
    let mut out = Vec::new();
    let mut run = |name, f: &dyn Fn(&mut HeightField) -> Result<(), TerrainError>| {
        let mut h = hf.clone();
        out.push((name, f(&mut h).map(|()| h)));
    };
    run("thermal", &|h| {
        Thermal::new(ThermalParams::default(), h)?.run(h, 5, &NoProgress)
    });
    run("pipe", &|h| {
        PipeModel::new(PipeParams::default(), h)?.run(h, 5, &NoProgress)
    });
    run("diffusion", &|h| {
        Diffusion::new(DiffusionParams::default(), h)?.run(h, 5, &NoProgress)
    });
    run("hydraulic", &|h| {
        MusgraveHydraulic::new(MusgraveParams::default(), h)?.run(h, 5, &NoProgress)
    });
    run("droplets", &|h| {
        DropletErosion::new(DropletParams::default(), h, Seed(3))?.run(h, 2000, &NoProgress)
    });
    run("stream power", &|h| {
        StreamPower::new(StreamPowerParams::default(), h)?.run(h, 3, &NoProgress)
    });
    out
}

#[test]
fn huge_heights_are_refused_by_every_model() {
    for z in [3e38f32, -3e38, 1e7, 2.0 * MAX_HEIGHT] {
        for (name, r) in each_model(&field(z)) {
            let e = r
                .err()
                .unwrap_or_else(|| panic!("{name} accepted heights ±{z}"));
            assert!(e.to_string().contains("height"), "{name}: {e}");
        }
    }
}

#[test]
fn heights_at_the_limit_stay_finite() {
    for (name, r) in each_model(&field(0.5 * MAX_HEIGHT)) {
        if let Ok(h) = r {
            assert!(
                h.heights().as_slice().iter().all(|v| v.is_finite()),
                "{name}"
            );
        }
    }
}

#[test]
fn absurd_stream_power_erodibility_is_refused() {
    for k in [1e300, 2.0, f64::NAN, -1.0] {
        let p = StreamPowerParams {
            k,
            ..StreamPowerParams::default()
        };
        let e = StreamPower::new(p, &field(100.0)).unwrap_err().to_string();
        assert!(e.contains("::k"), "{k}: {e}");
    }
}

#[test]
fn flow_on_slices_of_the_wrong_length_is_an_error() {
    for (len, nx, ny) in [
        (15, 4, 4),
        (17, 4, 4),
        (0, 0, 0),
        (4, 0, 4),
        (4, usize::MAX, 2),
    ] {
        let mut h = vec![1.0f32; len];
        assert!(matches!(
            FlowGraph::build(&mut h, nx, ny, Depressions::Fill),
            Err(TerrainError::SizeMismatch { .. })
        ));
        assert!(priority_flood_levels(&h, nx, ny).is_err());
    }
    let mut h = vec![1.0, f32::NAN, 1.0, 1.0];
    assert!(matches!(
        FlowGraph::build(&mut h, 2, 2, Depressions::Fill),
        Err(TerrainError::NonFinite { .. })
    ));
    assert!(priority_flood_levels(&[1.0; 4], 2, 2).is_ok());
}
