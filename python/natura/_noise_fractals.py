"""The fractals, multifractals and distortions of natura.noise."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Optional

import numpy as np

from natura import _native
from natura._noise_bases import BasisLike, Floats, _basis, _grid


def fbm(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
) -> np.ndarray:
    """Fractional Brownian motion: the octave sum of the basis.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``: as the Rust ``Fbm`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "fbm",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
        },
        points,
    )


def fbm_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
) -> np.ndarray:
    """Fractional Brownian motion: the octave sum of the basis.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``: as the Rust ``Fbm`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "fbm",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
        },
        shape,
        origin,
        step,
    )


def turbulence(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
) -> np.ndarray:
    """Turbulence: the octave sum of |basis|.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``: as the Rust ``Turbulence`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "turbulence",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
        },
        points,
    )


def turbulence_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
) -> np.ndarray:
    """Turbulence: the octave sum of |basis|.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``: as the Rust ``Turbulence`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "turbulence",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
        },
        shape,
        origin,
        step,
    )


def multifractal(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.25,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    form: str = "weighted",
) -> np.ndarray:
    """Multiplicative-cascade multifractal.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``form``: as the Rust ``Multifractal`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "form": form,
        },
        points,
    )


def multifractal_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.25,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    form: str = "weighted",
) -> np.ndarray:
    """Multiplicative-cascade multifractal.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``form``: as the Rust ``Multifractal`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "form": form,
        },
        shape,
        origin,
        step,
    )


def hetero_terrain(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.8,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    threshold: float = 0.5,
) -> np.ndarray:
    """Musgrave's heterogeneous terrain: each octave weighted by the value so far.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``threshold``: as the Rust ``HeteroTerrain`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "hetero_terrain",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "threshold": threshold,
        },
        points,
    )


def hetero_terrain_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.8,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    threshold: float = 0.5,
) -> np.ndarray:
    """Musgrave's heterogeneous terrain: each octave weighted by the value so far.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``threshold``: as the Rust ``HeteroTerrain`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "hetero_terrain",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "threshold": threshold,
        },
        shape,
        origin,
        step,
    )


def hybrid_multifractal(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.25,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 0.7,
) -> np.ndarray:
    """Musgrave's hybrid multifractal: smooth valleys, rough peaks.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``: as the Rust ``HybridMultifractal`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "hybrid_multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
        },
        points,
    )


def hybrid_multifractal_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.25,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 0.7,
) -> np.ndarray:
    """Musgrave's hybrid multifractal: smooth valleys, rough peaks.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``: as the Rust ``HybridMultifractal`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "hybrid_multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
        },
        shape,
        origin,
        step,
    )


def ridged_multifractal(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 1.0,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    gain: float = 2.0,
) -> np.ndarray:
    """Musgrave's ridged multifractal: sharp ridges, (offset - |N|)^2 per octave.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``gain``: as the Rust ``RidgedMultifractal`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "ridged_multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "gain": gain,
        },
        points,
    )


def ridged_multifractal_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 1.0,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    offset: float = 1.0,
    gain: float = 2.0,
) -> np.ndarray:
    """Musgrave's ridged multifractal: sharp ridges, (offset - |N|)^2 per octave.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``offset``, ``gain``: as the Rust ``RidgedMultifractal`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "ridged_multifractal",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "offset": offset,
            "gain": gain,
        },
        shape,
        origin,
        step,
    )


def stats_by_altitude(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.8,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    shift: float = 0.7,
    scale: float = 1.0,
    sea_level: float = 0.0,
) -> np.ndarray:
    """Fractal statistics by altitude: octave power proportional to altitude.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``shift``, ``scale``, ``sea_level``: as the Rust ``StatsByAltitude`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "stats_by_altitude",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "shift": shift,
            "scale": scale,
            "sea_level": sea_level,
        },
        points,
    )


def stats_by_altitude_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.8,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    shift: float = 0.7,
    scale: float = 1.0,
    sea_level: float = 0.0,
) -> np.ndarray:
    """Fractal statistics by altitude: octave power proportional to altitude.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``shift``, ``scale``, ``sea_level``: as the Rust ``StatsByAltitude`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "stats_by_altitude",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "shift": shift,
            "scale": scale,
            "sea_level": sea_level,
        },
        shape,
        origin,
        step,
    )


def filtered_fbm(
    points: np.ndarray,
    *,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    width: float = 0.0,
) -> np.ndarray:
    """fBm with its octaves faded out above the filter `width` (world units; 0 is plain fBm).

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``width``: as the Rust ``FilteredFbm`` and its ``Params``.
    """
    return _native.noise_points(
        {
            "kind": "filtered_fbm",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "width": width,
        },
        points,
    )


def filtered_fbm_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    h: float = 0.5,
    lacunarity: float = 2.218281828459045,
    octaves: float = 8.0,
    frequency: float = 1.0,
    convention: str = "h",
    width: float = 0.0,
) -> np.ndarray:
    """fBm with its octaves faded out above the filter `width` (world units; 0 is plain fBm).

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``h``, ``lacunarity``, ``octaves``, ``frequency``, ``convention``, ``width``: as the Rust ``FilteredFbm`` and its ``Params``.
    """
    return _grid(
        {
            "kind": "filtered_fbm",
            "basis": _basis(basis, seed),
            "h": h,
            "lacunarity": lacunarity,
            "octaves": octaves,
            "frequency": frequency,
            "convention": convention,
            "width": width,
        },
        shape,
        origin,
        step,
    )


def dist_noise(
    points: np.ndarray, *, basis: BasisLike = "perlin", seed: int = 0, distortion: float = 1.0
) -> np.ndarray:
    """Musgrave's DistNoise: the basis at the point displaced by `distortion` times VecNoise.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``distortion``: as the Rust ``DistNoise::dist_noise`` and its ``Params``.
    """
    return _native.noise_points(
        {"kind": "dist_noise", "basis": _basis(basis, seed), "distortion": distortion}, points
    )


def dist_noise_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    distortion: float = 1.0,
) -> np.ndarray:
    """Musgrave's DistNoise: the basis at the point displaced by `distortion` times VecNoise.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``distortion``: as the Rust ``DistNoise::dist_noise`` and its ``Params``.
    """
    return _grid(
        {"kind": "dist_noise", "basis": _basis(basis, seed), "distortion": distortion},
        shape,
        origin,
        step,
    )


def vl_noise(
    points: np.ndarray, *, basis: BasisLike = "perlin", seed: int = 0, scale: float = 1.0
) -> np.ndarray:
    """Musgrave's VLNoise: the basis at `scale`*p displaced by its own gradient noise (perlin basis only).

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``basis``, ``seed``, ``scale``: as the Rust ``VlNoise::vl_noise`` and its ``Params``.
    """
    return _native.noise_points(
        {"kind": "vl_noise", "basis": _basis(basis, seed), "scale": scale}, points
    )


def vl_noise_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    basis: BasisLike = "perlin",
    seed: int = 0,
    scale: float = 1.0,
) -> np.ndarray:
    """Musgrave's VLNoise: the basis at `scale`*p displaced by its own gradient noise (perlin basis only).

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``basis``, ``seed``, ``scale``: as the Rust ``VlNoise::vl_noise`` and its ``Params``.
    """
    return _grid(
        {"kind": "vl_noise", "basis": _basis(basis, seed), "scale": scale}, shape, origin, step
    )
