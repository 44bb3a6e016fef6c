"""natura.plant.ecosystem: instance arrays equal to the Rust API's."""

import numpy as np
import pytest

from natura import plant
from conftest import REFERENCE, hash_array

REF = REFERENCE["eco"]


def slope():
    """The heights of the Rust reference: (i + j)·0.2 in float32, 33 × 33."""
    i = np.arange(33, dtype=np.float32)
    return (i[None, :] + i[:, None]) * np.float32(0.2)


def test_instances_equal_the_rust_api_bit_for_bit():
    e = plant.ecosystem(slope(), cell_size=2.0, steps=4, per_species=2)
    n = REF["plants"]
    assert e["positions"].shape == (n, 3) and e["positions"].dtype == np.float32
    assert hash_array(e["positions"]) == REF["positions"]
    assert hash_array(e["scale"]) == REF["scale"]
    assert hash_array(e["rotation"]) == REF["rotation"]
    assert e["species"].dtype == np.uint16 and hash_array(e["species"]) == REF["species"]
    assert e["prototype"].dtype == np.uint32 and hash_array(e["prototype"]) == REF["prototype"]
    assert len(e["prototypes"]) == REF["prototypes"]
    assert e["species_names"] == ["tree", "shrub", "wet_shrub", "grass"]
    for k in ("radius", "vigor", "age"):
        assert e[k].shape == (n,)
    assert e["age"].max() <= 4
    assert int(e["prototype"].max()) < len(e["prototypes"])
    # Each plant stands on the ground: z is the terrain's height there
    # (bilinear between samples; the slope is a plane, so exactly the plane).
    x, y, z = e["positions"].T
    np.testing.assert_allclose(z, (x + y) / 2.0 * 0.2, rtol=1e-4, atol=1e-4)


def test_prototypes_are_meshes_of_their_species():
    e = plant.ecosystem(slope(), cell_size=2.0, steps=2, per_species=1)
    for p in e["prototypes"]:
        assert p["positions"].shape[1] == 3 and p["indices"].max() < len(p["positions"])
        assert 0 <= p["species"] < 4 and p["radius"] > 0.0
    m = plant.instance_matrices(e)
    assert m.shape == (len(e["scale"]), 4, 4)
    np.testing.assert_allclose(m[:, :3, 3], e["positions"], rtol=0, atol=0)
    np.testing.assert_allclose(np.linalg.det(m[:, :3, :3]), e["scale"].astype(np.float64) ** 3,
                               rtol=1e-9)


def test_species_presets_dicts_and_defaults():
    d = plant.ecosystem_defaults()
    assert d["steps"] == 25 and d["seed"] == 1998 and len(d["species"]) == 4
    assert d["species"][0] == plant.species_preset("tree")
    tree = plant.species_preset("tree")
    only = plant.ecosystem(slope(), cell_size=2.0, steps=2, species=[tree])
    assert only["species_names"] == ["tree"] and set(only["species"]) <= {0}
    named = plant.ecosystem(slope(), cell_size=2.0, steps=2, species=["tree"])
    assert np.array_equal(only["positions"], named["positions"])
    custom = plant.ecosystem(slope(), cell_size=2.0, steps=2,
                             species=[{"name": "moss", "max_radius": 0.5, "r0_max": 0.2}])
    assert custom["species_names"] == ["moss"]


def test_bad_parameters_are_named():
    with pytest.raises(ValueError, match="species\\[0\\]"):
        plant.ecosystem(slope(), species=["oak"])
    with pytest.raises(ValueError, match="max_radiu"):
        plant.ecosystem(slope(), species=[{"max_radiu": 3.0}])
    with pytest.raises(ValueError, match="growth"):
        plant.ecosystem(slope(), species=[{"growth": -1.0}])
    with pytest.raises(ValueError, match="sun"):
        plant.ecosystem(slope(), sun=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="per_species"):
        plant.ecosystem(slope(), steps=1, per_species=0)
    with pytest.raises(TypeError, match="heights"):
        plant.ecosystem(slope().astype(np.float64))
    calls = []
    plant.ecosystem(slope(), cell_size=2.0, steps=3, progress=lambda *a: calls.append(a))
    assert calls[0][1] == 0 and calls[-1][1] == calls[-1][2] == 3


def test_nan_and_zero_size_heights_are_refused():
    h = slope()
    h[2, 2] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        plant.ecosystem(h)
    with pytest.raises(ValueError, match="zero"):
        plant.ecosystem(np.zeros((0, 8), np.float32))
    # A non-contiguous view is the same terrain.
    wide = np.zeros((33, 66), np.float32)
    wide[:, ::2] = slope()
    a = plant.ecosystem(wide[:, ::2], cell_size=2.0, steps=2)
    b = plant.ecosystem(slope(), cell_size=2.0, steps=2)
    assert np.array_equal(a["positions"], b["positions"])


def test_keyword_defaults_are_the_rust_defaults():
    import inspect

    sig = inspect.signature(plant.ecosystem).parameters
    d = plant.ecosystem_defaults()
    for k in ("steps", "seed", "max_plants"):
        assert sig[k].default == d[k], k
    assert list(sig["sun"].default) == d["sun"]
    assert [s["name"] for s in d["species"]] == ["tree", "shrub", "wet_shrub", "grass"]


def test_a_given_wetness_is_the_map_the_plants_read():
    from natura import terrain

    h = slope()
    plain = plant.ecosystem(h, cell_size=2.0, steps=4, per_species=2)
    # The terrain's own wetness, given: the same plants bit for bit.
    own = terrain.wetness(h, cell_size=2.0)
    given = plant.ecosystem(h, cell_size=2.0, steps=4, per_species=2, wetness=own)
    for k in ("positions", "species", "prototype", "scale", "rotation", "radius"):
        assert np.array_equal(plain[k], given[k]), k
    # Soaked and parched ground: the wet shrub (index 2), whose preference
    # is for wet soil, grows more on the soaked one.
    wet = plant.ecosystem(h, cell_size=2.0, steps=4, wetness=np.ones_like(h))
    dry = plant.ecosystem(h, cell_size=2.0, steps=4, wetness=np.zeros_like(h))
    assert not np.array_equal(wet["species"], dry["species"])
    assert np.sum(wet["species"] == 2) > np.sum(dry["species"] == 2)


def test_bad_wetness_is_named():
    h = slope()
    with pytest.raises(ValueError, match="wetness"):
        plant.ecosystem(h, wetness=np.full((33, 32), 0.5, np.float32))
    with pytest.raises(ValueError, match="wetness"):
        plant.ecosystem(h, wetness=np.full_like(h, 1.5))
    bad = np.full_like(h, 0.5)
    bad[3, 4] = np.nan
    with pytest.raises(ValueError, match="wetness"):
        plant.ecosystem(h, wetness=bad)
    with pytest.raises(TypeError, match="wetness"):
        plant.ecosystem(h, wetness=np.full(h.shape, 0.5))
    with pytest.raises(ValueError, match="wetness"):
        plant.ecosystem(h, wetness=np.full(33 * 33, 0.5, np.float32))
