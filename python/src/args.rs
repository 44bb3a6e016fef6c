//! Argument checks shared by the bindings: keyword dictionaries whose unknown
//! keys are errors, numpy arrays of the right dtype and shape, and the
//! boundary that releases the GIL and catches panics.

use std::borrow::Cow;
use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::panic::{AssertUnwindSafe, catch_unwind};

use glam::Vec3;
use natura_core::{Grid2, Grid3, Image};
use numpy::{
    IntoPyArray, PyArray3, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods, PyString};

/// Runs `f` without the GIL and turns a panic inside it into `RuntimeError`
/// (its message included), so no panic crosses into Python.
///
/// # Errors
/// `f`'s own error, or `RuntimeError` if it panicked.
pub fn run<T: Send>(py: Python<'_>, f: impl FnOnce() -> PyResult<T> + Send) -> PyResult<T> {
    py.detach(|| caught(f))
}

/// As [`run`], but a call of `work` elements below [`SMALL`] keeps the GIL:
/// releasing and taking it back costs more than so little work, and other
/// threads gain nothing from the pause.
///
/// # Errors
/// `f`'s own error, or `RuntimeError` if it panicked.
pub fn run_sized<T: Send>(
    py: Python<'_>,
    work: usize,
    f: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    if work < SMALL { caught(f) } else { run(py, f) }
}

/// Below this many elements a call keeps the GIL (see [`run_sized`]).
pub const SMALL: usize = 256;

fn caught<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
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
    }
}

/// A library error as `ValueError` (natura's errors name the parameter).
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `img`'s linear radiance as a float32 `(height, width, 3)` array.
pub fn image_array<'py>(py: Python<'py>, img: &Image) -> PyResult<Bound<'py, PyArray3<f32>>> {
    rgb_array(py, img.pixels())
}

/// A grid of colours as a float32 `(height, width, 3)` array.
pub fn rgb_array<'py>(py: Python<'py>, g: &Grid2<Vec3>) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let flat: Vec<f32> = g.as_slice().iter().flat_map(|c| c.to_array()).collect();
    numpy::ndarray::Array3::from_shape_vec((g.height(), g.width(), 3), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `key` as an interned Python string, made once per thread and key: a
/// dict looked up by it neither allocates a string nor hashes one (an
/// interned string keeps its hash), which a `&str` key does on every call.
/// The strings are found by the key's address and length.
pub fn key_str<'py>(py: Python<'py>, key: &'static str) -> Bound<'py, PyString> {
    /// Interned strings by their key's address and length.
    type Keys = HashMap<(usize, usize), Py<PyString>, BuildHasherDefault<AddressHasher>>;
    thread_local! {
        static KEYS: RefCell<Keys> = RefCell::new(HashMap::default());
    }
    let id = (key.as_ptr() as usize, key.len());
    KEYS.with_borrow_mut(|keys| {
        keys.entry(id)
            .or_insert_with(|| PyString::intern(py, key).unbind())
            .bind(py)
            .clone()
    })
}

/// A hasher for [`key_str`]'s addresses: one multiply a word (the keys are
/// the program's own, so nothing adversarial reaches it).
#[derive(Default)]
struct AddressHasher(u64);

impl Hasher for AddressHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
    fn write_usize(&mut self, n: usize) {
        self.write_u64(n as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// Which of `names` the string `v` is, by its index: first by identity
/// with the names' interned strings (Python interns the literals a caller
/// passes, such as keyword defaults), else by its text, which is returned
/// as the error when it is none of them.
///
/// # Errors
/// `not_str()` when `v` is not a string.
fn which_name(
    v: &Bound<'_, PyAny>,
    names: impl Iterator<Item = &'static str> + Clone,
    not_str: impl Fn() -> PyErr,
) -> PyResult<Result<usize, String>> {
    let py = v.py();
    if let Some(i) = names.clone().position(|n| v.is(key_str(py, n))) {
        return Ok(Ok(i));
    }
    let s: String = v.extract().map_err(|_| not_str())?;
    Ok(names.into_iter().position(|n| n == s).ok_or(s))
}

/// What a [`Kw`] names in its errors: a call, or a call's parameter that
/// is itself a dict (made into text only when an error needs it).
#[derive(Clone, Debug)]
struct What {
    base: Cow<'static, str>,
    key: Option<&'static str>,
}

impl std::fmt::Display for What {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.key {
            Some(k) => write!(f, "{}: {k}", self.base),
            None => f.write_str(&self.base),
        }
    }
}

/// The keyword arguments of one call: each read notes its key, and
/// [`Kw::finish`] refuses any key that was not read. (The caller's
/// dictionary is only read, never copied or changed.)
#[derive(Debug)]
pub struct Kw<'py> {
    dict: Bound<'py, PyDict>,
    what: What,
    read: RefCell<Vec<&'static str>>,
}

impl<'py> Kw<'py> {
    /// The parameters in `dict`, `what` naming the call in errors.
    ///
    /// # Errors
    /// `TypeError` if `dict` is not a dict.
    pub fn new(dict: &Bound<'py, PyAny>, what: &str) -> PyResult<Self> {
        Self::named(dict, Cow::Owned(what.to_owned()), None)
    }

    /// [`Kw::new`] with a name that needs no copy (a `'static` one).
    ///
    /// # Errors
    /// `TypeError` if `dict` is not a dict.
    pub fn new_static(dict: &Bound<'py, PyAny>, what: Cow<'static, str>) -> PyResult<Self> {
        Self::named(dict, what, None)
    }

    fn named(
        dict: &Bound<'py, PyAny>,
        base: Cow<'static, str>,
        key: Option<&'static str>,
    ) -> PyResult<Self> {
        let what = What { base, key };
        let dict = dict
            .cast::<PyDict>()
            .map_err(|_| PyTypeError::new_err(format!("{what}: parameters must be a dict")))?
            .clone();
        Ok(Self {
            dict,
            what,
            read: RefCell::new(Vec::new()),
        })
    }

    /// Notes `key` as read (a parameter the caller has read itself).
    ///
    /// # Errors
    /// The dict lookup's error.
    pub fn mark(&self, key: &'static str) -> PyResult<()> {
        self.get(key).map(|_| ())
    }

    /// The value of `key` (also when it is `None`), noting the key as read.
    fn get(&self, key: &'static str) -> PyResult<Option<Bound<'py, PyAny>>> {
        let v = self.dict.get_item(key_str(self.dict.py(), key))?;
        if v.is_some() {
            let mut read = self.read.borrow_mut();
            if !read.contains(&key) {
                read.push(key);
            }
        }
        Ok(v)
    }

    fn take(&self, key: &'static str) -> PyResult<Option<Bound<'py, PyAny>>> {
        Ok(self.get(key)?.filter(|v| !v.is_none()))
    }

    /// A float parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a real number.
    pub fn f64(&self, key: &'static str, default: f64) -> PyResult<f64> {
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
        key: &'static str,
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
    pub fn bool(&self, key: &'static str, default: bool) -> PyResult<bool> {
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
    pub fn opt_f64(&self, key: &'static str, default: Option<f64>) -> PyResult<Option<f64>> {
        match self.get(key)? {
            None => Ok(default),
            Some(v) => {
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
    pub fn choice<T: Copy>(
        &self,
        key: &'static str,
        choices: &[(&'static str, T)],
        default: T,
    ) -> PyResult<T> {
        let Some(v) = self.take(key)? else {
            return Ok(default);
        };
        let not_str = || PyTypeError::new_err(format!("{}: {key} must be a string", self.what));
        match which_name(&v, choices.iter().map(|(n, _)| *n), not_str)? {
            Ok(i) => Ok(choices[i].1),
            Err(s) => {
                let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
                Err(PyValueError::new_err(format!(
                    "{}: {key} = {s:?} is not one of {}",
                    self.what,
                    names.join(", ")
                )))
            }
        }
    }

    /// Which of `names` the string parameter `key` is, `default` when
    /// absent or `None`; `Ok(Err(text))` with its text when it is none of
    /// them (the caller words that error).
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a string.
    pub fn name(
        &self,
        key: &'static str,
        names: &[&'static str],
        default: &'static str,
    ) -> PyResult<Result<&'static str, String>> {
        let Some(v) = self.take(key)? else {
            return Ok(Ok(default));
        };
        let not_str = || PyTypeError::new_err(format!("{}: {key} must be a string", self.what));
        Ok(which_name(&v, names.iter().copied(), not_str)?.map(|i| names[i]))
    }

    /// A nested dictionary parameter (e.g. a basis), if present.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a dict.
    pub fn dict(&self, key: &'static str) -> PyResult<Option<Kw<'py>>> {
        match self.take(key)? {
            None => Ok(None),
            Some(v) => {
                // A dict in a dict in a call: the outer name made into text.
                let base = match self.what.key {
                    None => self.what.base.clone(),
                    Some(_) => Cow::Owned(self.what.to_string()),
                };
                Kw::named(&v, base, Some(key)).map(Some)
            }
        }
    }

    /// A string parameter, `default` when absent or `None`.
    ///
    /// # Errors
    /// `TypeError` naming `key` if the value is not a string.
    pub fn string(&self, key: &'static str, default: &str) -> PyResult<String> {
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
        let read = self.read.into_inner();
        if self.dict.len() == read.len() {
            return Ok(());
        }
        for (k, _) in self.dict.iter() {
            let known = k
                .extract::<String>()
                .is_ok_and(|name| read.contains(&name.as_str()));
            if !known {
                return Err(PyTypeError::new_err(format!(
                    "{}: unknown parameter {}",
                    self.what,
                    k.repr()?
                )));
            }
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

/// `obj` as a float32 numpy array of `ndim` dimensions (any layout), its
/// values in C order and its shape; `axes` names the dimensions in errors
/// (`"rows, columns"`).
///
/// # Errors
/// `TypeError` naming `name` if `obj` is not a float32 numpy array,
/// `ValueError` if it has another number of dimensions.
pub fn f32_array(
    obj: &Bound<'_, PyAny>,
    name: &str,
    ndim: usize,
    axes: &str,
) -> PyResult<(Vec<f32>, Vec<usize>)> {
    let arr = obj
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be a numpy array")))?;
    let Ok(a) = obj.cast::<PyArrayDyn<f32>>() else {
        return Err(PyTypeError::new_err(format!(
            "{name} must have dtype float32, not {}",
            arr.dtype()
        )));
    };
    if arr.ndim() != ndim {
        return Err(PyValueError::new_err(format!(
            "{name} must be {ndim}-D ({axes}), not {}-D",
            arr.ndim()
        )));
    }
    let shape = arr.shape().to_vec();
    let ro = a.readonly();
    Ok((ro.as_array().iter().copied().collect(), shape))
}

/// `obj`, a 2-D float32 array ([`f32_array`]), as a grid: its columns along
/// x, its rows along y.
///
/// # Errors
/// As [`f32_array`]; `ValueError` if the grid cannot be made (zero size).
pub fn grid2(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Grid2<f32>> {
    let (data, shape) = f32_array(obj, name, 2, "rows, columns")?;
    Grid2::from_vec(shape[1], shape[0], data).map_err(value_error)
}

/// A `Grid3` as a float32 `(nz, ny, nx)` array (its buffer moved, not copied).
///
/// # Errors
/// `ValueError` if the array cannot be made (it always can from a `Grid3`).
pub fn array3(py: Python<'_>, g: Grid3<f32>) -> PyResult<Bound<'_, PyArray3<f32>>> {
    let (nx, ny, nz) = g.dims();
    let a = numpy::ndarray::Array3::from_shape_vec((nz, ny, nx), g.into_vec())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// A float32 `(nz, ny, nx)` numpy array (any layout) as a `Grid3`.
///
/// # Errors
/// As [`f32_array`]; `ValueError` naming `name` if the grid cannot be made.
pub fn grid3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Grid3<f32>> {
    let (data, s) = f32_array(obj, name, 3, "nz, ny, nx")?;
    let (nz, ny, nx) = (s[0], s[1], s[2]);
    Grid3::from_vec(nx, ny, nz, data).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
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

/// An `f32` as written (0.3, not 0.30000001192092896): the Python float
/// that rounds to it, for comparing defaults with Python signatures.
#[must_use]
pub fn as_written(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

/// Declares `$parse(kw) -> $ty` (each field read from `kw` with the
/// `Default` value as its default) and `$defaults() -> [(name, default)]`
/// from one field list, so names and defaults cannot drift apart. A field's
/// kind is `f64`, `f32` (read as a Python float, its default given as
/// written), `int`, `bool`, `opt` (an optional float), `[TABLE]` (one of a
/// table's names) or `rain_law` (natura.terrain's rain keys, read by the
/// caller's `rain` and `rain_name`).
macro_rules! params {
    ($parse:ident, $defaults:ident, $ty:ident { $($f:ident: $how:tt),* $(,)? }) => {
        fn $parse(kw: &Kw<'_>) -> PyResult<$ty> {
            let d = $ty::default();
            Ok($ty { $($f: params!(@get kw, d, $f, $how)),* })
        }
        fn $defaults() -> Vec<(&'static str, Dv)> {
            let d = $ty::default();
            vec![$((stringify!($f), params!(@dv d, $f, $how))),*]
        }
    };
    (@get $kw:ident, $d:ident, $f:ident, f64) => { $kw.f64(stringify!($f), $d.$f)? };
    (@get $kw:ident, $d:ident, $f:ident, f32) => {
        $kw.f64(stringify!($f), f64::from($d.$f))? as f32
    };
    (@get $kw:ident, $d:ident, $f:ident, int) => { $kw.int(stringify!($f), $d.$f)? };
    (@get $kw:ident, $d:ident, $f:ident, bool) => { $kw.bool(stringify!($f), $d.$f)? };
    (@get $kw:ident, $d:ident, $f:ident, [$table:ident]) => {
        $kw.choice(stringify!($f), $table, $d.$f)?
    };
    (@get $kw:ident, $d:ident, $f:ident, rain_law) => { rain(&$kw, $d.$f)? };
    (@get $kw:ident, $d:ident, $f:ident, opt) => { $kw.opt_f64(stringify!($f), $d.$f)? };
    (@dv $d:ident, $f:ident, f64) => { Dv::F($d.$f) };
    (@dv $d:ident, $f:ident, f32) => { Dv::F($crate::args::as_written($d.$f)) };
    (@dv $d:ident, $f:ident, int) => { Dv::I($d.$f as u64) };
    (@dv $d:ident, $f:ident, bool) => { Dv::B($d.$f) };
    (@dv $d:ident, $f:ident, [$table:ident]) => { Dv::S(name_of($table, $d.$f)) };
    (@dv $d:ident, $f:ident, rain_law) => { Dv::S(rain_name($d.$f)) };
    (@dv $d:ident, $f:ident, opt) => { $d.$f.map_or(Dv::N, Dv::F) };
}
pub(crate) use params;
