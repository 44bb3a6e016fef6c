"""A Blender add-on: an eroded natura terrain and a forest grown on it.

Install it in Blender (Edit > Preferences > Add-ons > Install…, choosing
this file, with the ``natura-rs`` package installed into Blender's Python),
or call :func:`register` from a script. It adds *Add > Mesh > natura
Landscape* (operator ``mesh.natura_landscape``), whose properties are the
scene's seed and size:

* the terrain: ``size`` × ``size`` samples ``cell_size`` metres apart, by
  spectral synthesis (:func:`natura.terrain.spectral`) worn by droplet
  erosion and thermal weathering, as one mesh object of ``size²`` vertices
  and ``(size − 1)²`` quads;
* the forest: natura-plant's ecosystem grown on those heights
  (:func:`natura.plant.ecosystem`), each prototype one mesh (the GLB
  prototypes' geometry, kept in a hidden collection) and each plant an
  object sharing its prototype's mesh (a linked duplicate), moved, turned
  and scaled as the instance arrays say.

The functions that build the data (:func:`landscape`, :func:`grid_mesh`)
need no Blender; those that make objects take the ``bpy`` module as an
argument, so they run against Blender's ``bpy`` or any stand-in with the
same calls.
"""

# No `from __future__ import annotations`: Blender reads the operator's
# properties from its class annotations, which must be evaluated.
from typing import Any, Dict, List, Tuple

import numpy as np

bl_info = {
    "name": "natura Landscape",
    "author": "natura contributors",
    "version": (0, 1, 0),
    "blender": (4, 0, 0),
    "location": "View3D > Add > Mesh > natura Landscape",
    "description": "An eroded fractal terrain with a forest grown on it (natura)",
    "category": "Add Mesh",
}


def landscape(
    seed: int = 1,
    size: int = 64,
    cell_size: float = 2.0,
    relief_m: float = 12.0,
    eco_steps: int = 12,
    max_plants: int = 2000,
) -> Tuple[np.ndarray, Dict[str, Any]]:
    """The terrain's heights (float32 ``(size, size)``) and the forest
    (:func:`natura.plant.ecosystem`'s dict, thinned to at most
    ``max_plants`` plants by taking every k-th) for ``seed``.

    Raises ``ValueError`` naming ``size``, ``relief_m`` or ``max_plants``
    when out of range (and natura's own errors for the rest)."""
    from natura import plant, terrain

    if size < 3:
        raise ValueError(f"size = {size} must be at least 3")
    if not relief_m > 0.0:
        raise ValueError(f"relief_m = {relief_m} must be positive")
    if max_plants < 0:
        raise ValueError(f"max_plants = {max_plants} must not be negative")
    h = terrain.spectral((size, size), cell_size=cell_size, seed=seed,
                         sigma_m=1.0, h=0.8)
    span = float(h.max() - h.min())
    h = ((h - h.min()) * np.float32(relief_m / span if span > 0 else 0.0)).astype(np.float32)
    h = terrain.erode_droplet(h, cell_size=cell_size, droplets=size * size, seed=seed)
    h = terrain.erode_thermal(h, cell_size=cell_size, steps=10)
    eco = plant.ecosystem(h, cell_size=cell_size, steps=eco_steps, seed=seed, per_species=2)
    n = len(eco["scale"])
    if n > max_plants:
        keep = np.arange(0, n, -(-n // max_plants)) if max_plants else np.arange(0)
        for key in ("positions", "species", "prototype", "scale", "rotation", "radius",
                    "vigor", "age"):
            eco[key] = eco[key][keep]
    return h, eco


def grid_mesh(heights: np.ndarray, cell_size: float) -> Tuple[np.ndarray, np.ndarray]:
    """The height field as a quad mesh: vertices float32 ``(ny·nx, 3)``
    (sample ``(i, j)`` at ``(i·cell, j·cell, h[j, i])``, z up as in natura
    and Blender) and quads int32 ``((ny − 1)·(nx − 1), 4)``,
    counter-clockwise seen from above."""
    h = np.asarray(heights, dtype=np.float32)
    if h.ndim != 2 or min(h.shape) < 2:
        raise ValueError(f"heights must be 2-D with at least 2 × 2 samples, not {h.shape}")
    ny, nx = h.shape
    jj, ii = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    verts = np.stack([ii * cell_size, jj * cell_size, h], axis=-1).reshape(-1, 3)
    idx = (jj * nx + ii)[:-1, :-1].reshape(-1)
    quads = np.stack([idx, idx + 1, idx + nx + 1, idx + nx], axis=-1).astype(np.int32)
    return verts.astype(np.float32), quads


def _mesh(bpy: Any, name: str, verts: np.ndarray, faces: np.ndarray) -> Any:
    m = bpy.data.meshes.new(name)
    m.from_pydata(verts.tolist(), [], faces.tolist())
    m.update()
    return m


def add_terrain(bpy: Any, collection: Any, heights: np.ndarray, cell_size: float) -> Any:
    """Adds the terrain mesh object to ``collection``; returns it."""
    verts, quads = grid_mesh(heights, cell_size)
    obj = bpy.data.objects.new("natura terrain", _mesh(bpy, "natura terrain", verts, quads))
    collection.objects.link(obj)
    return obj


def add_forest(bpy: Any, collection: Any, eco: Dict[str, Any]) -> List[Any]:
    """Adds the forest: one mesh per prototype (its objects linked to a
    hidden ``natura prototypes`` collection inside ``collection``) and one
    object per plant sharing its prototype's mesh. Returns the plant
    objects."""
    protos = bpy.data.collections.new("natura prototypes")
    collection.children.link(protos)
    protos.hide_render = True
    protos.hide_viewport = True
    meshes = []
    for k, p in enumerate(eco["prototypes"]):
        name = f"natura {eco['species_names'][p['species']]} {k}"
        m = _mesh(bpy, name, p["positions"], p["indices"])
        protos.objects.link(bpy.data.objects.new(name, m))
        meshes.append(m)
    plants = []
    pos, rot, scale, proto = eco["positions"], eco["rotation"], eco["scale"], eco["prototype"]
    for i in range(len(scale)):
        obj = bpy.data.objects.new(f"natura plant {i}", meshes[int(proto[i])])
        obj.location = tuple(float(c) for c in pos[i])
        obj.rotation_euler = (0.0, 0.0, float(rot[i]))
        obj.scale = (float(scale[i]),) * 3
        collection.objects.link(obj)
        plants.append(obj)
    return plants


def add_landscape(bpy: Any, scene: Any, seed: int = 1, size: int = 64, cell_size: float = 2.0,
                  relief_m: float = 12.0, eco_steps: int = 12, max_plants: int = 2000,
                  forest: bool = True) -> Tuple[Any, List[Any]]:
    """Adds a ``natura landscape`` collection to ``scene`` holding the
    terrain and (when ``forest``) the forest of :func:`landscape`; returns
    the terrain object and the plant objects."""
    heights, eco = landscape(seed, size, cell_size, relief_m, eco_steps,
                             max_plants if forest else 0)
    col = bpy.data.collections.new("natura landscape")
    scene.collection.children.link(col)
    terrain = add_terrain(bpy, col, heights, cell_size)
    plants = add_forest(bpy, col, eco) if forest else []
    return terrain, plants


def _classes() -> List[Any]:
    import bpy
    from bpy.props import BoolProperty, FloatProperty, IntProperty

    class NATURA_OT_landscape(bpy.types.Operator):
        """Add an eroded natura terrain with a forest grown on it"""

        bl_idname = "mesh.natura_landscape"
        bl_label = "natura Landscape"
        bl_options = {"REGISTER", "UNDO"}

        seed: IntProperty(name="Seed", default=1, min=0)
        size: IntProperty(name="Size", description="Samples along each side",
                          default=64, min=3, max=1024)
        cell_size: FloatProperty(name="Cell size", description="Metres between samples",
                                 default=2.0, min=0.01)
        relief_m: FloatProperty(name="Relief", description="Height range (m)",
                                default=12.0, min=0.01)
        forest: BoolProperty(name="Forest", default=True)
        eco_steps: IntProperty(name="Forest steps", default=12, min=0, max=200)
        max_plants: IntProperty(name="Most plants", default=2000, min=0)

        def execute(self, context):
            try:
                add_landscape(bpy, context.scene, self.seed, self.size, self.cell_size,
                              self.relief_m, self.eco_steps, self.max_plants, self.forest)
            except ValueError as e:
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            return {"FINISHED"}

    return [NATURA_OT_landscape]


_registered: List[Any] = []


def _menu(self, context):
    self.layout.operator("mesh.natura_landscape", text="natura Landscape")


def register() -> None:
    """Registers the operator and its *Add > Mesh* menu entry (in Blender)."""
    import bpy

    for c in _classes():
        bpy.utils.register_class(c)
        _registered.append(c)
    bpy.types.VIEW3D_MT_mesh_add.append(_menu)


def unregister() -> None:
    """Removes what :func:`register` added."""
    import bpy

    bpy.types.VIEW3D_MT_mesh_add.remove(_menu)
    while _registered:
        bpy.utils.unregister_class(_registered.pop())
