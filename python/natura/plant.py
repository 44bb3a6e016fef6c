"""L-systems and ecosystems (natura-plant): parse and derive a system
written in natura's cpfg / L-Py-style language, interpret the string with
the 3-D turtle and mesh it into numpy vertex and index arrays, or write the
mesh as binary glTF; grow an ecosystem of species on a height array and get
its plants as instance arrays (:func:`ecosystem`).

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
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from natura import _native, _progress
from natura._progress import ProgressArg

__all__ = [
    "SPECIES_PRESETS", "derive", "ecosystem", "ecosystem_defaults", "instance_matrices", "mesh",
    "save_glb",
    "species_preset",
]

#: The species presets of natura-plant's ecosystems (``Species::tree``,
#: ``Species::default`` = ``"shrub"``, ``Species::wet_shrub``, ``Species::grass``).
SPECIES_PRESETS: Tuple[str, ...] = ("tree", "shrub", "wet_shrub", "grass")


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


def ecosystem_defaults() -> Dict[str, Any]:
    """The Rust ``EcoParams::default()`` as a dict (its four species as
    dicts of their fields)."""
    return _native.ecosystem_defaults()


def species_preset(name: str) -> Dict[str, Any]:
    """One of :data:`SPECIES_PRESETS` as a dict of the Rust ``Species``
    fields, to change and pass in ``species``."""
    return _native.species_preset(name)


def ecosystem(
    heights: np.ndarray,
    *,
    cell_size: float = 1.0,
    species: Optional[Sequence[Union[str, Dict[str, Any]]]] = None,
    steps: int = 25,
    seed: int = 1998,
    sun: Tuple[float, float, float] = (-1.0, 1.0, 1.5),
    max_plants: int = 20_000_000,
    per_species: int = 3,
    progress: ProgressArg = None,
    wetness: Optional[np.ndarray] = None,
) -> Dict[str, Any]:
    """Grows an ecosystem on the height field ``heights`` (float32 ``(ny,
    nx)``, ``cell_size`` metres apart) and returns its plants as instances
    (Deussen et al. 1998: the Rust ``Ecosystem::new``, ``Ecosystem::run``,
    then ``Instancing::new`` with at most ``per_species`` prototypes per
    species).

    ``wetness`` (float32, the shape of ``heights``, values in ``[0, 1]``)
    is the soil moisture the species' preferences read; by default it is
    :func:`natura.terrain.wetness` of ``heights``. Pass a map cut from a
    larger terrain's wetness when ``heights`` is a piece of it, so the
    plants see the same moisture as everything else that reads it (the
    Rust ``Ecosystem::with_wetness``).

    Keyword parameters are the fields of ``EcoParams`` with its defaults:
    ``species`` (default: tree, shrub, wet shrub, grass) is a list of preset
    names (:data:`SPECIES_PRESETS`) or dicts of ``Species`` fields (fields
    left out take the shrub's values, ``Species::default``), ``steps``,
    ``seed``, ``sun`` (direction towards the sun) and ``max_plants``.

    Returns a dict, one row per living plant: ``positions`` (float32 ``(n,
    3)``, metres, z on the ground), ``species`` (uint16, index into
    ``species_names``), ``prototype`` (uint32, index into ``prototypes``),
    ``scale`` (prototype to plant), ``rotation`` (radians about z),
    ``radius`` (metres), ``vigor`` (float32) and ``age`` (uint32, steps
    lived); ``species_names`` (list of str) and ``prototypes``: a list of
    dicts, each the mesh arrays of :func:`mesh` (default mesh parameters)
    with the prototype's ``species``, ``radius`` and derivation ``steps``.
    A plant is the prototype's mesh scaled by ``scale``, turned by
    ``rotation`` about z and moved to ``positions``. ``progress`` hears one
    unit per simulation step."""
    params: Dict[str, Any] = {
        "steps": steps,
        "seed": seed,
        "sun": [float(c) for c in sun],
        "max_plants": max_plants,
    }
    if species is not None:
        params["species"] = list(species)
    cb = _progress.reporter(progress)
    try:
        return _native.plant_ecosystem(heights, cell_size, params, per_species, cb, wetness)
    finally:
        _progress.closing(cb)


def instance_matrices(eco: Dict[str, Any]) -> np.ndarray:
    """The 4 × 4 transform of each instance of :func:`ecosystem`'s result
    (scale, then rotation about z, then translation), float64 ``(n, 4,
    4)``, column vectors: ``world = M @ [x, y, z, 1]``."""
    s = np.asarray(eco["scale"], dtype=np.float64)
    r = np.asarray(eco["rotation"], dtype=np.float64)
    p = np.asarray(eco["positions"], dtype=np.float64)
    m = np.zeros((len(s), 4, 4))
    c, si = np.cos(r) * s, np.sin(r) * s
    m[:, 0, 0], m[:, 0, 1] = c, -si
    m[:, 1, 0], m[:, 1, 1] = si, c
    m[:, 2, 2] = s
    m[:, :3, 3] = p
    m[:, 3, 3] = 1.0
    return m
