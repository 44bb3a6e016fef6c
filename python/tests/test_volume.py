"""natura.volume: clouds and smoke equal to the Rust API's, VDB files read
back."""

import numpy as np
import pytest

from natura import volume
from conftest import REFERENCE, hash_array

REF = REFERENCE["volume"]


def test_cumulus_and_layer_equal_the_rust_api_bit_for_bit():
    v = volume.cloud("cumulus", cell=0.5, seed=7, density_scale=0.35)
    assert v.density.dtype == np.float32 and list(v.density.shape) == REF["cumulus_shape"]
    assert list(v.origin) == [np.float32(x) for x in REF["cumulus_origin"]]
    assert hash_array(v.density) == REF["cumulus"]
    assert 0.0 < v.density.max() <= 1.0 and v.density.min() >= 0.0
    lay = volume.layer_clouds(
        cell=250.0, seed=3, region_min=[-2000.0, -2000.0], region_max=[2000.0, 2000.0]
    )
    assert list(lay.density.shape) == REF["layer_shape"]
    assert hash_array(lay.density) == REF["layer"]


def test_smoke_equals_the_rust_api_bit_for_bit():
    s = volume.smoke_plume(cells=24, steps=3)
    assert s.density.shape == (48, 24, 24) and s.temperature.shape == (48, 24, 24)
    assert hash_array(s.density) == REF["smoke_density"]
    assert hash_array(s.temperature) == REF["smoke_temperature"]
    assert s.density.max() > 0.0 and s.temperature.max() > 293.15


def test_defaults_are_the_rust_defaults_and_bad_values_are_named():
    d = volume.cloud_defaults()
    assert d["density_scale"] == pytest.approx(0.3) and d["blend_form"] == "product"
    assert volume.layer_defaults()["base_m"] == 1500.0
    with pytest.raises(ValueError, match="density_scal"):
        volume.cloud(cell=1.0, density_scal=0.3)
    with pytest.raises(ValueError, match="blend"):
        volume.cloud(cell=1.0, blend=2.0)
    with pytest.raises(ValueError, match="cell"):
        volume.cloud(cell=-1.0)
    with pytest.raises(ValueError, match="shape"):
        volume.cloud("anvil")
    with pytest.raises(ValueError, match="coverage"):
        volume.layer_clouds(cell=1000.0, coverage=1.5)
    with pytest.raises(ValueError, match="cells"):
        volume.smoke_plume(cells=2)


def test_progress_counts_slices_and_steps():
    calls = []
    v = volume.cloud(cell=1.0, progress=lambda *a: calls.append(a))
    assert calls[0] == ("bake", 0, v.density.shape[0]) and calls[-1][1] == v.density.shape[0]
    calls.clear()
    volume.smoke_plume(cells=4, steps=2, progress=lambda *a: calls.append(a))
    assert [c for c in calls if c[0] == "smoke"] == [
        ("smoke", 0, 2), ("smoke", 1, 2), ("smoke", 2, 2), ("smoke", 2, 2)]


def test_vdb_round_trip(tmp_path):
    v = volume.cloud(cell=0.5, seed=7)
    path = tmp_path / "cloud.vdb"
    volume.write_vdb(path, v)
    assert [p.name for p in tmp_path.iterdir()] == ["cloud.vdb"]
    back = volume.read_vdb(path)
    assert list(back) == ["density"]
    g = back["density"]
    assert g.cell == v.cell
    # The reader returns the bounding box of the active (non-zero) voxels:
    # placed by its origin, it equals the baked grid there.
    off = np.rint((np.array(g.origin) - np.array(v.origin)) / v.cell).astype(int)
    nz, ny, nx = g.density.shape
    sub = v.density[off[2]:off[2] + nz, off[1]:off[1] + ny, off[0]:off[0] + nx]
    assert np.array_equal(sub, g.density)
    assert sub.sum() == v.density.sum()
    # Two named grids; bad arrays named.
    volume.write_vdb(path, {"a": v.density, "b": 2 * v.density}, origin=v.origin, cell=v.cell)
    assert sorted(volume.read_vdb(path)) == ["a", "b"]
    with pytest.raises(TypeError, match="grids"):
        volume.write_vdb(path, v.density.astype(np.float64))
    with pytest.raises(ValueError, match="3-D"):
        volume.write_vdb(path, v.density[0])
    with pytest.raises(ValueError, match="voxel|NaN|finite"):
        bad = v.density.copy()
        bad[1, 1, 1] = np.nan
        volume.write_vdb(path, bad)
    with pytest.raises(OSError):
        volume.read_vdb(tmp_path / "missing.vdb")


def test_non_contiguous_zero_size_and_nan_grids(tmp_path):
    v = volume.cloud(cell=1.0)
    view = v.density[:, ::-1, ::2]
    volume.write_vdb(tmp_path / "v.vdb", view, cell=2.0)
    g = volume.read_vdb(tmp_path / "v.vdb")["density"]
    assert g.density.sum() == np.ascontiguousarray(view).sum()
    with pytest.raises(ValueError, match="zero"):
        volume.write_vdb(tmp_path / "z.vdb", np.zeros((0, 2, 2), np.float32))
    with pytest.raises(ValueError, match="cell"):
        volume.cloud(cell=float("nan"))
    assert not (tmp_path / "z.vdb").exists()
