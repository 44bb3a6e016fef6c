"""Noise bases, fractals, multifractals and distortions (natura-noise).

Every noise ``NAME`` has two functions:

* ``NAME(points, **params)`` evaluates it at each point of ``points``, a numpy
  array of float32 or float64 with shape ``(..., 2)`` or ``(..., 3)`` (any
  layout; 2-D or 3-D noise by the last axis), and returns float32 values of
  shape ``points.shape[:-1]``. 3-D points of a plain Perlin basis take the
  SIMD batch path ``Perlin::fill_points3``; other points are evaluated one by
  one (``Field::eval2``/``eval3``).
* ``NAME_grid(shape, origin=..., step=..., **params)`` fills the regular
  lattice ``origin + index * step`` through the SIMD row kernels
  (``Field::fill_grid2``/``fill_grid3``): ``shape`` is ``(ny, nx)`` or
  ``(nz, ny, nx)``, ``origin`` and ``step`` are ``(x, y)`` or ``(x, y, z)``;
  the result is float32 of that shape, ``out[j, i]`` at
  ``origin + (i * step[0], j * step[1])``.

The keyword parameters are those of the Rust ``Params`` structs (the
``Spectral`` fields ``h``, ``lacunarity``, ``octaves``, ``frequency``,
``convention`` and each fractal's own), with the same defaults and
validation: a bad value raises ``ValueError`` naming the parameter. A
fractal's ``basis`` is the name of a basis (seeded by ``seed``) or a basis
object such as ``Perlin(seed=7, fade="cubic")``.
"""

from natura._noise_bases import *
from natura._noise_bases import Basis
from natura._noise_fractals import *

__all__ = [
    "Basis",
    "Checkerboard",
    "Perlin",
    "Simplex",
    "Sine",
    "SparseConvolution",
    "Steps",
    "Value",
    "Worley",
    "checkerboard",
    "checkerboard_grid",
    "dist_noise",
    "dist_noise_grid",
    "fbm",
    "fbm_grid",
    "filtered_fbm",
    "filtered_fbm_grid",
    "hetero_terrain",
    "hetero_terrain_grid",
    "hybrid_multifractal",
    "hybrid_multifractal_grid",
    "multifractal",
    "multifractal_grid",
    "perlin",
    "perlin_grid",
    "ridged_multifractal",
    "ridged_multifractal_grid",
    "simplex",
    "simplex_grid",
    "sine",
    "sine_grid",
    "sparse_convolution",
    "sparse_convolution_grid",
    "stats_by_altitude",
    "stats_by_altitude_grid",
    "steps",
    "steps_grid",
    "turbulence",
    "turbulence_grid",
    "value",
    "value_grid",
    "vl_noise",
    "vl_noise_grid",
    "worley",
    "worley_grid",
]
