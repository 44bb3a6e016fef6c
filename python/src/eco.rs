//! `natura.plant.ecosystem`: natura-plant's ecosystem (Deussen et al. 1998)
//! grown on a height array, its plants as instance arrays and its
//! prototypes as meshes.

use natura_plant::eco::{EcoParams, Ecosystem, Instancing, Species};
use natura_plant::{MeshParams, PlantMesh};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::args::{grid2, run, value_error};
use crate::progress::PyProgress;
use crate::terrain::field;
use crate::values::{from_value, to_params, to_toml};

/// The species presets of natura-plant, by the name each carries.
fn preset(name: &str) -> Option<Species> {
    Some(match name {
        "tree" => Species::tree(),
        "shrub" => Species::default(),
        "wet_shrub" => Species::wet_shrub(),
        "grass" => Species::grass(),
        _ => return None,
    })
}

/// The names [`preset`] knows.
const PRESETS: [&str; 4] = ["tree", "shrub", "wet_shrub", "grass"];

/// `EcoParams` from the keyword dict: `species` items that are preset
/// names become those species; dicts are `Species` fields over the shrub
/// (`Species::default()`).
fn eco_params(params: &Bound<'_, PyAny>) -> PyResult<EcoParams> {
    let mut value = to_toml(params, "")?;
    if let Some(toml::Value::Array(items)) = value.get_mut("species") {
        for (i, item) in items.iter_mut().enumerate() {
            if let toml::Value::String(name) = item {
                let sp = preset(name).ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "species[{i}] = {name:?} is not one of {}",
                        PRESETS.join(", ")
                    ))
                })?;
                *item = toml::Value::try_from(sp).map_err(value_error)?;
            }
        }
    }
    let p: EcoParams = from_value(value, "ecosystem")?;
    p.validate().map_err(value_error)?;
    Ok(p)
}

/// The mesh arrays of one prototype, as `lsystem_mesh` returns them.
fn mesh_dict<'py>(py: Python<'py>, m: PlantMesh) -> PyResult<Bound<'py, PyDict>> {
    let rows = |v: Vec<f32>, w: usize| {
        Array2::from_shape_vec((v.len() / w, w), v)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    };
    let d = PyDict::new(py);
    let pos: Vec<f32> = m.positions.iter().flat_map(|p| p.to_array()).collect();
    let nrm: Vec<f32> = m.normals.iter().flat_map(|p| p.to_array()).collect();
    let uv: Vec<f32> = m.uvs.iter().flat_map(|p| p.to_array()).collect();
    d.set_item("positions", rows(pos, 3)?.into_pyarray(py))?;
    d.set_item("normals", rows(nrm, 3)?.into_pyarray(py))?;
    d.set_item("uvs", rows(uv, 2)?.into_pyarray(py))?;
    let idx = Array2::from_shape_vec((m.indices.len() / 3, 3), m.indices)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    d.set_item("indices", idx.into_pyarray(py))?;
    Ok(d)
}

fn vec1<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyArray1<T>> {
    Array1::from_vec(v).into_pyarray(py)
}

/// `ecosystem(heights, cell_size, params, per_species, progress)`: runs the
/// simulation (`EcoParams` from `params`), builds at most `per_species`
/// prototypes per species (`Instancing::new`) and returns a dict of arrays,
/// one row per living plant: `positions` (float32 `(n, 3)`, metres, z the
/// ground), `species` (uint16), `prototype` (uint32), `scale`, `rotation`
/// (radians about z), `radius` (metres), `vigor` (float32) and `age` (uint32,
/// steps lived); `species_names` (list of str) and `prototypes` (a list of
/// dicts: `species`, `radius`, `steps` and the mesh arrays of
/// `lsystem_mesh` with default mesh parameters). `wetness`, if given (a
/// float32 array of the heights' shape, values in `[0, 1]`), is the map the
/// plants read instead of the one computed from `heights`
/// (`Ecosystem::with_wetness`).
#[pyfunction]
#[pyo3(signature = (heights, cell_size, params, per_species=3, progress=None, wetness=None))]
fn plant_ecosystem<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
    params: &Bound<'py, PyAny>,
    per_species: usize,
    progress: Option<Py<PyAny>>,
    wetness: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = field(heights, "heights", cell_size)?;
    // Its size is checked against the heights' by `Site::with_wetness`.
    let wet = wetness.map(|w| grid2(w, "wetness")).transpose()?;
    let p = eco_params(params)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        let mut eco = match wet {
            None => Ecosystem::new(&hf, p),
            Some(w) => Ecosystem::with_wetness(&hf, w, p),
        }
        .map_err(value_error)?;
        eco.run(&sink).map_err(value_error)?;
        let inst = Instancing::new(&eco, per_species).map_err(value_error)?;
        let meshes = inst
            .prototypes
            .iter()
            .map(|pr| PlantMesh::from_geometry(&pr.geometry, &MeshParams::default()))
            .collect::<Result<Vec<_>, _>>()
            .map_err(value_error)?;
        Ok((eco, inst, meshes))
    });
    let (eco, inst, meshes) = sink.finish_call(out)?;
    let steps = eco.steps();
    let d = PyDict::new(py);
    let pos: Vec<f32> = inst
        .instances
        .iter()
        .flat_map(|i| i.position.to_array())
        .collect();
    let n = inst.instances.len();
    let pos =
        Array2::from_shape_vec((n, 3), pos).map_err(|e| PyValueError::new_err(e.to_string()))?;
    d.set_item("positions", pos.into_pyarray(py))?;
    d.set_item(
        "species",
        vec1(py, inst.instances.iter().map(|i| i.species).collect()),
    )?;
    d.set_item(
        "prototype",
        vec1(py, inst.instances.iter().map(|i| i.prototype).collect()),
    )?;
    d.set_item(
        "scale",
        vec1(py, inst.instances.iter().map(|i| i.scale).collect()),
    )?;
    d.set_item(
        "rotation",
        vec1(py, inst.instances.iter().map(|i| i.rotation).collect()),
    )?;
    let plants = eco.plants();
    d.set_item(
        "radius",
        vec1(py, plants.iter().map(|p| p.radius).collect()),
    )?;
    d.set_item("vigor", vec1(py, plants.iter().map(|p| p.vigor).collect()))?;
    d.set_item(
        "age",
        vec1(
            py,
            plants
                .iter()
                .map(|p| steps.saturating_sub(p.born()))
                .collect(),
        ),
    )?;
    let names: Vec<&str> = eco
        .params()
        .species
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    d.set_item("species_names", PyList::new(py, names)?)?;
    let protos = PyList::empty(py);
    for (pr, mesh) in inst.prototypes.iter().zip(meshes) {
        let m = mesh_dict(py, mesh)?;
        m.set_item("species", pr.species)?;
        m.set_item("radius", pr.radius)?;
        m.set_item("steps", pr.steps)?;
        protos.append(m)?;
    }
    d.set_item("prototypes", protos)?;
    Ok(d)
}

/// `ecosystem_defaults()`: `EcoParams::default()` as a dict (species as
/// dicts of their fields).
#[pyfunction]
fn ecosystem_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    to_params(py, &EcoParams::default())
}

/// `species_preset(name)`: one of natura-plant's species presets as a dict.
#[pyfunction]
fn species_preset<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let sp = preset(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "name = {name:?} is not one of {}",
            PRESETS.join(", ")
        ))
    })?;
    to_params(py, &sp)
}

/// Adds the ecosystem functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(plant_ecosystem, m)?)?;
    m.add_function(wrap_pyfunction!(ecosystem_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(species_preset, m)?)?;
    Ok(())
}
