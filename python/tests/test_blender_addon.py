"""The Blender add-on's data and object building, against a stand-in for
the few ``bpy`` calls it makes (Blender's own ``bpy`` is tested by
python/blender/test_addon_bpy.py where it installs)."""

import numpy as np
import pytest

from natura import blender_addon, plant


class Links(list):
    def link(self, x):
        self.append(x)


class Mesh:
    def __init__(self, name):
        self.name, self.vertices, self.polygons, self.updated = name, [], [], False

    def from_pydata(self, verts, edges, faces):
        self.vertices, self.polygons = verts, faces

    def update(self):
        self.updated = True


class Object:
    def __init__(self, name, data):
        self.name, self.data = name, data
        self.location, self.rotation_euler, self.scale = (0, 0, 0), (0, 0, 0), (1, 1, 1)


class Collection:
    def __init__(self, name):
        self.name, self.objects, self.children = name, Links(), Links()
        self.hide_render = self.hide_viewport = False


class Factory:
    def __init__(self, cls):
        self.cls, self.made = cls, []

    def new(self, *a):
        x = self.cls(*a)
        self.made.append(x)
        return x


class FakeBpy:
    def __init__(self):
        self.data = type("data", (), {})()
        self.data.meshes = Factory(Mesh)
        self.data.objects = Factory(Object)
        self.data.collections = Factory(Collection)


class Scene:
    def __init__(self):
        self.collection = Collection("Scene Collection")


def test_grid_mesh_counts_positions_and_winding():
    h = np.arange(12, dtype=np.float32).reshape(3, 4)
    v, q = blender_addon.grid_mesh(h, 2.0)
    assert v.shape == (12, 3) and q.shape == (6, 4)
    assert v[5].tolist() == [2.0, 2.0, 5.0]  # sample (i=1, j=1)
    # Counter-clockwise seen from above: positive signed area.
    a, b, c = v[q[0, 0]], v[q[0, 1]], v[q[0, 2]]
    assert np.cross(b - a, c - a)[2] > 0
    assert q.max() == 11 and q.min() == 0
    with pytest.raises(ValueError, match="heights"):
        blender_addon.grid_mesh(np.zeros(5, dtype=np.float32), 1.0)


def test_landscape_objects_against_the_bpy_stand_in():
    bpy, scene = FakeBpy(), Scene()
    terrain, plants = blender_addon.add_landscape(bpy, scene, seed=3, size=24, cell_size=2.0,
                                                  eco_steps=4, max_plants=50)
    (col,) = scene.collection.children
    assert col.name == "natura landscape" and terrain in col.objects
    assert len(terrain.data.vertices) == 24 * 24 and len(terrain.data.polygons) == 23 * 23
    z = np.array(terrain.data.vertices)[:, 2]
    assert 0.0 <= z.min() and z.max() <= 12.0 + 1e-3  # the relief, worn down
    assert 0 < len(plants) <= 50
    (protos,) = col.children
    assert protos.hide_render and protos.hide_viewport
    proto_meshes = [o.data for o in protos.objects]
    # Linked duplicates: every plant uses one of the prototype meshes, not a copy.
    assert all(any(p.data is m for m in proto_meshes) for p in plants)
    assert len(bpy.data.meshes.made) == 1 + len(proto_meshes)
    # The same seed gives the same forest; the plants stand where the ecosystem put them.
    h, eco = blender_addon.landscape(3, 24, 2.0, 12.0, 4, 50)
    assert np.array_equal(np.array(terrain.data.vertices, dtype=np.float32)[:, 2], h.reshape(-1))
    np.testing.assert_array_equal([p.location for p in plants], eco["positions"].astype(float))
    assert [p.rotation_euler[2] for p in plants] == [float(r) for r in eco["rotation"]]


def test_no_forest_and_bad_values():
    bpy, scene = FakeBpy(), Scene()
    terrain, plants = blender_addon.add_landscape(bpy, scene, seed=1, size=8, forest=False)
    assert plants == [] and len(terrain.data.vertices) == 64
    with pytest.raises(ValueError, match="size"):
        blender_addon.landscape(size=2)
    with pytest.raises(ValueError, match="relief_m"):
        blender_addon.landscape(relief_m=0.0)
    assert blender_addon.bl_info["blender"] >= (4, 0, 0)
