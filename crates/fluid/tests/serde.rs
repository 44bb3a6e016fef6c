//! Round-trips of every parameter struct through TOML (`--features serde`):
//! values come back identical, and invalid values read from a file are still
//! refused by validation (deserialisation never bypasses it).
#![cfg(feature = "serde")]

use natura_fluid::liquid::LiquidParams;
use natura_fluid::pressure::SolverParams;
use natura_fluid::smoke::SmokeParams;
use natura_fluid::stable::StableParams;
use serde::{Deserialize, Serialize};

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Everything {
    liquid: LiquidParams,
    solver: SolverParams,
    smoke: SmokeParams,
    stable: StableParams,
}

#[test]
fn every_params_struct_round_trips_through_toml() {
    let e = Everything {
        liquid: LiquidParams::default(),
        solver: SolverParams::default(),
        smoke: SmokeParams::default(),
        stable: StableParams::default(),
    };
    let text = toml::to_string(&e).unwrap();
    let back: Everything = toml::from_str(&text).unwrap();
    assert_eq!(back, e);

    let mut bad = back;
    bad.liquid.max_cfl = 1e30;
    let text = toml::to_string(&bad).unwrap();
    let again: Everything = toml::from_str(&text).unwrap();
    let err = again.liquid.validate().unwrap_err().to_string();
    assert!(err.contains("max_cfl"), "{err}");
}
