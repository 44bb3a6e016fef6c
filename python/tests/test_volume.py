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


def test_custom_cloud_shapes_equal_the_named_ones_and_bad_primitives_are_named():
    prims = volume.cloud_primitives("cumulus")
    assert len(prims) == 9 and prims[0]["skeleton"] == {"point": [0.0, 0.0, 2.0]}
    named = volume.cloud("cumulus", cell=0.5, seed=7, density_scale=0.35)
    custom = volume.cloud(prims, cell=0.5, seed=7, density_scale=0.35)
    assert np.array_equal(named.density, custom.density) and named.origin == custom.origin
    # One sphere of radius 2 at (10, 0, 3): the cloud lies about it.
    one = volume.cloud([{"skeleton": {"point": [10.0, 0.0, 3.0]}, "radius": 2.0}], cell=0.25)
    nz, ny, nx = one.density.shape
    centre = [one.origin[i] + one.cell * n / 2 for i, n in enumerate((nx, ny, nz))]
    assert centre == pytest.approx([10.0, 0.0, 3.0], abs=0.5)
    assert one.density[nz // 2, ny // 2, nx // 2] > 0.0 and one.density[0, 0, 0] == 0.0
    with pytest.raises(ValueError, match="radius"):
        volume.cloud([{"skeleton": {"point": [0.0, 0.0, 0.0]}, "radius": -1.0}], cell=0.5)
    with pytest.raises(ValueError, match="skeleton"):
        volume.cloud([{"radius": 1.0}], cell=0.5)


def _ball(n=16, value=1.0):
    """A ball of constant density filling an n³ grid of 1/8 m voxels."""
    c = (np.arange(n, dtype=np.float32) + 0.5) / n * 2.0 - 1.0
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    d = np.where(x * x + y * y + z * z < 1.0, value, 0.0).astype(np.float32)
    return volume.Volume(d, (-1.0, -1.0, -1.0), 2.0 / n)


VIEW = dict(eye=(0.0, -4.0, 0.5), target=(0.0, 0.0, 0.0), fov_deg=40.0, width=24, height=24)


def test_an_empty_volume_renders_the_sky_in_both_modes():
    empty = _ball(value=0.0)
    for mode, settings in [("fast", {}), ("reference", {"samples_per_pixel": 2})]:
        img = volume.render(empty, sky=(0.1, 0.2, 0.3), mode=mode, settings=settings, **VIEW)
        assert img.dtype == np.float32 and img.shape == (24, 24, 3)
        assert np.allclose(img, np.array([0.1, 0.2, 0.3], dtype=np.float32), rtol=1e-6)


def test_the_fast_mode_agrees_with_the_reference_on_a_ball():
    ball = _ball()
    medium = {"extinction": 2.0, "albedo": 0.95, "phase": {"henyey_greenstein": 0.6}}
    fast = volume.render(ball, medium=medium, **VIEW)
    ref = volume.render(
        ball, medium=medium, mode="reference",
        settings={"samples_per_pixel": 64, "seed": 3}, **VIEW)
    sky = np.array([0.25, 0.35, 0.55], dtype=np.float32)
    seen = np.abs(ref - sky).sum(axis=2) > 1e-3
    assert 100 < seen.sum() < 24 * 24
    lum = lambda a: (a * np.array([0.2126, 0.7152, 0.0722])).sum(axis=2)
    ratio = lum(fast)[seen].sum() / lum(ref)[seen].sum()
    assert abs(ratio - 1.0) < 0.05, ratio
    # Another variant of an enumeration replaces the default whole.
    rays = volume.render(ball, medium=medium, settings={"shadows": {"rays": 0.05}}, **VIEW)
    assert abs(lum(rays)[seen].sum() / lum(ref)[seen].sum() - 1.0) < 0.05


def test_supersampling_keeps_the_sky_and_softens_the_ball():
    ball = _ball()
    medium = {"extinction": 2.0, "albedo": 0.95, "phase": {"henyey_greenstein": 0.6}}
    one = volume.render(ball, medium=medium, **VIEW)
    four = volume.render(ball, medium=medium, supersample=4, **VIEW)
    assert four.shape == one.shape and four.dtype == np.float32
    # The sky far from the ball stays exactly the sky.
    assert np.array_equal(four[0, 0], one[0, 0])
    # The image's total light agrees within a few per cent, and the edge is
    # softer: fewer large jumps between neighbours.
    lum = lambda a: (a * np.array([0.2126, 0.7152, 0.0722])).sum(axis=2)
    assert abs(lum(four).sum() / lum(one).sum() - 1.0) < 0.03
    jumps = lambda a: (np.abs(np.diff(lum(a), axis=1)) > 0.05).sum()
    assert jumps(four) <= jumps(one)
    with pytest.raises(ValueError, match="supersample"):
        volume.render(ball, supersample=0, **VIEW)
    with pytest.raises(ValueError, match="supersample"):
        volume.render(ball, supersample=2, mode="reference", **VIEW)


def test_bad_render_input_is_named():
    ball = _ball()
    with pytest.raises(ValueError, match="albedo"):
        volume.render(ball, medium={"albedo": 1.5}, **VIEW)
    with pytest.raises(ValueError, match="mode"):
        volume.render(ball, mode="slow", **VIEW)
    with pytest.raises(ValueError, match="fov_deg"):
        volume.render(ball, **{**VIEW, "fov_deg": 0.0})
    with pytest.raises(ValueError, match="target|eye"):
        volume.render(ball, **{**VIEW, "target": VIEW["eye"]})
    with pytest.raises(ValueError, match="stepp"):
        volume.render(ball, settings={"stepp": 0.1}, **VIEW)
    with pytest.raises(ValueError, match="samples_per_pixel"):
        volume.render(ball, mode="reference", settings={"samples_per_pixel": 0}, **VIEW)
    with pytest.raises(ValueError, match="width|resolution"):
        volume.render(ball, **{**VIEW, "width": 0})
    bad = ball.density.copy()
    bad[3, 3, 3] = np.nan
    with pytest.raises(ValueError):
        volume.render(volume.Volume(bad, ball.origin, ball.cell), **VIEW)


def test_render_reports_progress():
    calls = []
    volume.render(_ball(), progress=lambda *a: calls.append(a), **VIEW)
    stages = {c[0] for c in calls}
    assert "shadow tables" in stages and len(stages) >= 2
