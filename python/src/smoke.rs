//! `natura._native.SmokeSolver`: natura-fluid's smoke solver (`Smoke`, after
//! Fedkiw, Stam and Jensen 2001) set up from Python: any box of cells, the
//! `SmokeParams`, sources and obstacles of any shape, stepped with the GIL
//! released, its fields read and written as float32 `(nz, ny, nx)` arrays.

use natura_core::Grid3;
use natura_fluid::grid::{CellKind, Dims};
use natura_fluid::shape::Obstacle;
use natura_fluid::smoke::{Smoke, SmokeParams, SmokeSource};
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{array3, grid3, run, value_error};
use crate::progress::PyProgress;
use crate::values::{from_params, to_params};

/// The smoke solver on a box of cells whose corner is at the origin.
#[pyclass(module = "natura._native")]
#[derive(Debug)]
pub struct SmokeSolver {
    smoke: Smoke,
}

#[pymethods]
impl SmokeSolver {
    /// `SmokeSolver(dims, cell, params=None)`: still air at the ambient
    /// temperature on `dims = (nx, ny, nz)` cells of edge `cell` metres,
    /// with `SmokeParams` from the dict `params` over its defaults.
    #[new]
    #[pyo3(signature = (dims, cell, params=None))]
    fn new(
        dims: (usize, usize, usize),
        cell: f32,
        params: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let params: SmokeParams = match params {
            Some(p) => from_params(p, "params")?,
            None => SmokeParams::default(),
        };
        let dims = Dims::new(dims.0, dims.1, dims.2)
            .map_err(|e| PyValueError::new_err(format!("dims: {e}")))?;
        let smoke = Smoke::new(dims, cell, params).map_err(value_error)?;
        Ok(Self { smoke })
    }

    /// `add_source(source)`: a `SmokeSource` from the dict `source`
    /// (`shape`, `density`, `temperature`, optional `velocity`).
    fn add_source(&mut self, source: &Bound<'_, PyAny>) -> PyResult<()> {
        let s: SmokeSource = from_params(source, "source")?;
        self.smoke.add_source(s).map_err(value_error)
    }

    /// `add_obstacle(obstacle)`: an `Obstacle` from the dict `obstacle`
    /// (`shape`, optional `velocity`, `angular_velocity`, `temperature`).
    fn add_obstacle(&mut self, obstacle: &Bound<'_, PyAny>) -> PyResult<()> {
        let o: Obstacle = from_params(obstacle, "obstacle")?;
        self.smoke.add_obstacle(o).map_err(value_error)
    }

    /// `step(dt, steps, force, progress)`: `steps` steps of `dt` seconds,
    /// the GIL released, with the user force `force` (a sequence of three
    /// float32 `(nz, ny, nx)` arrays, m/s² at cell centres) in each of them;
    /// returns the last step's report as a dict.
    #[pyo3(signature = (dt, steps=1, force=None, progress=None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        dt: f32,
        steps: u32,
        force: Option<Vec<Bound<'py, PyAny>>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        if steps == 0 {
            return Err(PyValueError::new_err("steps = 0: at least one step"));
        }
        let force = match force {
            None => None,
            Some(f) if f.len() == 3 => {
                let names = ["force[0]", "force[1]", "force[2]"];
                let mut g = Vec::with_capacity(3);
                for (a, name) in f.iter().zip(names) {
                    g.push(self.field(a, name, Values::Any)?);
                }
                Some(g)
            }
            Some(f) => {
                return Err(PyValueError::new_err(format!(
                    "force has {} arrays; it must have three (x, y and z)",
                    f.len()
                )));
            }
        };
        let sink = PyProgress::new(progress);
        let smoke = &mut self.smoke;
        let out = run(py, || {
            natura_core::Progress::start(&sink, "smoke", u64::from(steps));
            let mut last = None;
            for _ in 0..steps {
                if let Some(f) = &force {
                    for (slot, g) in smoke.force_mut().iter_mut().zip(f) {
                        slot.as_mut_slice().copy_from_slice(g.as_slice());
                    }
                }
                last = Some(smoke.step(dt).map_err(value_error)?);
                natura_core::Progress::advance(&sink, 1);
            }
            natura_core::Progress::finish(&sink);
            Ok((last, smoke.velocity().max_abs()))
        });
        let (report, max_speed) = sink.finish_call(out)?;
        let d = PyDict::new(py);
        if let Some(r) = report {
            d.set_item("max_divergence", r.max_divergence)?;
            d.set_item("kinetic_energy", r.kinetic_energy)?;
            d.set_item("pressure_iterations", r.pressure_iterations)?;
            if let Some(p) = r.pressure {
                d.set_item("relative_residual", p.relative_residual)?;
                d.set_item("converged", p.converged)?;
            }
        }
        d.set_item("max_speed", max_speed)?;
        Ok(d)
    }

    /// The smoke density, a float32 `(nz, ny, nx)` copy.
    #[getter]
    fn density<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        array3(py, self.smoke.density().clone())
    }

    /// The temperature (K), a float32 `(nz, ny, nx)` copy.
    #[getter]
    fn temperature<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        array3(py, self.smoke.temperature().clone())
    }

    /// `set_density(a)`: replaces the density by the float32 `(nz, ny, nx)`
    /// array `a` (finite, non-negative).
    fn set_density(&mut self, a: &Bound<'_, PyAny>) -> PyResult<()> {
        let g = self.field(a, "density", Values::NonNegative)?;
        *self.smoke.density_mut() = g;
        Ok(())
    }

    /// `set_temperature(a)`: replaces the temperature by the float32
    /// `(nz, ny, nx)` array `a` (finite, positive kelvin).
    fn set_temperature(&mut self, a: &Bound<'_, PyAny>) -> PyResult<()> {
        let g = self.field(a, "temperature", Values::Positive)?;
        *self.smoke.temperature_mut() = g;
        Ok(())
    }

    /// The staggered velocity: float32 arrays of the x, y and z faces,
    /// `(nz, ny, nx + 1)`, `(nz, ny + 1, nx)` and `(nz + 1, ny, nx)` (m/s).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArray3<f32>>>> {
        self.smoke
            .velocity()
            .comps()
            .iter()
            .map(|g| array3(py, g.clone()))
            .collect()
    }

    /// Which cells obstacles occupy, a bool `(nz, ny, nx)` array.
    #[getter]
    fn solid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<bool>>> {
        let k = self.smoke.cell_kinds();
        let (nx, ny, nz) = k.dims();
        let flags: Vec<bool> = k.as_slice().iter().map(|c| *c == CellKind::Solid).collect();
        let a = numpy::ndarray::Array3::from_shape_vec((nz, ny, nx), flags)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py))
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.smoke.time()
    }

    /// `(nx, ny, nz)`.
    #[getter]
    fn dims(&self) -> (usize, usize, usize) {
        let [nx, ny, nz] = self.smoke.dims().n();
        (nx, ny, nz)
    }

    /// The cell edge (m).
    #[getter]
    fn cell(&self) -> f32 {
        self.smoke.h()
    }

    /// The solver's `SmokeParams` as a dict.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_params(py, self.smoke.params())
    }
}

/// What a field's values must be, besides finite.
#[derive(Clone, Copy, Debug)]
enum Values {
    /// Any finite value (a force).
    Any,
    /// At least zero (a density).
    NonNegative,
    /// Above zero (a temperature in kelvin).
    Positive,
}

impl Values {
    fn admits(self, v: f32) -> bool {
        v.is_finite()
            && match self {
                Values::Any => true,
                Values::NonNegative => v >= 0.0,
                Values::Positive => v > 0.0,
            }
    }

    fn words(self) -> &'static str {
        match self {
            Values::Any => "finite",
            Values::NonNegative => "finite and non-negative",
            Values::Positive => "finite and positive",
        }
    }
}

impl SmokeSolver {
    /// `a` as a field of this grid's size whose every value is as `values` says.
    fn field(&self, a: &Bound<'_, PyAny>, name: &str, values: Values) -> PyResult<Grid3<f32>> {
        let g = grid3(a, name)?;
        let want = self.dims();
        if g.dims() != want {
            let (nx, ny, nz) = g.dims();
            return Err(PyValueError::new_err(format!(
                "{name} has shape ({nz}, {ny}, {nx}); the solver's is ({}, {}, {})",
                want.2, want.1, want.0
            )));
        }
        if let Some(v) = g.as_slice().iter().find(|v| !values.admits(**v)) {
            return Err(PyValueError::new_err(format!(
                "{name} holds {v}; every value must be {}",
                values.words()
            )));
        }
        Ok(g)
    }
}

/// Adds the smoke solver to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<SmokeSolver>()?;
    Ok(())
}
