"""L-systems (natura-plant): parse and derive a system written in natura's
cpfg / L-Py-style language, interpret the string with the 3-D turtle and
mesh it into numpy vertex and index arrays, or write the mesh as binary glTF.

``text`` is the system's source, e.g.::

    axiom: A
    A -> AB
    B -> A

``steps`` defaults to the source's ``derivation length:`` and ``seed`` to its
``seed:`` (else 1). The turtle's ``angle_deg`` and ``step`` default to the
source's ``angle:`` and ``step:`` (else 90 degrees and 1), ``width`` to 0.1
and ``width_factor`` to 0.7 (the Rust ``TurtleParams::for_lsystem``); the
mesh parameters are those of the Rust ``MeshParams`` (8 radial segments,
caps, 5 leaf rows, single-sided leaves). A syntax error raises
``ValueError`` naming its place in ``text``.
"""

from __future__ import annotations

import os
from typing import Dict, Optional, Union

import numpy as np

from natura import _native

__all__ = ["derive", "mesh", "save_glb"]


def _params(
    angle_deg: Optional[float],
    step: Optional[float],
    width: Optional[float],
    width_factor: Optional[float],
    radial_segments: int,
    caps: bool,
    leaf_rows: int,
    double_sided_leaves: bool,
) -> Dict[str, object]:
    return {
        "angle_deg": angle_deg,
        "step": step,
        "width": width,
        "width_factor": width_factor,
        "radial_segments": radial_segments,
        "caps": caps,
        "leaf_rows": leaf_rows,
        "double_sided_leaves": double_sided_leaves,
    }


def derive(text: str, *, steps: Optional[int] = None, seed: Optional[int] = None) -> str:
    """The string ``text``'s L-system derives in ``steps`` steps, as text
    (the Rust ``Derivation`` then ``ModuleString::display``)."""
    return _native.lsystem_derive(text, steps, seed)


def mesh(
    text: str,
    *,
    steps: Optional[int] = None,
    seed: Optional[int] = None,
    angle_deg: Optional[float] = None,
    step: Optional[float] = None,
    width: Optional[float] = None,
    width_factor: Optional[float] = None,
    radial_segments: int = 8,
    caps: bool = True,
    leaf_rows: int = 5,
    double_sided_leaves: bool = False,
) -> Dict[str, np.ndarray]:
    """The turtle interpretation of the derived string as a triangle mesh
    (``Turtle::interpret`` then ``PlantMesh::from_geometry``; z up): a dict
    of ``positions`` and ``normals`` (float32, ``(n, 3)``), ``uvs``
    (float32, ``(n, 2)``) and ``indices`` (uint32, ``(m, 3)``)."""
    p = _params(angle_deg, step, width, width_factor, radial_segments, caps, leaf_rows,
                double_sided_leaves)
    return _native.lsystem_mesh(text, steps, seed, p)


def save_glb(
    text: str,
    path: Union[str, "os.PathLike[str]"],
    *,
    steps: Optional[int] = None,
    seed: Optional[int] = None,
    angle_deg: Optional[float] = None,
    step: Optional[float] = None,
    width: Optional[float] = None,
    width_factor: Optional[float] = None,
    radial_segments: int = 8,
    caps: bool = True,
    leaf_rows: int = 5,
    double_sided_leaves: bool = False,
) -> None:
    """Writes the mesh of :func:`mesh` as binary glTF with its bark and leaf
    materials (``natura_plant::mesh::save_glb``; a temporary file renamed)."""
    p = _params(angle_deg, step, width, width_factor, radial_segments, caps, leaf_rows,
                double_sided_leaves)
    _native.lsystem_save_glb(text, os.fspath(path), steps, seed, p)
