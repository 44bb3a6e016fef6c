"""natura: simulate and render nature from Python.

numpy arrays in and out of natura's Rust crates:

* :mod:`natura.noise` -- every basis, fractal, multifractal and distortion of
  natura-noise, at arbitrary points or on regular grids;
* :mod:`natura.terrain` -- terrain synthesis, the erosion models, drainage
  analysis and export to 16-bit PNG, EXR, OBJ and GLB;
* :mod:`natura.plant` -- L-systems: derivation, turtle meshes as numpy
  arrays, binary glTF;
* :mod:`natura.ocean` -- Tessendorf's ocean: height, slope, choppy
  displacement, Jacobian and foam fields at given times.

Every parameter mirrors the Rust ``Params`` structs (same names, defaults and
validation); a bad value raises ``ValueError`` naming the parameter, a wrong
argument type or dtype raises ``TypeError`` naming the argument. Long calls
release the GIL.
"""

from natura import noise, ocean, plant, terrain
from natura._native import __version__

__all__ = ["__version__", "noise", "ocean", "plant", "terrain"]
