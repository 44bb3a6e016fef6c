//! `natura.volume`: natura-volume's Ebert clouds and layer clouds baked to
//! voxel density arrays, natura-fluid's smoke plume simulated to density
//! and temperature arrays, and OpenVDB files written and read by
//! natura-volume's VDB writer and reader.
//!
//! Arrays are float32 `(nz, ny, nx)`: voxel `(x, y, z)` is `a[z, y, x]`,
//! natura's `Grid3` layout, so no copy reorders them.

use natura_fluid::plume::Plume;
use natura_volume::cloud::{CloudParams, cirrostratus_primitives, cloud, nine_sphere_cumulus};
use natura_volume::glam::Vec3;
use natura_volume::grid::GridDensity;
use natura_volume::implicit::ImplicitPrimitive;
use natura_volume::layer::{LayerClouds, LayerParams};
use natura_volume::transport::{
    CacheParams, FastRenderer, FastSettings, LookAtCamera, MediumParams, ReferenceRenderer,
    ReferenceSettings, Scattering, Scene, Shadows, Sun,
};
use natura_volume::vdb::{read_vdb, write_vdb};
use numpy::PyArray3;
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{array3, grid3, image_array, run, value_error};
use crate::progress::PyProgress;
use crate::values::{from_params, from_value, overlay, to_params, to_toml};

/// A baked density as `(density, origin, cell)`.
type Baked<'py> = (Bound<'py, PyArray3<f32>>, (f32, f32, f32), f32);

fn baked(py: Python<'_>, g: GridDensity) -> PyResult<Baked<'_>> {
    let o = g.origin();
    let cell = g.cell();
    Ok((array3(py, g.grid().clone())?, (o.x, o.y, o.z), cell))
}

/// The implicit primitives of a named cloud shape (`"cumulus"`: the
/// nine-sphere cumulus; `"cirrostratus"`: the veil and cirrus cylinders).
fn named_shape(name: &str) -> PyResult<Vec<ImplicitPrimitive>> {
    match name {
        "cumulus" => Ok(nine_sphere_cumulus()),
        "cirrostratus" => Ok(cirrostratus_primitives()),
        other => Err(PyValueError::new_err(format!(
            "shape = {other:?} is not one of cumulus, cirrostratus"
        ))),
    }
}

/// `cloud_primitives(name)`: the implicit primitives of a named shape as a
/// list of dicts (`ImplicitPrimitive`'s fields), to edit and pass back.
#[pyfunction]
fn cloud_primitives<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    to_params(py, &named_shape(name)?)
}

/// `cloud_density(shape, cell, seed, params, progress)`: Ebert's cloud of
/// the implicit primitives `shape` gives (a name of [`named_shape`], or a
/// list of dicts with `ImplicitPrimitive`'s fields), with `CloudParams`
/// from `params` (over the cumulus default), baked at voxel centres with
/// voxel edge `cell` over the cloud's bounds.
#[pyfunction]
#[pyo3(signature = (shape, cell, seed, params, progress=None))]
fn cloud_density<'py>(
    py: Python<'py>,
    shape: &Bound<'py, PyAny>,
    cell: f32,
    seed: u64,
    params: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Baked<'py>> {
    let prims = match shape.extract::<String>() {
        Ok(name) => named_shape(&name)?,
        Err(_) => from_params(shape, "shape")?,
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

/// A point, direction or colour from Python.
type Triple = (f32, f32, f32);

/// The fast mode's settings for a grid of voxel edge `cell` and `dims`
/// voxels: steps of half a voxel, a shadow table with a node per voxel
/// along the longest axis (2 to 256), the multiple-scattering cache with a
/// cell per voxel along that axis (16 to the crate's default 64) and 16
/// events per cell (one to the default four million); the keys of `over`
/// laid over them. (The crate's default cache costs about 15 s on a 16³
/// grid; this one 0.5 s, with the same agreement with the reference.)
fn fast_settings_for(
    cell: f32,
    dims: (usize, usize, usize),
    over: &Bound<'_, PyAny>,
) -> PyResult<FastSettings> {
    let longest = dims.0.max(dims.1).max(dims.2);
    let default = CacheParams::default();
    let cells = (longest as u32).clamp(16, default.cells);
    let base = FastSettings {
        step: 0.5 * cell,
        shadows: Shadows::Table((longest + 1).clamp(2, 256)),
        scattering: Scattering::Cache(CacheParams {
            cells,
            events: 16u32
                .saturating_mul(cells.saturating_pow(3))
                .clamp(1_000_000, default.events),
            ..default
        }),
        ..FastSettings::default()
    };
    let mut value =
        toml::Value::try_from(base).map_err(|e| PyValueError::new_err(e.to_string()))?;
    overlay(&mut value, to_toml(over, "")?);
    from_value(value, "settings")
}

/// `volume_render(density, origin, cell, view, medium, mode, settings,
/// progress)`: the float32 `(nz, ny, nx)` density (voxel centres at
/// `origin + (index + ½)·cell`) rendered by natura-volume's fast mode
/// (`mode = "fast"`, `FastSettings` keys in `settings` over
/// [`fast_settings_for`]) or its null-scattering reference path tracer
/// (`"reference"`, `ReferenceSettings` keys), lit by the sun and a uniform
/// sky; linear radiance as float32 `(height, width, 3)`. In the fast mode
/// `supersample > 1` traces that many rays a pixel side, resolved by the
/// camera's pixel filter (`FastRenderer::render_supersampled`); 1 is one
/// ray through each pixel's centre.
#[pyfunction]
#[pyo3(signature = (density, origin, cell, eye, target, fov_deg, width, height, sun, sky, medium, mode, settings, progress=None, supersample=1))]
#[allow(clippy::too_many_arguments)]
fn volume_render<'py>(
    py: Python<'py>,
    density: &Bound<'py, PyAny>,
    origin: (f32, f32, f32),
    cell: f32,
    eye: (f32, f32, f32),
    target: (f32, f32, f32),
    fov_deg: f32,
    width: u32,
    height: u32,
    sun: Option<(Triple, Triple)>,
    sky: (f32, f32, f32),
    medium: &Bound<'py, PyAny>,
    mode: &str,
    settings: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
    supersample: usize,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let v3 = |t: (f32, f32, f32)| Vec3::new(t.0, t.1, t.2);
    if !(1..=natura_volume::transport::MAX_SUPERSAMPLE).contains(&supersample) {
        return Err(PyValueError::new_err(format!(
            "supersample = {supersample} must be in 1..=8 (rays per pixel side)"
        )));
    }
    if supersample > 1 && mode != "fast" {
        return Err(PyValueError::new_err(
            "supersample applies to mode = \"fast\" (the reference averages samples_per_pixel paths)",
        ));
    }
    let g = grid3(density, "density")?;
    let dims = g.dims();
    let grid = GridDensity::new(g, v3(origin), cell).map_err(value_error)?;
    let medium: MediumParams = from_params(medium, "medium")?;
    let sun = sun.map(|(d, e)| Sun {
        direction: v3(d),
        irradiance: v3(e),
    });
    enum Mode {
        Fast(FastSettings),
        Reference(ReferenceSettings),
    }
    let mode = match mode {
        "fast" => Mode::Fast(fast_settings_for(cell, dims, settings)?),
        "reference" => Mode::Reference(from_params(settings, "settings")?),
        other => {
            return Err(PyValueError::new_err(format!(
                "mode = {other:?} is not one of fast, reference"
            )));
        }
    };
    if !(fov_deg > 0.0 && fov_deg < 180.0) {
        return Err(PyValueError::new_err(format!(
            "fov_deg = {fov_deg} must lie in (0, 180)"
        )));
    }
    let camera = LookAtCamera::look_at(
        v3(eye),
        v3(target),
        Vec3::Z,
        fov_deg.to_radians(),
        width,
        height,
    )
    .map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        let scene = Scene {
            sun,
            ..Scene::new(&grid, medium, v3(sky))
        };
        match mode {
            Mode::Fast(s) => FastRenderer::new_with_progress(&scene, s, &sink).and_then(|r| {
                if supersample > 1 {
                    r.render_supersampled(&camera, supersample, &sink)
                } else {
                    r.render_with_progress(&camera, &sink)
                }
            }),
            Mode::Reference(s) => ReferenceRenderer::new(&scene, s)
                .and_then(|r| r.render_with_progress(&camera, &sink)),
        }
        .map_err(value_error)
    });
    image_array(py, &sink.finish_call(out)?)
}

/// Adds the volume functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cloud_density, m)?)?;
    m.add_function(wrap_pyfunction!(cloud_primitives, m)?)?;
    m.add_function(wrap_pyfunction!(layer_density, m)?)?;
    m.add_function(wrap_pyfunction!(volume_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(smoke_plume, m)?)?;
    m.add_function(wrap_pyfunction!(vdb_write, m)?)?;
    m.add_function(wrap_pyfunction!(vdb_read, m)?)?;
    m.add_function(wrap_pyfunction!(volume_render, m)?)?;
    Ok(())
}
