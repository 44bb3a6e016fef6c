//! `natura.plant`: L-systems of natura-plant — parse and derive a system
//! given as text, interpret the string with the 3-D turtle and mesh it into
//! vertex and index arrays, or write the mesh as binary glTF.

use natura_plant::mesh::save_glb;
use natura_plant::string::ModuleString;
use natura_plant::{Derivation, LSystem, MeshParams, PlantMesh, Turtle, TurtleParams};
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{Kw, run, value_error};

/// Parses `text`, derives `steps` steps (the file's `derivation length:`
/// when `None`) with `seed` (the file's `seed:`, else 1, as the `lsystem`
/// example does) and hands the system and its string to `f`.
fn with_string<T>(
    text: &str,
    steps: Option<u32>,
    seed: Option<u64>,
    f: impl FnOnce(&LSystem, &ModuleString) -> PyResult<T>,
) -> PyResult<T> {
    let lsys = LSystem::parse(text).map_err(|e| PyValueError::new_err(format!("text: {e}")))?;
    let seed = seed.or(lsys.seed()).unwrap_or(1);
    let mut d = Derivation::new(&lsys, seed).map_err(value_error)?;
    d.derive(steps.unwrap_or(lsys.derivation_length()))
        .map_err(value_error)?;
    f(&lsys, d.string())
}

/// The turtle and mesh parameters of a `params` dict (the Rust
/// `TurtleParams::for_lsystem` and `MeshParams::default()` where absent).
fn mesh_of(
    lsys: &LSystem,
    s: &ModuleString,
    tp: TurtleParams,
    mp: MeshParams,
) -> PyResult<PlantMesh> {
    let geo = Turtle::new(lsys, tp)
        .and_then(|t| t.interpret(s))
        .map_err(value_error)?;
    PlantMesh::from_geometry(&geo, &mp).map_err(value_error)
}

fn params(kw: &Kw<'_>, lsys: &LSystem) -> PyResult<(TurtleParams, MeshParams)> {
    let d = TurtleParams::for_lsystem(lsys);
    let tp = TurtleParams {
        angle_deg: kw.f64("angle_deg", d.angle_deg)?,
        step: kw.f64("step", d.step)?,
        width: kw.f64("width", d.width)?,
        width_factor: kw.f64("width_factor", d.width_factor)?,
        ..d
    };
    let m = MeshParams::default();
    let mp = MeshParams {
        radial_segments: kw.int("radial_segments", m.radial_segments)?,
        caps: kw.bool("caps", m.caps)?,
        leaf_rows: kw.int("leaf_rows", m.leaf_rows)?,
        double_sided_leaves: kw.bool("double_sided_leaves", m.double_sided_leaves)?,
    };
    Ok((tp, mp))
}

/// `lsystem_derive(text, steps, seed)`: the derived string, as text.
#[pyfunction]
#[pyo3(signature = (text, steps=None, seed=None))]
fn lsystem_derive(
    py: Python<'_>,
    text: String,
    steps: Option<u32>,
    seed: Option<u64>,
) -> PyResult<String> {
    run(py, move || {
        with_string(&text, steps, seed, |l, s| Ok(s.display(l.symbols())))
    })
}

/// `lsystem_mesh(text, steps, seed, params)`: the turtle's mesh as a dict of
/// arrays: `positions`, `normals` (float32, `(n, 3)`), `uvs` (float32,
/// `(n, 2)`) and `indices` (uint32, `(m, 3)`, one row per triangle).
#[pyfunction]
#[pyo3(signature = (text, steps=None, seed=None, params=None))]
fn lsystem_mesh<'py>(
    py: Python<'py>,
    text: String,
    steps: Option<u32>,
    seed: Option<u64>,
    params: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let lsys = LSystem::parse(&text).map_err(|e| PyValueError::new_err(format!("text: {e}")))?;
    let empty = PyDict::new(py);
    let kw = Kw::new(params.unwrap_or(empty.as_any()), "lsystem_mesh")?;
    let (tp, mp) = self::params(&kw, &lsys)?;
    kw.finish()?;
    let mesh = run(py, move || {
        with_string(&text, steps, seed, |l, s| mesh_of(l, s, tp, mp))
    })?;
    let rows = |v: Vec<f32>, w: usize| {
        numpy::ndarray::Array2::from_shape_vec((v.len() / w, w), v)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    };
    let dict = PyDict::new(py);
    let pos: Vec<f32> = mesh.positions.iter().flat_map(|p| p.to_array()).collect();
    let nrm: Vec<f32> = mesh.normals.iter().flat_map(|p| p.to_array()).collect();
    let uv: Vec<f32> = mesh.uvs.iter().flat_map(|p| p.to_array()).collect();
    dict.set_item("positions", rows(pos, 3)?.into_pyarray(py))?;
    dict.set_item("normals", rows(nrm, 3)?.into_pyarray(py))?;
    dict.set_item("uvs", rows(uv, 2)?.into_pyarray(py))?;
    let idx = numpy::ndarray::Array2::from_shape_vec((mesh.indices.len() / 3, 3), mesh.indices)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let idx: Bound<'py, PyArray2<u32>> = idx.into_pyarray(py);
    dict.set_item("indices", idx)?;
    Ok(dict)
}

/// `lsystem_save_glb(text, path, steps, seed, params)`: the mesh of
/// `lsystem_mesh` written as binary glTF (a temporary file renamed).
#[pyfunction]
#[pyo3(signature = (text, path, steps=None, seed=None, params=None))]
fn lsystem_save_glb<'py>(
    py: Python<'py>,
    text: String,
    path: std::path::PathBuf,
    steps: Option<u32>,
    seed: Option<u64>,
    params: Option<&Bound<'py, PyAny>>,
) -> PyResult<()> {
    let lsys = LSystem::parse(&text).map_err(|e| PyValueError::new_err(format!("text: {e}")))?;
    let empty = PyDict::new(py);
    let kw = Kw::new(params.unwrap_or(empty.as_any()), "lsystem_save_glb")?;
    let (tp, mp) = self::params(&kw, &lsys)?;
    kw.finish()?;
    run(py, move || {
        let mesh = with_string(&text, steps, seed, |l, s| mesh_of(l, s, tp, mp))?;
        save_glb(&mesh, &path).map_err(|e| PyOSError::new_err(e.to_string()))
    })
}

/// Adds the L-system functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lsystem_derive, m)?)?;
    m.add_function(wrap_pyfunction!(lsystem_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(lsystem_save_glb, m)?)?;
    Ok(())
}
