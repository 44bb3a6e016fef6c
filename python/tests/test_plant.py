"""natura.plant: L-system strings and meshes equal to the Rust API's."""

import pathlib
import struct

import numpy as np
import pytest

from natura import plant
from conftest import REFERENCE, fnv, hash_array

REF = REFERENCE["plant"]
BUSH = (pathlib.Path(__file__).parents[2] / "examples/lsystems/fig1_25.l").read_text()


def test_the_algae_string_of_the_crate_docs():
    text = "axiom: A\nA -> AB\nB -> A"
    assert plant.derive(text, steps=5) == "ABAABABAABAAB"
    assert plant.derive(text, steps=0) == "A"


def test_string_and_mesh_equal_the_rust_api_bit_for_bit():
    s = plant.derive(BUSH, steps=4)
    assert len(s) == REF["string_len"] and fnv(s.encode()) == REF["string_hash"]
    m = plant.mesh(BUSH, steps=4)
    assert m["positions"].dtype == np.float32 and m["positions"].shape == (REF["vertices"], 3)
    assert m["normals"].shape == m["positions"].shape
    assert m["uvs"].shape == (REF["vertices"], 2)
    assert m["indices"].dtype == np.uint32 and m["indices"].shape == (REF["triangles"], 3)
    assert hash_array(m["positions"]) == REF["positions"]
    assert hash_array(m["normals"]) == REF["normals"]
    assert hash_array(m["indices"]) == REF["indices"]
    assert int(m["indices"].max()) < len(m["positions"])
    np.testing.assert_allclose(np.linalg.norm(m["normals"], axis=1), 1.0, atol=1e-4)


def test_mesh_parameters_change_the_mesh_and_are_checked():
    a = plant.mesh(BUSH, steps=3)
    b = plant.mesh(BUSH, steps=3, radial_segments=5)
    assert len(b["positions"]) < len(a["positions"])
    with pytest.raises(ValueError, match="radial_segments"):
        plant.mesh(BUSH, steps=3, radial_segments=0)
    with pytest.raises(ValueError, match="width"):
        plant.mesh(BUSH, steps=3, width=-1.0)
    with pytest.raises(ValueError, match="text"):
        plant.derive("axiom: A\nA -> [B")
    with pytest.raises(TypeError, match="radial_segments"):
        plant.mesh(BUSH, radial_segments=2.5)


def test_glb_file(tmp_path):
    plant.save_glb(BUSH, tmp_path / "bush.glb", steps=3)
    glb = (tmp_path / "bush.glb").read_bytes()
    assert glb[:4] == b"glTF" and struct.unpack("<I", glb[8:12])[0] == len(glb)
    assert [p.name for p in tmp_path.iterdir()] == ["bush.glb"]
