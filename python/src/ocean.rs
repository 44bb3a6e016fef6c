//! `natura.ocean`: Tessendorf's ocean patch (natura-ocean) evaluated at
//! given times: the height, slope, choppy displacement and Jacobian fields
//! as float32 arrays `(times, ny, nx)` (rows are `y`), and the foam
//! coverage accumulated over those times in order.

use natura_core::Seed;
use natura_ocean::{
    AmplitudeScheme, Directional, Dispersion, Foam, FoamParams, FrameField, FrequencySpectrum, G,
    Jonswap, Ocean, OceanParams, Phillips, PiersonMoskowitz, Spectrum, Spreading, Tma,
};
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{Dv, Kw, defaults_dict, name_of, params, run, value_error};

const AMPLITUDES: &[(&str, AmplitudeScheme)] = &[
    ("complex_gaussian", AmplitudeScheme::ComplexGaussian),
    (
        "gaussian_uniform_phase",
        AmplitudeScheme::GaussianUniformPhase,
    ),
];

/// The spectra, by their Python names.
pub const SPECTRA: &[&str] = &["phillips", "pierson_moskowitz", "jonswap", "tma"];

/// The dispersion relation from the keywords `dispersion` (`"deep"`,
/// `"finite_depth"` or `"capillary"`), `g`, and `depth` (finite depth
/// only) or `capillary_length` (capillary only); a key the relation does
/// not use must be absent or `None`.
fn dispersion(kw: &Kw<'_>) -> PyResult<Dispersion> {
    let g = kw.f64("g", G)?;
    let kind = kw.string("dispersion", "deep")?;
    let depth = kw.opt_f64("depth", None)?;
    let capillary = kw.opt_f64("capillary_length", None)?;
    let only = |key: &str, v: Option<f64>, wanted: bool| -> PyResult<Option<f64>> {
        match (v, wanted) {
            (None, true) => Err(PyValueError::new_err(format!(
                "ocean: {key} is needed for dispersion = {kind:?}"
            ))),
            (Some(_), false) => Err(PyValueError::new_err(format!(
                "ocean: {key} is not used by dispersion = {kind:?}"
            ))),
            _ => Ok(v),
        }
    };
    let (d, c) = match kind.as_str() {
        "deep" => (false, false),
        "finite_depth" => (true, false),
        "capillary" => (false, true),
        other => {
            return Err(PyValueError::new_err(format!(
                "ocean: dispersion = {other:?} is not one of deep, finite_depth, capillary"
            )));
        }
    };
    let depth = only("depth", depth, d)?;
    let capillary = only("capillary_length", capillary, c)?;
    Ok(match (depth, capillary) {
        (Some(depth), _) => Dispersion::FiniteDepth { g, depth },
        (_, Some(capillary_length)) => Dispersion::Capillary {
            g,
            capillary_length,
        },
        _ => Dispersion::Deep { g },
    })
}

/// The ocean patch's parameters (the keys of `OceanParams`, with the
/// dispersion as above).
fn ocean_params(kw: &Kw<'_>) -> PyResult<OceanParams> {
    let d = OceanParams::default();
    Ok(OceanParams {
        nx: kw.int("nx", d.nx)?,
        ny: kw.int("ny", d.ny)?,
        lx: kw.f64("lx", d.lx)?,
        ly: kw.f64("ly", d.ly)?,
        dispersion: dispersion(kw)?,
        loop_period: kw.opt_f64("loop_period", d.loop_period)?,
        choppiness: kw.f64("choppiness", d.choppiness)?,
        amplitudes: kw.choice("amplitudes", AMPLITUDES, d.amplitudes)?,
        k_min: kw.f64("k_min", d.k_min)?,
        k_max: kw.f64("k_max", d.k_max)?,
    })
}

params!(
    phillips_params,
    phillips_defaults,
    Phillips {
        amplitude: f64,
        wind_speed: f64,
        wind_direction: f64,
        g: f64,
        small_wave_length: f64,
        direction_exponent: f64,
        against_wind: f64,
    }
);
params!(
    pierson_moskowitz_params,
    pierson_moskowitz_defaults,
    PiersonMoskowitz {
        wind_speed: f64,
        g: f64,
    }
);
params!(
    jonswap_params,
    jonswap_defaults,
    Jonswap {
        wind_speed: f64,
        fetch: f64,
        gamma: f64,
        sigma_low: f64,
        sigma_high: f64,
        g: f64,
    }
);
params!(
    foam_params,
    foam_defaults,
    FoamParams {
        threshold: f32,
        range: f32,
        decay_time: f32,
    }
);

/// `spreading`: `"hasselmann"` or a number, the fixed exponent `s` of `cos2s`.
fn spreading(kw: &Kw<'_>) -> PyResult<Spreading> {
    match kw.opt_f64("spreading_s", None)? {
        Some(s) => {
            let name = kw.string("spreading", "cos2s")?;
            if name != "cos2s" {
                return Err(PyValueError::new_err(format!(
                    "spectrum: spreading_s is read only for spreading = \"cos2s\", not {name:?}"
                )));
            }
            Ok(Spreading::Cos2s { s })
        }
        None => match kw.string("spreading", "hasselmann")?.as_str() {
            "hasselmann" => Ok(Spreading::Hasselmann),
            "cos2s" => Err(PyValueError::new_err(
                "spectrum: spreading = \"cos2s\" needs spreading_s",
            )),
            other => Err(PyValueError::new_err(format!(
                "spectrum: spreading = {other:?} is not one of hasselmann, cos2s"
            ))),
        },
    }
}

/// The frequency spectrum `f` spread about `wind_direction` by `spreading`
/// (both read from `kw`), its wavenumbers mapped by `dispersion`.
fn directional<F: FrequencySpectrum + 'static>(
    kw: &Kw<'_>,
    f: F,
    dispersion: Dispersion,
) -> PyResult<Box<dyn Spectrum>> {
    Ok(Box::new(Directional {
        spectrum: f,
        spreading: spreading(kw)?,
        wind_direction: kw.f64("wind_direction", 0.0)?,
        dispersion,
    }))
}

/// The spectrum of the dictionary `spec` (`kind` and the Rust struct's
/// fields; a frequency spectrum also takes `spreading`, `spreading_s` and
/// `wind_direction`, and maps wavenumber to frequency with the ocean's
/// dispersion relation `dispersion`).
fn spectrum(spec: &Bound<'_, PyAny>, dispersion: Dispersion) -> PyResult<Box<dyn Spectrum>> {
    let kw = Kw::new(spec, "spectrum")?;
    let kind = kw.string("kind", "phillips")?;
    let s: Box<dyn Spectrum> = match kind.as_str() {
        "phillips" => Box::new(phillips_params(&kw)?),
        "pierson_moskowitz" => directional(&kw, pierson_moskowitz_params(&kw)?, dispersion)?,
        "jonswap" => directional(&kw, jonswap_params(&kw)?, dispersion)?,
        "tma" => {
            let jonswap = jonswap_params(&kw)?;
            let depth = kw.opt_f64("depth", None)?.ok_or_else(|| {
                PyValueError::new_err("spectrum: depth is needed for kind = \"tma\"")
            })?;
            directional(&kw, Tma { jonswap, depth }, dispersion)?
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "spectrum: kind = {other:?} is not one of {}",
                SPECTRA.join(", ")
            )));
        }
    };
    kw.finish()?;
    s.validate().map_err(value_error)?;
    Ok(s)
}

/// A float32 3-D numpy array.
type F32Array3<'py> = Bound<'py, PyArray3<f32>>;

/// `ocean_frames(params, spectrum, seed, times, foam)`: the ocean patch of
/// `params` (the keys of `OceanParams` and its dispersion) with the
/// spectrum `spectrum` (a dict with `kind`) and `seed`, evaluated at each
/// of `times` (seconds): a dict of float32 arrays `(len(times), ny, nx)`,
/// one per field (`height`, `slope_x`, `slope_y`, `disp_x`, `disp_y`,
/// `jxx`, `jyy`, `jxy`), and `foam` when `foam` is a dict of `FoamParams`
/// (the coverage after each time, accumulated over `times` in order, which
/// must then not decrease).
#[pyfunction]
#[pyo3(signature = (params, spectrum_spec, seed, times, foam=None))]
fn ocean_frames<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    spectrum_spec: &Bound<'py, PyAny>,
    seed: u64,
    times: Vec<f64>,
    foam: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let kw = Kw::new(params, "ocean")?;
    let p = ocean_params(&kw)?;
    kw.finish()?;
    p.validate().map_err(value_error)?;
    let spec = spectrum(spectrum_spec, p.dispersion)?;
    let foam = match foam {
        None => None,
        Some(f) if f.is_none() => None,
        Some(f) => {
            let kw = Kw::new(f, "foam")?;
            let fp = foam_params(&kw)?;
            kw.finish()?;
            fp.validate().map_err(value_error)?;
            Some(fp)
        }
    };
    if times.is_empty() {
        return Err(PyValueError::new_err("times: at least one time is needed"));
    }
    if let Some(i) = times.iter().position(|t| !t.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "times: times[{i}] = {} is not finite",
            times[i]
        )));
    }
    if foam.is_some() && times.windows(2).any(|w| w[1] < w[0]) {
        return Err(PyValueError::new_err(
            "times: foam accumulates forward in time, so times must not decrease",
        ));
    }
    let (nx, ny) = (p.nx, p.ny);
    let fields = run(py, move || {
        let ocean = Ocean::new(&p, spec.as_ref(), Seed(seed)).map_err(value_error)?;
        let n = nx * ny;
        let mut out: Vec<Vec<f32>> = (0..FrameField::ALL.len() + usize::from(foam.is_some()))
            .map(|_| Vec::with_capacity(n * times.len()))
            .collect();
        let mut frame = ocean.evaluate(times[0]).map_err(value_error)?;
        let mut coverage = match foam {
            Some(fp) => Some(Foam::for_frame(&frame, fp).map_err(value_error)?),
            None => None,
        };
        for (k, &t) in times.iter().enumerate() {
            if k > 0 {
                ocean.evaluate_into(t, &mut frame).map_err(value_error)?;
            }
            for (o, f) in out.iter_mut().zip(FrameField::ALL) {
                o.extend_from_slice(frame.field(f).as_slice());
            }
            if let Some(c) = coverage.as_mut() {
                c.update(&frame).map_err(value_error)?;
                out[FrameField::ALL.len()].extend_from_slice(c.coverage().as_slice());
            }
        }
        Ok(out)
    })?;
    let dict = PyDict::new(py);
    let names = FrameField::ALL.iter().map(|f| f.name()).chain(["foam"]);
    let shape = (fields[0].len() / (nx * ny), ny, nx);
    for (name, v) in names.zip(fields) {
        let a = numpy::ndarray::Array3::from_shape_vec(shape, v)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let a: F32Array3<'py> = a.into_pyarray(py);
        dict.set_item(name, a)?;
    }
    Ok(dict)
}

/// `ocean_defaults(name)`: the defaults of `"ocean"` (`OceanParams`, with
/// the deep-water dispersion), `"foam"` (`FoamParams`) or a spectrum, as a
/// dict, so the tests can check the Python signatures against them.
#[pyfunction]
fn ocean_defaults<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    let f = Dv::F;
    let d: Vec<(&'static str, Dv)> = match name {
        "ocean" => {
            let o = OceanParams::default();
            let Dispersion::Deep { g } = o.dispersion else {
                return Err(PyValueError::new_err("the default dispersion is not deep"));
            };
            vec![
                ("nx", Dv::I(o.nx as u64)),
                ("ny", Dv::I(o.ny as u64)),
                ("lx", f(o.lx)),
                ("ly", f(o.ly)),
                ("dispersion", Dv::S("deep")),
                ("g", f(g)),
                ("loop_period", o.loop_period.map_or(Dv::N, f)),
                ("choppiness", f(o.choppiness)),
                ("amplitudes", Dv::S(name_of(AMPLITUDES, o.amplitudes))),
                ("k_min", f(o.k_min)),
                ("k_max", f(o.k_max)),
            ]
        }
        "foam" => foam_defaults(),
        "phillips" => phillips_defaults(),
        "pierson_moskowitz" => pierson_moskowitz_defaults(),
        // TMA takes JONSWAP's parameters and a depth, which has no default.
        "jonswap" | "tma" => jonswap_defaults(),
        other => {
            return Err(PyValueError::new_err(format!(
                "{other:?} is not ocean, foam or one of {}",
                SPECTRA.join(", ")
            )));
        }
    };
    defaults_dict(py, &d)
}

/// Adds the ocean functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ocean_frames, m)?)?;
    m.add_function(wrap_pyfunction!(ocean_defaults, m)?)?;
    m.add("OCEAN_SPECTRA", SPECTRA.to_vec())?;
    Ok(())
}
