"""The physical sky (natura-atmos): Rayleigh and Mie scattering with ozone
in a spherical atmosphere, multiple scattering by Hillaire's precomputed
tables, as linear RGB radiance for arrays of view directions.

Parameters are the fields of the Rust ``AtmosphereParams`` as keyword
arguments (nested ``rayleigh``, ``mie``, ``ozone``, ``luts`` as dicts);
:func:`defaults` lists them. An unknown name or a bad value raises
``ValueError`` naming it.
"""

from __future__ import annotations

import math
from typing import Any, Dict

import numpy as np

from natura import _native

__all__ = ["defaults", "sky", "sky_image"]


def defaults() -> Dict[str, Any]:
    """The Rust ``AtmosphereParams::default()`` (Earth's clear sky) as a dict."""
    return _native.atmosphere_defaults()


def sky(
    directions: np.ndarray,
    *,
    sun_elevation_deg: float = 30.0,
    sun_azimuth_deg: float = 0.0,
    altitude_m: float = 300.0,
    **params: Any,
) -> np.ndarray:
    """The sky's radiance seen from ``altitude_m`` metres above sea level in
    each unit direction of ``directions`` (float ``(n, 3)``, z up), with
    the sun at ``sun_elevation_deg`` above the horizon and
    ``sun_azimuth_deg`` counter-clockwise from +x (``Atmosphere::sky_view``
    then ``SkyView::radiance_batch``): linear RGB in W·m⁻²·sr⁻¹·nm⁻¹,
    float32 ``(n, 3)``. A direction that is not unit length (within 1e-3)
    gives black. The GIL is released."""
    return _native.sky_radiance(directions, sun_elevation_deg, sun_azimuth_deg, altitude_m, params)


def sky_image(width: int, height: int, **kwargs: Any) -> np.ndarray:
    """The sky of :func:`sky` over the upper hemisphere as an
    equirectangular image, float32 ``(height, width, 3)``: row 0 at the
    zenith, the last row just above the horizon, column 0 at azimuth -180°
    (pixel centres)."""
    if width < 1 or height < 1:
        raise ValueError(f"width and height must be at least 1, not {width} x {height}")
    el = math.pi / 2 - (np.arange(height) + 0.5) * (math.pi / 2 / height)
    az = -math.pi + (np.arange(width) + 0.5) * (2 * math.pi / width)
    el, az = np.meshgrid(el, az, indexing="ij")
    d = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)
    return sky(d.reshape(-1, 3), **kwargs).reshape(height, width, 3)
