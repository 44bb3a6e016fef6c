"""natura.terrain: synthesis, erosion and drainage equal to the Rust API's,
defaults equal to the Rust `Params`' defaults, argument checks, export."""

import inspect
import struct

import numpy as np
import pytest

from natura import _native, terrain
from conftest import REFERENCE, hash_array

REF = REFERENCE["terrain"]


def start():
    return terrain.spectral((40, 48), cell_size=10.0, seed=3)


def test_synthesis_equals_the_rust_api():
    h = start()
    assert h.dtype == np.float32 and h.shape == (40, 48)
    assert hash_array(h) == REF["spectral"]
    assert hash_array(terrain.sra((40, 48), cell_size=10.0, seed=3)) == REF["sra"]
    assert hash_array(terrain.faults((40, 48), cell_size=10.0, seed=3)) == REF["faults"]


@pytest.mark.parametrize("model", _native.TERRAIN_MODELS)
def test_erosion_equals_the_rust_api_bit_for_bit(model):
    h = start()
    f = getattr(terrain, "erode_" + model)
    if model == "droplet":
        out = f(h, cell_size=10.0, droplets=2000, seed=5)
    else:
        out = f(h, cell_size=10.0, steps=20)
    assert out.dtype == np.float32 and out.shape == h.shape
    assert hash_array(out) == REF[model]
    assert not np.array_equal(out, h)
    assert hash_array(h) == REF["spectral"], "the input is left alone"


def test_drainage_equals_the_rust_api():
    h = start()
    filled, depth = terrain.fill_depressions(h, cell_size=10.0)
    assert [hash_array(filled), hash_array(depth)] == REF["fill_depressions"]
    area = terrain.flow_accumulation(h, cell_size=10.0)
    assert hash_array(area) == REF["flow_accumulation"]
    order = terrain.strahler_order(h, cell_size=10.0, threshold_m2=5000.0)
    assert order.dtype == np.uint8 and hash_array(order) == REF["strahler_order"]
    assert hash_array(terrain.wetness(h, cell_size=10.0)) == REF["wetness"]
    channels = terrain.channel_network(area, threshold_m2=5000.0)
    assert channels.dtype == np.bool_
    assert np.array_equal(channels, area >= 5000.0)


@pytest.mark.parametrize("name", _native.TERRAIN_MODELS + _native.TERRAIN_SYNTHS)
def test_python_defaults_are_the_rust_defaults(name):
    rust = _native.terrain_defaults(name)
    f = getattr(terrain, name if name in _native.TERRAIN_SYNTHS else "erode_" + name)
    sig = inspect.signature(f)
    for k, v in rust.items():
        assert sig.parameters[k].default == v, k


@pytest.mark.parametrize(
    "model, kwargs, name",
    [
        ("thermal", dict(talus_rate=-1.0), "talus_rate"),
        ("thermal", dict(edges="wrap"), "edges"),
        ("hydraulic", dict(k_c=float("nan")), "k_c"),
        ("hydraulic", dict(rain="monsoon"), "rain"),
        ("droplet", dict(radius=0), "radius"),
        ("pipe", dict(dt=0.0), "dt"),
        ("stream_power", dict(m=-1.0), "m"),
        ("diffusion", dict(rate=-0.5), "rate"),
    ],
)
def test_bad_parameters_raise_value_error_naming_them(model, kwargs, name):
    with pytest.raises(ValueError, match=name):
        getattr(terrain, "erode_" + model)(start(), **kwargs)


def test_bad_synthesis_parameters_name_them():
    with pytest.raises(ValueError, match="h"):
        terrain.spectral((16, 16), h=1.5)
    with pytest.raises(ValueError, match="lacunarity"):
        terrain.sra((16, 16), lacunarity=1.0)


def test_heights_of_wrong_dtype_or_shape_name_the_argument():
    with pytest.raises(TypeError, match="heights.*float32"):
        terrain.erode_thermal(np.zeros((8, 8)))
    with pytest.raises(ValueError, match="heights must be 2-D"):
        terrain.erode_thermal(np.zeros((8, 8, 2), dtype=np.float32))
    with pytest.raises(TypeError, match="heights.*numpy array"):
        terrain.wetness([[0.0]])
    with pytest.raises(TypeError, match="area.*float32"):
        terrain.channel_network(np.zeros((4, 4)), threshold_m2=1.0)


def test_non_contiguous_zero_size_and_nan_heights_do_not_crash():
    h = start()
    f = np.asfortranarray(h)
    assert np.array_equal(terrain.erode_thermal(f, steps=3), terrain.erode_thermal(h, steps=3))
    view = np.zeros((80, 96), dtype=np.float32)
    view[::2, ::2] = h
    assert np.array_equal(
        terrain.erode_diffusion(view[::2, ::2], steps=3), terrain.erode_diffusion(h, steps=3)
    )
    with pytest.raises(ValueError):
        terrain.erode_thermal(np.zeros((0, 4), dtype=np.float32))
    with pytest.raises(ValueError):
        terrain.flow_accumulation(np.zeros((0, 0), dtype=np.float32))
    bad = h.copy()
    bad[3, 4] = np.nan
    for model in _native.TERRAIN_MODELS:
        with pytest.raises(ValueError):
            getattr(terrain, "erode_" + model)(bad)
    with pytest.raises(ValueError):
        terrain.flow_accumulation(bad)


def test_png16_exr_obj_glb_files(tmp_path):
    h = start()
    terrain.save_png16(h, tmp_path / "h.png")
    png = (tmp_path / "h.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height, depth, colour = struct.unpack(">IIBB", png[16:26])
    assert (width, height, depth, colour) == (48, 40, 16, 0)
    terrain.save_exr(h, tmp_path / "h.exr", cell_size=10.0)
    assert (tmp_path / "h.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"
    terrain.save_obj(h, tmp_path / "h.obj", cell_size=10.0, step=2)
    lines = (tmp_path / "h.obj").read_text().splitlines()
    # Every second sample, the last row and column always included.
    assert sum(line.startswith("v ") for line in lines) == 25 * 21
    terrain.save_glb(h, tmp_path / "h.glb", cell_size=10.0)
    glb = (tmp_path / "h.glb").read_bytes()
    assert glb[:4] == b"glTF" and struct.unpack("<I", glb[8:12])[0] == len(glb)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.exr", "h.glb", "h.obj", "h.png"]
    with pytest.raises(OSError):
        terrain.save_png16(h, tmp_path / "missing" / "h.png")
    with pytest.raises(ValueError, match="step"):
        terrain.save_obj(h, tmp_path / "x.obj", step=0)
