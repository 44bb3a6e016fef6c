//! `natura.terrain`: synthesis, the erosion models, drainage analysis and
//! export of natura-terrain, on float32 2-D height arrays (rows are `y`,
//! columns `x`; the array's row `j` is the height field's row `j`).

use natura_core::{Grid2, HeightField, Seed};
use natura_terrain::analysis::{
    Depressions, channel_network, fill_depressions, flow_accumulation_mfd, strahler_order, wetness,
};
use natura_terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, Edges, MusgraveHydraulic,
    MusgraveParams, Neighbourhood, PipeModel, PipeParams, RainLaw, SedimentTransport, StreamPower,
    StreamPowerParams, Thermal, ThermalParams,
};
use natura_terrain::export;
use natura_terrain::synth::{
    FaultParams, SpectralParams, SraParams, poisson_faults, spectral_synthesis,
    successive_random_additions,
};
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::args::{Dv, Kw, defaults_dict, grid2, name_of, params, run, value_error};

const NEIGHBOURHOODS: &[(&str, Neighbourhood)] = &[
    ("four", Neighbourhood::Four),
    ("eight", Neighbourhood::Eight),
];
const EDGES: &[(&str, Edges)] = &[
    ("closed", Edges::Closed),
    ("periodic", Edges::Periodic),
    ("open", Edges::Open),
];
const TRANSPORTS: &[(&str, SedimentTransport)] = &[
    ("conservative", SedimentTransport::Conservative),
    ("semi_lagrangian", SedimentTransport::SemiLagrangian),
];
const DEPRESSIONS: &[(&str, Depressions)] = &[
    ("keep", Depressions::Keep),
    ("route", Depressions::Route),
    ("fill", Depressions::Fill),
];

/// The erosion models, by their Python names.
pub const MODELS: &[&str] = &[
    "thermal",
    "hydraulic",
    "droplet",
    "pipe",
    "stream_power",
    "diffusion",
];

/// The synthesis methods, by their Python names.
pub const SYNTHS: &[&str] = &["spectral", "sra", "faults"];

params!(
    thermal_params,
    thermal_defaults,
    ThermalParams {
        talus_angle: f64,
        talus_rate: f64,
        neighbourhood: [NEIGHBOURHOODS],
        edges: [EDGES],
    }
);
params!(
    hydraulic_params,
    hydraulic_defaults,
    MusgraveParams {
        k_c: f64,
        k_d: f64,
        k_s: f64,
        rain: rain_law,
        rain_period: int,
        transfer: f64,
        evaporation: f64,
        erosion_guard: bool,
        neighbourhood: [NEIGHBOURHOODS],
        edges: [EDGES],
    }
);
params!(
    droplet_params,
    droplet_defaults,
    DropletParams {
        inertia: f64,
        capacity: f64,
        min_slope: f64,
        erode: f64,
        deposit: f64,
        evaporate: f64,
        gravity: f64,
        radius: int,
        lifetime: int,
        initial_water: f64,
        initial_speed: f64,
        batch: int,
    }
);
params!(
    pipe_params,
    pipe_defaults,
    PipeParams {
        dt: f64,
        gravity: f64,
        pipe_area: f64,
        rain_m_per_s: f64,
        k_c: f64,
        k_s: f64,
        k_d: f64,
        k_e: f64,
        min_tilt: f64,
        depth_ref: f64,
        transport: [TRANSPORTS],
        edges: [EDGES],
    }
);
params!(
    stream_power_params,
    stream_power_defaults,
    StreamPowerParams {
        k: f64,
        m: f64,
        n: f64,
        uplift_m_per_yr: f64,
        dt_yr: f64,
        depressions: [DEPRESSIONS],
    }
);
params!(
    diffusion_params,
    diffusion_defaults,
    DiffusionParams {
        rate: f64,
        neighbourhood: [NEIGHBOURHOODS],
        edges: [EDGES],
    }
);
params!(
    spectral_params,
    spectral_defaults,
    SpectralParams {
        h: f64,
        sigma_m: f64,
        low_cut: f64,
        high_cut: opt,
    }
);
params!(
    sra_params,
    sra_defaults,
    SraParams {
        h: f64,
        lacunarity: f64,
        sigma_m: f64
    }
);
params!(
    fault_params,
    fault_defaults,
    FaultParams {
        faults: int,
        amplitude_m: f64
    }
);

/// The Musgrave model's rain law: `"altitude_linear"` (with `rain_k`,
/// `rain_base_m`) or `"uniform"` (with `rain_depth_m`).
fn rain(kw: &Kw<'_>, d: RainLaw) -> PyResult<RainLaw> {
    let (dk, db) = match d {
        RainLaw::AltitudeLinear { k, base_m } => (k, base_m),
        RainLaw::Uniform { .. } => (0.001, 0.0),
    };
    let kind = kw.string("rain", rain_name(d))?;
    match kind.as_str() {
        "altitude_linear" => Ok(RainLaw::AltitudeLinear {
            k: kw.f64("rain_k", dk)?,
            base_m: kw.f64("rain_base_m", db)?,
        }),
        "uniform" => Ok(RainLaw::Uniform {
            depth_m: kw.f64("rain_depth_m", 0.01)?,
        }),
        other => Err(PyValueError::new_err(format!(
            "hydraulic: rain = {other:?} is not one of altitude_linear, uniform"
        ))),
    }
}

fn rain_name(r: RainLaw) -> &'static str {
    match r {
        RainLaw::Uniform { .. } => "uniform",
        RainLaw::AltitudeLinear { .. } => "altitude_linear",
    }
}

fn model_defaults(model: &str) -> Option<Vec<(&'static str, Dv)>> {
    Some(match model {
        "thermal" => thermal_defaults(),
        "hydraulic" => {
            let mut v = hydraulic_defaults();
            if let RainLaw::AltitudeLinear { k, base_m } = MusgraveParams::default().rain {
                v.push(("rain_k", Dv::F(k)));
                v.push(("rain_base_m", Dv::F(base_m)));
            }
            v
        }
        "droplet" => droplet_defaults(),
        "pipe" => pipe_defaults(),
        "stream_power" => stream_power_defaults(),
        "diffusion" => diffusion_defaults(),
        "spectral" => spectral_defaults(),
        "sra" => sra_defaults(),
        "faults" => fault_defaults(),
        _ => return None,
    })
}

/// The height field of a float32 2-D array.
pub(crate) fn field(obj: &Bound<'_, PyAny>, name: &str, cell_size: f32) -> PyResult<HeightField> {
    HeightField::new(grid2(obj, name)?, cell_size).map_err(value_error)
}

fn array<'py, T: numpy::Element>(
    py: Python<'py>,
    g: Grid2<T>,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let (nx, ny) = (g.width(), g.height());
    let a = numpy::ndarray::Array2::from_shape_vec((ny, nx), g.into_vec())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// `terrain_erode(model, heights, cell_size, steps, params, seed, progress)`:
/// runs `steps` steps (droplets for `"droplet"`) of an erosion model on a
/// copy of `heights` and returns the eroded heights. `progress`, if given,
/// is called as `progress(stage, done, total)` with the model's own reports
/// (its steps, or droplets in batches), which never change the result.
#[pyfunction]
#[pyo3(signature = (model, heights, cell_size, steps, params, seed, progress=None))]
#[allow(clippy::too_many_arguments)]
fn terrain_erode<'py>(
    py: Python<'py>,
    model: &str,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
    steps: u64,
    params: &Bound<'py, PyAny>,
    seed: u64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let mut hf = field(heights, "heights", cell_size)?;
    let kw = Kw::new(params, model)?;
    let steps32 = || {
        u32::try_from(steps)
            .map_err(|_| PyValueError::new_err(format!("steps = {steps} exceeds 2^32 - 1")))
    };
    let e = value_error;
    enum M {
        Thermal(Thermal),
        Hydraulic(MusgraveHydraulic),
        Droplet(Box<DropletErosion>),
        Pipe(Box<PipeModel>),
        StreamPower(StreamPower),
        Diffusion(Diffusion),
    }
    let m = match model {
        "thermal" => M::Thermal(Thermal::new(thermal_params(&kw)?, &hf).map_err(e)?),
        "hydraulic" => {
            M::Hydraulic(MusgraveHydraulic::new(hydraulic_params(&kw)?, &hf).map_err(e)?)
        }
        "droplet" => M::Droplet(Box::new(
            DropletErosion::new(droplet_params(&kw)?, &hf, Seed(seed)).map_err(e)?,
        )),
        "pipe" => M::Pipe(Box::new(PipeModel::new(pipe_params(&kw)?, &hf).map_err(e)?)),
        "stream_power" => {
            M::StreamPower(StreamPower::new(stream_power_params(&kw)?, &hf).map_err(e)?)
        }
        "diffusion" => M::Diffusion(Diffusion::new(diffusion_params(&kw)?, &hf).map_err(e)?),
        other => {
            return Err(PyValueError::new_err(format!(
                "model = {other:?} is not one of {}",
                MODELS.join(", ")
            )));
        }
    };
    kw.finish()?;
    let n = if model == "droplet" { 0 } else { steps32()? };
    let sink = crate::progress::PyProgress::new(progress);
    let out = run(py, || {
        let p = &sink;
        match m {
            M::Thermal(mut m) => m.run(&mut hf, n, p),
            M::Hydraulic(mut m) => m.run(&mut hf, n, p),
            M::Droplet(mut m) => m.run(&mut hf, steps, p),
            M::Pipe(mut m) => m.run(&mut hf, n, p),
            M::StreamPower(mut m) => m.run(&mut hf, n, p),
            M::Diffusion(mut m) => m.run(&mut hf, n, p),
        }
        .map_err(value_error)?;
        Ok(hf.into_heights())
    });
    array(py, sink.finish_call(out)?)
}

/// `terrain_synth(method, nx, ny, cell_size, params, seed)`: a new height
/// field by spectral synthesis, successive random additions or faulting.
#[pyfunction]
fn terrain_synth<'py>(
    py: Python<'py>,
    method: &str,
    nx: usize,
    ny: usize,
    cell_size: f32,
    params: &Bound<'py, PyAny>,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let kw = Kw::new(params, method)?;
    let seed = Seed(seed);
    let out = match method {
        "spectral" => {
            let p = spectral_params(&kw)?;
            kw.finish()?;
            run(py, move || {
                spectral_synthesis(nx, ny, cell_size, &p, seed).map_err(value_error)
            })?
        }
        "sra" => {
            let p = sra_params(&kw)?;
            kw.finish()?;
            run(py, move || {
                successive_random_additions(nx, ny, cell_size, &p, seed).map_err(value_error)
            })?
        }
        "faults" => {
            let p = fault_params(&kw)?;
            kw.finish()?;
            run(py, move || {
                poisson_faults(nx, ny, cell_size, &p, seed).map_err(value_error)
            })?
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "method = {other:?} is not one of {}",
                SYNTHS.join(", ")
            )));
        }
    };
    array(py, out.into_heights())
}

/// `terrain_defaults(name)`: every parameter of an erosion model or
/// synthesis method with its Rust default.
#[pyfunction]
fn terrain_defaults<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    let d = model_defaults(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "{name:?} is not an erosion model or synthesis method"
        ))
    })?;
    defaults_dict(py, &d)
}

/// A float32 2-D numpy array.
type F32Array<'py> = Bound<'py, PyArray2<f32>>;

/// `terrain_fill_depressions(heights, cell_size)`: `(filled, depth)`, the
/// depression-filled heights and the water depth filling adds.
#[pyfunction]
fn terrain_fill_depressions<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
) -> PyResult<(F32Array<'py>, F32Array<'py>)> {
    let hf = field(heights, "heights", cell_size)?;
    let (filled, depth) = run(py, move || fill_depressions(&hf).map_err(value_error))?;
    Ok((array(py, filled.into_heights())?, array(py, depth)?))
}

/// `terrain_flow_accumulation(heights, cell_size, exponent)`: the
/// multiple-flow-direction drainage area of every cell, square metres.
#[pyfunction]
fn terrain_flow_accumulation<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
    exponent: f64,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let hf = field(heights, "heights", cell_size)?;
    let a = run(py, move || {
        flow_accumulation_mfd(&hf, exponent).map_err(value_error)
    })?;
    array(py, a)
}

/// `terrain_strahler_order(heights, cell_size, threshold_m2)`: the Strahler
/// order of the channel cells (0 off the channels).
#[pyfunction]
fn terrain_strahler_order<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
    threshold_m2: f32,
) -> PyResult<Bound<'py, PyArray2<u8>>> {
    let hf = field(heights, "heights", cell_size)?;
    let a = run(py, move || {
        strahler_order(&hf, threshold_m2).map_err(value_error)
    })?;
    array(py, a)
}

/// `terrain_channel_network(area, threshold_m2)`: the cells whose drainage
/// area reaches `threshold_m2`.
#[pyfunction]
fn terrain_channel_network<'py>(
    py: Python<'py>,
    area: &Bound<'py, PyAny>,
    threshold_m2: f32,
) -> PyResult<Bound<'py, PyArray2<bool>>> {
    let grid = grid2(area, "area")?;
    let a = run(py, move || {
        channel_network(&grid, threshold_m2).map_err(value_error)
    })?;
    array(py, a)
}

/// `terrain_wetness(heights, cell_size)`: the wetness in `[0, 1]`
/// (natura-terrain's `analysis::wetness`: the topographic wetness index
/// rescaled from the driest cell to the wettest).
#[pyfunction]
fn terrain_wetness<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    cell_size: f32,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let hf = field(heights, "heights", cell_size)?;
    let a = run(py, move || wetness(&hf).map_err(value_error))?;
    array(py, a)
}

/// `terrain_save(format, heights, cell_size, path, range, step)`: writes
/// `heights` as a 16-bit PNG (`"png16"`, mapping `range` to 0..65535), an
/// EXR (`"exr"`), or a mesh sampling every `step` cells (`"obj"`, `"glb"`),
/// atomically (a temporary file renamed).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn terrain_save(
    py: Python<'_>,
    format: &str,
    heights: &Bound<'_, PyAny>,
    cell_size: f32,
    path: std::path::PathBuf,
    range: Option<(f32, f32)>,
    step: usize,
) -> PyResult<()> {
    let hf = field(heights, "heights", cell_size)?;
    let io = |e: String| PyOSError::new_err(e);
    match format {
        "png16" => {
            let range = range.unwrap_or_else(|| hf.min_max());
            run(py, move || {
                hf.save_png16(&path, range).map_err(|e| io(e.to_string()))
            })
        }
        "exr" => run(py, move || {
            export::save_height_exr(&hf, &path).map_err(|e| io(e.to_string()))
        }),
        "obj" | "glb" => {
            let glb = format == "glb";
            run(py, move || {
                let m = export::mesh(&hf, step).map_err(value_error)?;
                if glb {
                    export::save_glb(&m, &path)
                } else {
                    export::save_obj(&m, &path)
                }
                .map_err(|e| io(e.to_string()))
            })
        }
        other => Err(PyValueError::new_err(format!(
            "format = {other:?} is not one of png16, exr, obj, glb"
        ))),
    }
}

/// Adds the terrain functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(terrain_erode, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_synth, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_fill_depressions, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_flow_accumulation, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_strahler_order, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_channel_network, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_wetness, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_save, m)?)?;
    m.add("TERRAIN_MODELS", MODELS.to_vec())?;
    m.add("TERRAIN_SYNTHS", SYNTHS.to_vec())?;
    Ok(())
}
