"""The noise bases of natura.noise, their parameter objects and the shared helpers."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Dict, Optional, Union

import numpy as np

from natura import _native
from natura._params import Params


class Basis(Params):
    """A basis with its parameters, for a fractal's ``basis`` argument."""


class Perlin(Basis):
    """Perlin gradient noise (quintic fade by default), values in [-1, 1]."""

    kind = "perlin"

    def __init__(self, *, seed: int = 0, fade: str = "quintic") -> None:
        super().__init__(seed=seed, fade=fade)


class Value(Basis):
    """Value noise (multilinear by default; 'cubic' or 'quintic' interpolation)."""

    kind = "value"

    def __init__(self, *, seed: int = 0, interp: str = "linear") -> None:
        super().__init__(seed=seed, interp=interp)


class Simplex(Basis):
    """Simplex noise."""

    kind = "simplex"

    def __init__(self, *, seed: int = 0) -> None:
        super().__init__(seed=seed)


class Worley(Basis):
    """Worley (cellular) noise: the distance `feature` (f1..f4, f2_minus_f1, ...) under `metric`.

    `feature_points` (the Rust ``WorleyParams::points``; ``points`` names
    the coordinates here) chooses the feature points: ``"one_per_cell"`` (the default,
    jittered by `jitter`) or one of MojoWorld's seed tables, ``"poisson"``
    (a Poisson count of mean `density` per cell), ``"variable"`` (that mean
    varying in space) or ``"gaussian"`` (clustered); `density` in [0.5, 16]
    is used by the tables only.
    """

    kind = "worley"

    def __init__(
        self,
        *,
        seed: int = 0,
        feature: str = "f1",
        metric: str = "euclidean",
        jitter: float = 1.0,
        feature_points: str = "one_per_cell",
        density: float = 4.0,
    ) -> None:
        super().__init__(
            seed=seed,
            feature=feature,
            metric=metric,
            jitter=jitter,
            feature_points=feature_points,
            density=density,
        )


class SparseConvolution(Basis):
    """Sparse convolution noise: `density` impulses per cell convolved with `kernel`."""

    kind = "sparse_convolution"

    def __init__(self, *, seed: int = 0, density: int = 4, kernel: str = "cone") -> None:
        super().__init__(seed=seed, density=density, kernel=kernel)


class Sine(Basis):
    """Musgrave's sine basis: the product of sines along each axis."""

    kind = "sine"

    def __init__(self) -> None:
        super().__init__()


class Steps(Basis):
    """Musgrave's steps basis: a random constant per lattice cell."""

    kind = "steps"

    def __init__(self, *, seed: int = 0) -> None:
        super().__init__(seed=seed)


class Checkerboard(Basis):
    """Musgrave's checkerboard basis: +1/-1 alternating over unit cells."""

    kind = "checkerboard"

    def __init__(self) -> None:
        super().__init__()


BasisLike = Union[str, Basis]
Floats = Sequence[float]


def _basis(basis: BasisLike, seed: int) -> Dict[str, Any]:
    # A name first: the common case, and the cheaper test.
    if isinstance(basis, str):
        return (
            {"kind": basis, "seed": seed}
            if basis not in ("sine", "checkerboard")
            else {"kind": basis}
        )
    if isinstance(basis, Basis):
        return basis.spec()
    raise TypeError(
        f"basis must be a basis name or a natura.noise.Basis, not {type(basis).__name__}"
    )


def _grid(
    spec: Dict[str, Any], shape: Sequence[int], origin: Optional[Floats], step: Optional[Floats]
) -> np.ndarray:
    dim = len(shape)
    return _native.noise_grid(
        spec,
        list(shape),
        [0.0] * dim if origin is None else list(origin),
        [1.0] * dim if step is None else list(step),
    )


def perlin(points: np.ndarray, *, seed: int = 0, fade: str = "quintic") -> np.ndarray:
    """Perlin gradient noise (quintic fade by default), values in [-1, 1].

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``, ``fade``: as the Rust ``Perlin`` and its ``Params``.
    """
    return _native.noise_points({"kind": "perlin", "seed": seed, "fade": fade}, points)


def perlin_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
    fade: str = "quintic",
) -> np.ndarray:
    """Perlin gradient noise (quintic fade by default), values in [-1, 1].

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``, ``fade``: as the Rust ``Perlin`` and its ``Params``.
    """
    return _grid({"kind": "perlin", "seed": seed, "fade": fade}, shape, origin, step)


def value(points: np.ndarray, *, seed: int = 0, interp: str = "linear") -> np.ndarray:
    """Value noise (multilinear by default; 'cubic' or 'quintic' interpolation).

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``, ``interp``: as the Rust ``Value`` and its ``Params``.
    """
    return _native.noise_points({"kind": "value", "seed": seed, "interp": interp}, points)


def value_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
    interp: str = "linear",
) -> np.ndarray:
    """Value noise (multilinear by default; 'cubic' or 'quintic' interpolation).

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``, ``interp``: as the Rust ``Value`` and its ``Params``.
    """
    return _grid({"kind": "value", "seed": seed, "interp": interp}, shape, origin, step)


def simplex(points: np.ndarray, *, seed: int = 0) -> np.ndarray:
    """Simplex noise.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``: as the Rust ``Simplex`` and its ``Params``.
    """
    return _native.noise_points({"kind": "simplex", "seed": seed}, points)


def simplex_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
) -> np.ndarray:
    """Simplex noise.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``: as the Rust ``Simplex`` and its ``Params``.
    """
    return _grid({"kind": "simplex", "seed": seed}, shape, origin, step)


def worley(
    points: np.ndarray,
    *,
    seed: int = 0,
    feature: str = "f1",
    metric: str = "euclidean",
    jitter: float = 1.0,
    feature_points: str = "one_per_cell",
    density: float = 4.0,
) -> np.ndarray:
    """Worley (cellular) noise: the distance `feature` (f1..f4, f2_minus_f1, ...) under `metric`.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``, ``feature``, ``metric``, ``jitter``: as the Rust ``Worley`` and its ``Params``;
    ``feature_points`` and ``density``: its ``points`` (see :class:`Worley`).
    """
    return _native.noise_points(
        {
            "kind": "worley",
            "seed": seed,
            "feature": feature,
            "metric": metric,
            "jitter": jitter,
            "feature_points": feature_points,
            "density": density,
        },
        points,
    )


def worley_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
    feature: str = "f1",
    metric: str = "euclidean",
    jitter: float = 1.0,
    feature_points: str = "one_per_cell",
    density: float = 4.0,
) -> np.ndarray:
    """Worley (cellular) noise: the distance `feature` (f1..f4, f2_minus_f1, ...) under `metric`.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``, ``feature``, ``metric``, ``jitter``:
    as the Rust ``Worley`` and its ``Params``; ``feature_points`` and ``density``: its ``points``
    (see :class:`Worley`).
    """
    return _grid(
        {
            "kind": "worley",
            "seed": seed,
            "feature": feature,
            "metric": metric,
            "jitter": jitter,
            "feature_points": feature_points,
            "density": density,
        },
        shape,
        origin,
        step,
    )


def sparse_convolution(
    points: np.ndarray, *, seed: int = 0, density: int = 4, kernel: str = "cone"
) -> np.ndarray:
    """Sparse convolution noise: `density` impulses per cell convolved with `kernel`.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``, ``density``, ``kernel``: as the Rust ``SparseConvolution`` and its ``Params``.
    """
    return _native.noise_points(
        {"kind": "sparse_convolution", "seed": seed, "density": density, "kernel": kernel}, points
    )


def sparse_convolution_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
    density: int = 4,
    kernel: str = "cone",
) -> np.ndarray:
    """Sparse convolution noise: `density` impulses per cell convolved with `kernel`.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``, ``density``, ``kernel``: as the Rust ``SparseConvolution`` and its ``Params``.
    """
    return _grid(
        {"kind": "sparse_convolution", "seed": seed, "density": density, "kernel": kernel},
        shape,
        origin,
        step,
    )


def sine(points: np.ndarray) -> np.ndarray:
    """Musgrave's sine basis: the product of sines along each axis.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    No parameters (the Rust ``Sine``).
    """
    return _native.noise_points({"kind": "sine"}, points)


def sine_grid(
    shape: Sequence[int], *, origin: Optional[Floats] = None, step: Optional[Floats] = None
) -> np.ndarray:
    """Musgrave's sine basis: the product of sines along each axis.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. No parameters (the Rust ``Sine``).
    """
    return _grid({"kind": "sine"}, shape, origin, step)


def steps(points: np.ndarray, *, seed: int = 0) -> np.ndarray:
    """Musgrave's steps basis: a random constant per lattice cell.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    Parameters ``seed``: as the Rust ``Steps`` and its ``Params``.
    """
    return _native.noise_points({"kind": "steps", "seed": seed}, points)


def steps_grid(
    shape: Sequence[int],
    *,
    origin: Optional[Floats] = None,
    step: Optional[Floats] = None,
    seed: int = 0,
) -> np.ndarray:
    """Musgrave's steps basis: a random constant per lattice cell.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. Parameters ``seed``: as the Rust ``Steps`` and its ``Params``.
    """
    return _grid({"kind": "steps", "seed": seed}, shape, origin, step)


def checkerboard(points: np.ndarray) -> np.ndarray:
    """Musgrave's checkerboard basis: +1/-1 alternating over unit cells.

    Evaluated at ``points`` (float32/float64, shape ``(..., 2)`` or
    ``(..., 3)``); returns float32 of shape ``points.shape[:-1]``.
    No parameters (the Rust ``Checkerboard``).
    """
    return _native.noise_points({"kind": "checkerboard"}, points)


def checkerboard_grid(
    shape: Sequence[int], *, origin: Optional[Floats] = None, step: Optional[Floats] = None
) -> np.ndarray:
    """Musgrave's checkerboard basis: +1/-1 alternating over unit cells.

    On the lattice ``origin + index * step`` (``shape`` ``(ny, nx)`` or
    ``(nz, ny, nx)``; ``origin`` defaults to zeros, ``step`` to ones);
    returns float32 of shape ``shape``. No parameters (the Rust ``Checkerboard``).
    """
    return _grid({"kind": "checkerboard"}, shape, origin, step)
