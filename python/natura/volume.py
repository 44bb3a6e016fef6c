"""Clouds and smoke as voxel density arrays, and OpenVDB files
(natura-volume, natura-fluid). Smoke comes as the plume preset
(:func:`smoke_plume`) or from a solver you set up (:class:`SmokeSolver`).

Arrays are float32 of shape ``(nz, ny, nx)`` (voxel ``(x, y, z)`` is
``a[z, y, x]``; z up, metres). A baked volume comes as a :class:`Volume`:
the density array, the world position of its minimum corner and the voxel
edge. Parameters are the fields of the Rust ``Params`` structs as keyword
arguments, same names (nested structs and options as dicts, enumerations by
name in snake case); what is left out keeps the Rust default
(:func:`cloud_defaults`, :func:`layer_defaults`). An unknown name or a
wrong type raises ``ValueError`` naming it, as does a bad value.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from natura import _native, _progress
from natura._progress import ProgressArg

__all__ = [
    "Smoke", "SmokeSolver", "Volume", "cloud", "cloud_defaults", "cloud_primitives",
    "cuboid", "ellipsoid", "layer_clouds", "layer_defaults", "oriented_box", "read_vdb", "render",
    "smoke_plume", "sphere", "write_vdb",
]


class Volume(NamedTuple):
    """A voxel grid: ``density`` float32 ``(nz, ny, nx)``, voxel centres at
    ``origin + (index + 0.5) * cell``."""

    density: np.ndarray
    origin: Tuple[float, float, float]
    cell: float


class Smoke(NamedTuple):
    """A smoke simulation's state: ``density`` and ``temperature`` (kelvin)
    float32 ``(nz, ny, nx)``, cell-centred samples ``cell`` metres apart
    with the box's corner at the origin, after ``steps`` steps of ``dt``
    seconds."""

    density: np.ndarray
    temperature: np.ndarray
    cell: float
    dt: float
    steps: int


def _volume(t: tuple) -> Volume:
    return Volume(t[0], tuple(t[1]), t[2])


def cloud_defaults() -> Dict[str, Any]:
    """The Rust ``CloudParams::default()`` (Ebert's cumulus) as a dict."""
    return _native.volume_defaults("cloud")


def layer_defaults() -> Dict[str, Any]:
    """The Rust ``LayerParams::default()`` as a dict."""
    return _native.volume_defaults("layer")


def cloud_primitives(name: str = "cumulus") -> List[Dict[str, Any]]:
    """The implicit primitives of a named cloud shape (``"cumulus"`` or
    ``"cirrostratus"``) as a list of dicts with the fields of the Rust
    ``ImplicitPrimitive``: ``skeleton`` (``{"point": [x, y, z]}``,
    ``{"segment": {"a": [...], "b": [...]}}`` or ``{"ellipsoid": {...}}``),
    ``radius`` and ``weight``. Edit them and pass them to :func:`cloud` as
    its ``shape``."""
    return _native.cloud_primitives(name)


def cloud(
    shape: Union[str, Sequence[Dict[str, Any]]] = "cumulus",
    *,
    cell: float = 0.25,
    seed: int = 7,
    progress: ProgressArg = None,
    **params: Any,
) -> Volume:
    """Ebert's implicit cloud baked to voxels (``cloud`` then
    ``GridDensity::bake_with_progress``: density at each voxel centre over
    the cloud's bounds).

    ``shape``: ``"cumulus"`` (the nine-sphere cumulus of Ebert's Figure 1,
    about 10 m across), ``"cirrostratus"`` (Figure 4's veil and cirrus), or
    your own list of implicit primitives (see :func:`cloud_primitives`); a
    bad primitive (a radius that is not positive, say) raises
    ``ValueError`` naming the field.
    ``params``: the fields of ``CloudParams`` (``density_scale``,
    ``exponent``, ``blend``, ``displacement``, ``noise_frequency``,
    ``blend_form``, ``frame``, ``jet_stream``, ``mackerel``, ``detail``)."""
    cb = _progress.reporter(progress)
    try:
        if not isinstance(shape, str):
            shape = list(shape)
        return _volume(_native.cloud_density(shape, cell, seed, params, cb))
    finally:
        _progress.closing(cb)


def layer_clouds(
    *,
    cell: float = 200.0,
    seed: int = 1,
    progress: ProgressArg = None,
    **params: Any,
) -> Volume:
    """natura-volume's layer clouds (kilometre scale) baked to voxels over
    the layer's bounds. ``params``: the fields of ``LayerParams``
    (``region_min``, ``region_max``, ``base_m``, ``top_m``, ``coverage``,
    ``cloud_type``, …); the default region is 40 km square, so choose
    ``cell`` (metres) to suit."""
    cb = _progress.reporter(progress)
    try:
        return _volume(_native.layer_density(cell, seed, params, cb))
    finally:
        _progress.closing(cb)


def smoke_plume(
    *,
    cells: int = 48,
    width: float = 1.0,
    epsilon: float = 4.0,
    steps: int = 10,
    progress: ProgressArg = None,
) -> Smoke:
    """natura-fluid's plume (the Rust ``Plume``, the ``smoke3d`` example's
    set-up: warm smoke rising past a fixed sphere in a box ``width`` wide,
    ``cells × cells × 2·cells``, vorticity confinement ``epsilon``) after
    ``steps`` steps of the solver (``Smoke::step``) at the plume's time step.
    ``progress`` hears one unit per step."""
    cb = _progress.reporter(progress)
    try:
        d, t, cell, dt = _native.smoke_plume(cells, width, epsilon, steps, cb)
    finally:
        _progress.closing(cb)
    return Smoke(d, t, cell, dt, steps)


Vec3 = Tuple[float, float, float]


def sphere(centre: Vec3, radius: float) -> Dict[str, Any]:
    """A ball for a smoke source or obstacle (natura-fluid's
    ``Shape::Sphere``), metres."""
    return {"kind": "sphere", "centre": list(centre), "radius": radius}


def cuboid(min: Vec3, max: Vec3) -> Dict[str, Any]:  # noqa: A002 - the Rust field names
    """An axis-aligned box from its ``min`` to its ``max`` corner
    (``Shape::Cuboid``), metres."""
    return {"kind": "cuboid", "min": list(min), "max": list(max)}


def oriented_box(
    centre: Vec3, half: Vec3, rotation: Tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
) -> Dict[str, Any]:
    """A box of half extents ``half`` about ``centre``, turned by the unit
    quaternion ``rotation`` ``(x, y, z, w)`` (``Shape::OrientedBox``)."""
    return {"kind": "oriented_box", "centre": list(centre), "half": list(half),
            "rotation": list(rotation)}


def ellipsoid(
    centre: Vec3, radii: Vec3, rotation: Tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
) -> Dict[str, Any]:
    """An ellipsoid of semi-axes ``radii`` about ``centre``, turned by the
    unit quaternion ``rotation`` ``(x, y, z, w)`` (``Shape::Ellipsoid``),
    metres."""
    return {"kind": "ellipsoid", "centre": list(centre), "radii": list(radii),
            "rotation": list(rotation)}


class SmokeSolver:
    """natura-fluid's smoke solver (the Rust ``Smoke``: Fedkiw, Stam and
    Jensen 2001, buoyancy, vorticity confinement and a pressure projection on
    a staggered grid) on ``dims = (nx, ny, nz)`` cells of edge ``cell``
    metres, the box's corner at the origin, z up; still air at the ambient
    temperature to start with. ``ny = 1`` is a 2-D simulation in the x–z
    plane.

    ``params`` are the fields of the Rust ``SmokeParams`` (``alpha``,
    ``beta``, ``ambient_temperature``, ``epsilon``, ``advection``,
    ``solver``, ``bounds``; :attr:`params` shows them all). Add sources and
    obstacles (shapes from :func:`sphere`, :func:`cuboid`,
    :func:`oriented_box`), then :meth:`step`. A bad value raises
    ``ValueError`` naming it, a wrong array dtype ``TypeError``.

    ``SmokeSolver`` built like :func:`smoke_plume`'s preset steps to the same
    fields bit for bit."""

    def __init__(self, dims: Tuple[int, int, int], cell: float, **params: Any) -> None:
        self._s = _native.SmokeSolver(tuple(dims), cell, params)

    def add_source(
        self,
        shape: Dict[str, Any],
        *,
        density: float,
        temperature: float,
        velocity: Optional[Vec3] = None,
    ) -> None:
        """Places smoke each step (``SmokeSource``): inside ``shape`` the
        density and temperature (K) are raised to at least these, and with
        ``velocity`` (m/s) the free faces inside are set to it (a jet). The
        shape must lie inside the box."""
        src: Dict[str, Any] = {"shape": shape, "density": density, "temperature": temperature}
        if velocity is not None:
            src["velocity"] = list(velocity)
        self._s.add_source(src)

    def add_obstacle(
        self,
        shape: Dict[str, Any],
        *,
        velocity: Vec3 = (0.0, 0.0, 0.0),
        angular_velocity: Vec3 = (0.0, 0.0, 0.0),
        temperature: Optional[float] = None,
    ) -> None:
        """A solid the smoke flows round (``Obstacle``), moving rigidly at
        ``velocity`` (m/s) and turning at ``angular_velocity`` (rad/s) about
        its centre; with ``temperature`` (K) its cells hold that
        temperature. The shape must lie inside the box."""
        ob: Dict[str, Any] = {
            "shape": shape, "velocity": list(velocity), "angular_velocity": list(angular_velocity),
        }
        if temperature is not None:
            ob["temperature"] = temperature
        self._s.add_obstacle(ob)

    def step(
        self,
        dt: float,
        steps: int = 1,
        *,
        force: Optional[Sequence[np.ndarray]] = None,
        progress: ProgressArg = None,
    ) -> Dict[str, Any]:
        """Advances ``steps`` steps of ``dt`` seconds (``Smoke::step``; the
        GIL is released), with the user force ``force`` (three float32
        ``(nz, ny, nx)`` arrays, x, y and z, in m/s² at the cell centres:
        wind, a fan) in each of them. Returns the last step's report:
        ``max_speed`` (m/s; keep ``max_speed * dt / cell`` to a few cells),
        ``max_divergence``, ``kinetic_energy``, ``pressure_iterations`` and
        the pressure solve's ``relative_residual`` and ``converged``.
        ``progress`` hears one unit per step."""
        cb = _progress.reporter(progress)
        try:
            return self._s.step(dt, steps, None if force is None else list(force), cb)
        finally:
            _progress.closing(cb)

    @property
    def density(self) -> np.ndarray:
        """The smoke density, float32 ``(nz, ny, nx)`` (a copy)."""
        return self._s.density

    @property
    def temperature(self) -> np.ndarray:
        """The temperature (K), float32 ``(nz, ny, nx)`` (a copy)."""
        return self._s.temperature

    def set_density(self, a: np.ndarray) -> None:
        """Replaces the density by float32 ``(nz, ny, nx)`` values, finite
        and non-negative."""
        self._s.set_density(a)

    def set_temperature(self, a: np.ndarray) -> None:
        """Replaces the temperature by float32 ``(nz, ny, nx)`` values,
        finite and positive (K)."""
        self._s.set_temperature(a)

    @property
    def velocity(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The staggered velocity (m/s): float32 arrays on the x, y and z
        faces, ``(nz, ny, nx + 1)``, ``(nz, ny + 1, nx)``, ``(nz + 1, ny, nx)``."""
        u, v, w = self._s.velocity
        return u, v, w

    @property
    def solid(self) -> np.ndarray:
        """The cells obstacles occupy, bool ``(nz, ny, nx)``."""
        return self._s.solid

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._s.time

    @property
    def dims(self) -> Tuple[int, int, int]:
        """``(nx, ny, nz)``."""
        return self._s.dims

    @property
    def cell(self) -> float:
        """The cell edge (m)."""
        return self._s.cell

    @property
    def params(self) -> Dict[str, Any]:
        """The solver's ``SmokeParams`` as a dict."""
        return self._s.params

    def volume(self) -> Volume:
        """The density as a :class:`Volume` (corner at the origin), for
        :func:`render` and :func:`write_vdb`."""
        return Volume(self.density, (0.0, 0.0, 0.0), self.cell)


def write_vdb(
    path: Union[str, "os.PathLike[str]"],
    grids: Union[np.ndarray, Dict[str, np.ndarray], Volume],
    *,
    origin: Tuple[float, float, float] = (0.0, 0.0, 0.0),
    cell: float = 1.0,
) -> None:
    """Writes float grids to an OpenVDB file (natura-volume's ``write_vdb``;
    a temporary file renamed). ``grids``: one float32 ``(nz, ny, nx)``
    array (named ``density``), a dict name → array, or a :class:`Volume`
    (its origin and cell used). Voxels must be finite and non-negative."""
    if isinstance(grids, Volume):
        grids, origin, cell = {"density": grids.density}, grids.origin, grids.cell
    elif isinstance(grids, np.ndarray):
        grids = {"density": grids}
    _native.vdb_write(os.fspath(path), grids, tuple(origin), cell)


def read_vdb(path: Union[str, "os.PathLike[str]"]) -> Dict[str, Volume]:
    """The float grids of an OpenVDB file as written by :func:`write_vdb`
    (natura-volume's ``read_vdb``), name → :class:`Volume` over the bounding
    box of the grid's active voxels."""
    return {k: _volume(v) for k, v in _native.vdb_read(os.fspath(path)).items()}


def render(
    volume: Volume,
    *,
    eye: Tuple[float, float, float],
    target: Tuple[float, float, float],
    fov_deg: float = 40.0,
    width: int = 256,
    height: int = 256,
    sun_direction: Optional[Tuple[float, float, float]] = (0.4, -0.6, 0.7),
    sun_irradiance: Tuple[float, float, float] = (3.0, 3.0, 3.0),
    sky: Tuple[float, float, float] = (0.25, 0.35, 0.55),
    medium: Optional[Dict[str, Any]] = None,
    mode: str = "fast",
    settings: Optional[Dict[str, Any]] = None,
    supersample: int = 1,
    progress: ProgressArg = None,
) -> np.ndarray:
    """Renders a voxel density (a :class:`Volume`: one of this module's
    clouds or smoke, a grid read from OpenVDB, or your own array) lit by a
    sun and a uniform sky, seen from ``eye`` looking at ``target`` (z up,
    metres; ``fov_deg`` the vertical field of view). Returns linear
    radiance as float32 ``(height, width, 3)``.

    ``medium``: the fields of the Rust ``MediumParams`` (``extinction`` in
    1/m per unit density, ``albedo``, ``phase``: for example
    ``{"henyey_greenstein": 0.6}`` or ``{"cloud": {"diameter_um": 10.0}}``).
    ``mode``: ``"fast"`` (natura-volume's ``FastRenderer``: shadow tables
    and the multiple-scattering cache; ``settings`` are ``FastSettings``
    fields over steps of half a voxel, a table node per voxel along the
    longest axis up to 256, and a cache cell per voxel along it from 16 to
    64 with 16 events a cell from one to four million) or ``"reference"`` (the
    null-scattering path tracer, the fast mode's oracle; ``settings`` are
    ``ReferenceSettings`` fields, ``samples_per_pixel`` and ``seed``).
    ``supersample`` (fast mode, 1 to 8): that many rays a pixel side,
    resolved by the camera's pixel filter (the Rust
    ``FastRenderer::render_supersampled``), which smooths the edges of thin
    wisps; 1 is one ray through each pixel's centre.
    ``sun_direction=None`` leaves the sky alone. A bad value raises
    ``ValueError`` naming it."""
    sun = None
    if sun_direction is not None:
        sun = (tuple(map(float, sun_direction)), tuple(map(float, sun_irradiance)))
    cb = _progress.reporter(progress)
    try:
        return _native.volume_render(
            volume.density, tuple(volume.origin), float(volume.cell),
            tuple(map(float, eye)), tuple(map(float, target)), float(fov_deg),
            int(width), int(height), sun, tuple(map(float, sky)),
            medium or {}, mode, settings or {}, cb, int(supersample),
        )
    finally:
        _progress.closing(cb)
