"""natura: simulate and render nature from Python.

numpy arrays in and out of natura's Rust crates:

* :mod:`natura.noise` -- every basis, fractal, multifractal and distortion of
  natura-noise, at arbitrary points or on regular grids;
* :mod:`natura.terrain` -- terrain synthesis, the erosion models, drainage
  analysis and export to 16-bit PNG, EXR, OBJ and GLB;
* :mod:`natura.plant` -- L-systems: derivation, turtle meshes as numpy
  arrays, binary glTF; ecosystems grown on a terrain as instance arrays;
* :mod:`natura.ocean` -- Tessendorf's ocean: height, slope, choppy
  displacement, Jacobian and foam fields at given times;
* :mod:`natura.volume` -- Ebert's clouds, layer clouds, the smoke plume and
  a smoke solver of your own set-up as 3-D density arrays; OpenVDB files;
* :mod:`natura.texture` -- Musgrave's solid textures and planets at points
  and over a sphere;
* :mod:`natura.atmos` -- the physical sky's radiance in given directions;
* :mod:`natura.render` -- a landscape scene (TOML text or a dict) rendered
  to a float image array.

The Blender add-on :mod:`natura.blender_addon` adds an eroded terrain and a
forest to a Blender scene.

Every parameter mirrors the Rust ``Params`` structs (same names, defaults and
validation); a bad value raises ``ValueError`` naming the parameter, a wrong
argument type or dtype raises ``TypeError`` naming the argument. Long calls
release the GIL and report progress to a callback (or a ``tqdm`` bar).
"""

from natura import atmos, noise, ocean, plant, render, terrain, texture, volume
from natura._native import __version__

__all__ = [
    "__version__", "atmos", "noise", "ocean", "plant", "render", "terrain", "texture", "volume",
]
