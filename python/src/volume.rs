//! `natura.volume`: natura-volume's Ebert clouds and layer clouds baked to
//! voxel density arrays, natura-fluid's smoke plume simulated to density
//! and temperature arrays, and OpenVDB files written and read by
//! natura-volume's VDB writer and reader.
//!
//! Arrays are float32 `(nz, ny, nx)`: voxel `(x, y, z)` is `a[z, y, x]`,
//! natura's `Grid3` layout, so no copy reorders them.

use natura_core::Grid3;
use natura_fluid::plume::Plume;
use natura_volume::cloud::{CloudParams, cirrostratus_primitives, cloud, nine_sphere_cumulus};
use natura_volume::glam::Vec3;
use natura_volume::grid::GridDensity;
use natura_volume::layer::{LayerClouds, LayerParams};
use natura_volume::vdb::{read_vdb, write_vdb};
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{run, value_error};
use crate::progress::PyProgress;
use crate::values::{from_params, to_params};

/// A `Grid3` as a float32 `(nz, ny, nx)` array (its buffer moved, not copied).
fn array3(py: Python<'_>, g: Grid3<f32>) -> PyResult<Bound<'_, PyArray3<f32>>> {
    let (nx, ny, nz) = g.dims();
    let a = numpy::ndarray::Array3::from_shape_vec((nz, ny, nx), g.into_vec())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// A float32 `(nz, ny, nx)` numpy array (any layout) as a `Grid3`.
fn grid3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Grid3<f32>> {
    let (data, s) = crate::args::f32_array(obj, name, 3, "nz, ny, nx")?;
    let (nz, ny, nx) = (s[0], s[1], s[2]);
    Grid3::from_vec(nx, ny, nz, data).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// A baked density as `(density, origin, cell)`.
type Baked<'py> = (Bound<'py, PyArray3<f32>>, (f32, f32, f32), f32);

fn baked(py: Python<'_>, g: GridDensity) -> PyResult<Baked<'_>> {
    let o = g.origin();
    let cell = g.cell();
    Ok((array3(py, g.grid().clone())?, (o.x, o.y, o.z), cell))
}

/// `cloud_density(shape, cell, seed, params, progress)`: Ebert's cloud of
/// the implicit primitives `shape` names (`"cumulus"`: the nine-sphere
/// cumulus; `"cirrostratus"`: the veil and cirrus cylinders), with
/// `CloudParams` from `params` (over the cumulus default), baked at voxel
/// centres with voxel edge `cell` over the cloud's bounds.
#[pyfunction]
#[pyo3(signature = (shape, cell, seed, params, progress=None))]
fn cloud_density<'py>(
    py: Python<'py>,
    shape: &str,
    cell: f32,
    seed: u64,
    params: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Baked<'py>> {
    let prims = match shape {
        "cumulus" => nine_sphere_cumulus(),
        "cirrostratus" => cirrostratus_primitives(),
        other => {
            return Err(PyValueError::new_err(format!(
                "shape = {other:?} is not one of cumulus, cirrostratus"
            )));
        }
    };
    let p: CloudParams = from_params(params, "cloud")?;
    let c = cloud(prims, p, seed).map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        GridDensity::bake_with_progress(&c, cell, &sink).map_err(value_error)
    });
    baked(py, sink.finish_call(out)?)
}

/// `layer_density(cell, seed, params, progress)`: natura-volume's layer
/// clouds (`LayerParams` from `params`) baked with voxel edge `cell` over
/// the layer's bounds.
#[pyfunction]
#[pyo3(signature = (cell, seed, params, progress=None))]
fn layer_density<'py>(
    py: Python<'py>,
    cell: f32,
    seed: u64,
    params: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Baked<'py>> {
    let p: LayerParams = from_params(params, "layer_clouds")?;
    let layer = LayerClouds::new(p, seed).map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        GridDensity::bake_with_progress(&layer, cell, &sink).map_err(value_error)
    });
    baked(py, sink.finish_call(out)?)
}

/// `cloud_defaults(kind)`: `CloudParams::default()` (`"cloud"`) or
/// `LayerParams::default()` (`"layer"`) as a dict.
#[pyfunction]
fn volume_defaults<'py>(py: Python<'py>, kind: &str) -> PyResult<Bound<'py, PyAny>> {
    match kind {
        "cloud" => to_params(py, &CloudParams::default()),
        "layer" => to_params(py, &LayerParams::default()),
        other => Err(PyValueError::new_err(format!(
            "kind = {other:?} is not one of cloud, layer"
        ))),
    }
}

/// The smoke's density and temperature, its cell size and time step.
type SmokeArrays<'py> = (
    Bound<'py, PyArray3<f32>>,
    Bound<'py, PyArray3<f32>>,
    f32,
    f32,
);

/// `smoke_plume(cells, width, epsilon, steps, progress)`: natura-fluid's
/// plume preset (`Plume`: warm smoke rising past a sphere, a box
/// `cells × cells × 2·cells`) after `steps` steps of its time step, as
/// `(density, temperature, cell, dt)`; density and temperature are float32
/// `(2·cells, cells, cells)`.
#[pyfunction]
#[pyo3(signature = (cells, width, epsilon, steps, progress=None))]
fn smoke_plume<'py>(
    py: Python<'py>,
    cells: usize,
    width: f32,
    epsilon: f32,
    steps: u32,
    progress: Option<Py<PyAny>>,
) -> PyResult<SmokeArrays<'py>> {
    let plume = Plume {
        cells,
        width,
        epsilon,
    };
    plume.validate().map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        let mut smoke = plume.build().map_err(value_error)?;
        let dt = plume.dt();
        natura_core::Progress::start(&sink, "smoke", u64::from(steps));
        for _ in 0..steps {
            smoke.step(dt).map_err(value_error)?;
            natura_core::Progress::advance(&sink, 1);
        }
        natura_core::Progress::finish(&sink);
        Ok(smoke)
    });
    let smoke = sink.finish_call(out)?;
    let (cell, dt) = (plume.cell(), plume.dt());
    Ok((
        array3(py, smoke.density().clone())?,
        array3(py, smoke.temperature().clone())?,
        cell,
        dt,
    ))
}

/// `vdb_write(path, grids, origin, cell)`: writes the float32 `(nz, ny, nx)`
/// arrays of the dict `grids` (name → array, same origin and cell) as float
/// grids of one OpenVDB file, through a temporary name and a rename.
#[pyfunction]
fn vdb_write(
    py: Python<'_>,
    path: std::path::PathBuf,
    grids: &Bound<'_, PyDict>,
    origin: (f32, f32, f32),
    cell: f32,
) -> PyResult<()> {
    let o = Vec3::new(origin.0, origin.1, origin.2);
    let mut named = Vec::new();
    for (k, v) in grids.iter() {
        let name: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err("grids: names must be strings"))?;
        let g = grid3(&v, &format!("grids[{name:?}]"))?;
        let d = GridDensity::new(g, o, cell)
            .map_err(|e| PyValueError::new_err(format!("grids[{name:?}]: {e}")))?;
        named.push((name, d));
    }
    if named.is_empty() {
        return Err(PyValueError::new_err("grids must name at least one grid"));
    }
    run(py, || {
        let refs: Vec<(&str, &GridDensity)> = named.iter().map(|(n, d)| (n.as_str(), d)).collect();
        write_vdb(&path, &refs).map_err(|e| PyOSError::new_err(e.to_string()))
    })
}

/// `vdb_read(path)`: the float grids of an OpenVDB file natura can read
/// (the subset its writer writes) as a dict name → `(array, origin, cell)`,
/// each array over the bounding box of the grid's active voxels.
#[pyfunction]
fn vdb_read<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let grids = run(py, || {
        read_vdb(&path).map_err(|e| PyOSError::new_err(e.to_string()))
    })?;
    let d = PyDict::new(py);
    for g in grids {
        d.set_item(g.name.clone(), baked(py, g.density)?)?;
    }
    Ok(d)
}

/// Adds the volume functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cloud_density, m)?)?;
    m.add_function(wrap_pyfunction!(layer_density, m)?)?;
    m.add_function(wrap_pyfunction!(volume_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(smoke_plume, m)?)?;
    m.add_function(wrap_pyfunction!(vdb_write, m)?)?;
    m.add_function(wrap_pyfunction!(vdb_read, m)?)?;
    Ok(())
}
