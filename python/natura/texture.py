"""Solid textures and planets (natura-texture) at arrays of points.

A texture is a function of a 3-D point (texture space), filtered to a
footprint (the width a sample covers, in texture units): Musgrave's clouds,
storms, fire, water, rock strata and whole planets. :func:`sample`
evaluates one at the rows of an ``(n, 3)`` array; :func:`equirect` paints
it over a sphere as an equirectangular (longitude × latitude) RGB image.
:func:`planet` maps a whole planet of natura-texture's (Gaea, Venus,
Jupiter, Selene: displaced terrain, biomes, bands) the same way.

Names (:data:`NAMES`): ``puffy_clouds``, ``planet_clouds``, ``cyclone``,
``venus``, ``flame``, ``ripples``, ``windy_wave``, ``strata``, ``terran``,
``luna``, ``ridge``, ``gas_giant``, ``rings``, ``multicolor``, ``git``. Parameters
are the fields of the texture's Rust ``Params`` struct (e.g.
``TerranParams``) as keyword arguments (nested structs as dicts,
enumerations by name); :func:`defaults` lists them with their defaults. An
unknown name or a bad value raises ``ValueError`` naming it.
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, NamedTuple

import numpy as np

from natura import _native, _progress
from natura._progress import ProgressArg

__all__ = [
    "NAMES", "PLANETS", "PlanetMap", "Samples", "colour_ellipsoid", "defaults", "equirect",
    "git_filter", "git_filter_defaults", "planet", "planet_defaults", "sample",
]

#: The planet presets (the Rust ``PlanetParams::gaea``, ``venus``,
#: ``jupiter``, ``selene``).
PLANETS = ("gaea", "venus", "jupiter", "selene")

#: Every texture name.
NAMES: List[str] = list(_native.TEXTURE_NAMES)


class Samples(NamedTuple):
    """The texture's ``Sample`` at each point: linear RGB ``colour``
    (float64 ``(n, 3)``, each channel in [0, 1]), ``opacity`` (density of
    clouds and rings; 1 for opaque surfaces) and ``height`` (displacement
    along the normal, texture units), float64 ``(n,)``."""

    colour: np.ndarray
    opacity: np.ndarray
    height: np.ndarray


def defaults(name: str) -> Dict[str, Any]:
    """The texture's Rust ``Params::default()`` as a dict."""
    return _native.texture_defaults(name)


def colour_ellipsoid(colours: np.ndarray) -> Dict[str, Any]:
    """The colour ellipsoid (the Rust ``ColourEllipsoid::from_colours``:
    mean, principal axes, spreads) of the rows of ``colours`` (float32 or
    float64 ``(n, 3)``, display RGB in [0, 1], at least two), as the dict
    the ``git`` texture's ``ellipsoid`` parameter takes::

        texture.sample("git", points, ellipsoid=texture.colour_ellipsoid(palette))
    """
    return _native.colour_ellipsoid(colours)


def git_filter(image: np.ndarray, *, progress: ProgressArg = None, **params: Any) -> np.ndarray:
    """The picture ``image`` (linear RGB, float32 ``(height, width, 3)``)
    repainted in brush strokes by the GIT filter (the Rust
    ``git::git_filter``; ``params`` are the fields of ``GitFilterParams``,
    :func:`git_filter_defaults`): float32 ``(height·expand, width·expand,
    3)``. ``progress`` hears one unit per row of each of its three
    passes."""
    cb = _progress.reporter(progress)
    try:
        return _native.git_filter(image, params, cb)
    finally:
        _progress.closing(cb)


def git_filter_defaults() -> Dict[str, Any]:
    """The Rust ``GitFilterParams::default()`` as a dict."""
    return _native.git_filter_defaults()


def sample(name: str, points: np.ndarray, *, footprint: float = 1e-3, **params: Any) -> Samples:
    """The texture ``name`` (``SolidTexture::sample``) at each row of
    ``points`` (float32 or float64, ``(n, 3)``), filtered to ``footprint``
    texture units (0: every octave)."""
    return Samples(*_native.texture_sample(name, points, footprint, params))


def equirect(
    name: str,
    width: int,
    height: int,
    *,
    radius: float = 1.0,
    footprint: float = -1.0,
    **params: Any,
) -> np.ndarray:
    """The texture over a sphere of ``radius`` (texture units) centred at
    the origin, as an equirectangular linear-RGB image: float32
    ``(height, width, 3)``, row 0 at latitude +90°, column 0 at longitude
    -180° (pixel centres; z is the pole, longitude counter-clockwise from
    +x). ``footprint`` defaults to the arc one pixel spans at the equator
    (``2π·radius / width``), so the texture is filtered to the image."""
    if width < 1 or height < 1:
        raise ValueError(f"width and height must be at least 1, not {width} x {height}")
    if footprint < 0.0:
        footprint = 2.0 * math.pi * radius / width
    lat = math.pi / 2 - (np.arange(height) + 0.5) * (math.pi / height)
    lon = -math.pi + (np.arange(width) + 0.5) * (2.0 * math.pi / width)
    lat, lon = np.meshgrid(lat, lon, indexing="ij")
    p = np.stack(
        [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1
    ).reshape(-1, 3) * radius
    s = sample(name, p, footprint=footprint, **params)
    return s.colour.reshape(height, width, 3).astype(np.float32)


class PlanetMap(NamedTuple):
    """A planet's surface on an equirectangular map: unlit linear-RGB
    ``colour`` float32 ``(height, width, 3)`` and ``height`` above the
    sea-level sphere (metres) float32 ``(height, width)``."""

    colour: np.ndarray
    height: np.ndarray


def planet_defaults(preset: str = "gaea") -> Dict[str, Any]:
    """The preset's ``PlanetParams`` as a dict (every key; a layer the
    preset lacks, such as Gaea's rings, is absent)."""
    return _native.planet_defaults(preset)


def planet(
    preset: str = "gaea",
    *,
    width: int = 256,
    height: int = 128,
    progress: ProgressArg = None,
    **params: Any,
) -> PlanetMap:
    """The planet ``preset`` (:data:`PLANETS`), with the ``PlanetParams``
    fields of ``params`` laid over it (nested dicts merge key by key:
    ``radius_m=…``, ``light={"sun_direction": …}``), sampled onto a
    ``width × height`` equirectangular map (the Rust ``Planet::equirect``:
    column ``i`` at longitude ``-π + 2π(i + ½)/width``, row ``j`` at
    latitude ``π/2 - π(j + ½)/height``). ``progress`` hears one unit per
    row."""
    cb = _progress.reporter(progress)
    try:
        return PlanetMap(*_native.planet_equirect(preset, width, height, params, cb))
    finally:
        _progress.closing(cb)
