//! `natura.noise`: every basis, fractal, multifractal and distortion of
//! natura-noise, built from a parameter dictionary and evaluated at numpy
//! points or on a regular grid.

use std::borrow::Cow;
use std::sync::Arc;

use natura_noise::glam::{DVec2, DVec3};
use natura_noise::{
    CascadeForm, Checkerboard, DistNoise, Fade, Fbm, FeaturePoints, Field, FilteredFbm,
    GainConvention, HeteroTerrain, HeteroTerrainParams, HybridMultifractal, HybridParams, Lattice2,
    Lattice3, Metric, Multifractal, MultifractalParams, Perlin, RidgedMultifractal, RidgedParams,
    Simplex, Sine, SparseConvolution, SparseKernel, SparseParams, Spectral, StatsByAltitude,
    StatsByAltitudeParams, Steps, Turbulence, Value, ValueInterp, VlNoise, Worley, WorleyFeature,
    WorleyParams,
};
use numpy::{IntoPyArray, PyArrayDyn};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{Dv, Kw, floats, key_str, name_of, run, run_sized, value_error};

const FADES: &[(&str, Fade)] = &[("quintic", Fade::Quintic), ("cubic", Fade::Cubic)];
const INTERPS: &[(&str, ValueInterp)] = &[
    ("linear", ValueInterp::Linear),
    ("cubic", ValueInterp::Cubic),
    ("quintic", ValueInterp::Quintic),
];
const FEATURES: &[(&str, WorleyFeature)] = &[
    ("f1", WorleyFeature::F1),
    ("f2", WorleyFeature::F2),
    ("f3", WorleyFeature::F3),
    ("f4", WorleyFeature::F4),
    ("f2_minus_f1", WorleyFeature::F2MinusF1),
    ("f3_minus_f2", WorleyFeature::F3MinusF2),
    ("f4_minus_f3", WorleyFeature::F4MinusF3),
];
/// The feature-point distributions (`WorleyParams::points`) by name, each
/// made from the separate keyword `density` (which one point per cell
/// ignores).
type Table = fn(f64) -> FeaturePoints;
const TABLES: &[(&str, Table)] = &[
    ("one_per_cell", |_| FeaturePoints::OnePerCell),
    ("poisson", |density| FeaturePoints::Poisson { density }),
    ("variable", |density| FeaturePoints::Variable { density }),
    ("gaussian", |density| FeaturePoints::Gaussian { density }),
];
const METRICS: &[(&str, Metric)] = &[
    ("euclidean", Metric::Euclidean),
    ("euclidean_squared", Metric::EuclideanSquared),
    ("manhattan", Metric::Manhattan),
    ("chebyshev", Metric::Chebyshev),
];
const KERNELS: &[(&str, SparseKernel)] = &[
    ("cone", SparseKernel::Cone),
    ("quartic", SparseKernel::Quartic),
];
const CONVENTIONS: &[(&str, GainConvention)] = &[
    ("h", GainConvention::H),
    ("half_beta", GainConvention::HalfBeta),
    ("raw", GainConvention::Raw),
];
const FORMS: &[(&str, CascadeForm)] = &[
    ("weighted", CascadeForm::Weighted),
    ("additive", CascadeForm::Additive),
];

/// The bases, by their Python names.
pub const BASES: &[&str] = &[
    "perlin",
    "value",
    "simplex",
    "worley",
    "sparse_convolution",
    "sine",
    "steps",
    "checkerboard",
];

/// The fractals, multifractals and distortions, by their Python names.
pub const FRACTALS: &[&str] = &[
    "fbm",
    "turbulence",
    "multifractal",
    "hetero_terrain",
    "hybrid_multifractal",
    "ridged_multifractal",
    "stats_by_altitude",
    "filtered_fbm",
    "dist_noise",
    "vl_noise",
];

/// The spectral defaults of a fractal kind (its `Params::default()`).
fn spectral_default(kind: &str) -> Spectral {
    match kind {
        "multifractal" => MultifractalParams::default().spectral,
        "hetero_terrain" => HeteroTerrainParams::default().spectral,
        "hybrid_multifractal" => HybridParams::default().spectral,
        "ridged_multifractal" => RidgedParams::default().spectral,
        "stats_by_altitude" => StatsByAltitudeParams::default().spectral,
        _ => Spectral::default(),
    }
}

/// Every parameter of `kind` with its default, in the Rust `Params`'
/// order (the basis parameters of a fractal excluded: its `basis` dict).
fn defaults(kind: &str) -> Option<Vec<(&'static str, Dv)>> {
    let spectral = |s: Spectral| {
        vec![
            ("h", Dv::F(s.h)),
            ("lacunarity", Dv::F(s.lacunarity)),
            ("octaves", Dv::F(s.octaves)),
            ("frequency", Dv::F(s.frequency)),
            ("convention", Dv::S(name_of(CONVENTIONS, s.convention))),
        ]
    };
    let w = WorleyParams::default();
    let sp = SparseParams::default();
    let mut v = match kind {
        "perlin" => vec![
            ("seed", Dv::I(0)),
            ("fade", Dv::S(name_of(FADES, Fade::default()))),
        ],
        "value" => vec![
            ("seed", Dv::I(0)),
            ("interp", Dv::S(name_of(INTERPS, ValueInterp::default()))),
        ],
        "simplex" | "steps" => vec![("seed", Dv::I(0))],
        "worley" => vec![
            ("seed", Dv::I(0)),
            ("feature", Dv::S(name_of(FEATURES, w.feature))),
            ("metric", Dv::S(name_of(METRICS, w.metric))),
            ("jitter", Dv::F(w.jitter)),
            ("feature_points", Dv::S("one_per_cell")),
            ("density", Dv::F(4.0)),
        ],
        "sparse_convolution" => vec![
            ("seed", Dv::I(0)),
            ("density", Dv::I(u64::from(sp.density))),
            ("kernel", Dv::S(name_of(KERNELS, sp.kernel))),
        ],
        "sine" | "checkerboard" => vec![],
        "fbm" | "turbulence" => spectral(spectral_default(kind)),
        "multifractal" => {
            let p = MultifractalParams::default();
            let mut v = spectral(p.spectral);
            v.push(("offset", Dv::F(p.offset)));
            v.push(("form", Dv::S(name_of(FORMS, p.form))));
            v
        }
        "hetero_terrain" => {
            let p = HeteroTerrainParams::default();
            let mut v = spectral(p.spectral);
            v.push(("offset", Dv::F(p.offset)));
            v.push(("threshold", Dv::F(p.threshold)));
            v
        }
        "hybrid_multifractal" => {
            let p = HybridParams::default();
            let mut v = spectral(p.spectral);
            v.push(("offset", Dv::F(p.offset)));
            v
        }
        "ridged_multifractal" => {
            let p = RidgedParams::default();
            let mut v = spectral(p.spectral);
            v.push(("offset", Dv::F(p.offset)));
            v.push(("gain", Dv::F(p.gain)));
            v
        }
        "stats_by_altitude" => {
            let p = StatsByAltitudeParams::default();
            let mut v = spectral(p.spectral);
            v.push(("shift", Dv::F(p.shift)));
            v.push(("scale", Dv::F(p.scale)));
            v.push(("sea_level", Dv::F(p.sea_level)));
            v
        }
        // FilteredFbm has no default width: 0 is the unfiltered sum.
        "filtered_fbm" => {
            let mut v = spectral(Spectral::default());
            v.push(("width", Dv::F(0.0)));
            v
        }
        // The C code's defaults: DistNoise's distortion 1, VLNoise's scale 1.
        "dist_noise" => vec![("distortion", Dv::F(1.0))],
        "vl_noise" => vec![("scale", Dv::F(1.0))],
        _ => return None,
    };
    if FRACTALS.contains(&kind) {
        v.insert(0, ("basis", Dv::S("perlin")));
    }
    Some(v)
}

fn spectral(kw: &Kw<'_>, d: Spectral) -> PyResult<Spectral> {
    Ok(Spectral {
        h: kw.f64("h", d.h)?,
        lacunarity: kw.f64("lacunarity", d.lacunarity)?,
        octaves: kw.f64("octaves", d.octaves)?,
        frequency: kw.f64("frequency", d.frequency)?,
        convention: kw.choice("convention", CONVENTIONS, d.convention)?,
    })
}

/// The basis a fractal sums, from its `basis` dict (Perlin, seed 0 when absent).
fn basis_of(kw: &Kw<'_>) -> PyResult<(&'static str, Arc<dyn Field>, Option<Perlin>)> {
    match kw.dict("basis")? {
        None => Ok(("perlin", Arc::new(Perlin::new(0)), Some(Perlin::new(0)))),
        Some(b) => {
            let kind = match b.name("kind", BASES, "perlin")? {
                Ok(kind) => kind,
                Err(kind) => {
                    return Err(PyValueError::new_err(format!(
                        "basis: kind = {kind:?} is not one of {}",
                        BASES.join(", ")
                    )));
                }
            };
            let (field, perlin) = build_basis(kind, &b)?;
            b.finish()?;
            Ok((kind, field, perlin))
        }
    }
}

/// A basis field (and the concrete Perlin, for the SIMD point path).
fn build_basis(kind: &str, kw: &Kw<'_>) -> PyResult<(Arc<dyn Field>, Option<Perlin>)> {
    let seed = |kw: &Kw<'_>| kw.int::<u64>("seed", 0);
    Ok(match kind {
        "perlin" => {
            let p = Perlin::with_fade(seed(kw)?, kw.choice("fade", FADES, Fade::default())?);
            (Arc::new(p), Some(p))
        }
        "value" => {
            let v = Value::with_interp(
                seed(kw)?,
                kw.choice("interp", INTERPS, ValueInterp::default())?,
            );
            (Arc::new(v), None)
        }
        "simplex" => (Arc::new(Simplex::new(seed(kw)?)), None),
        "worley" => {
            let d = WorleyParams::default();
            let seed = seed(kw)?;
            // `feature_points`: Python's name for `points`, which there names the
            // coordinates evaluated.
            let table = kw.choice("feature_points", TABLES, TABLES[0].1)?;
            let density = kw.f64("density", 4.0)?;
            let p = WorleyParams {
                feature: kw.choice("feature", FEATURES, d.feature)?,
                metric: kw.choice("metric", METRICS, d.metric)?,
                jitter: kw.f64("jitter", d.jitter)?,
                points: table(density),
            };
            (Arc::new(Worley::new(seed, p).map_err(value_error)?), None)
        }
        "sparse_convolution" => {
            let d = SparseParams::default();
            let seed = seed(kw)?;
            let p = SparseParams {
                density: kw.int::<u32>("density", d.density)?,
                kernel: kw.choice("kernel", KERNELS, d.kernel)?,
            };
            let f = SparseConvolution::new(seed, p).map_err(value_error)?;
            (Arc::new(f), None)
        }
        "sine" => (Arc::new(Sine), None),
        "steps" => (Arc::new(Steps::new(seed(kw)?)), None),
        "checkerboard" => (Arc::new(Checkerboard), None),
        _ => unreachable!("checked against BASES"),
    })
}

/// A field and, when it is a plain Perlin basis, the basis itself (whose 3-D
/// point batches take the SIMD path `Perlin::fill_points3`).
struct Built {
    field: Arc<dyn Field>,
    perlin: Option<Perlin>,
}

fn build(spec: &Bound<'_, PyAny>) -> PyResult<Built> {
    // A known kind is held as its `'static` name (the dict's errors name it
    // without a copy).
    let kind: Cow<'static, str> = match spec.get_item(key_str(spec.py(), "kind")) {
        Ok(k) => {
            let text: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err("kind must be a string"))?;
            match BASES.iter().chain(FRACTALS).find(|n| **n == text) {
                Some(name) => Cow::Borrowed(*name),
                None => Cow::Owned(text),
            }
        }
        Err(_) => Cow::Borrowed(""),
    };
    let kw = Kw::new_static(spec, kind.clone())?;
    kw.mark("kind")?;
    if BASES.contains(&kind.as_ref()) {
        let (field, perlin) = build_basis(&kind, &kw)?;
        kw.finish()?;
        return Ok(Built { field, perlin });
    }
    if !FRACTALS.contains(&kind.as_ref()) {
        return Err(PyValueError::new_err(format!(
            "kind = {kind:?} is not a noise of natura.noise ({}, {})",
            BASES.join(", "),
            FRACTALS.join(", ")
        )));
    }
    let (basis_kind, basis, perlin) = basis_of(&kw)?;
    let e = value_error;
    let field: Arc<dyn Field> = match kind.as_ref() {
        "fbm" => Arc::new(Fbm::new(basis, spectral(&kw, Spectral::default())?).map_err(e)?),
        "turbulence" => {
            Arc::new(Turbulence::new(basis, spectral(&kw, Spectral::default())?).map_err(e)?)
        }
        "multifractal" => {
            let d = MultifractalParams::default();
            let p = MultifractalParams {
                spectral: spectral(&kw, d.spectral)?,
                offset: kw.f64("offset", d.offset)?,
                form: kw.choice("form", FORMS, d.form)?,
            };
            Arc::new(Multifractal::new(basis, p).map_err(e)?)
        }
        "hetero_terrain" => {
            let d = HeteroTerrainParams::default();
            let p = HeteroTerrainParams {
                spectral: spectral(&kw, d.spectral)?,
                offset: kw.f64("offset", d.offset)?,
                threshold: kw.f64("threshold", d.threshold)?,
            };
            Arc::new(HeteroTerrain::new(basis, p).map_err(e)?)
        }
        "hybrid_multifractal" => {
            let d = HybridParams::default();
            let p = HybridParams {
                spectral: spectral(&kw, d.spectral)?,
                offset: kw.f64("offset", d.offset)?,
            };
            Arc::new(HybridMultifractal::new(basis, p).map_err(e)?)
        }
        "ridged_multifractal" => {
            let d = RidgedParams::default();
            let p = RidgedParams {
                spectral: spectral(&kw, d.spectral)?,
                offset: kw.f64("offset", d.offset)?,
                gain: kw.f64("gain", d.gain)?,
            };
            Arc::new(RidgedMultifractal::new(basis, p).map_err(e)?)
        }
        "stats_by_altitude" => {
            let d = StatsByAltitudeParams::default();
            let p = StatsByAltitudeParams {
                spectral: spectral(&kw, d.spectral)?,
                shift: kw.f64("shift", d.shift)?,
                scale: kw.f64("scale", d.scale)?,
                sea_level: kw.f64("sea_level", d.sea_level)?,
            };
            Arc::new(StatsByAltitude::new(basis, p).map_err(e)?)
        }
        "filtered_fbm" => {
            let s = spectral(&kw, Spectral::default())?;
            Arc::new(FilteredFbm::new(basis, s, kw.f64("width", 0.0)?).map_err(e)?)
        }
        "dist_noise" => {
            Arc::new(DistNoise::dist_noise(basis, kw.f64("distortion", 1.0)?).map_err(e)?)
        }
        "vl_noise" => {
            let Some(p) = perlin else {
                return Err(PyValueError::new_err(format!(
                    "vl_noise: basis = {basis_kind:?} is not smooth; vl_noise needs the \
                     gradient of a perlin basis"
                )));
            };
            Arc::new(VlNoise::vl_noise(p, kw.f64("scale", 1.0)?).map_err(e)?)
        }
        _ => unreachable!("checked against FRACTALS"),
    };
    kw.finish()?;
    Ok(Built {
        field,
        perlin: None,
    })
}

/// `noise_points(spec, points)`: the noise `spec` describes at each point of
/// `points` (float32 or float64, shape `(..., 2)` or `(..., 3)`), as float32
/// of shape `points.shape[:-1]`.
#[pyfunction]
fn noise_points<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let built = build(spec)?;
    let (coords, shape) = floats(points, "points")?;
    let dim = match shape.last() {
        Some(&d @ (2 | 3)) => d,
        _ => {
            return Err(PyValueError::new_err(format!(
                "points must have shape (..., 2) or (..., 3), not {shape:?}"
            )));
        }
    };
    let out_shape = shape[..shape.len() - 1].to_vec();
    let values = run_sized(py, coords.len() / dim, move || {
        let n = coords.len() / dim;
        let mut out = vec![0.0f32; n];
        if dim == 2 {
            for (o, p) in out.iter_mut().zip(coords.chunks_exact(2)) {
                *o = built.field.eval2(DVec2::new(p[0], p[1])) as f32;
            }
        } else if let Some(perlin) = built.perlin {
            let mut xyz = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            for (i, p) in coords.chunks_exact(3).enumerate() {
                xyz[0][i] = p[0];
                xyz[1][i] = p[1];
                xyz[2][i] = p[2];
            }
            perlin
                .fill_points3(&xyz[0], &xyz[1], &xyz[2], &mut out)
                .map_err(value_error)?;
        } else {
            for (o, p) in out.iter_mut().zip(coords.chunks_exact(3)) {
                *o = built.field.eval3(DVec3::new(p[0], p[1], p[2])) as f32;
            }
        }
        Ok(out)
    })?;
    let arr = numpy::ndarray::ArrayD::from_shape_vec(out_shape, values)
        .map_err(|e| PyValueError::new_err(format!("points: {e}")))?;
    Ok(arr.into_pyarray(py))
}

/// `noise_grid(spec, shape, origin, step)`: the noise on the regular lattice
/// `origin + index·step` (row-major; `shape` is `(ny, nx)` or `(nz, ny, nx)`,
/// `origin` and `step` are `(x, y)` or `(x, y, z)`), through the SIMD row
/// kernels of `Field::fill_grid2`/`fill_grid3`.
#[pyfunction]
fn noise_grid<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    shape: Vec<usize>,
    origin: Vec<f64>,
    step: Vec<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let built = build(spec)?;
    let dim = shape.len();
    if !(dim == 2 || dim == 3) {
        return Err(PyValueError::new_err(format!(
            "shape must be (ny, nx) or (nz, ny, nx), not {shape:?}"
        )));
    }
    for (name, v) in [("origin", &origin), ("step", &step)] {
        if v.len() != dim {
            return Err(PyValueError::new_err(format!(
                "{name} must have {dim} components (x, y{}), not {}",
                if dim == 3 { ", z" } else { "" },
                v.len()
            )));
        }
    }
    let dims = shape.clone();
    let values = run(py, move || {
        let shape = dims;
        if dim == 2 {
            let lattice = Lattice2::new(
                DVec2::new(origin[0], origin[1]),
                DVec2::new(step[0], step[1]),
                shape[1],
                shape[0],
            )
            .map_err(value_error)?;
            let mut out = vec![0.0f32; lattice.len()];
            built
                .field
                .fill_grid2(&lattice, &mut out)
                .map_err(value_error)?;
            Ok(out)
        } else {
            let lattice = Lattice3::new(
                DVec3::new(origin[0], origin[1], origin[2]),
                DVec3::new(step[0], step[1], step[2]),
                shape[2],
                shape[1],
                shape[0],
            )
            .map_err(value_error)?;
            let mut out = vec![0.0f32; lattice.len()];
            built
                .field
                .fill_grid3(&lattice, &mut out)
                .map_err(value_error)?;
            Ok(out)
        }
    })?;
    let arr = numpy::ndarray::ArrayD::from_shape_vec(shape, values)
        .map_err(|e| PyValueError::new_err(format!("shape: {e}")))?;
    Ok(arr.into_pyarray(py))
}

/// `noise_defaults(kind)`: every parameter of `kind` with its Rust default.
#[pyfunction]
fn noise_defaults<'py>(py: Python<'py>, kind: &str) -> PyResult<Bound<'py, PyDict>> {
    let d = defaults(kind)
        .ok_or_else(|| PyValueError::new_err(format!("kind = {kind:?} is not a noise")))?;
    crate::args::defaults_dict(py, &d)
}

/// `noise_bound(spec)`: the field's bound on `|f|` (`Field::bound`).
#[pyfunction]
fn noise_bound(spec: &Bound<'_, PyAny>) -> PyResult<f64> {
    Ok(build(spec)?.field.bound())
}

/// Adds the noise functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(noise_points, m)?)?;
    m.add_function(wrap_pyfunction!(noise_grid, m)?)?;
    m.add_function(wrap_pyfunction!(noise_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(noise_bound, m)?)?;
    m.add("NOISE_BASES", BASES.to_vec())?;
    m.add("NOISE_FRACTALS", FRACTALS.to_vec())?;
    Ok(())
}
