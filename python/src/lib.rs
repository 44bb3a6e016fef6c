//! The compiled part of the `natura` Python package (`natura._native`):
//! numpy arrays in and out of natura's noise, terrain, plant, ocean,
//! volume, fluid, texture, atmosphere and render crates.
//!
//! The Python modules `natura.noise`, `natura.terrain`, `natura.plant`,
//! `natura.ocean`, `natura.volume`, `natura.texture`, `natura.atmos` and
//! `natura.render` (in `python/natura/`) give these functions their keyword
//! signatures and docstrings; this module checks every argument (a wrong
//! dtype, shape or value raises `TypeError` or `ValueError` naming it),
//! releases the GIL for the computation (a noise call on fewer than 256
//! points keeps it) and turns a Rust panic into `RuntimeError`.
//!
//! The module is compiled with the crate's `extension` feature, which the
//! package's `pyproject.toml` turns on for maturin; without it the crate is
//! empty (so `cargo test --workspace` compiles no PyO3).
#![cfg(feature = "extension")]

mod args;
mod eco;
mod noise;
mod ocean;
mod plant;
mod progress;
mod render;
mod smoke;
mod terrain;
mod texture;
mod values;
mod volume;

use pyo3::prelude::*;

/// Raises `RuntimeError` from a Rust panic carrying `message`: the boundary's
/// last resort, exposed so the Python tests can show that a panic never
/// crosses into Python as anything else.
#[pyfunction]
fn _panic_for_test(py: Python<'_>, message: String) -> PyResult<()> {
    args::run(py, move || -> PyResult<()> { panic!("{message}") })
}

/// The module `natura._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    noise::register(m)?;
    terrain::register(m)?;
    plant::register(m)?;
    ocean::register(m)?;
    eco::register(m)?;
    volume::register(m)?;
    smoke::register(m)?;
    texture::register(m)?;
    render::register(m)?;
    Ok(())
}
