//! Round trips of the parameter structs through TOML (`--features serde`):
//! values come back equal, and invalid values read from a file are still
//! refused when the texture or planet is built.
#![cfg(feature = "serde")]

use natura_texture::air::{CycloneParams, PlanetCloudsParams, PuffyCloudsParams, VenusParams};
use natura_texture::earth::{LunaParams, RidgeParams, StrataParams, TerranParams};
use natura_texture::fire::FlameParams;
use natura_texture::giants::{GasGiantParams, RingsParams};
use natura_texture::multicolor::MulticolorParams;
use natura_texture::planet::{GroundViewParams, Planet, PlanetParams, TraceSettings};
use natura_texture::water::{RipplesParams, WindyWaveParams};
use serde::{Deserialize, Serialize};

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Everything {
    puffy: PuffyCloudsParams,
    clouds: PlanetCloudsParams,
    cyclone: CycloneParams,
    venus: VenusParams,
    flame: FlameParams,
    ripples: RipplesParams,
    windywave: WindyWaveParams,
    strata: StrataParams,
    terran: TerranParams,
    gaea: TerranParams,
    luna: LunaParams,
    ridge: RidgeParams,
    gas_giant: GasGiantParams,
    rings: RingsParams,
    multicolor: MulticolorParams,
    planet: PlanetParams,
    jupiter: PlanetParams,
    ground: GroundViewParams,
    trace: TraceSettings,
}

#[test]
fn every_params_struct_round_trips() {
    let all = Everything {
        puffy: Default::default(),
        clouds: Default::default(),
        cyclone: Default::default(),
        venus: Default::default(),
        flame: Default::default(),
        ripples: Default::default(),
        windywave: Default::default(),
        strata: Default::default(),
        terran: Default::default(),
        gaea: TerranParams::gaea(),
        luna: Default::default(),
        ridge: Default::default(),
        gas_giant: GasGiantParams::saturn(),
        rings: Default::default(),
        multicolor: Default::default(),
        planet: PlanetParams::gaea(),
        jupiter: PlanetParams::jupiter(),
        ground: Default::default(),
        trace: Default::default(),
    };
    let text = toml::to_string(&all).unwrap();
    let back: Everything = toml::from_str(&text).unwrap();
    assert_eq!(back, all);
}

#[test]
fn invalid_values_from_a_file_are_refused() {
    let mut p = PlanetParams::gaea();
    p.radius_m = -1.0;
    let text = toml::to_string(&p).unwrap();
    let back: PlanetParams = toml::from_str(&text).unwrap();
    let e = Planet::new(back).unwrap_err().to_string();
    assert!(e.contains("radius_m"), "{e}");
}
