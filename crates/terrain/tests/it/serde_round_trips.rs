//! Round-trips of every parameter struct through TOML (`--features serde`):
//! values come back identical, and invalid values read from a file are still
//! refused by validation (deserialisation never bypasses it).
#![cfg(feature = "serde")]

use natura_terrain::erosion::{
    DiffusionParams, DropletParams, MusgraveParams, PipeParams, StreamPowerParams, ThermalParams,
};
use natura_terrain::synth::{
    FaultParams, MidpointParams, SpectralParams, SraParams, SubdivisionParams,
};
use serde::{Deserialize, Serialize};

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Everything {
    diffusion: DiffusionParams,
    droplets: DropletParams,
    hydraulic: MusgraveParams,
    pipe: PipeParams,
    stream_power: StreamPowerParams,
    thermal: ThermalParams,
    fault: FaultParams,
    midpoint: MidpointParams,
    spectral: SpectralParams,
    sra: SraParams,
    subdivision: SubdivisionParams,
}

fn everything() -> Everything {
    Everything {
        diffusion: DiffusionParams::default(),
        droplets: DropletParams::default(),
        hydraulic: MusgraveParams::default(),
        pipe: PipeParams::default(),
        stream_power: StreamPowerParams::default(),
        thermal: ThermalParams::default(),
        fault: FaultParams::default(),
        midpoint: MidpointParams::default(),
        spectral: SpectralParams::default(),
        sra: SraParams::default(),
        subdivision: SubdivisionParams::default(),
    }
}

#[test]
fn every_params_struct_round_trips_through_toml() {
    let e = everything();
    let text = toml::to_string(&e).unwrap();
    let back: Everything = toml::from_str(&text).unwrap();
    assert_eq!(back, e);
}

#[test]
fn invalid_values_from_a_file_are_still_refused() {
    let mut e = everything();
    e.stream_power.k = 5.0;
    let text = toml::to_string(&e).unwrap();
    let back: Everything = toml::from_str(&text).unwrap();
    let err = back.stream_power.validate().unwrap_err().to_string();
    assert!(err.contains("::k"), "{err}");
}
