"""Terrain synthesis, erosion, drainage analysis and export (natura-terrain).

Height fields are float32 numpy arrays of shape ``(ny, nx)``, heights in
metres; ``cell_size`` is the spacing of the samples in metres (row ``j`` is
the height field's row ``j``, column ``i`` its column ``i``). Arrays of any
layout are accepted (they are copied); other dtypes and shapes raise
``TypeError``/``ValueError`` naming the argument. The functions return new
arrays and release the GIL while they run.

Each erosion model and synthesis method takes the fields of its Rust
``Params`` struct as keyword arguments, with the same names, defaults and
validation (a bad value raises ``ValueError`` naming it). Enumerations are
given by name in snake case (``edges="periodic"``). The Musgrave model's
``rain`` law is ``"altitude_linear"`` (``rain_k``, ``rain_base_m``) or
``"uniform"`` (``rain_depth_m``).

Every erosion function takes ``progress``: ``None``, ``True`` (a ``tqdm``
bar when tqdm is installed) or a callable ``progress(stage, done, total)``
called with the model's own reports (natura-core's ``Progress``: its steps,
or droplets in batches); reports never change the result.
"""

from __future__ import annotations

import os
from typing import Optional, Tuple, Union

import numpy as np

from natura import _native, _progress
from natura._progress import ProgressArg

PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "erode_thermal",
    "erode_hydraulic",
    "erode_droplet",
    "erode_pipe",
    "erode_stream_power",
    "erode_diffusion",
    "spectral",
    "sra",
    "faults",
    "fill_depressions",
    "flow_accumulation",
    "strahler_order",
    "channel_network",
    "wetness",
    "save_png16",
    "save_exr",
    "save_obj",
    "save_glb",
]


def erode_thermal(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    steps: int = 1,
    talus_angle: float = 0.5759586531581288,
    talus_rate: float = 0.001,
    neighbourhood: str = "eight",
    edges: str = "closed",
    progress: ProgressArg = None,
) -> np.ndarray:
    """Thermal weathering: material above the talus angle slides to lower neighbours.

    Runs ``steps`` steps of the Rust ``Thermal`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``ThermalParams``, same names and defaults.
    """
    params = {
        "talus_angle": talus_angle,
        "talus_rate": talus_rate,
        "neighbourhood": neighbourhood,
        "edges": edges,
    }
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("thermal", heights, cell_size, steps, params, 0, cb)
    finally:
        _progress.closing(cb)


def erode_hydraulic(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    steps: int = 1,
    k_c: float = 5.0,
    k_d: float = 0.1,
    k_s: float = 0.3,
    rain: str = "altitude_linear",
    rain_period: int = 65,
    transfer: float = 0.5,
    evaporation: float = 0.0,
    erosion_guard: bool = True,
    neighbourhood: str = "eight",
    edges: str = "closed",
    rain_k: float = 0.001,
    rain_base_m: float = 0.0,
    rain_depth_m: float = 0.01,
    progress: ProgressArg = None,
) -> np.ndarray:
    """Musgrave et al. 1989 hydraulic erosion: rain, water and sediment moved between cells.

    Runs ``steps`` steps of the Rust ``MusgraveHydraulic`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``MusgraveParams``, same names and defaults.
    The default rain law is ``altitude_linear``; ``rain_depth_m`` is read only for ``rain="uniform"``.
    """
    params = {
        "k_c": k_c,
        "k_d": k_d,
        "k_s": k_s,
        "rain": rain,
        "rain_period": rain_period,
        "transfer": transfer,
        "evaporation": evaporation,
        "erosion_guard": erosion_guard,
        "neighbourhood": neighbourhood,
        "edges": edges,
        "rain_k": rain_k,
        "rain_base_m": rain_base_m,
        "rain_depth_m": rain_depth_m,
    }
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("hydraulic", heights, cell_size, steps, _rain(params), 0, cb)
    finally:
        _progress.closing(cb)


def erode_droplet(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    droplets: int = 1000,
    seed: int = 0,
    inertia: float = 0.05,
    capacity: float = 4.0,
    min_slope: float = 0.01,
    erode: float = 0.3,
    deposit: float = 0.3,
    evaporate: float = 0.01,
    gravity: float = 4.0,
    radius: int = 3,
    lifetime: int = 30,
    initial_water: float = 1.0,
    initial_speed: float = 1.0,
    batch: int = 1,
    progress: ProgressArg = None,
) -> np.ndarray:
    """Particle (droplet) hydraulic erosion: `droplets` droplets descend, erode and deposit.

    Runs ``droplets`` droplets of the Rust ``DropletErosion`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``DropletParams``, same names and defaults.
    """
    params = {
        "inertia": inertia,
        "capacity": capacity,
        "min_slope": min_slope,
        "erode": erode,
        "deposit": deposit,
        "evaporate": evaporate,
        "gravity": gravity,
        "radius": radius,
        "lifetime": lifetime,
        "initial_water": initial_water,
        "initial_speed": initial_speed,
        "batch": batch,
    }
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("droplet", heights, cell_size, droplets, params, seed, cb)
    finally:
        _progress.closing(cb)


def erode_pipe(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    steps: int = 1,
    dt: float = 0.05,
    gravity: float = 9.81,
    pipe_area: float = 1.0,
    rain_m_per_s: float = 0.01,
    k_c: float = 0.05,
    k_s: float = 0.3,
    k_d: float = 0.3,
    k_e: float = 0.05,
    min_tilt: float = 0.05,
    depth_ref: float = 0.05,
    transport: str = "conservative",
    edges: str = "closed",
    progress: ProgressArg = None,
) -> np.ndarray:
    """Shallow-water pipe model: water flux through virtual pipes, sediment capacity erosion.

    Runs ``steps`` steps of the Rust ``PipeModel`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``PipeParams``, same names and defaults.
    """
    params = {
        "dt": dt,
        "gravity": gravity,
        "pipe_area": pipe_area,
        "rain_m_per_s": rain_m_per_s,
        "k_c": k_c,
        "k_s": k_s,
        "k_d": k_d,
        "k_e": k_e,
        "min_tilt": min_tilt,
        "depth_ref": depth_ref,
        "transport": transport,
        "edges": edges,
    }
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("pipe", heights, cell_size, steps, params, 0, cb)
    finally:
        _progress.closing(cb)


def erode_stream_power(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    steps: int = 1,
    k: float = 2e-05,
    m: float = 0.5,
    n: float = 1.0,
    uplift_m_per_yr: float = 0.0005,
    dt_yr: float = 5000.0,
    depressions: str = "fill",
    progress: ProgressArg = None,
) -> np.ndarray:
    """Stream-power law fluvial erosion with tectonic uplift.

    Runs ``steps`` steps of the Rust ``StreamPower`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``StreamPowerParams``, same names and defaults.
    """
    params = {
        "k": k,
        "m": m,
        "n": n,
        "uplift_m_per_yr": uplift_m_per_yr,
        "dt_yr": dt_yr,
        "depressions": depressions,
    }
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("stream_power", heights, cell_size, steps, params, 0, cb)
    finally:
        _progress.closing(cb)


def erode_diffusion(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    steps: int = 1,
    rate: float = 0.1,
    neighbourhood: str = "four",
    edges: str = "closed",
    progress: ProgressArg = None,
) -> np.ndarray:
    """Linear hillslope diffusion (soil creep).

    Runs ``steps`` steps of the Rust ``Diffusion`` on a copy of ``heights``
    (float32, ``(ny, nx)``) and returns the eroded heights. Keyword
    parameters: the fields of ``DiffusionParams``, same names and defaults.
    """
    params = {"rate": rate, "neighbourhood": neighbourhood, "edges": edges}
    cb = _progress.reporter(progress)
    try:
        return _native.terrain_erode("diffusion", heights, cell_size, steps, params, 0, cb)
    finally:
        _progress.closing(cb)


def _rain(params: dict) -> dict:
    if params["rain"] == "uniform":
        del params["rain_k"], params["rain_base_m"]
    else:
        del params["rain_depth_m"]
    return params


def spectral(
    shape: Tuple[int, int],
    *,
    cell_size: float = 1.0,
    seed: int = 0,
    h: float = 0.8,
    sigma_m: float = 100.0,
    low_cut: float = 0.0,
    high_cut: Optional[float] = None,
) -> np.ndarray:
    """A periodic fBm-like tile by spectral (FFT) synthesis.

    A new float32 height field of ``shape`` ``(ny, nx)`` from the Rust
    ``spectral_synthesis`` with seed ``seed``. Keyword parameters: the fields of
    ``SpectralParams``, same names and defaults.
    """
    ny, nx = shape
    return _native.terrain_synth(
        "spectral",
        nx,
        ny,
        cell_size,
        {"h": h, "sigma_m": sigma_m, "low_cut": low_cut, "high_cut": high_cut},
        seed,
    )


def sra(
    shape: Tuple[int, int],
    *,
    cell_size: float = 1.0,
    seed: int = 0,
    h: float = 0.8,
    lacunarity: float = 2.0,
    sigma_m: float = 100.0,
) -> np.ndarray:
    """Successive random additions (Voss).

    A new float32 height field of ``shape`` ``(ny, nx)`` from the Rust
    ``successive_random_additions`` with seed ``seed``. Keyword parameters: the fields of
    ``SraParams``, same names and defaults.
    """
    ny, nx = shape
    return _native.terrain_synth(
        "sra", nx, ny, cell_size, {"h": h, "lacunarity": lacunarity, "sigma_m": sigma_m}, seed
    )


def faults(
    shape: Tuple[int, int],
    *,
    cell_size: float = 1.0,
    seed: int = 0,
    faults: int = 1000,
    amplitude_m: float = 10.0,
) -> np.ndarray:
    """Random (Poisson) faulting.

    A new float32 height field of ``shape`` ``(ny, nx)`` from the Rust
    ``poisson_faults`` with seed ``seed``. Keyword parameters: the fields of
    ``FaultParams``, same names and defaults.
    """
    ny, nx = shape
    return _native.terrain_synth(
        "faults", nx, ny, cell_size, {"faults": faults, "amplitude_m": amplitude_m}, seed
    )


def fill_depressions(
    heights: np.ndarray, *, cell_size: float = 1.0
) -> Tuple[np.ndarray, np.ndarray]:
    """Priority-flood depression filling: ``(filled, depth)``, the filled
    heights and the depth of water filling adds (``fill_depressions``)."""
    return _native.terrain_fill_depressions(heights, cell_size)


def flow_accumulation(
    heights: np.ndarray, *, cell_size: float = 1.0, exponent: float = 1.1
) -> np.ndarray:
    """Multiple-flow-direction drainage area of every cell, square metres
    (``flow_accumulation_mfd``; ``exponent`` weights the slopes, 1.1 after
    Freeman 1991)."""
    return _native.terrain_flow_accumulation(heights, cell_size, exponent)


def strahler_order(
    heights: np.ndarray, *, cell_size: float = 1.0, threshold_m2: float
) -> np.ndarray:
    """Strahler order (uint8) of the channel cells, those draining at least
    ``threshold_m2``; 0 elsewhere (``strahler_order``)."""
    return _native.terrain_strahler_order(heights, cell_size, threshold_m2)


def channel_network(area: np.ndarray, *, threshold_m2: float) -> np.ndarray:
    """The cells (bool) whose drainage ``area`` (float32, square metres, as
    :func:`flow_accumulation` returns) reaches ``threshold_m2``."""
    return _native.terrain_channel_network(area, threshold_m2)


def wetness(heights: np.ndarray, *, cell_size: float = 1.0) -> np.ndarray:
    """The wetness of every cell in ``[0, 1]`` (the Rust ``analysis::wetness``):
    the topographic wetness index ``ln(a / tan b)`` (Beven & Kirkby 1979)
    over the multiple-flow-direction drainage area, rescaled so the driest
    cell is 0 and the wettest 1. The map the ecosystem's species read
    (:func:`natura.plant.ecosystem`'s ``wetness``) and the renderer's
    materials."""
    return _native.terrain_wetness(heights, cell_size)


def save_png16(
    heights: np.ndarray, path: PathLike, *, range: Optional[Tuple[float, float]] = None
) -> None:
    """Writes a 16-bit greyscale PNG mapping ``range`` (default: the lowest
    and highest height) to 0..65535, the range stored in the file
    (``HeightField::save_png16``); written to a temporary name and renamed."""
    _native.terrain_save("png16", heights, 1.0, os.fspath(path), range, 1)


def save_exr(heights: np.ndarray, path: PathLike, *, cell_size: float = 1.0) -> None:
    """Writes the heights as a single-channel float32 EXR (``save_height_exr``)."""
    _native.terrain_save("exr", heights, cell_size, os.fspath(path), None, 1)


def save_obj(heights: np.ndarray, path: PathLike, *, cell_size: float = 1.0, step: int = 1) -> None:
    """Writes a triangle mesh sampling every ``step`` cells as Wavefront OBJ
    (``export::mesh`` then ``save_obj``; z up, metres)."""
    _native.terrain_save("obj", heights, cell_size, os.fspath(path), None, step)


def save_glb(heights: np.ndarray, path: PathLike, *, cell_size: float = 1.0, step: int = 1) -> None:
    """Writes a triangle mesh sampling every ``step`` cells as binary glTF
    (``export::mesh`` then ``save_glb``)."""
    _native.terrain_save("glb", heights, cell_size, os.fspath(path), None, step)
