//! `natura.render`: natura-render's scenes (TOML text or a dict with the
//! same keys) rendered to a linear-radiance float32 image array.

use natura_render::{DEFAULT_SCENE_TOML, SceneDesc, render_scene};
use numpy::PyArray3;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::args::{image_array, run, value_error};
use crate::progress::PyProgress;
use crate::values::to_toml;

/// The scene of `scene`: `None` the built-in scene, a str its TOML text, a
/// dict the same keys as a TOML file (laid over the built-in scene as the
/// text is). Errors name the key (`scene:3:1: key 'sun.elevation' ...`).
fn scene_of(scene: Option<&Bound<'_, PyAny>>) -> PyResult<SceneDesc> {
    let text = match scene {
        None => DEFAULT_SCENE_TOML.to_owned(),
        Some(s) if s.is_instance_of::<PyString>() => s.extract::<String>()?,
        Some(s) if s.is_instance_of::<PyDict>() => {
            let value = to_toml(s, "scene")?;
            toml::to_string(&value).map_err(|e| PyValueError::new_err(format!("scene: {e}")))?
        }
        Some(_) => {
            return Err(PyTypeError::new_err(
                "scene must be TOML text (str), a dict or None",
            ));
        }
    };
    SceneDesc::from_toml_str(&text, "scene").map_err(value_error)
}

/// `scene_toml(scene)`: the whole scene with every key written out, after
/// the dict or text is parsed and validated (the TOML `render_scene` renders).
#[pyfunction]
#[pyo3(signature = (scene=None, quick=false))]
fn scene_toml(scene: Option<&Bound<'_, PyAny>>, quick: bool) -> PyResult<String> {
    let mut s = scene_of(scene)?;
    if quick {
        s = s.quick();
    }
    s.validate().map_err(value_error)?;
    s.to_toml_string().map_err(value_error)
}

/// `render_scene(scene, width, height, spp, seed, quick, progress)`: the
/// scene's linear radiance as float32 `(height, width, 3)` and the exposure
/// (stops) the scene asks for or the automatic one; with `quick`, the
/// scene's quick preview (`SceneDesc::quick`) before the overrides. The GIL
/// is released; `progress` is called as `progress(stage, done, total)`.
#[pyfunction]
#[pyo3(signature = (scene=None, width=None, height=None, spp=None, seed=None, quick=false, progress=None))]
fn render_scene_array<'py>(
    py: Python<'py>,
    scene: Option<&Bound<'py, PyAny>>,
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    seed: Option<u64>,
    quick: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyArray3<f32>>, f32)> {
    let mut s = scene_of(scene)?;
    if quick {
        s = s.quick();
    }
    if let Some(w) = width {
        s.render.width = w;
    }
    if let Some(h) = height {
        s.render.height = h;
    }
    if let Some(n) = spp {
        s.render.spp = n;
    }
    if let Some(seed) = seed {
        s.seed = seed;
    }
    s.validate().map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || render_scene(&s, &sink).map_err(value_error));
    let out = sink.finish_call(out)?;
    Ok((image_array(py, &out.image)?, out.exposure_ev))
}

/// Adds the render functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("DEFAULT_SCENE_TOML", DEFAULT_SCENE_TOML)?;
    m.add_function(wrap_pyfunction!(scene_toml, m)?)?;
    m.add_function(wrap_pyfunction!(render_scene_array, m)?)?;
    Ok(())
}
