//! Argument checks shared by the bindings: keyword dictionaries whose unknown
//! keys are errors, numpy arrays of the right dtype and shape, and the
//! boundary that releases the GIL and catches panics.

use std::panic::{AssertUnwindSafe, catch_unwind};

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods};

/// Runs `f` without the GIL and turns a panic inside it into `RuntimeError`
/// (its message included), so no panic crosses into Python.
///
/// # Errors
/// `f`'s own error, or `RuntimeError` if it panicked.
pub fn run<T: Send>(py: Python<'_>, f: impl FnOnce() -> PyResult<T> + Send) -> PyResult<T> {
    py.detach(|| match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("(no message)");
            Err(PyRuntimeError::new_err(format!(
                "internal error (a Rust panic): {msg}"
            )))
        }
    })
}

/// A library error as `ValueError` (natura's errors name the parameter).
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The keyword arguments of one call: each read removes its key, and
/// [`Kw::finish`] refuses whatever is left.
#[derive(Debug)]
pub struct Kw<'py> {
    dict: Bound<'py, PyDict>,
    what: String,
}

impl<'py> Kw<'py> {
    /// A copy of `dict` (the caller's dictionary is left alone), `what`
    /// naming the call in errors.
    ///
    /// # Errors
    /// `TypeError` if `dict` is not a dict.
    pub fn new(dict: &Bound<'py, PyAny>, what: &str) -> PyResult<Self> {
        let dict = dict
            .cast::<PyDict>()
            .map_err(|_| PyTypeError::new_err(format!("{what}: parameters must be a dict")))?
            .copy()?;
        Ok(Self {
            dict,
            what: what.to_owned(),
        })
    }

    fn take(&self, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        let v = self.dict.get_item(key)?;
        if v.is_some() {
            self.dict.del_item(key)?;
        }
        Ok(v.filter(|v| !v.is_none()))
    }

    /// A float parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a real number.
    pub fn f64(&self, key: &str, default: f64) -> PyResult<f64> {
        match self.take(key)? {
            None => Ok(default),
            Some(v) => v.extract::<f64>().map_err(|_| {
                PyTypeError::new_err(format!("{}: {key} must be a real number", self.what))
            }),
        }
    }

    /// An integer parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not an integer, `ValueError`
    /// if it does not fit.
    pub fn int<T: pyo3::conversion::FromPyObjectOwned<'py>>(
        &self,
        key: &str,
        default: T,
    ) -> PyResult<T> {
        match self.take(key)? {
            None => Ok(default),
            Some(v) => {
                if v.extract::<i128>().is_err() {
                    return Err(PyTypeError::new_err(format!(
                        "{}: {key} must be an integer",
                        self.what
                    )));
                }
                v.extract::<T>().map_err(|_| {
                    PyValueError::new_err(format!("{}: {key} is out of range", self.what))
                })
            }
        }
    }

    /// A boolean parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a bool.
    pub fn bool(&self, key: &str, default: bool) -> PyResult<bool> {
        match self.take(key)? {
            None => Ok(default),
            Some(v) => v
                .extract::<bool>()
                .map_err(|_| PyTypeError::new_err(format!("{}: {key} must be a bool", self.what))),
        }
    }

    /// An optional float parameter: `default` when absent, `None` when given as `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is neither a real number nor `None`.
    pub fn opt_f64(&self, key: &str, default: Option<f64>) -> PyResult<Option<f64>> {
        match self.dict.get_item(key)? {
            None => Ok(default),
            Some(v) => {
                self.dict.del_item(key)?;
                if v.is_none() {
                    return Ok(None);
                }
                v.extract::<f64>().map(Some).map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{}: {key} must be a real number or None",
                        self.what
                    ))
                })
            }
        }
    }

    /// One of `choices` (by name), `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a string, `ValueError`
    /// naming it and listing the choices if it is none of them.
    pub fn choice<T: Copy>(&self, key: &str, choices: &[(&str, T)], default: T) -> PyResult<T> {
        let Some(v) = self.take(key)? else {
            return Ok(default);
        };
        let s: String = v
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("{}: {key} must be a string", self.what)))?;
        choices
            .iter()
            .find(|(name, _)| *name == s)
            .map(|(_, t)| *t)
            .ok_or_else(|| {
                let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
                PyValueError::new_err(format!(
                    "{}: {key} = {s:?} is not one of {}",
                    self.what,
                    names.join(", ")
                ))
            })
    }

    /// A nested dictionary parameter (e.g. a basis), if present.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a dict.
    pub fn dict(&self, key: &str) -> PyResult<Option<Kw<'py>>> {
        match self.take(key)? {
            None => Ok(None),
            Some(v) => Kw::new(&v, &format!("{}: {key}", self.what)).map(Some),
        }
    }

    /// A string parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a string.
    pub fn string(&self, key: &str, default: &str) -> PyResult<String> {
        match self.take(key)? {
            None => Ok(default.to_owned()),
            Some(v) => v.extract::<String>().map_err(|_| {
                PyTypeError::new_err(format!("{}: {key} must be a string", self.what))
            }),
        }
    }

    /// Refuses any parameter left unread.
    ///
    /// # Errors
    /// `TypeError` naming the first unknown parameter.
    pub fn finish(self) -> PyResult<()> {
        if let Some((k, _)) = self.dict.iter().next() {
            return Err(PyTypeError::new_err(format!(
                "{}: unknown parameter {}",
                self.what,
                k.repr()?
            )));
        }
        Ok(())
    }
}

/// A numpy float array (float32 or float64, any layout) as owned `f64`
/// values in C order, with its shape.
///
/// # Errors
/// `TypeError` naming `name` if `obj` is not a numpy array of float32 or float64.
pub fn floats(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let arr = obj
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be a numpy array")))?;
    let shape = arr.shape().to_vec();
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        let ro = a.readonly();
        let v = ro.as_array().iter().copied().collect();
        return Ok((v, shape));
    }
    if let Ok(a) = obj.cast::<PyArrayDyn<f32>>() {
        let ro = a.readonly();
        let v = ro.as_array().iter().map(|&x| f64::from(x)).collect();
        return Ok((v, shape));
    }
    Err(PyTypeError::new_err(format!(
        "{name} must have dtype float32 or float64, not {}",
        arr.dtype()
    )))
}

/// A 2-D float32 numpy array (any layout) as owned values in C order, with
/// its `(rows, cols)` shape.
///
/// # Errors
/// `TypeError` naming `name` if `obj` is not a float32 numpy array,
/// `ValueError` if it is not 2-D.
pub fn heights(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f32>, usize, usize)> {
    let arr = obj
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be a numpy array")))?;
    let Ok(a) = obj.cast::<PyArrayDyn<f32>>() else {
        return Err(PyTypeError::new_err(format!(
            "{name} must have dtype float32, not {}",
            arr.dtype()
        )));
    };
    if arr.ndim() != 2 {
        return Err(PyValueError::new_err(format!(
            "{name} must be 2-D (rows, columns), not {}-D",
            arr.ndim()
        )));
    }
    let (rows, cols) = (arr.shape()[0], arr.shape()[1]);
    let ro = a.readonly();
    Ok((ro.as_array().iter().copied().collect(), rows, cols))
}

/// The name of `v` in a `(name, value)` table ("" if absent).
pub fn name_of<T: PartialEq + Copy>(table: &[(&'static str, T)], v: T) -> &'static str {
    table.iter().find(|(_, t)| *t == v).map_or("", |(n, _)| n)
}

/// A parameter's default value, as reported to Python.
#[derive(Debug, Clone, Copy)]
pub enum Dv {
    /// A real number.
    F(f64),
    /// An integer.
    I(u64),
    /// A bool.
    B(bool),
    /// A name (an enum's variant).
    S(&'static str),
    /// No value (`None`).
    N,
}

/// `(name, default)` pairs as a Python dict.
///
/// # Errors
/// A Python error from building the dict.
pub fn defaults_dict<'py>(
    py: Python<'py>,
    d: &[(&'static str, Dv)],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for &(k, v) in d {
        match v {
            Dv::F(x) => dict.set_item(k, x)?,
            Dv::I(x) => dict.set_item(k, x)?,
            Dv::B(x) => dict.set_item(k, x)?,
            Dv::S(x) => dict.set_item(k, x)?,
            Dv::N => dict.set_item(k, py.None())?,
        }
    }
    Ok(dict)
}
