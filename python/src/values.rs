//! Python values as TOML values and back, so a dict of parameters reaches a
//! Rust `Params` struct through its own serde implementation: the struct's
//! field names are the keyword names, its `Default` fills what is left out,
//! and serde refuses an unknown key or a wrong type (naming it) exactly as
//! it does for a TOML file.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// `obj` (a dict, list, tuple, str, bool, int or float, nested) as a TOML
/// value; `path` names it in errors (`sun.elevation_deg`).
///
/// # Errors
/// `TypeError` naming the key of a value TOML cannot hold (`None`, an
/// object) or of a dict key that is not a string.
pub fn to_toml(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    let bad = |what: &str| {
        PyTypeError::new_err(format!(
            "{path}: {what} (a value must be a dict, list, str, bool, int or float)"
        ))
    };
    if obj.is_none() {
        return Err(bad(
            "None has no TOML form; leave the key out for its default",
        ));
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj
            .extract()
            .map_err(|_| PyValueError::new_err(format!("{path}: integer out of range")))?;
        return Ok(toml::Value::Integer(i));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                bad(&format!(
                    "key {} is not a string",
                    k.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                ))
            })?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            table.insert(key, to_toml(&v, &sub)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            out.push(to_toml(&v?, &format!("{path}[{i}]"))?);
        }
        return Ok(toml::Value::Array(out));
    }
    // numpy scalars: integers (they have `__index__`), then floats.
    if let Ok(i) = obj.extract::<i64>() {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    let ty = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string());
    Err(bad(&format!("a value of type {ty}")))
}

/// A TOML value as the Python value it came from.
///
/// # Errors
/// A Python error from building a dict or list.
pub fn to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// The Rust type `T` from the keyword dict `params` through its serde
/// implementation (`T`'s `#[serde(default)]` fills what is left out).
///
/// # Errors
/// `TypeError` from [`to_toml`]; `ValueError` starting with `what` and
/// naming the key serde refused (unknown, or of the wrong type).
pub fn from_params<T: DeserializeOwned>(params: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    from_value(to_toml(params, "")?, what)
}

/// The Rust type `T` from a TOML value through its serde implementation
/// (what [`from_params`] does once the dict is TOML; callers that edit the
/// value first, laying it over a preset, call this).
///
/// # Errors
/// `ValueError` starting with `what` and naming the key serde refused.
pub fn from_value<T: DeserializeOwned>(value: toml::Value, what: &str) -> PyResult<T> {
    T::deserialize(value)
        .map_err(|e| PyValueError::new_err(format!("{what}: {}", e.message().trim())))
}

/// `value` (a Rust parameter struct) as a Python dict of its fields.
///
/// # Errors
/// `ValueError` if it has no TOML form (a non-finite number).
pub fn to_params<'py, T: Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let v = toml::Value::try_from(value).map_err(|e| PyValueError::new_err(e.to_string()))?;
    to_py(py, &v)
}

/// Lays `top` over `base`: tables merge key by key, any other value
/// replaces. A one-key table laid over a one-key table of another key is a
/// different variant of an enumeration (`{ rays = 1.0 }` over
/// `{ table = 64 }`) and replaces it whole.
pub fn overlay(base: &mut toml::Value, top: toml::Value) {
    match (base, top) {
        (toml::Value::Table(b), toml::Value::Table(t))
            if b.len() == 1 && t.len() == 1 && b.keys().ne(t.keys()) =>
        {
            *b = t;
        }
        (toml::Value::Table(b), toml::Value::Table(t)) => {
            for (k, v) in t {
                match b.get_mut(&k) {
                    Some(slot) => overlay(slot, v),
                    None => {
                        b.insert(k, v);
                    }
                }
            }
        }
        (slot, v) => *slot = v,
    }
}
