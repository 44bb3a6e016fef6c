//! `natura.texture` and `natura.atmos`: natura-texture's solid textures
//! sampled at arrays of points, its planets on equirectangular maps, and
//! natura-atmos's physical sky radiance for arrays of view directions.

use natura_atmos::Dir3;
use natura_atmos::sky::{Atmosphere, AtmosphereParams};
use natura_core::{Grid2, Image};
use natura_texture::air::{Cyclone, PlanetClouds, PuffyClouds, Venus};
use natura_texture::earth::{Luna, Ridge, Strata, Terran};
use natura_texture::fire::Flame;
use natura_texture::giants::{GasGiant, Rings};
use natura_texture::git::{ColourEllipsoid, Git, GitFilterParams};
use natura_texture::glam::{DVec3, Vec3};
use natura_texture::multicolor::Multicolor;
use natura_texture::planet::{Planet, PlanetParams};
use natura_texture::water::{Ripples, WindyWave};
use natura_texture::{Footprint, SolidTexture};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::args::{f32_array, floats, image_array, rgb_array, run, run_sized, value_error};
use crate::progress::PyProgress;
use crate::values::{from_params, from_value, overlay, to_params, to_toml};

/// The textures by name: `(name, build from a params dict, defaults)`.
macro_rules! textures {
    ($($name:literal => $ty:ty),* $(,)?) => {
        /// Every texture name, in the order of the table.
        const NAMES: &[&str] = &[$($name),*];

        /// The texture `name` with its `Params` from `params`.
        fn build(name: &str, params: &Bound<'_, PyAny>) -> PyResult<Box<dyn SolidTexture>> {
            match name {
                $($name => {
                    let p = from_params(params, $name)?;
                    Ok(Box::new(<$ty>::new(p).map_err(value_error)?))
                })*
                other => Err(unknown(other)),
            }
        }

        /// `Params::default()` of the texture `name`, as a dict.
        fn defaults<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
            match name {
                $($name => to_params(py, &<<$ty as HasParams>::P>::default()),)*
                other => Err(unknown(other)),
            }
        }
    };
}

/// The parameter struct of a texture type.
trait HasParams {
    /// Its `Params`.
    type P: Default + serde::Serialize;
}

macro_rules! has_params {
    ($($ty:ty => $p:ty),* $(,)?) => { $(impl HasParams for $ty { type P = $p; })* };
}

has_params! {
    PuffyClouds => natura_texture::air::PuffyCloudsParams,
    PlanetClouds => natura_texture::air::PlanetCloudsParams,
    Cyclone => natura_texture::air::CycloneParams,
    Venus => natura_texture::air::VenusParams,
    Flame => natura_texture::fire::FlameParams,
    Ripples => natura_texture::water::RipplesParams,
    WindyWave => natura_texture::water::WindyWaveParams,
    Strata => natura_texture::earth::StrataParams,
    Terran => natura_texture::earth::TerranParams,
    Luna => natura_texture::earth::LunaParams,
    Ridge => natura_texture::earth::RidgeParams,
    GasGiant => natura_texture::giants::GasGiantParams,
    Rings => natura_texture::giants::RingsParams,
    Multicolor => natura_texture::multicolor::MulticolorParams,
    Git => natura_texture::git::GitParams,
}

textures! {
    "puffy_clouds" => PuffyClouds,
    "planet_clouds" => PlanetClouds,
    "cyclone" => Cyclone,
    "venus" => Venus,
    "flame" => Flame,
    "ripples" => Ripples,
    "windy_wave" => WindyWave,
    "strata" => Strata,
    "terran" => Terran,
    "luna" => Luna,
    "ridge" => Ridge,
    "gas_giant" => GasGiant,
    "rings" => Rings,
    "multicolor" => Multicolor,
    "git" => Git,
}

fn unknown(name: &str) -> PyErr {
    PyValueError::new_err(format!(
        "name = {name:?} is not one of {}",
        NAMES.join(", ")
    ))
}

/// `(n, 3)` points of a float array (the last axis 3), as `DVec3`s.
fn points3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<DVec3>> {
    let (v, shape) = floats(obj, name)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (n, 3), not {shape:?}"
        )));
    }
    Ok(v.chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect())
}

type Samples<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// `texture_sample(name, points, footprint, params)`: the texture `name`
/// (`Params` from `params`) at each row of the float `(n, 3)` array
/// `points`, filtered to the footprint width `footprint` (texture units),
/// as `(colour (n, 3), opacity (n,), height (n,))`, float64: the `Sample`
/// fields as computed.
#[pyfunction]
fn texture_sample<'py>(
    py: Python<'py>,
    name: &str,
    points: &Bound<'py, PyAny>,
    footprint: f64,
    params: &Bound<'py, PyAny>,
) -> PyResult<Samples<'py>> {
    let pts = points3(points, "points")?;
    let fp =
        Footprint::new(footprint).map_err(|e| PyValueError::new_err(format!("footprint: {e}")))?;
    let tex = build(name, params)?;
    let n = pts.len();
    let (colour, opacity, height) = run_sized(py, n, || {
        let mut c = Vec::with_capacity(3 * n);
        let (mut o, mut h) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for p in pts {
            let s = tex.sample(p, fp);
            c.extend_from_slice(&s.colour.to_array());
            o.push(s.opacity);
            h.push(s.height);
        }
        Ok((c, o, h))
    })?;
    let colour =
        Array2::from_shape_vec((n, 3), colour).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((
        colour.into_pyarray(py),
        Array1::from_vec(opacity).into_pyarray(py),
        Array1::from_vec(height).into_pyarray(py),
    ))
}

/// `texture_defaults(name)`: the texture's `Params::default()` as a dict.
#[pyfunction]
fn texture_defaults<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    defaults(py, name)
}

/// `sky_radiance(directions, sun_elevation_deg, sun_azimuth_deg, altitude_m,
/// params)`: the sky's linear RGB radiance seen from `altitude_m` metres
/// above the origin for each unit direction of the float `(n, 3)` array
/// (z up), with the sun at the given elevation and azimuth (degrees,
/// counter-clockwise from +x) and `AtmosphereParams` from `params`; float32
/// `(n, 3)` (`SkyView::radiance_batch`: a direction that is not unit length
/// gives black).
#[pyfunction]
fn sky_radiance<'py>(
    py: Python<'py>,
    directions: &Bound<'py, PyAny>,
    sun_elevation_deg: f64,
    sun_azimuth_deg: f64,
    altitude_m: f64,
    params: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let dirs: Vec<Vec3> = points3(directions, "directions")?
        .into_iter()
        .map(|d| d.as_vec3())
        .collect();
    let p: AtmosphereParams = from_params(params, "atmosphere")?;
    let sun = Dir3::from_angles(sun_elevation_deg.to_radians(), sun_azimuth_deg.to_radians())
        .map_err(|e| PyValueError::new_err(format!("sun: {e}")))?;
    if !altitude_m.is_finite() {
        return Err(PyValueError::new_err(format!(
            "altitude_m = {altitude_m} must be finite"
        )));
    }
    let n = dirs.len();
    let out = run(py, || {
        let atm = Atmosphere::new(p).map_err(value_error)?;
        let view = atm
            .sky_view(DVec3::new(0.0, 0.0, altitude_m), sun)
            .map_err(value_error)?;
        let mut out = vec![Vec3::ZERO; n];
        view.radiance_batch(&dirs, &mut out).map_err(value_error)?;
        Ok(out)
    })?;
    let flat: Vec<f32> = out.iter().flat_map(|c| c.to_array()).collect();
    let a =
        Array2::from_shape_vec((n, 3), flat).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// The planet presets of natura-texture, by name.
fn planet_preset(name: &str) -> PyResult<PlanetParams> {
    Ok(match name {
        "gaea" => PlanetParams::gaea(),
        "venus" => PlanetParams::venus(),
        "jupiter" => PlanetParams::jupiter(),
        "selene" => PlanetParams::selene(),
        other => {
            return Err(PyValueError::new_err(format!(
                "preset = {other:?} is not one of gaea, venus, jupiter, selene"
            )));
        }
    })
}

/// A planet's colour and height maps.
type PlanetMap<'py> = (Bound<'py, PyArray3<f32>>, Bound<'py, PyArray2<f32>>);

/// `planet_equirect(preset, width, height, params, progress)`: the planet
/// (the `PlanetParams` preset with the fields of `params` laid over it)
/// sampled onto a `width × height` equirectangular map
/// (`Planet::equirect`): unlit linear-RGB colour float32 `(height, width,
/// 3)` and height above the sea-level radius (metres) float32 `(height,
/// width)`.
#[pyfunction]
#[pyo3(signature = (preset, width, height, params, progress=None))]
fn planet_equirect<'py>(
    py: Python<'py>,
    preset: &str,
    width: usize,
    height: usize,
    params: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PlanetMap<'py>> {
    let mut value = toml::Value::try_from(planet_preset(preset)?).map_err(value_error)?;
    overlay(&mut value, to_toml(params, "")?);
    let p: PlanetParams = from_value(value, "planet")?;
    let planet = Planet::new(p).map_err(value_error)?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        planet.equirect(width, height, &sink).map_err(value_error)
    });
    let map = sink.finish_call(out)?;
    let colour = rgb_array(py, &map.colour)?;
    let h = Array2::from_shape_vec((height, width), map.height.into_vec())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((colour, h.into_pyarray(py)))
}

/// `planet_defaults(preset)`: the planet preset's `PlanetParams` as a dict.
#[pyfunction]
fn planet_defaults<'py>(py: Python<'py>, preset: &str) -> PyResult<Bound<'py, PyAny>> {
    to_params(py, &planet_preset(preset)?)
}

/// `atmosphere_defaults()`: `AtmosphereParams::default()` as a dict.
#[pyfunction]
fn atmosphere_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    to_params(py, &AtmosphereParams::default())
}

/// `git_filter(image, params, progress)`: the picture `image` (linear RGB,
/// float32 `(height, width, 3)`) repainted by natura-texture's GIT filter
/// (`git_filter`, `GitFilterParams` from `params`): float32 `(height·e,
/// width·e, 3)` for the enlargement `e = params["expand"]`.
#[pyfunction]
#[pyo3(signature = (image, params, progress=None))]
fn git_filter<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    params: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (data, shape) = f32_array(image, "image", 3, "rows, columns, RGB")?;
    if shape[2] != 3 {
        return Err(PyValueError::new_err(format!(
            "image must have shape (height, width, 3), not {shape:?}"
        )));
    }
    let pixels: Vec<Vec3> = data
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    let grid = Grid2::from_vec(shape[1], shape[0], pixels).map_err(value_error)?;
    let p: GitFilterParams = from_params(params, "git_filter")?;
    let sink = PyProgress::new(progress);
    let out = run(py, || {
        natura_texture::git::git_filter(&Image::from_grid(grid), &p, &sink).map_err(value_error)
    });
    let img = sink.finish_call(out)?;
    image_array(py, &img)
}

/// `git_filter_defaults()`: `GitFilterParams::default()` as a dict.
#[pyfunction]
fn git_filter_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    to_params(py, &GitFilterParams::default())
}

/// `colour_ellipsoid(colours)`: the `ColourEllipsoid` of the rows of the
/// float `(n, 3)` array `colours` (display RGB in `[0, 1]`, at least two)
/// by principal components, as the dict the `git` texture's `ellipsoid`
/// parameter takes.
#[pyfunction]
fn colour_ellipsoid<'py>(
    py: Python<'py>,
    colours: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let c = points3(colours, "colours")?;
    let e = ColourEllipsoid::from_colours(&c).map_err(value_error)?;
    to_params(py, &e)
}

/// Adds the texture and sky functions to `m`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("TEXTURE_NAMES", NAMES.to_vec())?;
    m.add_function(wrap_pyfunction!(texture_sample, m)?)?;
    m.add_function(wrap_pyfunction!(texture_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(git_filter, m)?)?;
    m.add_function(wrap_pyfunction!(git_filter_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(colour_ellipsoid, m)?)?;
    m.add_function(wrap_pyfunction!(sky_radiance, m)?)?;
    m.add_function(wrap_pyfunction!(atmosphere_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(planet_equirect, m)?)?;
    m.add_function(wrap_pyfunction!(planet_defaults, m)?)?;
    Ok(())
}
