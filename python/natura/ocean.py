"""natura.ocean: Tessendorf's ocean waves (natura-ocean) as numpy arrays.

A periodic patch of ``nx x ny`` samples over ``lx x ly`` metres whose waves
are drawn from a spectrum and evolved in closed form (Tessendorf 2001,
"Simulating Ocean Water", sections 3.3-3.7). At each requested time the patch
gives eight float32 fields of shape ``(ny, nx)`` (rows are ``y``): the
``height``, its slopes ``slope_x`` and ``slope_y``, the choppy horizontal
displacement ``disp_x`` and ``disp_y`` and the derivatives ``jxx``, ``jyy``,
``jxy`` of the displaced positions (the Jacobian is ``jxx*jyy - jxy**2``;
below 0 the surface folds). With ``foam`` the whitecap coverage in [0, 1],
accumulated from the Jacobian over the requested times in order, is added.

>>> from natura import ocean
>>> f = ocean.frame(0.0, nx=32, ny=32, lx=100.0, ly=100.0, seed=7)
>>> f["height"].shape, f["height"].dtype.name
((32, 32), 'float32')

The spectra mirror natura-ocean's: :class:`Phillips` (the notes' eq. 23-24)
and the frequency spectra :class:`PiersonMoskowitz`, :class:`Jonswap` and
:class:`Tma`, spread about the wind (Hasselmann et al. 1980 by default, or
``cos^2s`` with ``spreading_s``) and mapped to wavenumbers with the patch's
dispersion relation. Every keyword mirrors the Rust ``Params`` (same names,
defaults and validation); a bad value raises ``ValueError`` naming it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Dict, Optional, Union

import numpy as np

from natura import _native
from natura._params import Params

#: Gravity natura-ocean uses by default, m/s^2.
G = 9.8


class Spectrum(Params):
    """A wave spectrum with its parameters, for the ``spectrum`` argument."""


class Phillips(Spectrum):
    """The Phillips spectrum (Tessendorf's eqs. 23-24); defaults: the notes' Figs. 6-7.

    ``amplitude`` A, ``wind_speed`` V (m/s), ``wind_direction`` (radians from
    +x toward +y), gravity ``g``, the small-wave suppression length
    ``small_wave_length`` (m, 0 disables), the directional exponent
    ``direction_exponent`` of ``|k.w|^p`` and the factor ``against_wind``
    (in [0, 1]) on waves running against the wind.
    """

    kind = "phillips"

    def __init__(
        self,
        *,
        amplitude: float = 0.0012891550390443521,
        wind_speed: float = 31.0,
        wind_direction: float = 0.0,
        g: float = G,
        small_wave_length: float = 1.0,
        direction_exponent: float = 2.0,
        against_wind: float = 1.0,
    ) -> None:
        super().__init__(
            amplitude=amplitude,
            wind_speed=wind_speed,
            wind_direction=wind_direction,
            g=g,
            small_wave_length=small_wave_length,
            direction_exponent=direction_exponent,
            against_wind=against_wind,
        )


class PiersonMoskowitz(Spectrum):
    """The Pierson-Moskowitz spectrum of a fully developed sea (``wind_speed`` at 19.5 m).

    Spread about ``wind_direction`` by ``spreading``: ``"hasselmann"`` (the
    default), or ``"cos2s"`` with the exponent ``spreading_s`` (giving
    ``spreading_s`` alone means ``"cos2s"``).
    """

    kind = "pierson_moskowitz"

    def __init__(
        self,
        *,
        wind_speed: float = 10.0,
        g: float = G,
        spreading: Optional[str] = None,
        spreading_s: Optional[float] = None,
        wind_direction: float = 0.0,
    ) -> None:
        super().__init__(
            wind_speed=wind_speed,
            g=g,
            spreading=spreading,
            spreading_s=spreading_s,
            wind_direction=wind_direction,
        )


class Jonswap(Spectrum):
    """The JONSWAP spectrum of a fetch-limited sea (``wind_speed`` at 10 m, ``fetch`` in m).

    Peak enhancement ``gamma`` with widths ``sigma_low`` and ``sigma_high``;
    spread about ``wind_direction`` by ``spreading`` as for
    :class:`PiersonMoskowitz`.
    """

    kind = "jonswap"

    def __init__(
        self,
        *,
        wind_speed: float = 10.0,
        fetch: float = 100000.0,
        gamma: float = 3.3,
        sigma_low: float = 0.07,
        sigma_high: float = 0.09,
        g: float = G,
        spreading: Optional[str] = None,
        spreading_s: Optional[float] = None,
        wind_direction: float = 0.0,
    ) -> None:
        super().__init__(
            wind_speed=wind_speed,
            fetch=fetch,
            gamma=gamma,
            sigma_low=sigma_low,
            sigma_high=sigma_high,
            g=g,
            spreading=spreading,
            spreading_s=spreading_s,
            wind_direction=wind_direction,
        )


class Tma(Spectrum):
    """The TMA spectrum: JONSWAP in water of finite ``depth`` (m, required).

    Use it with ``dispersion="finite_depth"`` and the same ``depth`` for the
    patch, as natura-ocean recommends.
    """

    kind = "tma"

    def __init__(
        self,
        *,
        depth: float,
        wind_speed: float = 10.0,
        fetch: float = 100000.0,
        gamma: float = 3.3,
        sigma_low: float = 0.07,
        sigma_high: float = 0.09,
        g: float = G,
        spreading: Optional[str] = None,
        spreading_s: Optional[float] = None,
        wind_direction: float = 0.0,
    ) -> None:
        super().__init__(
            depth=depth,
            wind_speed=wind_speed,
            fetch=fetch,
            gamma=gamma,
            sigma_low=sigma_low,
            sigma_high=sigma_high,
            g=g,
            spreading=spreading,
            spreading_s=spreading_s,
            wind_direction=wind_direction,
        )


class FoamParams(Params):
    """Whitecaps from the Jacobian J: coverage appears where J < ``threshold``,
    full ``range`` below it, and old foam decays with time constant
    ``decay_time`` (s)."""

    kind = "foam"

    def __init__(
        self, *, threshold: float = 0.3, range: float = 0.5, decay_time: float = 3.0
    ) -> None:
        super().__init__(threshold=threshold, range=range, decay_time=decay_time)


SpectrumLike = Union[Spectrum, Dict[str, Any]]


def frames(
    times: Sequence[float],
    *,
    nx: int = 512,
    ny: int = 512,
    lx: float = 1000.0,
    ly: float = 1000.0,
    dispersion: str = "deep",
    g: float = G,
    depth: Optional[float] = None,
    capillary_length: Optional[float] = None,
    loop_period: Optional[float] = None,
    choppiness: float = 0.0,
    amplitudes: str = "complex_gaussian",
    k_min: float = 0.0,
    k_max: float = math.inf,
    spectrum: Optional[SpectrumLike] = None,
    seed: int = 0,
    foam: Union[None, bool, FoamParams, Dict[str, Any]] = None,
) -> Dict[str, np.ndarray]:
    """The ocean patch at each of ``times`` (seconds).

    Returns a dict of float32 arrays of shape ``(len(times), ny, nx)``:
    ``height``, ``slope_x``, ``slope_y``, ``disp_x``, ``disp_y``, ``jxx``,
    ``jyy``, ``jxy``, and ``foam`` when ``foam`` is ``True``, a
    :class:`FoamParams` or a dict of its keys (the coverage after each time,
    accumulated over ``times`` in order, which must then not decrease).

    The patch's keywords are the fields of the Rust ``OceanParams``: ``nx``
    and ``ny`` (powers of two, 16 to 2048), the patch's sides ``lx``, ``ly``
    (m; the surface repeats with them), the dispersion relation
    (``"deep"``, ``"finite_depth"`` with ``depth``, or ``"capillary"`` with
    ``capillary_length``; gravity ``g``), ``loop_period`` (s; the animation
    repeats exactly after it), ``choppiness`` (0 to 100; crests sharpen and
    fold near 1), ``amplitudes`` (``"complex_gaussian"``, the notes' eq.
    25, or ``"gaussian_uniform_phase"``, the slides') and the wavenumber band
    ``k_min <= |k| < k_max`` (rad/m). ``spectrum`` defaults to
    :class:`Phillips`; ``seed`` draws the waves.
    """
    params = {
        "nx": nx,
        "ny": ny,
        "lx": lx,
        "ly": ly,
        "dispersion": dispersion,
        "g": g,
        "depth": depth,
        "capillary_length": capillary_length,
        "loop_period": loop_period,
        "choppiness": choppiness,
        "amplitudes": amplitudes,
        "k_min": k_min,
        "k_max": k_max,
    }
    if spectrum is None:
        spectrum = Phillips()
    spec = spectrum.spec() if isinstance(spectrum, Spectrum) else spectrum
    if foam is True:
        foam = FoamParams()
    elif foam is False:
        foam = None
    foam_spec = foam.params if isinstance(foam, FoamParams) else foam
    ts = [float(t) for t in np.atleast_1d(np.asarray(times, dtype=np.float64))]
    return _native.ocean_frames(params, spec, seed, ts, foam_spec)


def frame(t: float, **kwargs: Any) -> Dict[str, np.ndarray]:
    """The ocean patch at time ``t`` (seconds): :func:`frames` at one time,
    each array of shape ``(ny, nx)``. Takes the keywords of :func:`frames`."""
    return {k: v[0] for k, v in frames([t], **kwargs).items()}


__all__ = [
    "G",
    "Spectrum",
    "Phillips",
    "PiersonMoskowitz",
    "Jonswap",
    "Tma",
    "FoamParams",
    "frames",
    "frame",
]
