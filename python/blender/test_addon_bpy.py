"""The Blender add-on in Blender itself: headless, through the registry's
``bpy`` package (bpy 4.2 for CPython 3.11), the operator run as a user runs
it. Run with ``pytest python/blender`` in an environment with ``bpy`` and
the ``natura-rs`` wheel installed (not part of python/tests: bpy is a
large download that exists only for one Python version per release)."""

import bpy
import numpy as np
import pytest

from natura import blender_addon


def test_the_operator_adds_the_terrain_and_a_forest_of_linked_duplicates():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender_addon.register()
    try:
        assert bpy.ops.mesh.natura_landscape.poll()
        result = bpy.ops.mesh.natura_landscape(seed=3, size=24, cell_size=2.0, eco_steps=4,
                                               max_plants=50)
        assert result == {"FINISHED"}
        col = bpy.data.collections["natura landscape"]
        terrain = bpy.data.objects["natura terrain"]
        assert terrain.name in col.objects
        assert len(terrain.data.vertices) == 24 * 24
        assert len(terrain.data.polygons) == 23 * 23
        assert all(len(p.vertices) == 4 for p in terrain.data.polygons)
        h, eco = blender_addon.landscape(3, 24, 2.0, 12.0, 4, 50)
        z = np.array([v.co.z for v in terrain.data.vertices], dtype=np.float32)
        np.testing.assert_allclose(z, h.reshape(-1), rtol=0, atol=1e-6)

        protos = bpy.data.collections["natura prototypes"]
        assert protos.hide_render and len(protos.objects) == len(eco["prototypes"])
        plants = [o for o in col.objects if o.name.startswith("natura plant")]
        assert len(plants) == len(eco["scale"]) > 0
        proto_meshes = {o.data.name for o in protos.objects}
        # Linked duplicates: the plants use the prototypes' meshes, not copies.
        assert {p.data.name for p in plants} <= proto_meshes
        assert len(bpy.data.meshes) == 1 + len(proto_meshes)
        for k, p in enumerate(eco["prototypes"]):
            m = protos.objects[k].data
            assert len(m.vertices) == len(p["positions"])
            assert len(m.polygons) == len(p["indices"])
        first = bpy.data.objects["natura plant 0"]
        np.testing.assert_allclose(tuple(first.location), eco["positions"][0], atol=1e-5)
        np.testing.assert_allclose(first.rotation_euler.z, eco["rotation"][0], atol=1e-6)
        np.testing.assert_allclose(tuple(first.scale), [eco["scale"][0]] * 3, rtol=1e-6)

        # The properties are the scene's seed and size, bounded as natura needs.
        props = bpy.ops.mesh.natura_landscape.get_rna_type().properties
        assert props["size"].hard_min == 3 and props["seed"].hard_min == 0
        # Blender clamps a property to its bounds: size=1 builds the smallest terrain.
        assert bpy.ops.mesh.natura_landscape(size=1, forest=False) == {"FINISHED"}
        assert len(bpy.data.objects["natura terrain.001"].data.vertices) == 9
    finally:
        blender_addon.unregister()
    with pytest.raises(AttributeError, match="could not be found"):
        bpy.ops.mesh.natura_landscape.poll()
